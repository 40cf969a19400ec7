/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Kernel tests of the azimuth presummer [P-2.2]: exact baselines (DROP, BOXCAR), the
// phase-compensated coherent sum against a double-precision evaluation of eqs. (P-25..29),
// the Parks-McClellan design against a direct DTFT, and parameter validation.

#include <gnuradio/nrsar/kernel/cheby_presum.h>
#include "kernel/fmod_two_pi.h"
#include "test_util.h"
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

using namespace gr::nrsar;
using cd = std::complex<double>;

namespace {

const numerology num = numerology::preset("small");
const geometry geo = geometry::preset("paper");
const scene scn = scene::preset("paper3");
constexpr unsigned K = 16;
constexpr double first_m = 1020.0, bin_m = 1.5;

kernel::presum_config config(presum_method m, unsigned d)
{
    kernel::presum_config c;
    c.method = m;
    c.decim = d;
    return c;
}

// Runs the kernel over P pulses, returns the outputs.
std::vector<std::vector<gr_complex>> run(kernel::cheby_presum& k,
                                         const std::vector<gr_complex>& x,
                                         unsigned pulses)
{
    std::vector<std::vector<gr_complex>> out;
    std::vector<gr_complex> o(k.num_bins());
    for (unsigned p = 0; p < pulses; ++p)
        if (k.push(x.data() + std::size_t(p) * k.num_bins(), o.data()))
            out.push_back(o);
    return out;
}

} // namespace

TEST(cheby_presum, drop_keeps_every_dth_pulse)
{
    const unsigned d = 7, pulses = 100;
    kernel::cheby_presum k(num, geo, scn, K, first_m, bin_m, config(presum_method::DROP, d));
    const auto x = nrsar_test::gaussian_samples(std::size_t(pulses) * K, 1);
    const auto out = run(k, x, pulses);
    ASSERT_EQ(out.size(), (pulses + d - 1) / d);
    for (std::size_t g = 0; g < out.size(); ++g)
        for (unsigned n = 0; n < K; ++n)
            EXPECT_EQ(out[g][n], x[g * d * K + n]);
}

TEST(cheby_presum, boxcar_sums_groups)
{
    const unsigned d = 5, pulses = 50;
    kernel::cheby_presum k(num, geo, scn, K, first_m, bin_m, config(presum_method::BOXCAR, d));
    const auto x = nrsar_test::gaussian_samples(std::size_t(pulses) * K, 2);
    const auto out = run(k, x, pulses);
    ASSERT_EQ(out.size(), pulses / d);
    for (std::size_t g = 0; g < out.size(); ++g)
        for (unsigned n = 0; n < K; ++n) {
            cd acc = 0;
            for (unsigned j = 0; j < d; ++j)
                acc += cd(x[(g * d + j) * K + n]);
            EXPECT_NEAR(std::abs(cd(out[g][n]) - acc), 0.0, 1e-5);
        }
}

TEST(cheby_presum, cheby_sums_reference_history_coherently)
{
    // Input: the exact phase history of a scatterer at the scene's along-track centre on
    // every bin's closest-approach range, eq. (P-25); output g must be D times the
    // history at the window centre: eqs. (P-27..29), evaluated here in double.
    const unsigned d = 12, pulses = 1200;
    kernel::cheby_presum k(num, geo, scn, K, first_m, bin_m, config(presum_method::CHEBY, d));
    const double t = num.symbol_s();
    const double yc = 0.5 * (100.0 + 140.0); // paper3 targets at y = 100, 100, 140
    const double f = geo.carrier_hz + 0.5 * (num.num_subcarriers - 1) * num.subcarrier_spacing_hz;
    auto phase = [&](unsigned n, double time) {
        const double r0 = first_m + n * bin_m;
        const double u = geo.track_start_m + geo.velocity_mps * time - yc;
        return 4 * M_PI * f * std::sqrt(r0 * r0 + u * u) / speed_of_light;
    };
    std::vector<gr_complex> x(std::size_t(pulses) * K);
    for (unsigned p = 0; p < pulses; ++p)
        for (unsigned n = 0; n < K; ++n)
            x[std::size_t(p) * K + n] = gr_complex(std::polar(1.0, -phase(n, p * t)));
    const auto out = run(k, x, pulses);
    ASSERT_GT(out.size(), 10u);
    const unsigned g0 = (k.num_taps() + d - 1) / d; // past the zero history
    double worst = 0.0;
    for (std::size_t g = g0; g < out.size(); ++g)
        for (unsigned n = 0; n < K; ++n) {
            const cd want =
                double(d) * std::polar(1.0, -phase(n, (g * d + k.centre_offset()) * t));
            worst = std::max(worst, std::abs(cd(out[g][n]) - want) / d);
        }
    EXPECT_LT(worst, 2e-3);
}

TEST(cheby_presum, compensation_phase_matches_eq27)
{
    kernel::cheby_presum k(num, geo, scn, K, first_m, bin_m, config(presum_method::CHEBY, 10));
    const double f = geo.carrier_hz + 0.5 * (num.num_subcarriers - 1) * num.subcarrier_spacing_hz;
    const double t = num.symbol_s();
    for (unsigned n : { 0u, 7u, 15u })
        for (double tref : { 0.0, 0.7, 1.9 })
            for (int m : { 1, 5, 39 }) {
                const double r0 = first_m + n * bin_m;
                const double a = geo.velocity_mps * tref - 120.0;
                const double b = geo.velocity_mps * (tref + m * t) - 120.0;
                const double want =
                    4 * M_PI * f * (std::sqrt(r0 * r0 + b * b) - std::sqrt(r0 * r0 + a * a)) /
                    speed_of_light;
                EXPECT_NEAR(k.compensation_phase(n, tref, m), want, 1e-9);
            }
}

TEST(cheby_presum, design_meets_dtft)
{
    const unsigned d = 12;
    kernel::cheby_presum k(num, geo, scn, K, first_m, bin_m, config(presum_method::CHEBY, d));
    const auto& h = k.prototype();
    ASSERT_EQ(h.size(), 4 * d);
    EXPECT_TRUE(k.equiripple());
    double sum = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        sum += h[i];
        EXPECT_NEAR(h[i], h[h.size() - 1 - i], 1e-12); // linear phase
    }
    EXPECT_NEAR(sum, d, 1e-9);
    const double t = num.symbol_s();
    auto mag = [&](double fr) {
        cd acc = 0;
        for (std::size_t i = 0; i < h.size(); ++i)
            acc += h[i] * std::polar(1.0, -2 * M_PI * fr * i * t);
        return std::abs(acc);
    };
    double smax = 0.0;
    for (double fr = k.stopband_hz(); fr <= 0.5 / t; fr += 1.0)
        smax = std::max(smax, mag(fr));
    EXPECT_NEAR(20 * std::log10(d / smax), k.stopband_atten_db(), 0.05);
    EXPECT_GT(k.stopband_atten_db(), 30.0);
    EXPECT_LT(k.passband_ripple_db(), 0.5);
}

TEST(cheby_presum, filter_drop_passes_the_centroid)
{
    const unsigned d = 10, pulses = 800;
    kernel::cheby_presum k(
        num, geo, scn, 1, first_m, bin_m, config(presum_method::FILTER_DROP, d));
    const double t = num.symbol_s();
    for (double f : { k.doppler_centroid_hz(), k.doppler_centroid_hz() + 0.5 / (d * t) + 200 }) {
        kernel::cheby_presum kk(
            num, geo, scn, 1, first_m, bin_m, config(presum_method::FILTER_DROP, d));
        std::vector<gr_complex> x(pulses);
        for (unsigned p = 0; p < pulses; ++p)
            x[p] = gr_complex(std::polar(1.0, 2 * M_PI * f * p * t));
        const auto out = run(kk, x, pulses);
        const double a = std::abs(out[out.size() / 2][0]);
        if (f == k.doppler_centroid_hz())
            EXPECT_NEAR(a, d, 0.05 * d);
        else
            EXPECT_GE(20 * std::log10(d / a), k.stopband_atten_db() - 0.5);
    }
}

TEST(cheby_presum, invalid_parameters)
{
    EXPECT_THROW(kernel::cheby_presum(num, geo, scn, K, first_m, bin_m, config(presum_method::CHEBY, 0)),
                 std::invalid_argument);
    const unsigned dmax = kernel::cheby_presum::max_decim(num, geo, scn);
    try {
        kernel::cheby_presum(num, geo, scn, K, first_m, bin_m, config(presum_method::CHEBY, dmax + 1));
        FAIL() << "D above eq. (P-36) accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("D_max = " + std::to_string(dmax)), std::string::npos)
            << e.what();
    }
    auto c = config(presum_method::CHEBY, dmax + 1);
    c.enforce_qpe_bound = false;
    c.num_taps = 64;
    EXPECT_NO_THROW(kernel::cheby_presum(num, geo, scn, K, first_m, bin_m, c));
    c = config(presum_method::CHEBY, 10);
    c.domain = presum_domain::TF;
    EXPECT_THROW(kernel::cheby_presum(num, geo, scn, K, first_m, bin_m, c), std::invalid_argument);
}

TEST(cheby_presum, first_output_equals_the_whole_stream)
{
    // A strip's task (first_output g0) starts at the flight's pulse max(0, g0 D - a), a =
    // (L - 1) / 2 of the window centred on g D (D - 1 / 0 for BOXCAR / DROP: a = 0), and
    // emits outputs g0, g0 + 1, ...: each equals the whole stream's output g bit for bit
    // (the same slow times, ring slots and phase segments). A pulse interval set before the
    // first pulse (the adapter's tag) is the flight's from pulse 0 in both.
    const unsigned d = 6, pulses = 900;
    const auto x = nrsar_test::gaussian_samples(std::size_t(pulses) * num.num_subcarriers, 7);
    for (const auto method : { presum_method::CHEBY, presum_method::BOXCAR,
                               presum_method::DROP, presum_method::FILTER_DROP }) {
        for (const auto domain : { presum_domain::RANGE, presum_domain::TF }) {
            auto c = config(method, d);
            c.domain = domain;
            const unsigned bins = domain == presum_domain::TF ? num.num_subcarriers : K;
            kernel::cheby_presum whole(num, geo, scn, bins, first_m, bin_m, c);
            whole.set_pulse_interval(1.5 * num.symbol_s());
            const auto all = run(whole, x, pulses);
            const unsigned l = whole.num_taps();
            const unsigned a = method == presum_method::CHEBY ||
                                       method == presum_method::FILTER_DROP
                                   ? (l - 1) / 2
                                   : 0;
            EXPECT_EQ(whole.history(), a);
            // g0 = 1: its window reaches before the flight (first pulse 0); the others start
            // mid-flight, inside a phase segment for CHEBY
            for (const std::uint64_t g0 : { 1u, 17u, 61u }) {
                c.first_output = g0;
                kernel::cheby_presum task(num, geo, scn, bins, first_m, bin_m, c);
                task.set_pulse_interval(1.5 * num.symbol_s());
                const std::uint64_t p0 = g0 * d > a ? g0 * d - a : 0;
                ASSERT_EQ(task.first_pulse(), p0);
                std::vector<gr_complex> o(bins);
                std::uint64_t g = g0;
                for (std::uint64_t p = p0; p < pulses; ++p)
                    if (task.push(x.data() + p * bins, o.data())) {
                        ASSERT_LT(g, all.size());
                        for (unsigned n = 0; n < bins; ++n)
                            ASSERT_EQ(o[n], all[g][n])
                                << int(method) << " domain " << int(domain) << " g0 " << g0
                                << " output " << g << " bin " << n;
                        ++g;
                    }
                EXPECT_EQ(g, all.size()) << int(method) << " g0 " << g0;
                EXPECT_EQ(task.pulses_out(), all.size());
            }
            if (method == presum_method::CHEBY) {
                EXPECT_GT(whole.phase_segment(), 1u); // the mid-segment start is exercised
            }
        }
    }
    // LMS adapts from its first pulse: refused
    auto c = config(presum_method::LMS, d);
    c.first_output = 3;
    EXPECT_THROW(kernel::cheby_presum(num, geo, scn, K, first_m, bin_m, c), std::invalid_argument);
}

TEST(cheby_presum, first_output_along_a_path_equals_the_whole_stream)
{
    // CHEBY along a swaying navigation path: the phase segments adapt their length to the
    // path (halved from 64 pulses) within blocks of 64 from pulse 0; a task starting inside
    // one finds it from its block's start, so its outputs equal the whole stream's bit for bit
    const unsigned d = 4, pulses = 1500;
    std::vector<double> t;
    std::vector<vec3> p;
    for (double s = 0.0; s <= 0.1; s += 0.001) { // 5 mm of sway, 0.1 s period (20 m/s^2)
        const double w = 0.005 * std::sin(2.0 * M_PI * s / 0.1);
        t.push_back(s);
        p.push_back({ w, geo.track_start_m + geo.velocity_mps * s, geo.height_m + 0.5 * w });
    }
    const trajectory nav = trajectory::from_samples(t, p, {}, { 0.0, 0.0, 0.0 }, "sway");
    const auto x = nrsar_test::gaussian_samples(std::size_t(pulses) * num.num_subcarriers, 9);
    for (const auto domain : { presum_domain::RANGE, presum_domain::TF }) {
        auto c = config(presum_method::CHEBY, d);
        c.domain = domain;
        const unsigned bins = domain == presum_domain::TF ? num.num_subcarriers : K;
        kernel::cheby_presum whole(num, geo, scn, bins, first_m, bin_m, c, nav);
        ASSERT_TRUE(whole.follows_path());
        ASSERT_LT(pulses * whole.pulse_interval_s(), 0.1); // the path covers the stream
        std::vector<std::vector<gr_complex>> all;
        std::vector<gr_complex> out(bins);
        unsigned shortest = 64, longest = 1;
        for (unsigned q = 0; q < pulses; ++q) {
            if (whole.push(x.data() + std::size_t(q) * bins, out.data()))
                all.push_back(out);
            shortest = std::min(shortest, whole.phase_segment());
            longest = std::max(longest, whole.phase_segment());
        }
        EXPECT_LT(shortest, longest); // segments of several lengths: the replay is exercised
        EXPECT_GT(longest, 2u);
        for (const std::uint64_t g0 : { 20u, 97u, 250u }) {
            c.first_output = g0;
            kernel::cheby_presum task(num, geo, scn, bins, first_m, bin_m, c, nav);
            std::vector<gr_complex> o(bins);
            std::uint64_t g = g0;
            for (std::uint64_t q = task.first_pulse(); q < pulses; ++q)
                if (task.push(x.data() + q * bins, o.data())) {
                    ASSERT_LT(g, all.size());
                    for (unsigned n = 0; n < bins; ++n)
                        ASSERT_EQ(o[n], all[g][n]) << "domain " << int(domain) << " g0 " << g0
                                                   << " output " << g << " bin " << n;
                    ++g;
                }
            EXPECT_EQ(g, all.size());
        }
    }
}

// The phase rows' reduction equals std::fmod bit for bit: random phases up to the 1e5 rad
// of the paper geometry and far beyond, the multiples of 2 pi and their neighbours (where
// the quotient's rounding puts q off by one), and the fallbacks.
TEST(cheby_presum, fmod_two_pi_equals_std_fmod)
{
    constexpr double two_pi = 2.0 * M_PI;
    std::vector<double> x = { 0.0, -0.0, 1e-300, two_pi, -1.0, -3e5, 0x1p52, 1e300,
                              std::numeric_limits<double>::infinity(),
                              std::numeric_limits<double>::quiet_NaN() };
    for (int q = 0; q < 100000; q += 7) {
        const double m = q * two_pi;
        x.insert(x.end(), { m, std::nextafter(m, 0.0), std::nextafter(m, 1e300) });
    }
    std::mt19937_64 rng(5);
    for (double hi : { 10.0, 3e5, 1e12, 4e15 }) {
        std::uniform_real_distribution<double> u(0.0, hi);
        for (int i = 0; i < 100000; ++i)
            x.push_back(u(rng));
    }
    for (double v : x) {
        const double want = std::fmod(v, two_pi), got = kernel::fmod_two_pi(v);
        EXPECT_EQ(std::memcmp(&want, &got, sizeof(double)), 0) << v << ": " << got << " vs " << want;
    }
}
