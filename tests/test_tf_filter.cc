/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Kernel tests of the per-RE filters, eq. (25), against direct double-precision formulas.

#include <gnuradio/nrsar/kernel/tf_filter.h>
#include "kernel/cpu_features.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace gr::nrsar;
using cd = std::complex<double>;

namespace {

// 256-QAM points of SPEC 2 (38.211 5.1), unit mean power, written out here independently.
std::vector<gr_complex> qam256_points()
{
    std::vector<gr_complex> pts;
    for (int b = 0; b < 256; b++) {
        auto bit = [&](int i) { return 1 - 2 * ((b >> (7 - i)) & 1); };
        const double re = bit(0) * (8 - bit(2) * (4 - bit(4) * (2 - bit(6))));
        const double im = bit(1) * (8 - bit(3) * (4 - bit(5) * (2 - bit(7))));
        pts.emplace_back(float(re / std::sqrt(170.0)), float(im / std::sqrt(170.0)));
    }
    return pts;
}

// Standard deviation [dB] of the estimator's 10 log10(P^ / sigma^2^) for n REs of
// y = h s + z, |h| = 1, s uniform on 256-QAM, z ~ CN(0, sigma^2), worked out here: the
// estimator is the least-squares line |y|^2 = P |s|^2 + sigma^2 (slope P, intercept sigma^2),
// whose residual e = 2 Re(h s z*) + |z|^2 - sigma^2 has Var(e | u = |s|^2) = sigma^4 +
// 2 P sigma^2 u. Its covariance is M^-1 S M^-1 / n (M = E[x x^T], S = E[Var(e|u) x x^T],
// x = (1, u)), propagated to dB through the gradient (10 / ln 10) (-1 / sigma^2, 1 / P).
// A float64 Monte Carlo of 400 runs at 10 dB, n = 20000 gave 0.235 dB against 0.233 here.
double snr_estimate_std_db(double snr_db, double n)
{
    const double p = 1.0, s2 = std::pow(10.0, -snr_db / 10.0);
    double m[3] = { 0, 0, 0 }, sv[3] = { 0, 0, 0 }; // E[u^k], E[v u^k], k = 0..2
    for (const auto& pt : qam256_points()) {
        const double u = std::norm(std::complex<double>(pt));
        const double v = s2 * s2 + 2.0 * p * s2 * u;
        for (int k = 0; k < 3; k++) {
            m[k] += std::pow(u, k) / 256.0;
            sv[k] += v * std::pow(u, k) / 256.0;
        }
    }
    const double det = m[0] * m[2] - m[1] * m[1];
    const double mi[2][2] = { { m[2] / det, -m[1] / det }, { -m[1] / det, m[0] / det } };
    const double sm[2][2] = { { sv[0], sv[1] }, { sv[1], sv[2] } };
    double c[2][2] = { { 0, 0 }, { 0, 0 } }; // covariance of (sigma^2^, P^)
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++)
            for (int k = 0; k < 2; k++)
                for (int l = 0; l < 2; l++)
                    c[i][j] += mi[i][k] * sm[k][l] * mi[l][j] / n;
    const double g[2] = { -1.0 / s2, 1.0 / p };
    double var = 0.0;
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++)
            var += g[i] * c[i][j] * g[j];
    return 10.0 / std::log(10.0) * std::sqrt(var);
}

struct grid {
    std::vector<gr_complex> y, s;
};

grid random_grid(std::size_t n, unsigned seed, std::size_t every_empty = 0)
{
    std::mt19937 rng(seed);
    std::normal_distribution<float> g(0.0f, 1.0f);
    const auto pts = qam256_points();
    std::uniform_int_distribution<int> pick(0, 255);
    grid d;
    for (std::size_t i = 0; i < n; i++) {
        d.y.emplace_back(g(rng), g(rng));
        const bool empty = every_empty && (i % every_empty == 0);
        d.s.push_back(empty ? gr_complex(0, 0) : pts[pick(rng)]);
    }
    return d;
}

cd reference_g(filter_type type, cd s, double snr)
{
    const double m = std::norm(s);
    switch (type) {
    case filter_type::RF:
        return m == 0.0 ? cd(0) : 1.0 / s;
    case filter_type::MF:
        return std::conj(s);
    case filter_type::WF:
        return std::conj(s) / (m + 1.0 / snr);
    }
    return 0;
}

void expect_matches(filter_type type, double snr_db, std::size_t every_empty)
{
    const std::size_t n = 1001; // odd: exercises the VOLK tails
    auto d = random_grid(n, 7, every_empty);
    kernel::tf_filter f(n, type, snr_db, false);
    std::vector<gr_complex> out(n);
    EXPECT_EQ(f.process(d.y.data(), d.s.data(), out.data()), 0u);
    const double snr = std::pow(10.0, snr_db / 10.0);
    for (std::size_t i = 0; i < n; i++) {
        const cd ref = cd(d.y[i]) * reference_g(type, cd(d.s[i]), snr);
        EXPECT_NEAR(std::abs(cd(out[i]) - ref), 0.0, 1e-5 * (1.0 + std::abs(ref)))
            << "RE " << i;
    }
}

} // namespace

TEST(ReFilter, ReciprocalMatchesDirectFormula) { expect_matches(filter_type::RF, 0.0, 0); }
TEST(ReFilter, MatchedMatchesDirectFormula) { expect_matches(filter_type::MF, 0.0, 0); }
TEST(ReFilter, WienerMatchesDirectFormulaLowSnr) { expect_matches(filter_type::WF, -20.0, 0); }
TEST(ReFilter, WienerMatchesDirectFormulaHighSnr) { expect_matches(filter_type::WF, 20.0, 0); }
TEST(ReFilter, AllFiltersWithEmptyREs)
{
    for (auto t : { filter_type::RF, filter_type::MF, filter_type::WF })
        expect_matches(t, 5.0, 4);
}

// The one pass (AVX2 on eight REs per step with real and imaginary parts apart, then the
// scalar tail) rounds as the float formula written here, bit for bit: the same products,
// weight and window tap in the same order (range_compress's result equals the separate
// blocks', and nrsar-sim's metrics stay put, because of this).
TEST(ReFilter, OnePassRoundsAsTheFloatFormula)
{
    if (!kernel::cpu_supports_avx2())
        GTEST_SKIP() << "no AVX2: tf_filter takes VOLK's passes, not the one pass";
    const std::size_t n = 1003; // 125 steps of eight and a tail of three
    const auto d = random_grid(n, 11, 5);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> taps2(2 * n);
    for (std::size_t i = 0; i < n; i++)
        taps2[2 * i] = taps2[2 * i + 1] = u(rng);
    const float* windowed = taps2.data();
    const float inv_snr = static_cast<float>(1.0 / std::pow(10.0, -20.0 / 10.0));
    for (filter_type type : { filter_type::MF, filter_type::RF, filter_type::WF })
        for (const float* taps : { static_cast<const float*>(nullptr), windowed }) {
            kernel::tf_filter f(n, type, -20.0, false);
            std::vector<gr_complex> out(n);
            EXPECT_EQ(f.process(d.y.data(), d.s.data(), out.data(), taps), 0u);
            for (std::size_t i = 0; i < n; i++) {
                const float yr = d.y[i].real(), yi = d.y[i].imag(), sr = d.s[i].real(),
                            si = d.s[i].imag();
                const float m = sr * sr + si * si;
                const float e = m < std::numeric_limits<float>::min() ? 1.0f : 0.0f;
                float pr = yr * sr + yi * si, pi = yi * sr - yr * si;
                if (type != filter_type::MF) {
                    const float w = type == filter_type::WF ? 1.0f / (m + inv_snr)
                                                            : (1.0f - e) / (m + e);
                    pr *= w;
                    pi *= w;
                }
                if (taps) {
                    pr *= taps[2 * i];
                    pi *= taps[2 * i + 1];
                }
                const gr_complex want(pr, pi);
                EXPECT_EQ(std::memcmp(&out[i], &want, sizeof want), 0)
                    << "filter " << int(type) << " RE " << i << ": " << out[i] << " vs " << want;
            }
        }
}

TEST(ReFilter, FactoryReturnsRequestedType)
{
    for (auto t : { filter_type::RF, filter_type::MF, filter_type::WF })
        EXPECT_EQ(kernel::make_re_filter(t, 1.0)->type(), t);
}

TEST(TfFilter, EmptyREsGiveZeroAndAreCounted)
{
    const std::size_t n = 64;
    auto d = random_grid(n, 3, 4); // every 4th RE empty: 16 per vector
    for (auto t : { filter_type::RF, filter_type::MF, filter_type::WF }) {
        kernel::tf_filter f(n, t, 10.0, false);
        std::vector<gr_complex> out(n);
        f.process(d.y.data(), d.s.data(), out.data());
        f.process(d.y.data(), d.s.data(), out.data());
        EXPECT_EQ(f.empty_re_count(), 32u);
        for (std::size_t i = 0; i < n; i += 4) {
            EXPECT_EQ(out[i], gr_complex(0, 0));
        }
        for (std::size_t i = 1; i < n; i += 4)
            EXPECT_TRUE(std::isfinite(out[i].real()));
    }
}

TEST(TfFilter, NonFiniteInputsAreZeroedAndCounted)
{
    const std::size_t n = 40;
    auto d = random_grid(n, 5);
    d.y[3] = gr_complex(std::numeric_limits<float>::quiet_NaN(), 0.0f);
    d.y[10] = gr_complex(0.0f, std::numeric_limits<float>::infinity());
    d.s[20] = gr_complex(std::numeric_limits<float>::infinity(), 1.0f);
    kernel::tf_filter f(n, filter_type::RF, 10.0, false);
    std::vector<gr_complex> out(n);
    EXPECT_EQ(f.process(d.y.data(), d.s.data(), out.data()), 3u);
    EXPECT_EQ(f.nonfinite_count(), 3u);
    EXPECT_EQ(out[3], gr_complex(0, 0));
    EXPECT_EQ(out[10], gr_complex(0, 0));
    EXPECT_EQ(out[20], gr_complex(0, 0)); // zeroed reference: an empty RE
    EXPECT_EQ(f.empty_re_count(), 1u);
    for (std::size_t i = 0; i < n; i++)
        EXPECT_TRUE(std::isfinite(out[i].real()) && std::isfinite(out[i].imag()));
}

TEST(TfFilter, SetFilterTypeAndSnrTakeEffect)
{
    const std::size_t n = 16;
    auto d = random_grid(n, 9);
    kernel::tf_filter f(n, filter_type::MF, 0.0, false);
    std::vector<gr_complex> out(n);
    f.set_filter_type(filter_type::WF);
    f.set_snr_db(-10.0);
    EXPECT_EQ(f.type(), filter_type::WF);
    f.process(d.y.data(), d.s.data(), out.data());
    const cd ref = cd(d.y[2]) * reference_g(filter_type::WF, cd(d.s[2]), 0.1);
    EXPECT_NEAR(std::abs(cd(out[2]) - ref), 0.0, 1e-5 * (1 + std::abs(ref)));
}

TEST(TfFilter, RejectsBadParameters)
{
    EXPECT_THROW(kernel::tf_filter(0, filter_type::RF, 0.0, false), std::invalid_argument);
    EXPECT_THROW(kernel::tf_filter(8, filter_type::WF, NAN, false), std::invalid_argument);
    kernel::tf_filter f(8, filter_type::WF, 0.0, false);
    EXPECT_THROW(f.set_snr_db(INFINITY), std::invalid_argument);
}

// Echo y = H s + z of one target (|H|^2 = 1) in complex white noise.
class SnrEstimate : public ::testing::TestWithParam<double>
{
};

TEST_P(SnrEstimate, WithinFourSigmaFor256Qam)
{
    const double snr_db = GetParam();
    // 2^24 REs at -20 dB (the default window), 1000 symbols of 3333 REs above
    const std::size_t n = 3333, vectors = snr_db < 0 ? 5034 : 1000;
    const double sigma = std::sqrt(std::pow(10.0, -snr_db / 10.0) / 2.0);
    std::mt19937 rng(11);
    std::normal_distribution<double> g(0.0, sigma);
    std::uniform_int_distribution<int> pick(0, 255);
    std::uniform_real_distribution<double> ph(0, 2 * M_PI);
    const auto pts = qam256_points();
    kernel::tf_filter f(n, filter_type::WF, 0.0, true, n * vectors);
    std::vector<gr_complex> y(n), s(n), out(n);
    for (std::size_t v = 0; v < vectors; v++) {
        for (std::size_t i = 0; i < n; i++) {
            s[i] = pts[pick(rng)];
            const cd h = std::polar(1.0, ph(rng));
            y[i] = gr_complex(h * cd(s[i]) + cd(g(rng), g(rng)));
        }
        f.process(y.data(), s.data(), out.data());
    }
    // 4 standard deviations of the estimator for the REs in its window (0.17 dB at -20 dB,
    // 0.013 dB at 5 dB, 0.051 dB at 20 dB): a Gaussian error beyond it has probability 6e-5
    // (measured errors, seed 11: -0.066, +0.004, +0.020 dB)
    const double window =
        std::min<double>(n * vectors, kernel::snr_estimator::default_window_res);
    const double tol = 4.0 * snr_estimate_std_db(snr_db, window);
    EXPECT_NEAR(f.estimated_snr_db(), snr_db, tol);
    EXPECT_NEAR(f.effective_snr_db(), snr_db, tol);
}

INSTANTIATE_TEST_SUITE_P(Paper, SnrEstimate, ::testing::Values(-20.0, 5.0, 20.0));

TEST(SnrEstimator, ConstantModulusKeepsGivenSnr)
{
    const std::size_t n = 256;
    std::mt19937 rng(2);
    std::uniform_int_distribution<int> bit(0, 1);
    std::normal_distribution<float> g(0.0f, 0.3f);
    kernel::tf_filter f(n, filter_type::WF, 7.0, true);
    std::vector<gr_complex> y(n), s(n), out(n);
    for (int v = 0; v < 10; v++) {
        for (std::size_t i = 0; i < n; i++) {
            const float a = float(M_SQRT1_2);
            s[i] = gr_complex(bit(rng) ? a : -a, bit(rng) ? a : -a); // QPSK
            y[i] = s[i] + gr_complex(g(rng), g(rng));
        }
        f.process(y.data(), s.data(), out.data());
    }
    EXPECT_TRUE(std::isnan(f.estimated_snr_db()));
    EXPECT_DOUBLE_EQ(f.effective_snr_db(), 7.0);
}

TEST(SnrEstimator, WindowForgetsOldData)
{
    // 50000 REs at 0 dB, then 40000 at 10 dB, window 20000 REs of 10-RE vectors: the
    // estimate must be the second SNR alone.
    const std::size_t n = 10;
    kernel::snr_estimator est(20000);
    std::mt19937 rng(4);
    std::uniform_int_distribution<int> pick(0, 255);
    std::uniform_real_distribution<double> ph(0, 2 * M_PI);
    const auto pts = qam256_points();
    std::vector<gr_complex> y(n);
    std::vector<float> m(n);
    for (double snr_db : { 0.0, 10.0 }) {
        std::normal_distribution<double> g(0.0, std::sqrt(std::pow(10.0, -snr_db / 10) / 2));
        const std::size_t vectors = snr_db == 0.0 ? 5000 : 4000;
        for (std::size_t v = 0; v < vectors; v++) {
            for (std::size_t i = 0; i < n; i++) {
                const gr_complex s = pts[pick(rng)];
                m[i] = std::norm(s);
                y[i] = gr_complex(std::polar(1.0, ph(rng)) * cd(s) + cd(g(rng), g(rng)));
            }
            est.update(y.data(), m.data(), n);
        }
        EXPECT_TRUE(est.valid());
        // 4 standard deviations for the 20000-RE window (0.17 dB at 0 dB, 0.23 dB at 10 dB;
        // measured +0.18 and -0.25 dB); mixing in the 0 dB data would pull the 10 dB
        // estimate down by decibels
        EXPECT_NEAR(est.snr_db(), snr_db, 4.0 * snr_estimate_std_db(snr_db, 20000));
    }
}

TEST(SnrEstimator, HistoryFromPrepassEqualsTheWholeStream)
{
    // A strip's task starts its stream at vector t0 with the history the pre-pass's sums
    // give (docs/scale.md): from t0 on its estimate and output must equal the whole
    // stream's bit for bit, while the SNR falls from 10 to -5 dB along the stream (so the
    // window's content matters) and vectors [400, 600) carry no echo (y = 0, a zero-filled
    // gap longer than the window: the whole stream keeps its last estimate through it).
    // Window 1280 REs of 7-RE vectors: buckets of 20 REs -> 3 vectors (21 REs).
    const std::size_t n = 7, vectors = 700, window = 1280, gap0 = 400, gap1 = 600;
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> pick(0, 255);
    std::uniform_real_distribution<double> ph(0, 2 * M_PI);
    std::normal_distribution<double> g(0.0, 1.0);
    const auto pts = qam256_points();
    std::vector<gr_complex> y(n * vectors), s(n * vectors), whole_out(n * vectors);
    for (std::size_t v = 0; v < vectors; v++) {
        const double sigma = std::sqrt(std::pow(10.0, -(10.0 - 15.0 * v / vectors) / 10) / 2);
        const bool gap = v >= gap0 && v < gap1;
        for (std::size_t i = v * n; i < v * n + n; i++) {
            s[i] = pts[pick(rng)];
            const cd echo = std::polar(1.0, ph(rng)) * cd(s[i]) + sigma * cd(g(rng), g(rng));
            y[i] = gap ? gr_complex(0, 0) : gr_complex(echo);
        }
    }
    kernel::tf_filter whole(n, filter_type::WF, 0.0, true, window), pre(n, filter_type::WF,
                                                                        0.0, true, window);
    std::vector<double> est(vectors);
    std::vector<kernel::snr_estimator::sums> sums(vectors);
    for (std::size_t v = 0; v < vectors; v++) {
        whole.process(&y[v * n], &s[v * n], &whole_out[v * n]);
        est[v] = whole.estimated_snr_db();
        pre.snr_sums(&y[v * n], &s[v * n], sums[v]);
    }
    // the last estimate with echo energy in the window (the gap's start pulls it to the
    // -60 dB clamp), kept while the window holds none
    ASSERT_FALSE(std::isnan(est[gap1 - 1]));
    EXPECT_EQ(est[gap1 - 1], est[gap0 + 190]);
    EXPECT_TRUE(std::isnan(pre.estimated_snr_db())); // the pre-pass does not estimate
    const std::vector<std::uint64_t> starts{ 0, 1, 100, 182, 183, 299, 300, 301, 512, 590, 699 };
    const auto hist = kernel::snr_estimator::histories(sums, n, starts, {}, window);
    ASSERT_EQ(hist.size(), starts.size());
    for (std::size_t k = 0; k < starts.size(); k++) {
        const std::uint64_t t0 = starts[k];
        kernel::tf_filter task(n, filter_type::WF, 0.0, true, window),
            cold(n, filter_type::WF, 0.0, true, window);
        task.set_snr_history(hist[k]);
        std::vector<gr_complex> out(n), cold_out(n);
        for (std::uint64_t v = t0; v < vectors; v++) {
            task.process(&y[v * n], &s[v * n], out.data());
            cold.process(&y[v * n], &s[v * n], cold_out.data());
            const double e = task.estimated_snr_db(); // NaN before the first estimate
            ASSERT_TRUE(e == est[v] || (std::isnan(e) && std::isnan(est[v]))) << t0 << " " << v;
            ASSERT_TRUE(std::equal(out.begin(), out.end(), &whole_out[v * n])) << t0 << " " << v;
            if (v == t0 && t0 == 512) { // without the history: its own vectors only
                EXPECT_NE(cold.estimated_snr_db(), est[v]);
            }
            if (v == t0 && t0 == 590) { // inside the gap: no estimate of its own
                EXPECT_TRUE(std::isnan(cold.estimated_snr_db()));
            }
        }
        EXPECT_EQ(task.snr_history(), whole.snr_history()) << t0; // P, sigma^2, buckets
    }
    // a history round trip, and malformed ones named
    kernel::snr_estimator a(window), b(window);
    a.set_history(hist[8]);
    EXPECT_EQ(a.history(), hist[8]);
    EXPECT_EQ(hist[8].size(), 9u + 5u * 61u); // the window's 61 full buckets of 21 REs
    std::vector<double> h = hist[8];
    h.pop_back();
    EXPECT_THROW(b.set_history(h), std::invalid_argument);
    h = hist[8];
    h[9] = 14.0; // a bucket of fewer than 1280 / 64 REs
    EXPECT_THROW(b.set_history(h), std::invalid_argument);
    h = hist[8];
    h[4] = 21.0; // a partial bucket that is full
    EXPECT_THROW(b.set_history(h), std::invalid_argument);
    EXPECT_THROW(kernel::snr_estimator::histories(sums, n, { 5, 4 }, {}, window),
                 std::invalid_argument);
    EXPECT_THROW(kernel::snr_estimator::histories(sums, n, { vectors + 1 }, {}, window),
                 std::invalid_argument);
    // replayed a part at a time (the client's pre-pass): the same histories
    const std::vector<kernel::snr_estimator::sums> head(sums.begin(), sums.begin() + 300),
        tail(sums.begin() + 300, sums.end());
    const auto at300 = kernel::snr_estimator::histories(head, n, { 300 }, {}, window);
    EXPECT_EQ(kernel::snr_estimator::histories(tail, n, { 0, 1, 212, 290 }, at300[0], window),
              (std::vector<std::vector<double>>{ hist[6], hist[7], hist[8], hist[9] }));
}

// ------------------------------------------------ constant-modulus shortcut

namespace {

// 8-PSK points of modulus a (cos/sin in float: |s|^2 differs by float rounding between
// points), every `every_empty`-th RE empty (exactly 0).
grid psk_grid(std::size_t n, unsigned seed, float a, std::size_t every_empty = 0)
{
    std::mt19937 rng(seed);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::uniform_int_distribution<int> pick(0, 7);
    grid d;
    for (std::size_t i = 0; i < n; i++) {
        d.y.emplace_back(g(rng), g(rng));
        const float ph = float(M_PI / 4) * float(pick(rng)) + 0.3f;
        const bool empty = every_empty && (i % every_empty == 0);
        d.s.push_back(empty ? gr_complex(0, 0) : gr_complex(a * std::cos(ph), a * std::sin(ph)));
    }
    return d;
}

} // namespace

class ConstantModulus : public ::testing::TestWithParam<filter_type>
{
};

TEST_P(ConstantModulus, ShortcutMatchesGeneralPathAndFormula)
{
    const filter_type type = GetParam();
    const std::size_t n = 1001;
    const double snr_db = -20.0, snr = std::pow(10.0, snr_db / 10.0);
    for (std::size_t every_empty : { std::size_t(0), std::size_t(4) }) {
        const auto d = psk_grid(n, 11, 0.7f, every_empty);
        kernel::tf_filter fast(n, type, snr_db, false), slow(n, type, snr_db, false);
        slow.set_constant_modulus_path(false);
        std::vector<gr_complex> a(n), b(n);
        fast.process(d.y.data(), d.s.data(), a.data());
        slow.process(d.y.data(), d.s.data(), b.data());
        EXPECT_EQ(fast.constant_modulus_vectors(), type == filter_type::MF ? 0u : 1u);
        EXPECT_EQ(slow.constant_modulus_vectors(), 0u);
        for (std::size_t i = 0; i < n; i++) {
            const cd ref = cd(d.y[i]) * reference_g(type, cd(d.s[i]), snr); // eq. (25), double
            EXPECT_NEAR(std::abs(cd(a[i]) - ref), 0.0, 1e-6 * (1.0 + std::abs(ref))) << i;
            // shortcut vs per-RE weights: float rounding apart (relative 1e-6)
            EXPECT_NEAR(std::abs(cd(a[i]) - cd(b[i])), 0.0, 1e-6 * (1e-30 + std::abs(cd(b[i]))))
                << i;
            if (d.s[i] == gr_complex(0, 0)) {
                EXPECT_EQ(a[i], gr_complex(0, 0));
            }
        }
    }
}

INSTANTIATE_TEST_SUITE_P(AllFilters,
                         ConstantModulus,
                         ::testing::Values(filter_type::RF, filter_type::MF, filter_type::WF));

TEST(ConstantModulusDetect, OnlyConstantModulusTakesTheShortcut)
{
    const std::size_t n = 512;
    kernel::tf_filter f(n, filter_type::WF, 0.0, false);
    std::vector<gr_complex> out(n);
    auto qam = random_grid(n, 3); // 256-QAM: not constant modulus
    f.process(qam.y.data(), qam.s.data(), out.data());
    EXPECT_EQ(f.constant_modulus_vectors(), 0u);
    auto psk = psk_grid(n, 3, 1.0f);
    psk.s[17] *= 1.0001f; // one point off by 2e-4 in |s|^2: general path
    f.process(psk.y.data(), psk.s.data(), out.data());
    EXPECT_EQ(f.constant_modulus_vectors(), 0u);
    psk = psk_grid(n, 3, 1.0f);
    psk.s[17] = gr_complex(1e-20f, 0.0f); // |s|^2 = 1e-40 (subnormal): empty, not 0: general
    f.process(psk.y.data(), psk.s.data(), out.data());
    // (where the process flushes subnormals to zero, |s|^2 is 0 and the case below applies)
    const bool ftz = std::norm(psk.s[17]) == 0.0f;
    EXPECT_EQ(f.constant_modulus_vectors(), ftz ? 1u : 0u);
    // Below |s| ~ 1e-23 |s|^2 is exactly 0 in float, so such an RE cannot be told from an
    // empty one and the shortcut runs: its output is y conj(s) / m0, below 1e-22 |y| (the
    // general WF gives the same; RF gives 0): far below the float rounding of the vector.
    psk.s[17] = gr_complex(1e-25f, 0.0f);
    f.process(psk.y.data(), psk.s.data(), out.data());
    EXPECT_EQ(f.constant_modulus_vectors(), ftz ? 2u : 1u);
    EXPECT_LT(std::abs(out[17]), 1e-22f * (1.0f + std::abs(psk.y[17])));
    psk = psk_grid(n, 3, 1.0f, 2);
    f.process(psk.y.data(), psk.s.data(), out.data());
    EXPECT_EQ(f.constant_modulus_vectors(), ftz ? 3u : 2u);
    std::vector<gr_complex> zeros(n, gr_complex(0, 0)); // all empty: general path, zeros
    f.process(psk.y.data(), zeros.data(), out.data());
    EXPECT_EQ(f.constant_modulus_vectors(), ftz ? 3u : 2u);
    for (const auto& v : out)
        EXPECT_EQ(v, gr_complex(0, 0));
}
