/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::multipath_fir and kernel::td_echo against double-precision formulas evaluated
// here: a tone delayed by tau is the tone times e^{-j 2 pi f tau} (band-limited signal).

#include "test_util.h"
#include <gnuradio/nrsar/kernel/td_echo.h>
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

using namespace gr::nrsar;
using kernel::echo_path;
using kernel::multipath_fir;
using cd = std::complex<double>;

namespace {

// Worst error power [dB] relative to |y| = 1 of a unit tone at frequency f (cycles/sample)
// delayed by d samples, over n outputs in steady state.
double tone_error_db(multipath_fir& fir, double f, double d, std::size_t n = 512)
{
    const std::size_t hist = fir.max_lag();
    std::vector<gr_complex> buf(hist + n), y(n);
    for (std::size_t i = 0; i < buf.size(); i++) {
        const double t = double(i) - double(hist);
        buf[i] = gr_complex(std::polar(1.0, 2.0 * M_PI * f * t));
    }
    echo_path p;
    p.delay_samples = d;
    p.gain = 1.0;
    EXPECT_EQ(fir.set_paths(&p, 1), 0u);
    fir.filter(buf.data() + hist, y.data(), n);
    double worst = 0.0;
    for (std::size_t k = 0; k < n; k++) {
        const cd ref = std::polar(1.0, 2.0 * M_PI * f * (double(k) - d));
        worst = std::max(worst, std::norm(cd(y[k]) - ref));
    }
    return 10.0 * std::log10(worst + 1e-300);
}

double worst_over_band(unsigned taps, double edge)
{
    multipath_fir fir(taps, multipath_fir::default_beta(taps, edge), 200);
    double worst = -400.0;
    for (double f : { -edge, -0.3, -0.1, 0.0, 0.05, 0.2, 0.35, edge })
        for (double d : { 40.5, 41.25, 57.1, 63.999 })
            worst = std::max(worst, tone_error_db(fir, f, d));
    return worst;
}

} // namespace

TEST(MultipathFir, ToneErrorVersusTaps)
{
    // Paper numerology: |f| <= 1667 / 4096 = 0.407 cycles/sample.
    const double edge = 1667.0 / 4096.0;
    double prev = 0.0;
    for (unsigned taps : { 8u, 16u, 24u, 32u, 48u, 64u }) {
        const double e = worst_over_band(taps, edge);
        std::printf("taps %2u  beta %5.2f  worst tone error %7.1f dB\n",
                    taps,
                    multipath_fir::default_beta(taps, edge),
                    e);
        if (taps <= 32) {
            EXPECT_LT(e, prev - 10.0) << "taps " << taps; // falls fast with the length
        }
        prev = e;
        if (taps == 32) {
            EXPECT_LT(e, -80.0); // the default length
        }
    }
}

TEST(MultipathFir, Avx2AndVolkPathsAgree)
{
    multipath_fir fir(32, 9.0, 300);
    const auto x = nrsar_test::gaussian_samples(300 + 1003, 6);
    const echo_path p[] = { { 200.37, cd(0.3, 0.8) }, { 211.9, cd(-1.0, 0.1) } };
    fir.set_paths(p, 2);
    std::vector<gr_complex> a(1003), b(1003);
    fir.set_simd(true);
    fir.filter(x.data() + 300, a.data(), a.size());
    fir.set_simd(false);
    EXPECT_STREQ(fir.implementation(), "volk");
    fir.filter(x.data() + 300, b.data(), b.size());
    for (std::size_t k = 0; k < a.size(); k++) // odd length: the tails of both loops
        ASSERT_LT(std::abs(a[k] - b[k]), 1e-5f * (1.0f + std::abs(b[k]))) << k;
}

TEST(MultipathFir, Avx512EqualsAvx2BitForBit)
{
    // The AVX-512 loop does each output's arithmetic as the AVX2 loop does (taps in order,
    // one FMA each into x Re g and x Im g): equal bit for bit, at every length (32-output
    // blocks, then the AVX2 loop's 16-, 4- and tail paths) and span (1 tap is a copy).
    multipath_fir fir(32, 9.0, 300);
    if (fir.set_avx512(true), std::string(fir.implementation()) != "avx512")
        GTEST_SKIP() << "no AVX-512F on this CPU (" << fir.implementation() << ")";
    const auto x = nrsar_test::gaussian_samples(300 + 1003, 7);
    const std::vector<std::vector<echo_path>> cases = {
        { { 200.37, cd(0.3, 0.8) }, { 211.9, cd(-1.0, 0.1) } }, // span 44
        { { 250.5, cd(0.5, -0.2) } },                            // span 32
        { { 100.0, cd(1.0, 0.0) }, { 101.0, cd(0.0, 1.0) } },    // two integer lags
    };
    for (const auto& paths : cases) {
        fir.set_paths(paths.data(), paths.size());
        for (std::size_t n : { 1003, 64, 35, 31, 3 }) {
            std::vector<gr_complex> a(n), b(n);
            fir.set_avx512(true);
            fir.filter(x.data() + 300, a.data(), n);
            fir.set_avx512(false);
            EXPECT_STREQ(fir.implementation(), "avx2");
            fir.filter(x.data() + 300, b.data(), n);
            for (std::size_t k = 0; k < n; k++)
                ASSERT_EQ(a[k], b[k]) << "span " << fir.lag_hi() - fir.lag_lo() + 1 << " n " << n
                                      << " k " << k;
        }
    }
}

TEST(MultipathFir, IntegerDelayIsExact)
{
    multipath_fir fir(32, 9.0, 100);
    const auto x = nrsar_test::gaussian_samples(100 + 300, 3);
    std::vector<gr_complex> y(300);
    echo_path p;
    p.delay_samples = 37.0;
    p.gain = 1.0;
    ASSERT_EQ(fir.set_paths(&p, 1), 0u);
    fir.filter(x.data() + 100, y.data(), y.size());
    for (std::size_t k = 0; k < y.size(); k++)
        ASSERT_EQ(y[k], x[100 + k - 37]) << k;
    EXPECT_EQ(fir.lag_lo(), 37);
    EXPECT_EQ(fir.lag_hi(), 37);
}

TEST(MultipathFir, PathsAddLinearly)
{
    multipath_fir fir(16, 5.0, 100);
    const auto x = nrsar_test::gaussian_samples(100 + 200, 4);
    const echo_path a{ 20.3, cd(0.5, -0.2) }, b{ 22.0, cd(-1.0, 0.7) }, c{ 30.77, cd(0.1, 0.9) };
    const echo_path all[] = { a, b, c };
    std::vector<gr_complex> y(200), ysum(200, 0.0f), one(200);
    fir.set_paths(all, 3);
    fir.filter(x.data() + 100, y.data(), 200);
    for (const auto& p : all) {
        fir.set_paths(&p, 1);
        fir.filter(x.data() + 100, one.data(), 200);
        for (int k = 0; k < 200; k++)
            ysum[k] += one[k];
    }
    for (int k = 0; k < 200; k++)
        EXPECT_LT(std::abs(y[k] - ysum[k]), 1e-5f);
}

TEST(MultipathFir, DropsPathsBeyondMaxLagAndRefusesBadTaps)
{
    multipath_fir fir(8, 3.0, 50);
    const echo_path far{ 47.5, 1.0 }, near{ 10.0, 1.0 };
    const echo_path both[] = { far, near };
    EXPECT_EQ(fir.set_paths(both, 2), 1u);
    EXPECT_THROW(multipath_fir(7, 3.0, 50), std::invalid_argument);
    EXPECT_THROW(multipath_fir(0, 3.0, 50), std::invalid_argument);
    EXPECT_THROW(multipath_fir(258, 3.0, 300), std::invalid_argument);
    EXPECT_THROW(multipath_fir(8, -1.0, 50), std::invalid_argument);
}

TEST(TdEcho, ToneMatchesDelayAndCarrierPhase)
{
    // A subcarrier tone through the paper geometry: y = sqrt(rcs) e^{j phase}
    // x(t - tau) e^{-j 2 pi (fc + k0 Delta f) tau}, tau = 2 R(m) / c of eq. (8).
    const numerology num = numerology::preset("paper");
    const geometry geo = geometry::preset("paper");
    scene scn;
    scn.targets.push_back(point_target(300.0, 100.0, 2.0, 0.4));
    kernel::td_echo echo(num, geo, scn); // default 32 taps
    const unsigned sym = num.cp_samples + num.fft_size, hist = echo.history();
    const double fs = num.fft_size * num.subcarrier_spacing_hz;
    const unsigned k0 = num.dc_subcarrier();
    for (unsigned n : { 0u, 1000u, k0, 3332u }) {
        const double f = (double(n) - k0) / num.fft_size; // cycles/sample
        const std::uint64_t m = 7;                          // symbol 7
        const std::uint64_t s0 = m * sym;
        std::vector<gr_complex> x(hist + sym), y(sym);
        for (std::size_t i = 0; i < x.size(); i++) {
            const double t = double(s0) + double(i) - double(hist);
            x[i] = gr_complex(std::polar(1.0, 2.0 * M_PI * f * t));
        }
        echo.process(s0, x.data() + hist, y.data(), sym);
        const double yp = geo.velocity_mps * m * (num.cp_samples + num.fft_size) / fs;
        const double R = std::sqrt(300.0 * 300.0 + geo.height_m * geo.height_m +
                                   (yp - 100.0) * (yp - 100.0));
        const double tau = 2.0 * R / 299792458.0;
        const double frf = geo.carrier_hz + k0 * num.subcarrier_spacing_hz;
        double worst = 0.0;
        for (unsigned k = 0; k < sym; k++) {
            const double t = double(s0 + k);
            const cd ref = std::sqrt(2.0) * std::polar(1.0, 0.4) *
                           std::polar(1.0, 2.0 * M_PI * f * (t - tau * fs)) *
                           std::polar(1.0, -2.0 * M_PI * std::fmod(frf * tau, 1.0));
            worst = std::max(worst, std::norm(cd(y[k]) - ref) / 2.0);
        }
        std::printf("subcarrier %4u: worst error %.1f dB\n", n, 10.0 * std::log10(worst));
        EXPECT_LT(10.0 * std::log10(worst), -75.0) << "subcarrier " << n;
    }
}

TEST(TdEcho, NoiseDoesNotDependOnTheCutsAndHasTheVariance)
{
    numerology num = numerology::preset("tiny");
    const geometry geo = geometry::preset("paper");
    const scene scn = scene::preset("paper3");
    kernel::gaussian_noise noise(11);
    const unsigned hist = kernel::td_echo(num, geo, scn).history();
    const std::size_t n = 20000;
    const auto x = nrsar_test::gaussian_samples(hist + n, 5);
    std::vector<gr_complex> whole(n), cut(n);
    for (bool simd : { true, false }) {
        {
            kernel::td_echo e(num, geo, scn);
            e.fir().set_simd(simd);
            e.process(0, x.data() + hist, whole.data(), n, &noise, 0.5f);
        }
        {
            kernel::td_echo e(num, geo, scn);
            e.fir().set_simd(simd);
            std::size_t i = 0, len = 1;
            while (i < n) {
                const std::size_t l = std::min(len, n - i);
                e.process(i, x.data() + hist + i, cut.data() + i, l, &noise, 0.5f);
                i += l;
                len = len * 3 % 997 + 1;
            }
        }
        for (std::size_t i = 0; i < n; i++)
            ASSERT_EQ(whole[i], cut[i]) << i << (simd ? " avx2" : " volk");
    }

    // Noise alone (zero RCS scene): E|y|^2 = sigma^2.
    scene empty;
    empty.targets.push_back(point_target(300.0, 100.0, 0.0));
    kernel::td_echo e(num, geo, empty);
    e.process(0, x.data() + hist, whole.data(), n, &noise, 0.5f);
    double p = 0.0;
    for (const auto& v : whole)
        p += std::norm(v);
    EXPECT_NEAR(p / n, 0.25, 0.25 * 0.03);
}
