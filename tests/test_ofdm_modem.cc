/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Kernel tests of the CP-OFDM modem and the Schmidl & Cox acquirer, against direct
// double-precision formulas written here.

#include <gnuradio/nrsar/kernel/ofdm_modem.h>
#include "test_util.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

using namespace gr::nrsar;
using cd = std::complex<double>;

namespace {

// x[t] = 1/sqrt(F) sum_n S[n] exp(+j 2 pi (n - k0) t / F), t = -cp .. F-1.
std::vector<cd> direct_mod(const std::vector<gr_complex>& s, unsigned f, unsigned cp, unsigned k0)
{
    std::vector<cd> x(cp + f);
    for (unsigned i = 0; i < cp + f; i++) {
        const double t = double(i) - double(cp);
        cd acc = 0;
        for (std::size_t n = 0; n < s.size(); n++)
            acc += cd(s[n]) * std::polar(1.0, 2 * M_PI * (double(n) - k0) * t / f);
        x[i] = acc / std::sqrt(double(f));
    }
    return x;
}

double max_err(const gr_complex* a, const std::vector<cd>& b)
{
    double e = 0;
    for (std::size_t i = 0; i < b.size(); i++)
        e = std::max(e, std::abs(cd(a[i]) - b[i]));
    return e;
}

struct layout {
    unsigned n, f, cp;
};

class modem : public ::testing::TestWithParam<layout>
{
};

TEST_P(modem, modulator_matches_direct_formula)
{
    const auto p = GetParam();
    const unsigned k0 = (p.n / 2) & ~1u;
    const auto s = nrsar_test::gaussian_samples(p.n, 3);
    kernel::ofdm_modulator mod(p.n, p.f, p.cp, k0);
    std::vector<gr_complex> x(mod.symbol_length());
    mod.execute(s.data(), x.data());
    EXPECT_LT(max_err(x.data(), direct_mod(s, p.f, p.cp, k0)), 1e-5);
}

TEST_P(modem, demodulator_inverts_modulator_with_window_phase)
{
    const auto p = GetParam();
    const unsigned k0 = (p.n / 2) & ~1u;
    const auto s = nrsar_test::gaussian_samples(p.n, 4);
    kernel::ofdm_modulator mod(p.n, p.f, p.cp, k0);
    std::vector<gr_complex> x(mod.symbol_length()), y(p.n);
    mod.execute(s.data(), x.data());
    for (unsigned start : { p.cp, p.cp / 2, 0u }) {
        kernel::ofdm_demodulator dem(p.n, p.f, p.cp, k0, start);
        dem.execute(x.data(), y.data());
        // Window cp - start samples early: Y = S exp(-j 2 pi (n - k0)(cp - start)/F).
        std::vector<cd> ref(p.n);
        for (unsigned n = 0; n < p.n; n++)
            ref[n] = cd(s[n]) * std::polar(1.0,
                                           -2 * M_PI * (double(n) - k0) *
                                               double(p.cp - start) / p.f);
        EXPECT_LT(max_err(y.data(), ref), 1e-5) << "fft_start " << start;
    }
}

TEST_P(modem, demodulator_matches_direct_dft)
{
    const auto p = GetParam();
    const unsigned k0 = (p.n / 2) & ~1u;
    const auto x = nrsar_test::gaussian_samples(p.cp + p.f, 5);
    kernel::ofdm_demodulator dem(p.n, p.f, p.cp, k0, p.cp);
    std::vector<gr_complex> y(p.n);
    dem.execute(x.data(), y.data());
    std::vector<cd> ref(p.n);
    for (unsigned n = 0; n < p.n; n++) {
        cd acc = 0;
        for (unsigned t = 0; t < p.f; t++)
            acc += cd(x[p.cp + t]) * std::polar(1.0, -2 * M_PI * (double(n) - k0) * t / p.f);
        ref[n] = acc / std::sqrt(double(p.f));
    }
    EXPECT_LT(max_err(y.data(), ref), 1e-4);
}

TEST_P(modem, checked_demodulator_matches_direct_dft_and_refuses_nonfinite)
{
    // execute_if_finite: the direct DFT of the window (window mid-CP) when every sample is
    // finite; false, out untouched, when a NaN or Inf lies anywhere in the symbol (before,
    // inside or after the FFT window).
    const auto p = GetParam();
    const unsigned k0 = (p.n / 2) & ~1u, start = p.cp / 2;
    auto x = nrsar_test::gaussian_samples(p.cp + p.f, 6);
    kernel::ofdm_demodulator dem(p.n, p.f, p.cp, k0, start);
    std::vector<gr_complex> y(p.n);
    ASSERT_TRUE(dem.execute_if_finite(x.data(), y.data()));
    std::vector<cd> ref(p.n);
    for (unsigned n = 0; n < p.n; n++) {
        cd acc = 0;
        for (unsigned t = 0; t < p.f; t++)
            acc += cd(x[start + t]) * std::polar(1.0, -2 * M_PI * (double(n) - k0) * t / p.f);
        ref[n] = acc / std::sqrt(double(p.f));
    }
    EXPECT_LT(max_err(y.data(), ref), 1e-4);
    for (unsigned at : { 0u, start + p.f / 2, p.cp + p.f - 1 }) {
        auto bad = x;
        bad[at] = gr_complex(0.0f, std::numeric_limits<float>::infinity());
        std::vector<gr_complex> z(p.n, gr_complex(7.0f, 7.0f));
        EXPECT_FALSE(dem.execute_if_finite(bad.data(), z.data())) << "sample " << at;
        EXPECT_EQ(z[0], gr_complex(7.0f, 7.0f));
    }
}

INSTANTIATE_TEST_SUITE_P(layouts,
                         modem,
                         ::testing::Values(layout{ 64, 64, 16 },
                                           layout{ 50, 64, 16 },
                                           layout{ 51, 64, 8 },
                                           layout{ 612, 1024, 256 }));

TEST(modem, rejects_window_beyond_cp)
{
    EXPECT_THROW(kernel::ofdm_demodulator(64, 64, 16, 32, 17), std::invalid_argument);
    EXPECT_THROW(kernel::ofdm_modulator(65, 64, 16, 32), std::invalid_argument);
}

TEST(phase_rotator, keeps_double_precision_phase_over_long_streams)
{
    const double freq = 0.123456789;
    kernel::phase_rotator rot(freq);
    const std::size_t chunk = 10007, chunks = 300; // 3e6 samples
    std::vector<gr_complex> one(chunk, gr_complex(1.0f, 0.0f)), out(chunk);
    double worst = 0;
    for (std::size_t c = 0; c < chunks; c++) {
        rot.rotate(one.data(), out.data(), chunk);
        for (std::size_t i = 0; i < chunk; i += 97) {
            const double t = double(c * chunk + i);
            const double ph = std::remainder(2 * M_PI * freq * t, 2 * M_PI);
            worst = std::max(worst, std::abs(cd(out[i]) - std::polar(1.0, ph)));
        }
    }
    EXPECT_LT(worst, 5e-5);
}

TEST(phase_rotator, lock_window_matches_polar)
{
    // ofdm_sync's lock window: fft_size samples derotated by the fractional CFO from phase 0
    // (|cfo| < 1 / fft_size cycles per sample), against x[k] exp(-j 2 pi cfo k) in double.
    // Bound: 5e-5 relative (-86 dB): 512 float phasor steps between double seeds, each
    // rounding about 6e-8; measured 1.3e-5 at most (std::polar rounded to float: 1.3e-7).
    std::mt19937 gen(11);
    std::normal_distribution<float> g(0.0f, 1.0f);
    for (const unsigned f : { 1024u, 4096u }) {
        std::vector<gr_complex> x(f), out(f);
        for (auto& v : x)
            v = gr_complex(g(gen), g(gen));
        for (const double cfo : { 0.0, 0.31 / f, -0.77 / f, 0.999 / f, -0.999 / f }) {
            kernel::phase_rotator derotate(-cfo);
            derotate.rotate(x.data(), out.data(), f);
            double worst = 0.0;
            for (unsigned k = 0; k < f; k++) {
                const cd ref = cd(x[k]) * std::polar(1.0, -2.0 * M_PI * cfo * double(k));
                worst = std::max(worst, std::abs(cd(out[k]) - ref) / std::abs(cd(x[k])));
            }
            EXPECT_LT(worst, 5e-5) << "fft " << f << " cfo " << cfo;
        }
    }
}

// A burst: random data symbols (all bins) around one symbol whose body repeats with
// period F/2 (even bins only), with cyclic prefixes, a CFO, at a known offset.
struct burst {
    std::vector<gr_complex> x;
    std::int64_t d0;
};

burst make_burst(unsigned f,
                 unsigned cp,
                 std::int64_t lead,
                 unsigned before,
                 double cfo,
                 unsigned seed,
                 unsigned second = 0) // a second repeated symbol, `second` symbols later
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    burst b;
    b.x.assign(lead, gr_complex(0, 0));
    for (unsigned sym = 0; sym < before + 3 + second; sym++) {
        const bool rep = sym == before || (second > 0 && sym == before + second);
        if (sym == before)
            b.d0 = std::int64_t(b.x.size());
        std::vector<cd> body(f);
        for (unsigned k = 0; k < f; k++) {
            if (rep && k % 2)
                continue;
            const cd v(g(rng), g(rng));
            for (unsigned t = 0; t < f; t++)
                body[t] += v * std::polar(1.0, 2 * M_PI * k * t / f) / std::sqrt(double(f));
        }
        for (unsigned t = f - cp; t < f; t++)
            b.x.push_back(gr_complex(body[t]));
        for (unsigned t = 0; t < f; t++)
            b.x.push_back(gr_complex(body[t]));
    }
    b.x.resize(b.x.size() + 4 * f, gr_complex(0, 0));
    for (std::size_t i = 0; i < b.x.size(); i++)
        b.x[i] *= gr_complex(std::polar(1.0, 2 * M_PI * cfo * double(i)));
    return b;
}

// M(d) = |P|^2 / (E/2)^2 computed directly.
double direct_metric(const std::vector<gr_complex>& x, std::size_t d, unsigned f)
{
    const unsigned h = f / 2;
    cd p = 0;
    double e = 0;
    for (unsigned m = 0; m < h; m++) {
        p += std::conj(cd(x[d + m])) * cd(x[d + m + h]);
        e += std::norm(cd(x[d + m])) + std::norm(cd(x[d + m + h]));
    }
    return e > 0 ? std::norm(p) / (0.25 * e * e) : 0.0;
}

TEST(sc_acquirer, finds_symbol_and_cfo_without_noise)
{
    const unsigned f = 256, cp = 64;
    std::mt19937 rng(7);
    for (int trial = 0; trial < 6; trial++) {
        const double cfo = (trial - 2.5) * 0.3 / f; // up to +-0.75 Delta f
        const auto b = make_burst(f, cp, 1000 + 37 * trial, 2, cfo, 10 + trial);
        kernel::sc_acquirer acq(f, cp, 0.3, 3 * (f + cp));
        std::size_t pos = 0;
        bool locked = false;
        // Random chunk sizes: the running sums must not depend on how the stream is cut.
        while (pos < b.x.size() && !locked) {
            const std::size_t n = std::min<std::size_t>(1 + rng() % 700, b.x.size() - pos);
            locked = acq.push(b.x.data() + pos, n);
            pos += n;
        }
        ASSERT_TRUE(locked);
        const auto r = acq.get();
        // The edges' shapes depend on the neighbouring data symbols' power: a few samples.
        EXPECT_NEAR(double(r.symbol_start), double(b.d0), 3.0);
        EXPECT_NEAR(r.cfo * f, cfo * f, 1e-4); // in units of Delta f
        // The plateau window (cp + 1 positions) maximises the directly computed sum of M
        // among the windows starting within +-40 samples of the symbol.
        auto window_sum = [&](std::int64_t j) {
            double acc = 0;
            for (unsigned i = 0; i <= cp; i++)
                acc += direct_metric(b.x, std::size_t(j + i), f);
            return acc;
        };
        const std::int64_t j0 = std::int64_t(r.plateau_first);
        EXPECT_EQ(r.plateau_last - r.plateau_first, double(cp));
        const double s0 = window_sum(j0);
        for (std::int64_t j = b.d0 - 40; j <= b.d0 + 40; j += 3)
            EXPECT_LE(window_sum(j), s0 + 1e-9) << j;
        double mmax = 0;
        for (std::int64_t d = j0; d <= j0 + cp; d++)
            mmax = std::max(mmax, direct_metric(b.x, std::size_t(d), f));
        EXPECT_NEAR(r.metric, mmax, 1e-6);
        // The buffer still reaches back lookback samples before the detected symbol.
        EXPECT_LE(acq.buffer_start(), b.d0 - std::int64_t(2 * (f + cp)));
    }
}

TEST(sc_acquirer, further_repeated_symbols_enter_the_cfo)
{
    const unsigned f = 256, cp = 64;
    const double cfo = 0.37 / f;
    const auto b = make_burst(f, cp, 500, 2, cfo, 21, 3);
    kernel::sc_acquirer acq(f, cp, 0.3, 3 * (f + cp));
    acq.set_repeats({ 3 * std::int64_t(f + cp) });
    // Not locked until the second repeated symbol (3 symbols later) is in.
    const std::size_t cut = std::size_t(b.d0 + 3 * (f + cp) + f / 2);
    EXPECT_FALSE(acq.push(b.x.data(), cut));
    EXPECT_TRUE(acq.push(b.x.data() + cut, b.x.size() - cut));
    EXPECT_EQ(acq.get().repeats_used, 2u);
    EXPECT_NEAR(double(acq.get().symbol_start), double(b.d0), 3.0);
    EXPECT_NEAR(acq.get().cfo * f, 0.37, 1e-5);
    EXPECT_THROW(acq.set_repeats({ 0 }), std::invalid_argument);
}

TEST(sc_acquirer, cfo_beyond_delta_f_aliases)
{
    // P's phase is 2 pi CFO H: 1.2 Delta f (0.6 / H cycles per sample) reads as -0.8 Delta f.
    const unsigned f = 256, cp = 64;
    const auto b = make_burst(f, cp, 900, 2, 1.2 / f, 5);
    kernel::sc_acquirer acq(f, cp, 0.3, 3 * (f + cp));
    ASSERT_TRUE(acq.push(b.x.data(), b.x.size()));
    EXPECT_NEAR(acq.get().cfo * f, -0.8, 1e-4);
}

TEST(sc_acquirer, reject_searches_on_after_the_crossing)
{
    // Two repeated symbols 3 symbols apart, no repeats configured: each is a lock of its own.
    const unsigned f = 256, cp = 64;
    const double cfo = -0.21 / f;
    const auto b = make_burst(f, cp, 700, 2, cfo, 33, 3);
    kernel::sc_acquirer acq(f, cp, 0.3, 3 * (f + cp));
    ASSERT_TRUE(acq.push(b.x.data(), b.x.size()));
    EXPECT_NEAR(double(acq.get().symbol_start), double(b.d0), 3.0);
    // Rejected, each lock's window starts after the last one's: the first symbol's falling
    // edge (M above 0.3 for about H / 2 positions) may lock before the second symbol does.
    const std::int64_t second = b.d0 + 3 * std::int64_t(f + cp);
    std::vector<std::int64_t> starts;
    bool locked = true;
    while (locked && starts.size() < 20) {
        const double last = acq.get().plateau_last;
        acq.reject();
        EXPECT_FALSE(acq.locked());
        locked = acq.push(nullptr, 0); // n = 0: the buffered samples are searched
        if (locked) {
            EXPECT_GT(acq.get().plateau_first, last);
            starts.push_back(acq.get().symbol_start);
            if (std::abs(acq.get().symbol_start - second) <= 3)
                EXPECT_NEAR(acq.get().cfo * f, -0.21, 1e-4);
        }
    }
    EXPECT_FALSE(locked); // only data and zeros after the second symbol's edge
    ASSERT_GE(starts.size(), 1u);
    EXPECT_EQ(std::count_if(starts.begin(), starts.end(),
                            [&](std::int64_t d) { return std::abs(d - second) <= 3; }),
              1);
    for (auto d : starts) // the first symbol's edge or the second symbol and its edge
        EXPECT_TRUE(d < b.d0 + std::int64_t(f + cp) || d >= second - 3) << d;
}

TEST(sc_acquirer, noise_never_locks_and_memory_stays_bounded)
{
    const unsigned f = 512, cp = 128;
    const std::size_t lookback = 3 * (f + cp);
    kernel::sc_acquirer acq(f, cp, 0.3, lookback);
    std::size_t max_buffered = 0;
    for (unsigned c = 0; c < 200; c++) {
        const auto x = nrsar_test::gaussian_samples(20000, 100 + c); // 4e6 samples in all
        EXPECT_FALSE(acq.push(x.data(), x.size()));
        max_buffered = std::max(max_buffered, acq.buffered());
    }
    EXPECT_LT(max_buffered, 2 * ((1u << 16) + lookback + 2 * f) + 20000);
}

TEST(sc_acquirer, rejects_bad_parameters)
{
    EXPECT_THROW(kernel::sc_acquirer(255, 64, 0.3, 0), std::invalid_argument);
    EXPECT_THROW(kernel::sc_acquirer(256, 64, 0.0, 0), std::invalid_argument);
    EXPECT_THROW(kernel::sc_acquirer(256, 64, 1.0, 0), std::invalid_argument);
    EXPECT_THROW(kernel::sc_acquirer(256, 64, std::nan(""), 0), std::invalid_argument);
}

} // namespace

TEST(phase_rotator, output_independent_of_call_sizes)
{
    // qa_chunking: the same stream cut into irregular calls gives bit-identical output
    std::mt19937 gen(7);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<gr_complex> in(5000);
    for (auto& x : in)
        x = gr_complex(g(gen), g(gen));
    std::vector<gr_complex> whole(in.size()), cut(in.size());
    kernel::phase_rotator a(0.0123), b(0.0123);
    a.set_phase(0.4);
    b.set_phase(0.4);
    a.rotate(in.data(), whole.data(), in.size());
    std::uniform_int_distribution<std::size_t> len(1, 700);
    for (std::size_t i = 0; i < in.size();) {
        const std::size_t n = std::min(len(gen), in.size() - i);
        b.rotate(in.data() + i, cut.data() + i, n);
        i += n;
    }
    for (std::size_t i = 0; i < in.size(); i++)
        ASSERT_EQ(whole[i], cut[i]) << "sample " << i;
    EXPECT_NEAR(a.phase(), b.phase(), 0.0);
}
