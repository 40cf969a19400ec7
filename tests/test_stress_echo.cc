/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Numerical stress of kernel::scene_echo: very long streams (symbol 10^8, past 2^32) and
// large target phases, against eq. (7) with the exact range (8) evaluated here in long
// double, independently of the kernel.

#include <gnuradio/nrsar/kernel/scene_echo.h>
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <cstdio>
#include <random>
#include <vector>

using namespace gr::nrsar;
using cld = std::complex<long double>;

namespace {

// eq. (7)-(8): Y[n] = sum_q alpha_q S[n] exp(-j 4 pi (fc + n df) R_q(m) / c), in long
// double so the reference keeps ~1e-10 rad at phases of 1e9 rad (platform 10^4 km away).
std::vector<cld> direct_echo(const numerology& num,
                             const geometry& geo,
                             const scene& scn,
                             std::uint64_t m,
                             const std::vector<gr_complex>& s)
{
    const long double df = num.subcarrier_spacing_hz;
    const long double tsym = 1.0L / df + num.cp_samples / (num.fft_size * df);
    const long double yp = geo.track_start_m + geo.velocity_mps * static_cast<long double>(m) * tsym;
    const long double c = 299792458.0L;
    const long double pi = 3.141592653589793238462643383279502884L;
    std::vector<cld> y(num.num_subcarriers, cld(0.0L, 0.0L));
    for (const auto& t : scn.targets) {
        const long double dy = yp - t.y_m;
        const long double R = std::sqrt((long double)t.x_m * t.x_m +
                                        (long double)geo.height_m * geo.height_m + dy * dy);
        const cld alpha = std::polar(std::sqrt((long double)t.rcs), (long double)t.phase_rad);
        for (unsigned n = 0; n < num.num_subcarriers; n++) {
            const long double f = geo.carrier_hz + n * df;
            // reduce 2 f R / c (cycles) exactly enough in long double before the sincos
            const long double cycles = 2.0L * f * R / c;
            const long double frac = cycles - std::floor(cycles);
            y[n] += alpha * cld(s[n]) * std::polar(1.0L, -2.0L * pi * frac);
        }
    }
    return y;
}

double rel_error_db(const std::vector<gr_complex>& got, const std::vector<cld>& ref)
{
    long double err = 0.0L, pow = 0.0L;
    for (size_t i = 0; i < ref.size(); i++) {
        err += std::norm(cld(got[i]) - ref[i]);
        pow += std::norm(ref[i]);
    }
    return static_cast<double>(10.0L * std::log10(err / pow));
}

std::vector<gr_complex> random_qam(unsigned n, unsigned seed)
{
    std::mt19937 gen(seed);
    std::uniform_int_distribution<int> level(0, 15);
    std::vector<gr_complex> s(n);
    for (auto& v : s)
        v = gr_complex((2 * level(gen) - 15) / std::sqrt(170.0f),
                       (2 * level(gen) - 15) / std::sqrt(170.0f));
    return s;
}

} // namespace

class StressEchoAtSymbol : public ::testing::TestWithParam<std::uint64_t>
{
};

// paper numerology and scene, target phases of 1e5 rad and more on top of 4 pi R / lambda.
TEST_P(StressEchoAtSymbol, MatchesLongDoubleBelow80dB)
{
    const auto num = numerology::preset("paper");
    const auto geo = geometry::preset("paper");
    auto scn = scene::preset("paper3");
    scn.targets[0].phase_rad = 1.0e5;
    scn.targets[1].phase_rad = -2.5e5;
    scn.targets[1].rcs = 0.25;
    scn.targets[2].phase_rad = 3.0e6;
    kernel::scene_echo k(num, geo, scn);
    const auto s = random_qam(num.num_subcarriers, 11);
    std::vector<gr_complex> y(num.num_subcarriers), h(num.num_subcarriers);
    const std::uint64_t m = GetParam();
    k.echo(m, s.data(), y.data(), h.data());
    const double err_y = rel_error_db(y, direct_echo(num, geo, scn, m, s));
    const std::vector<gr_complex> ones(num.num_subcarriers, gr_complex(1.0f, 0.0f));
    const double err_h = rel_error_db(h, direct_echo(num, geo, scn, m, ones));
    std::printf("m = %llu: echo error %.1f dB, reference error %.1f dB\n",
                static_cast<unsigned long long>(m), err_y, err_h);
    EXPECT_LT(err_y, -80.0);
    EXPECT_LT(err_h, -80.0);
}

// 10^7 and 10^8 symbols (7 and 70 min of stream, platform 21 / 208 km on, phases 3e6 / 3e7
// rad), and just past 2^32 symbols (50 h; a 32-bit symbol counter would wrap here).
INSTANTIATE_TEST_SUITE_P(LongStream,
                         StressEchoAtSymbol,
                         ::testing::Values(10000000ull, 100000000ull, 4294967296ull + 12345ull));
