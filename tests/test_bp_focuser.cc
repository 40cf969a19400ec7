/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Kernel tests of the back-projection focuser: against a direct double-precision
// back-projection written here (DFT upsampling, linear interpolation, phase in double), a
// point target at its place with the predicted peak sqrt(N M), the AVX2 and generic builds
// and one and two threads alike, and the upsampling trade-off against U -> infinity.

#include <gnuradio/nrsar/bp_config.h>
#include <gnuradio/nrsar/kernel/bp_autofocus.h>
#include <gnuradio/nrsar/kernel/bp_focuser.h>
#include "bp_test_geometry.h"
#include "kernel/bp_focuser_impl.h"
#include "test_util.h"
#include <gtest/gtest.h>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

using gr::nrsar::kernel::bp_focuser;
using gr::nrsar::kernel::bp_grid;
using cd = std::complex<double>;
using vec3 = std::array<double, 3>;

namespace {

using namespace bp_test;
constexpr unsigned M = 200; // pulses and lines (25 m of track)

bp_grid grid(unsigned upsample) { return bp_test::grid(upsample, M); }

// Range-compressed echo of eq. (29) at fractional bin q for a target at slant range r:
// sum_n exp(j 2 pi n (q - q_r) / NFFT) / sqrt(N) exp(-j 4 pi r / lambda).
cd profile_at(double q, double r)
{
    const double qr = (r - FIRST) / RHO;
    cd acc(0.0, 0.0);
    for (unsigned n = 0; n < N; ++n)
        acc += std::polar(1.0, 2.0 * M_PI * n * (q - qr) / NFFT);
    return acc / std::sqrt(double(N)) * std::polar(1.0, -4.0 * M_PI * std::fmod(r / LAM, 1.0));
}

struct scenario {
    std::vector<gr_complex> pulses; // M x K
    std::vector<vec3> antenna;
    std::vector<double> r_target; // per pulse
};

// One target at ground (x, y); the antenna sways by `sway` m cross-track and vertically.
scenario make(double x, double y, double sway)
{
    scenario s;
    for (unsigned m = 0; m < M; ++m) {
        const double t = m * T;
        const vec3 a{ sway * std::sin(2.0 * M_PI * t), V * t, H + sway * std::cos(3.0 * t) };
        s.antenna.push_back(a);
        const double r = std::sqrt((x - a[0]) * (x - a[0]) + (y - a[1]) * (y - a[1]) + a[2] * a[2]);
        s.r_target.push_back(r);
        for (unsigned k = 0; k < K; ++k) {
            const cd v = profile_at(k, r);
            s.pulses.push_back(gr_complex(float(v.real()), float(v.imag())));
        }
    }
    return s;
}

// The direct back-projection in double: the kernel's algorithm written plainly. The
// demodulated profile's K-point DFT is evaluated by a direct sum; interp = true: at the
// upsampled samples and linearly interpolated (the kernel's method), false: at the exact
// fractional position q (trigonometric interpolation, the limit U -> infinity).
// ground: the pixels are (GX0 + k GDX, y, 0) instead of (sqrt(r0^2 - H^2), y, 0).
constexpr double GX0 = 760.0, GDX = 1.25;
std::vector<cd> direct_bp(const scenario& s, unsigned U, bool interp = true, bool ground = false)
{
    std::vector<cd> img(M * K, cd(0.0, 0.0));
    const unsigned L = U * K;
    std::vector<cd> up(L), spec(K);
    for (unsigned p = 0; p < M; ++p) {
        for (unsigned f = 0; f < K; ++f) {
            cd acc(0.0, 0.0);
            for (unsigned k = 0; k < K; ++k)
                acc += cd(s.pulses[p * K + k]) *
                       std::polar(1.0, -2.0 * M_PI * FCR * k - 2.0 * M_PI * double(f) * k / K);
            spec[f] = acc / double(K);
        }
        // sum_f spec[f] exp(j 2 pi f_s x / K), f_s the signed frequency of bin f
        auto trig = [&](double x) {
            const cd w = std::polar(1.0, 2.0 * M_PI * x / K);
            cd e = std::polar(1.0, -2.0 * M_PI * double(K / 2) * x / K), acc(0.0, 0.0);
            for (unsigned i = 0; i < K; ++i, e *= w) // f_s = i - K / 2
                acc += spec[(i + K - K / 2) % K] * e;
            return acc;
        };
        if (interp)
            for (unsigned u = 0; u < L; ++u)
                up[u] = trig(double(u) / U);
        const vec3& a = s.antenna[p];
        for (unsigned j = 0; j < M; ++j) {
            const double y = j * V * T;
            for (unsigned k = 0; k < K; ++k) {
                const double r0 = FIRST + k * RHO;
                const double g = ground ? GX0 + k * GDX : std::sqrt(r0 * r0 - H * H);
                const double r = std::sqrt((g - a[0]) * (g - a[0]) + (y - a[1]) * (y - a[1]) +
                                           a[2] * a[2]);
                const double q = (r - FIRST) / RHO;
                if (q < 0.0 || q >= K - 1)
                    continue;
                cd v;
                if (interp) {
                    const double pos = q * U;
                    const double fl = std::floor(pos);
                    const unsigned i = unsigned(fl);
                    const double mu = pos - fl;
                    v = up[i] + mu * (up[i + 1] - up[i]);
                } else {
                    v = trig(q);
                }
                img[j * K + k] += v * std::polar(1.0, 2.0 * M_PI * FCR * q) *
                                  std::polar(1.0, 4.0 * M_PI * std::fmod(r / LAM, 1.0));
            }
        }
    }
    for (auto& v : img)
        v /= std::sqrt(double(M));
    return img;
}

// The same with the short sinc: kernel::sinc_interpolator::at (tested with rd_focuser's RCMC)
// on the demodulated profile at q, phase and sum in double.
std::vector<cd> direct_bp_sinc(const scenario& s, unsigned taps)
{
    const gr::nrsar::kernel::sinc_interpolator interp(taps);
    std::vector<cd> img(M * K, cd(0.0, 0.0));
    std::vector<gr_complex> d(K);
    for (unsigned p = 0; p < M; ++p) {
        for (unsigned k = 0; k < K; ++k)
            d[k] = gr_complex(cd(s.pulses[p * K + k]) * std::polar(1.0, -2.0 * M_PI * FCR * k));
        const vec3& a = s.antenna[p];
        for (unsigned j = 0; j < M; ++j) {
            const double y = j * V * T;
            for (unsigned k = 0; k < K; ++k) {
                const double r0 = FIRST + k * RHO;
                const double g = std::sqrt(r0 * r0 - H * H);
                const double r = std::sqrt((g - a[0]) * (g - a[0]) + (y - a[1]) * (y - a[1]) +
                                           a[2] * a[2]);
                const double q = (r - FIRST) / RHO;
                if (q < 0.0 || q >= K - 1)
                    continue;
                img[j * K + k] += cd(interp.at(d.data(), K, q)) *
                                  std::polar(1.0, 2.0 * M_PI * FCR * q) *
                                  std::polar(1.0, 4.0 * M_PI * std::fmod(r / LAM, 1.0));
            }
        }
    }
    for (auto& v : img)
        v /= std::sqrt(double(M));
    return img;
}

std::vector<gr_complex> run(const scenario& s, const bp_grid& g, unsigned threads, bool simd)
{
    bp_focuser bp(g, threads, simd);
    bp.reset(0.0);
    // In two calls, as a stream would add them.
    bp.add(s.pulses.data(), 77, s.antenna.data());
    bp.add(s.pulses.data() + 77 * K, M - 77, s.antenna.data() + 77);
    std::vector<gr_complex> img(M * K);
    bp.image(img.data());
    return img;
}

std::vector<gr_complex> run(const scenario& s, unsigned U, unsigned threads, bool simd)
{
    return run(s, grid(U), threads, simd);
}

bp_grid ground_grid(unsigned U)
{
    bp_grid g = grid(U);
    g.ground = true;
    g.first_x_m = GX0;
    g.x_spacing_m = GDX;
    g.ground_height_m = 0.0;
    return g;
}

// U = 8, a line every step pulses.
bp_grid coarse_grid(unsigned step)
{
    bp_grid g = grid(8);
    g.num_lines = M / step;
    g.line_step = step;
    return g;
}

bp_grid ffbp_grid(unsigned U, unsigned subaperture, double beam_oversample)
{
    bp_grid g = grid(U);
    g.subaperture = subaperture;
    g.beam_oversample = beam_oversample;
    return g;
}

// The bins more than 8 from the window's ends of every line: FFBP's polar rows are not
// periodic like this test's profiles, and their FFT upsampling rings near either end.
std::vector<gr_complex> inner(const std::vector<gr_complex>& img)
{
    std::vector<gr_complex> v;
    for (size_t o = 0; o < img.size(); o += K)
        for (unsigned k = 8; k < K - 8; ++k)
            v.push_back(img[o + k]);
    return v;
}

size_t argmax(const std::vector<gr_complex>& img)
{
    size_t best = 0;
    for (size_t i = 0; i < img.size(); ++i)
        if (std::abs(img[i]) > std::abs(img[best]))
            best = i;
    return best;
}

template <typename A, typename B>
double nmse_db(const A& got, const B& ref)
{
    double e = 0.0, p = 0.0;
    for (size_t i = 0; i < ref.size(); ++i) {
        e += std::norm(cd(got[i]) - cd(ref[i]));
        p += std::norm(cd(ref[i]));
    }
    return 10.0 * std::log10(e / p);
}

} // namespace

TEST(bp_focuser, matches_direct_double_back_projection)
{
    const scenario s = make(800.0, 12.5, 0.2); // on a swaying path
    const std::vector<cd> ref = direct_bp(s, 4);
    for (bool simd : { false, true }) {
        const std::vector<gr_complex> img = run(s, 4, 1, simd);
        // float32 samples, phases and sums against double: about 1e-7 per term.
        EXPECT_LT(nmse_db(img, ref), -90.0) << "simd " << simd;
    }
}

TEST(bp_focuser, point_target_focused_at_its_place)
{
    // Target at closest-approach range 1000 m (bin 30) and y = 12.5 m (line 100).
    const scenario s = make(800.0, 12.5, 0.0);
    const std::vector<gr_complex> img = run(s, 8, 1, true);
    size_t best = 0;
    for (size_t i = 0; i < img.size(); ++i)
        if (std::abs(img[i]) > std::abs(img[best]))
            best = i;
    EXPECT_EQ(best / K, 100u);
    EXPECT_EQ(best % K, 30u);
    // Peak sqrt(N) M / sqrt(M); linear interpolation of a profile of bandwidth b = N / NFFT
    // cycles per bin upsampled U times loses at most (pi b / U)^2 / 8 = 0.48 % of amplitude.
    const double want = std::sqrt(double(N) * M);
    const double b = double(N) / NFFT;
    EXPECT_LE(std::abs(img[best]), want * (1.0 + 1e-5));
    EXPECT_GE(std::abs(img[best]), want * (1.0 - std::pow(M_PI * b / 8.0, 2) / 8.0));
}

TEST(bp_focuser, threads_and_simd_agree)
{
    const scenario s = make(805.0, 10.0, 0.3);
    const std::vector<gr_complex> one = run(s, 8, 1, true);
    const std::vector<gr_complex> two = run(s, 8, 2, true);
    EXPECT_EQ(one, two); // each line is computed by the same operations in either thread
    const std::vector<gr_complex> generic = run(s, 8, 1, false);
    EXPECT_LT(nmse_db(generic, one), -100.0); // FMA contraction only
}

// The exact BP's distance per pixel and pulse: from the pulse's previous line by one Newton
// step where the kernel takes that (bp_detail::recur_distance), else std::sqrt, against
// std::sqrt of the same r^2 in double. Lines 0.125 m apart (the recurrence) and 2 m apart
// (mostly sqrt), the antenna swaying by 1 m, every 7th pulse over all M lines in turn.
TEST(bp_focuser, line_recurrence_distance_is_exact)
{
    using gr::nrsar::kernel::bp_detail::line_job;
    const bp_grid g = grid(8);
    std::vector<double> ground(K), r(K), h(K);
    std::vector<int> idx(K);
    std::vector<float> mu(K), frac(K), sine(K);
    for (unsigned k = 0; k < K; ++k)
        ground[k] = std::sqrt(std::pow(FIRST + k * RHO, 2) - H * H);
    line_job j;
    j.ground = ground.data();
    j.K = K;
    j.r = r.data();
    j.h = h.data();
    j.idx = idx.data();
    j.mu = mu.data();
    j.frac = frac.data();
    j.sine = sine.data();
    j.pos_scale = 8.0 / RHO; // positions and phases are not checked here
    j.cyc_scale = 2.0 / LAM;
    for (double spacing : { g.line_spacing_m, 2.0 }) {
        unsigned recurred = 0;
        double worst = 0.0;
        for (unsigned p = 0; p < M; p += 7) {
            const double t = p * T;
            const vec3 a{ std::sin(2.0 * M_PI * t), V * t, H + std::cos(3.0 * t) };
            j.ax = a[0];
            j.c_last = -1.0;
            for (unsigned line = 0; line < M; ++line) {
                const double dy = line * spacing - a[1];
                j.c = dy * dy + a[2] * a[2];
                recurred += gr::nrsar::kernel::bp_detail::recur_distance(j);
                gr::nrsar::kernel::bp_detail::position_phase_passes(j, true);
                for (unsigned k = 0; k < K; ++k) {
                    const double dx = ground[k] - a[0];
                    const double want = std::sqrt(dx * dx + j.c);
                    worst = std::max(worst, std::abs(r[k] - want) / want);
                }
                j.c_last = j.c;
            }
        }
        const unsigned calls = M * ((M + 6) / 7);
        std::printf("lines %.3f m apart: %u of %u lines from the last, relative error %.2g\n",
                    spacing, recurred, calls, worst);
        if (spacing < 1.0)
            EXPECT_GT(recurred, calls * 9 / 10);
        else // only where the line passes abeam the antenna (dc near 0)
            EXPECT_LT(recurred, calls / 20);
        EXPECT_LE(worst, 4.5e-16); // two roundings (one: 2.2e-16)
    }
}

TEST(bp_focuser, upsampling_trade_off)
{
    // Against the limit U -> infinity (the trigonometric interpolation of the same window).
    // Linear interpolation of exp(j 2 pi f u) at fraction mu errs by (2 pi f)^2 mu (1 - mu) / 2
    // to leading order; averaged over mu (E{mu^2 (1 - mu)^2} = 1/30) and over the profile's
    // flat spectrum |f| <= b / (2 U) per upsampled sample (b = N / NFFT cycles per bin), the
    // error power is pi^4 b^4 / (600 U^4): -56.0 dB at U = 8, -68.1 dB at U = 16. The leading
    // order holds once 2 pi b / (2 U) << 1 (U >= 8 here); below it the formula is an upper
    // bound.
    const scenario s = make(800.0, 12.5, 0.2);
    const std::vector<cd> limit = direct_bp(s, 1, false);
    const double b = double(N) / NFFT;
    for (unsigned U : { 2u, 4u, 8u, 16u }) {
        const double e = nmse_db(run(s, U, 1, true), limit);
        const double f = 10.0 * std::log10(std::pow(M_PI * b / U, 4) / 600.0);
        std::printf("upsample %2u: NMSE against U = infinity %.1f dB (formula %.1f dB)\n", U, e, f);
        if (U >= 8)
            EXPECT_NEAR(e, f, 1.0) << "U " << U;
        else
            EXPECT_LT(e, f) << "U " << U;
    }
}

TEST(bp_focuser, validates)
{
    bp_grid g = grid(8);
    g.upsample = 0;
    EXPECT_NE(nrsar_test::error_of([&] { bp_focuser b(g); }).find("upsample = 0"), std::string::npos);
    g = grid(8);
    g.range_bin_m = -1.0;
    EXPECT_NE(nrsar_test::error_of([&] { bp_focuser b(g); }).find("range_bin_m = -1"),
              std::string::npos);
    EXPECT_NE(nrsar_test::error_of([&] { bp_focuser b(grid(8), 3); }).find("num_threads = 3"),
              std::string::npos);
    g = ground_grid(8);
    g.x_spacing_m = 0.0;
    EXPECT_NE(nrsar_test::error_of([&] { bp_focuser b(g); }).find("x_spacing_m = 0"),
              std::string::npos);
    g = ffbp_grid(8, 8, 0.5);
    EXPECT_NE(nrsar_test::error_of([&] { bp_focuser b(g); }).find("beam_oversample = 0.5"),
              std::string::npos);
    gr::nrsar::bp_config c;
    c.num_threads = 0;
    EXPECT_NE(nrsar_test::error_of([&] { c.validate(); }).find("num_threads = 0"), std::string::npos);
}

TEST(bp_focuser, line_step_keeps_every_lth_line)
{
    // line_step L: num_lines = M / L lines at pulse positions 0, L, 2 L, ... scaled by
    // 1 / sqrt(M): each the full grid's line j L (exact BP: linear and short sinc, slant and
    // ground, one and two threads). The AVX2 build takes a line's distances from the
    // previous line's (exact to 2 ulp, line_recurrence_distance_is_exact), and the previous
    // line differs between the grids, so the lines agree to float rounding: each pulse adds
    // peak / M, its phase at most one float ulp (6e-8 cycle) apart, so at most 2 pi 6e-8 of
    // the peak in all.
    const scenario s = make(800.0, 12.5, 0.2);
    bp_grid sinc = grid(8);
    sinc.sinc_taps = 8;
    for (const bp_grid& g0 : { grid(8), ground_grid(8), sinc }) {
        const std::vector<gr_complex> full = run(s, g0, 1, true);
        for (unsigned L : { 4u, 5u, 8u }) {
            bp_grid g = g0;
            g.num_lines = M / L;
            g.line_step = L;
            const std::vector<gr_complex> img = run(s, g, 2, true);
            float peak = 0.0f, worst = 0.0f;
            for (unsigned j = 0; j < M / L; ++j)
                for (unsigned k = 0; k < K; ++k) {
                    peak = std::max(peak, std::abs(full[j * L * K + k]));
                    worst = std::max(worst, std::abs(img[j * K + k] - full[j * L * K + k]));
                }
            std::printf("line_step %u ground %d sinc %u: largest difference %.2e of the peak "
                        "(bound %.2e)\n", L, int(g.ground), g.sinc_taps, worst / peak,
                        2.0 * M_PI * 6e-8);
            EXPECT_LE(worst, 2.0 * M_PI * 6e-8 * peak)
                << "L " << L << " ground " << g.ground << " sinc " << g.sinc_taps;
        }
    }
    // FFBP on the coarse grid: its beams span that grid's lines, so it matches exact BP's
    // coarse lines to FFBP's error bound (pi^4 / (600 os^4): -44.1 dB at os = 8), not bit
    // for bit; the inner bins as in ffbp_converges_to_back_projection.
    const unsigned L = 8, J = M / L;
    bp_grid g = coarse_grid(L);
    const std::vector<gr_complex> exact = run(s, g, 1, true);
    g.subaperture = 8;
    g.beam_oversample = 8.0;
    const double e = nmse_db(inner(run(s, g, 2, true)), inner(exact));
    std::printf("ffbp L 8 beams x8 on line_step 8: NMSE against BP %.1f dB inner\n", e);
    EXPECT_LT(e, 10.0 * std::log10(std::pow(M_PI / 8.0, 4) / 600.0) + 1.0);
    g.line_step = 0;
    EXPECT_NE(nrsar_test::error_of([&] { bp_focuser b(g); }).find("line_step = 0"),
              std::string::npos);
    g.line_step = 4097;
    EXPECT_NE(nrsar_test::error_of([&] { bp_focuser b(g); }).find("line_step = 4097"),
              std::string::npos);
    gr::nrsar::bp_config c;
    c.line_step = 4;
    c.trajectory_autofocus = true;
    const std::string err = nrsar_test::error_of([&] { c.validate(); });
    EXPECT_NE(err.find("line_step = 4"), std::string::npos) << err;
    EXPECT_NE(err.find("trajectory_autofocus"), std::string::npos) << err;
    g.line_step = 2;
    g.subaperture = 0;
    std::vector<gr_complex> out(static_cast<size_t>(J) * K);
    EXPECT_NE(nrsar_test::error_of([&] {
                  gr::nrsar::kernel::trajectory_autofocus(
                      s.pulses.data(), M, s.antenna.data(), g,
                      gr::nrsar::kernel::trajectory_autofocus_config(), out.data());
              }).find("line_step = 2"),
              std::string::npos);
}

TEST(bp_focuser, ground_grid_matches_direct_back_projection)
{
    // Target on the ground at x = 800 m = GX0 + 32 GDX, y = 12.5 m (line 100).
    const scenario s = make(800.0, 12.5, 0.2);
    const std::vector<cd> ref = direct_bp(s, 4, true, true);
    for (bool simd : { false, true })
        EXPECT_LT(nmse_db(run(s, ground_grid(4), 1, simd), ref), -90.0) << "simd " << simd;
    const size_t best = argmax(run(s, ground_grid(8), 2, true));
    EXPECT_EQ(best / K, 100u);
    EXPECT_EQ(best % K, 32u);
}

TEST(bp_focuser, ffbp_converges_to_back_projection)
{
    // FFBP against the exact BP of the same samples (U = 8). Its extra error is the linear
    // interpolation between beams: the subimage's angular spectrum is flat over the
    // subaperture's band (uniform pulses) and sampled `os` times above its Nyquist rate, so
    // by the same formula as the range interpolation (pi^4 w^4 / 600 for a flat band of w
    // cycles per sample, here w = 1 / os) the error power is pi^4 / (600 os^4): -20.0 dB at
    // os = 2, 12 dB less per doubling. Measured on the bins away from the window's ends: a
    // polar row is not periodic like this test's profiles, and its FFT upsampling rings within
    // a few bins of either end (docs/blocks/bp_focuser.md).
    const scenario s = make(800.0, 12.5, 0.2);
    const std::vector<gr_complex> exact = run(s, 8, 1, true);
    const size_t peak = argmax(exact);
    double prev = 0.0;
    for (double os : { 2.0, 4.0, 8.0 }) {
        for (unsigned L : { 8u, 25u }) {
            const std::vector<gr_complex> img = run(s, ffbp_grid(8, L, os), 1, true);
            const double e = nmse_db(inner(img), inner(exact));
            const double bound = 10.0 * std::log10(std::pow(M_PI / os, 4) / 600.0);
            std::printf("ffbp L %2u beams x%.0f: NMSE against BP %.1f dB inner (bound %.1f dB), "
                        "%.1f dB whole\n",
                        L,
                        os,
                        e,
                        bound,
                        nmse_db(img, exact));
            EXPECT_LT(e, bound + 1.0) << "L " << L << " os " << os;
            EXPECT_EQ(argmax(img), peak);
            // Linear interpolation loses at most (pi w)^2 / 8 of a tone's amplitude.
            const double ratio = std::abs(img[peak]) / std::abs(exact[peak]);
            EXPECT_LE(ratio, 1.001);
            EXPECT_GE(ratio, 1.0 - std::pow(M_PI / os, 2) / 8.0);
            if (L == 8u) {
                if (os > 2.0) {
                    EXPECT_LT(e, prev - 9.0) << "os " << os; // 12 dB per doubling
                }
                prev = e;
            }
        }
    }
    // Two threads: the same operations per beam and per line.
    EXPECT_EQ(run(s, ffbp_grid(8, 8, 4.0), 2, true), run(s, ffbp_grid(8, 8, 4.0), 1, true));
}

TEST(bp_focuser, recursive_ffbp_against_back_projection)
{
    // Recursive FFBP (levels n): subapertures of 4 pulses merged F at a time n - 1 times,
    // against the exact BP of the same samples. Every level interpolates once more between
    // beams sampled os times above their Nyquist rate (each merged subimage's beams at its
    // own D) and once more in range (rows upsampled U = 8 times, the band b = N / NFFT of a
    // bin: pi^4 (b / U)^4 / 600 = -56.1 dB). Linear interpolation's error is mostly an
    // attenuation of the same sign at every level, so the beam errors add in amplitude:
    // NMSE <= n^2 pi^4 / (600 os^4) + n pi^4 (b / U)^4 / 600 (at os = 8: -44.0, -37.9,
    // -34.4 dB for n = 1, 2, 3), between that and n times it for independent errors.
    const scenario s = make(800.0, 12.5, 0.2);
    const std::vector<gr_complex> exact = run(s, 8, 1, true);
    const size_t peak = argmax(exact);
    const double range_term = std::pow(M_PI * N / (NFFT * 8.0), 4) / 600.0;
    for (unsigned F : { 2u, 4u })
        for (double os : { 4.0, 8.0, 32.0 })
            for (unsigned n = 1; n <= (F == 2 ? 4u : 3u); ++n) {
                bp_grid g = ffbp_grid(8, 4, os);
                g.levels = n;
                g.merge_factor = F;
                const std::vector<gr_complex> img = run(s, g, 1, true);
                const double e = nmse_db(inner(img), inner(exact));
                const double beam_term = std::pow(M_PI / os, 4) / 600.0;
                const double bound = 10.0 * std::log10(n * n * beam_term + n * range_term);
                std::printf("ffbp levels %u F %u beams x%2.0f: NMSE against BP %.1f dB inner "
                            "(bound %.1f dB, n times %.1f dB), %.1f dB whole\n",
                            n, F, os, e, bound,
                            10.0 * std::log10(n * (beam_term + range_term)),
                            nmse_db(img, exact));
                EXPECT_LT(e, bound + 1.0) << "levels " << n << " F " << F << " os " << os;
                EXPECT_EQ(argmax(img), peak);
            }
    // Two threads: the same operations per beam and per line.
    bp_grid g = ffbp_grid(8, 4, 4.0);
    g.levels = 3;
    g.merge_factor = 2;
    EXPECT_EQ(run(s, g, 2, true), run(s, g, 1, true));
    // The image grid at line_step 8: the merged subimages span its lines.
    bp_grid c = coarse_grid(8);
    const std::vector<gr_complex> coarse = run(s, c, 1, true);
    c.subaperture = 4;
    c.beam_oversample = 8.0;
    c.levels = 3;
    c.merge_factor = 2;
    const double e = nmse_db(inner(run(s, c, 2, true)), inner(coarse));
    std::printf("ffbp levels 3 F 2 beams x8 on line_step 8: NMSE against BP %.1f dB inner\n", e);
    EXPECT_LT(e, 10.0 * std::log10(9.0 * std::pow(M_PI / 8.0, 4) / 600.0 + 3.0 * range_term) +
                     1.0);
    // More pulses per subaperture than an add() call holds (1000 x 16^7 of them): each
    // level one subimage of all of them, 8 interpolations.
    g = ffbp_grid(8, 1000, 8.0);
    g.levels = 8;
    g.merge_factor = 16;
    EXPECT_LT(nmse_db(inner(run(s, g, 1, true)), inner(exact)),
              10.0 * std::log10(64.0 * std::pow(M_PI / 8.0, 4) / 600.0 + 8.0 * range_term) +
                  1.0);
    // Refusals name the field, its value and the limit.
    g.levels = 9;
    EXPECT_NE(nrsar_test::error_of([&] { bp_focuser b(g); }).find("levels = 9"),
              std::string::npos);
    g.levels = 2;
    g.merge_factor = 1;
    EXPECT_NE(nrsar_test::error_of([&] { bp_focuser b(g); }).find("merge_factor = 1"),
              std::string::npos);
    gr::nrsar::bp_config cfg;
    cfg.ffbp_levels = 3;
    std::string err = nrsar_test::error_of([&] { cfg.validate(); });
    EXPECT_NE(err.find("ffbp_levels = 3"), std::string::npos) << err;
    EXPECT_NE(err.find("ffbp_subaperture < 2"), std::string::npos) << err;
    cfg.ffbp_subaperture = 16;
    cfg.ffbp_merge_factor = 17;
    err = nrsar_test::error_of([&] { cfg.validate(); });
    EXPECT_NE(err.find("ffbp_merge_factor = 17"), std::string::npos) << err;
    cfg.ffbp_merge_factor = 2;
    cfg.validate();
}

TEST(bp_focuser, short_sinc_interpolation)
{
    const scenario s = make(800.0, 12.5, 0.2);
    const std::vector<cd> limit = direct_bp(s, 1, false);
    double prev = 0.0;
    for (unsigned taps : { 4u, 8u, 16u }) {
        bp_grid g = grid(8);
        g.sinc_taps = taps;
        const std::vector<gr_complex> img = run(s, g, 1, true);
        // The kernel's sinc path is the interpolator's: float against double (the nearest
        // phase may differ at a rounding edge: a 1/1024-bin shift there).
        EXPECT_LT(nmse_db(img, direct_bp_sinc(s, taps)), -70.0) << "taps " << taps;
        // The trade-off against U -> infinity (docs): falls with the taps until the floor of
        // the window's ends (zeros outside it, where this test's reference is periodic) and
        // of the 1024-phase table (shift error up to 1/2048 bin: -61 dB at b = 0.5).
        const double e = nmse_db(img, limit);
        std::printf("sinc %2u taps: NMSE against U = infinity %.1f dB\n", taps, e);
        if (taps == 8) {
            EXPECT_LT(e, prev - 6.0);
        }
        if (taps == 16) {
            EXPECT_LT(e, prev + 0.5);
        }
        prev = e;
    }
    bp_grid g = grid(8);
    g.sinc_taps = 7;
    EXPECT_NE(nrsar_test::error_of([&] { bp_focuser b(g); }).find("sinc_taps = 7"),
              std::string::npos);
}
