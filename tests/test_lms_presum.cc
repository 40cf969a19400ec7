/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Kernel tests of the LMS presumming baseline [P-3.1]: the recursion against a
// double-precision implementation written here, the normalised-LMS misadjustment
// mu / (2 - mu) on white noise, a noise-free tone learnt and predicted, output timing,
// parameter validation (also through cheby_presum's method set).

#include <gnuradio/nrsar/kernel/cheby_presum.h>
#include <gnuradio/nrsar/kernel/lms_presum.h>
#include "test_util.h"
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <vector>

using namespace gr::nrsar;
using cd = std::complex<double>;

namespace {

// The adaptive line enhancer in double: y = w^H x, w += mu conj(e) x / ||x||^2, x the L
// previous samples of one element (zeros before the start). Returns y of every pulse.
std::vector<cd> ale_double(const std::vector<gr_complex>& x,
                           unsigned k,
                           unsigned element,
                           unsigned pulses,
                           unsigned l,
                           double mu)
{
    std::vector<cd> w(l), hist(l), y(pulses);
    for (unsigned m = 0; m < pulses; ++m) {
        cd acc = 0.0;
        double nrm = 0.0;
        for (unsigned j = 0; j < l; ++j) {
            acc += std::conj(w[j]) * hist[j];
            nrm += std::norm(hist[j]);
        }
        y[m] = acc;
        const cd s = cd(x[std::size_t(m) * k + element]);
        if (nrm > 0.0)
            for (unsigned j = 0; j < l; ++j)
                w[j] += mu * std::conj(s - acc) * hist[j] / nrm;
        for (unsigned j = l - 1; j > 0; --j)
            hist[j] = hist[j - 1];
        hist[0] = s;
    }
    return y;
}

} // namespace

TEST(lms_presum, matches_a_double_precision_ale)
{
    const unsigned k = 5, d = 4, l = 12, pulses = 3000;
    const double mu = 0.3;
    auto x = nrsar_test::gaussian_samples(std::size_t(pulses) * k, 3);
    for (unsigned m = 0; m < pulses; ++m) // a tone in element 2 at 0 dB
        x[std::size_t(m) * k + 2] += gr_complex(std::polar(1.4, 0.05 * m));
    kernel::lms_presum lms(k, d, l, mu);
    std::vector<gr_complex> o(k);
    std::vector<std::vector<gr_complex>> out;
    for (unsigned m = 0; m < pulses; ++m)
        if (lms.push(x.data() + std::size_t(m) * k, o.data()))
            out.push_back(o);
    ASSERT_EQ(out.size(), (pulses + d - 1) / d); // outputs at pulses 0, D, 2 D, ...
    for (unsigned n = 0; n < k; ++n) {
        const auto y = ale_double(x, k, n, pulses, l, mu);
        double err = 0.0, ref = 0.0;
        for (std::size_t g = 0; g < out.size(); ++g) {
            err += std::norm(cd(out[g][n]) - double(d) * y[g * d]);
            ref += std::norm(double(d) * y[g * d]);
        }
        EXPECT_LT(std::sqrt(err / ref), 1e-4) << "element " << n;
    }
}

TEST(lms_presum, white_noise_misadjustment)
{
    // Steady-state excess MSE of normalised LMS: mu / (2 - mu) of the input power; on white
    // noise the predictor's output is only that excess. L = 48: the O(2 / L) correction of
    // the estimate and 64 x 6000 correlated samples (time constant L / mu) stay below 8 %.
    const unsigned k = 64, l = 48, pulses = 8000, skip = 2000;
    for (double mu : { 0.2, 0.5 }) {
        const auto x = nrsar_test::gaussian_samples(std::size_t(pulses) * k, 7);
        kernel::lms_presum lms(k, 1, l, mu);
        std::vector<gr_complex> o(k);
        double p = 0.0;
        for (unsigned m = 0; m < pulses; ++m) {
            lms.push(x.data() + std::size_t(m) * k, o.data());
            if (m >= skip)
                for (auto v : o)
                    p += std::norm(v);
        }
        p /= double(pulses - skip) * k * 2.0; // input power 2 per sample
        EXPECT_NEAR(p / (mu / (2.0 - mu)), 1.0, 0.08) << "mu " << mu;
    }
}

TEST(lms_presum, learns_a_noise_free_tone)
{
    // A tone is predictable one pulse ahead exactly: the output becomes D s(g D).
    const unsigned d = 12, l = 48, pulses = 4000;
    kernel::lms_presum lms(1, d, l, 0.5);
    std::vector<gr_complex> x(pulses);
    for (unsigned m = 0; m < pulses; ++m)
        x[m] = gr_complex(std::polar(2.0, 2.0 * M_PI * 0.013 * m + 0.4));
    gr_complex o;
    for (unsigned m = 0; m < pulses; ++m) {
        if (lms.push(&x[m], &o) && m > pulses / 2) {
            EXPECT_LT(std::abs(o - float(d) * x[m]), 1e-3 * d * 2.0) << "pulse " << m;
        }
    }
}

TEST(lms_presum, rejects_bad_parameters)
{
    using nrsar_test::error_of;
    EXPECT_NE(error_of([] { kernel::lms_presum(0, 2, 4, 0.2); }).find("num_bins"), std::string::npos);
    EXPECT_NE(error_of([] { kernel::lms_presum(4, 0, 4, 0.2); }).find("decim"), std::string::npos);
    EXPECT_NE(error_of([] { kernel::lms_presum(4, 2, 0, 0.2); }).find("num_taps"), std::string::npos);
    for (double mu : { 0.0, 2.0, -0.1, double(NAN) })
        EXPECT_NE(error_of([mu] { kernel::lms_presum(4, 2, 4, mu); }).find("lms_step"),
                  std::string::npos)
            << mu;
    // through the presummer's method set
    kernel::presum_config c;
    c.method = presum_method::LMS;
    c.decim = 12;
    c.lms_step = 2.5;
    const auto num = numerology::preset("small");
    const auto geo = geometry::preset("paper");
    const auto scn = scene::preset("paper3");
    EXPECT_NE(error_of([&] { kernel::cheby_presum(num, geo, scn, 8, 1000.0, 1.5, c); })
                  .find("lms_step"),
              std::string::npos);
    c.lms_step = 0.2;
    kernel::cheby_presum p(num, geo, scn, 8, 1000.0, 1.5, c);
    EXPECT_EQ(p.num_taps(), 48u); // 4 D by default
    EXPECT_EQ(p.lookahead(), 0u);
    EXPECT_EQ(p.centre_offset(), 0.0);
}
