/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Kernel tests of autofocus by trajectory estimation: a known 3-D navigation error is
// injected into the path the processor believes; the estimated displacement along the
// line of sight is held against the injected one (closed form), and the image along the
// corrected path against back-projection along the true path moved by the error's
// constant and linear trend (what focus can see). The echo is written here in double
// (eq. 29), the noise seeded.

#include <gnuradio/nrsar/kernel/bp_autofocus.h>
#include "bp_test_geometry.h"
#include <gtest/gtest.h>
#include <array>
#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <vector>

using gr::nrsar::kernel::bp_focuser;
using gr::nrsar::kernel::bp_grid;
using gr::nrsar::kernel::trajectory_autofocus;
using gr::nrsar::kernel::trajectory_autofocus_config;
using cd = std::complex<double>;
using vec3 = std::array<double, 3>;

namespace {

using namespace bp_test;
constexpr unsigned M = 400; // pulses and lines (1 s, 50 m of track)
// Targets (ground x, y, amplitude): three look angles 52.1 / 53.1 / 54.1 degrees.
const std::vector<vec3> TGT = { { 800.0, 25.03, 1.0 }, { 830.0, 25.03, 0.5 },
                                { 770.0, 25.03, 0.3 } };

// The slant-range grid for a platform at height h.
bp_grid grid(double h = H)
{
    bp_grid g = bp_test::grid(8, M);
    g.reference_height_m = h;
    return g;
}

vec3 truth(unsigned n, double h = H) { return { 0.0, V * n * T, h }; }

// The injected navigation error a_nav - a_true [m]: offsets, a drift and swaying of a few
// centimetres at 0.6-2 Hz (GNSS-like: slow against the 16-pulse smoothing, 40 ms).
vec3 nav_error(unsigned n)
{
    const double t = n * T;
    return { 0.12 + 0.05 * t + 0.02 * std::sin(2 * M_PI * 1.3 * t + 0.4),
             -0.15 + 0.01 * std::sin(2 * M_PI * 0.6 * t),
             -0.20 - 0.08 * t + 0.03 * std::sin(2 * M_PI * 0.8 * t + 1.0) +
                 0.01 * std::cos(2 * M_PI * 2.0 * t) };
}

// Eq. (29): sum_q a_q D(k - k_q) exp(-j 4 pi R_q / lambda), D the Dirichlet kernel of the n_sub
// subcarriers in an n_fft-point IFFT (the K bins its first K: all of it for N, NFFT), from
// the true path at height h; complex white noise of variance sigma2 per sample.
std::vector<gr_complex> echo(double sigma2,
                             unsigned seed,
                             const std::vector<vec3>& targets = TGT,
                             double h = H,
                             unsigned n_sub = N,
                             unsigned n_fft = NFFT)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss(0.0, std::sqrt(sigma2 / 2.0));
    std::vector<gr_complex> out(std::size_t(M) * K);
    for (unsigned n = 0; n < M; ++n) {
        const vec3 a = truth(n, h);
        for (unsigned k = 0; k < K; ++k) {
            cd v(0.0, 0.0);
            for (const auto& q : targets) {
                const double r = std::sqrt((q[0] - a[0]) * (q[0] - a[0]) +
                                           (q[1] - a[1]) * (q[1] - a[1]) + a[2] * a[2]);
                const double qr = (r - FIRST) / RHO;
                cd acc(0.0, 0.0);
                for (unsigned s = 0; s < n_sub; ++s)
                    acc += std::polar(1.0, 2.0 * M_PI * s * (k - qr) / n_fft);
                v += q[2] * acc / std::sqrt(double(n_sub)) *
                     std::polar(1.0, -4.0 * M_PI * std::fmod(r / LAM, 1.0));
            }
            if (sigma2 > 0.0)
                v += cd(gauss(rng), gauss(rng));
            out[std::size_t(n) * K + k] = gr_complex(float(v.real()), float(v.imag()));
        }
    }
    return out;
}

std::vector<gr_complex>
bp_image(const std::vector<gr_complex>& pulses, const std::vector<vec3>& ant, double h = H)
{
    bp_focuser bp(grid(h));
    bp.reset(0.0);
    bp.add(pulses.data(), M, ant.data());
    std::vector<gr_complex> img(std::size_t(M) * K);
    bp.image(img.data());
    return img;
}

// v less its least-squares constant and linear trend over the pulses.
std::vector<double> detrend(std::vector<double> v)
{
    const double tm = 0.5 * (v.size() - 1.0);
    double s0 = 0.0, s1 = 0.0, stt = 0.0;
    for (std::size_t p = 0; p < v.size(); ++p) {
        s0 += v[p];
        s1 += v[p] * (p - tm);
        stt += (p - tm) * (p - tm);
    }
    for (std::size_t p = 0; p < v.size(); ++p)
        v[p] -= s0 / v.size() + s1 / stt * (p - tm);
    return v;
}

// The rms over the pulses of est - inj and of inj, both less their trend.
std::array<double, 2> rms_detrended(const std::vector<double>& est,
                                    const std::vector<double>& inj)
{
    const std::vector<double> e = detrend(est), i = detrend(inj);
    double err = 0.0, inj_rms = 0.0;
    for (std::size_t n = 0; n < e.size(); ++n) {
        err += (e[n] - i[n]) * (e[n] - i[n]) / e.size();
        inj_rms += i[n] * i[n] / e.size();
    }
    return { std::sqrt(err), std::sqrt(inj_rms) };
}

// The path a focus-based estimate can reach: the truth at height h plus the error's trend
// (per axis).
std::vector<vec3> truth_plus_trend(double h = H)
{
    std::vector<vec3> out(M);
    for (int c = 0; c < 3; ++c) {
        std::vector<double> e(M);
        for (unsigned n = 0; n < M; ++n)
            e[n] = nav_error(n)[c];
        const std::vector<double> d = detrend(e);
        for (unsigned n = 0; n < M; ++n)
            out[n][c] = truth(n, h)[c] + e[n] - d[n];
    }
    return out;
}

// SPEC 8's calibrated NMSE over the image after the best azimuth circular shift by whole
// lines (the trend moves the image; a sub-line shift is left in and counts).
double nmse_db(const std::vector<gr_complex>& img, const std::vector<gr_complex>& ref)
{
    double best = INFINITY, peak = 0.0;
    for (const auto& v : ref)
        peak = std::max(peak, double(std::norm(v)));
    for (int s = -40; s <= 40; ++s) {
        cd num(0.0, 0.0), den(0.0, 0.0);
        auto at = [&](unsigned j, unsigned k) {
            return cd(img[std::size_t((j + M + s) % M) * K + k]);
        };
        for (unsigned j = 0; j < M; ++j)
            for (unsigned k = 0; k < K; ++k) {
                num += std::conj(cd(ref[std::size_t(j) * K + k])) * at(j, k);
                den += std::norm(cd(ref[std::size_t(j) * K + k]));
            }
        const cd c = num / den;
        double e = 0.0;
        for (unsigned j = 0; j < M; ++j)
            for (unsigned k = 0; k < K; ++k)
                e += std::norm(at(j, k) / c - cd(ref[std::size_t(j) * K + k]));
        best = std::min(best, double(N) * M * (e / (double(M) * K)) / peak);
    }
    return 10.0 * std::log10(best);
}

// The targets' power-weighted mean line of sight in the x-z plane at the middle pulse
// (the direction the kernel solves along when the look angles hardly spread).
std::array<double, 2> mean_los()
{
    double mx = 0.0, mz = 0.0;
    const vec3 a = truth(M / 2);
    for (const auto& q : TGT) {
        const double dx = a[0] - q[0], dy = a[1] - q[1], dz = a[2];
        const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
        mx += q[2] * q[2] * dx / r;
        mz += q[2] * q[2] * dz / r;
    }
    const double m = std::hypot(mx, mz);
    return { mx / m, mz / m };
}

// Image energy of a - b.
double energy(const std::vector<gr_complex>& a, const std::vector<gr_complex>& b)
{
    double e = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        e += std::norm(cd(a[i]) - cd(b[i]));
    return e;
}

std::vector<vec3> true_path(double h = H)
{
    std::vector<vec3> tru(M);
    for (unsigned n = 0; n < M; ++n)
        tru[n] = truth(n, h);
    return tru;
}

// The autofocused image against BP of the noise-free echo along the reachable path: the
// noisy echo along that path is the floor, BP along the navigation what autofocus starts
// from; the navigation at least 5 dB above the floor, autofocus within 0.5 dB of it.
void expect_image_near_floor(const std::vector<gr_complex>& pulses,
                             const std::vector<gr_complex>& clean,
                             const std::vector<vec3>& nav,
                             const std::vector<gr_complex>& img,
                             double h = H)
{
    const auto ref = bp_image(clean, truth_plus_trend(h), h);
    const double floor_db = nmse_db(bp_image(pulses, truth_plus_trend(h), h), ref);
    const double nav_db = nmse_db(bp_image(pulses, nav, h), ref);
    const double af_db = nmse_db(img, ref);
    std::printf("NMSE: reachable path %.2f dB, navigation %.2f dB, autofocus %.2f dB\n",
                floor_db, nav_db, af_db);
    EXPECT_GT(nav_db, floor_db + 5.0);
    EXPECT_LT(af_db, floor_db + 0.5);
}

// The GCPs of the e_y and d_y tests: look angles 1 degree apart, each alone in its range
// bins, the middle one 25 m along track from the outer two (u_y's pattern not a linear
// function of the look angle, which x and z would absorb).
const std::vector<vec3> SPREAD = { { 800.0, 12.53, 1.0 },
                                   { 830.0, 37.53, 1.0 },
                                   { 770.0, 37.53, 1.0 } };

// Cramer-Rao-type standard error of the y of a GCP solve (x, y, z) from one estimate per GCP
// q: sqrt((G^-1)_yy), G = sum u u^T / var over the GCPs (u their line of sight at the middle
// pulse), var = 1 / ((2 pi cs)^2 2 g a^2 count) the estimate's: the mean phase (count n,
// the constant) or the slope (count sum (p - p_mid)^2) of a history at SNR g a^2 per pulse;
// g = 4 / 3 of the echo's snr, the Hann-tapered history (gcp_takes_out_an_along_track_offset).
double crb_y(const std::vector<vec3>& gcps, double snr, double count)
{
    const double cs = 2.0 / LAM + FCR / RHO;
    const vec3 am = truth(M / 2);
    double g[3][3] = {};
    for (const auto& q : gcps) {
        const vec3 d = { am[0] - q[0], am[1] - q[1], am[2] };
        const double r = std::hypot(d[0], d[1], d[2]);
        const double var = 1.0 / (std::pow(2.0 * M_PI * cs, 2) * 2.0 * (4.0 / 3.0) * snr *
                                  q[2] * q[2] * count);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                g[i][j] += d[i] * d[j] / (r * r * var);
    }
    // (G^-1)_yy = cofactor / det
    const double det = g[0][0] * (g[1][1] * g[2][2] - g[1][2] * g[2][1]) -
                       g[0][1] * (g[1][0] * g[2][2] - g[1][2] * g[2][0]) +
                       g[0][2] * (g[1][0] * g[2][1] - g[1][1] * g[2][0]);
    return std::sqrt((g[0][0] * g[2][2] - g[0][2] * g[2][0]) / det);
}


// The navigation of the d_y tests: the truth + an (x, z) offset and drift + e_y + d_y (t -
// t_mid) [m, m/s].
std::vector<vec3> nav_with_speed_error(double ey, double dy)
{
    std::vector<vec3> nav = true_path();
    const double tm = 0.5 * (M - 1.0);
    for (unsigned n = 0; n < M; ++n) {
        const double t = (n - tm) * T;
        nav[n][0] += 0.12 + 0.05 * t;
        nav[n][1] += ey + dy * t;
        nav[n][2] += -0.20 - 0.08 * t;
    }
    return nav;
}

} // namespace

TEST(bp_autofocus, recovers_an_injected_path_error)
{
    // 10 dB per range-compressed sample of the strongest target: sqrt(N) peak, sigma^2 = N / 10.
    const double sigma2 = N / 10.0;
    const auto pulses = echo(sigma2, 7), clean = echo(0.0, 7);
    std::vector<vec3> nav(M), tru(M);
    for (unsigned n = 0; n < M; ++n) {
        tru[n] = truth(n);
        for (int c = 0; c < 3; ++c)
            nav[n][c] = tru[n][c] + nav_error(n)[c];
    }
    trajectory_autofocus_config cfg;
    std::vector<gr_complex> img(std::size_t(M) * K);
    const auto r = trajectory_autofocus(pulses.data(), M, nav.data(), grid(), cfg, img.data());
    EXPECT_FALSE(r.two_dimensional); // 1 degree of look-angle spread: along the LOS only
    EXPECT_GE(r.points.size(), 3u);

    // Estimate against the injected error on the mean line of sight, trend removed.
    const auto m = mean_los();
    std::vector<double> los_true(M), los_est(M);
    for (unsigned n = 0; n < M; ++n) {
        los_true[n] = nav_error(n)[0] * m[0] + nav_error(n)[2] * m[1];
        los_est[n] = r.displacement_m[n][0] * m[0] + r.displacement_m[n][2] * m[1];
    }
    const auto [err, tru_rms] = rms_detrended(los_est, los_true);
    // Noise bound: per pulse the strongest point's phase noise 1 / sqrt(2 SNR) (SNR = 10),
    // over the 17-pulse sum 1 / sqrt(2 * 10 * 17) = 0.054 rad, i.e. lambda / (4 pi) * 0.054
    // = 0.37 mm (with the weaker points the kernel's standard error is 0.27 mm, the range
    // taper having dropped this echo's noise outside the band, and the estimate on the
    // true path scatters by that: test below); the smoothing's own bias on the 2 Hz
    // sway (1 cm, attenuated by sin(pi f L T) / (L sin(pi f T)) = 0.989) adds 0.1 mm, the
    // unsolved component across the line of sight (3 cm times the 0.6 degree spread about
    // the mean) 0.3 mm: 3 times the noise plus both, 1.5 mm.
    std::printf("LOS error %.3f mm rms against %.1f mm injected (trend removed), %u iterations\n",
                1e3 * err, 1e3 * tru_rms, r.iterations);
    EXPECT_GT(tru_rms, 0.005);
    EXPECT_LT(err, 1.5e-3);
    EXPECT_TRUE(r.accepted);

    expect_image_near_floor(pulses, clean, nav, img);
}

TEST(bp_autofocus, solves_x_and_z_on_a_wide_swath)
{
    // The platform at 950 m, targets at ground ranges 150 / 290 / 430 m (slant 962 / 993 /
    // 1043 m, in the same 64 bins): depression angles 81.0 / 73.0 / 65.7 degrees, 0.27 rad
    // from the first to the last (weighted rms spread 0.11 rad), so the per-pulse solve
    // takes x and z. They stand 20 m apart along track: their Doppler then differs by
    // 2 v dy / (lambda r) = 23 Hz, one turn over the 17-pulse moving sum, which also cancels
    // what each one's range sidelobes put into the others' pixels (at one y: the test
    // below). The injected error is nav_error's: sway in x (2 cm at 1.3 Hz) independent of
    // that in z (3 cm at 0.8 Hz, 1 cm at 2 Hz); 20 dB per range-compressed sample of the
    // strongest.
    constexpr double HW = 950.0;
    const std::vector<vec3> wide = { { 150.0, 5.0, 1.0 }, { 290.0, 25.0, 0.8 },
                                     { 430.0, 45.0, 0.9 } };
    const double sigma2 = N / 100.0;
    const auto pulses = echo(sigma2, 51, wide, HW), clean = echo(0.0, 51, wide, HW);
    const auto tru = true_path(HW);
    std::vector<vec3> nav(M);
    for (unsigned n = 0; n < M; ++n)
        for (int c = 0; c < 3; ++c)
            nav[n][c] = tru[n][c] + nav_error(n)[c];
    std::vector<gr_complex> img(std::size_t(M) * K);
    const auto r = trajectory_autofocus(
        pulses.data(), M, nav.data(), grid(HW), trajectory_autofocus_config(), img.data());
    std::printf("wide swath: %zu points, look-angle spread %.3f rad, %s, %u iterations, "
                "standard error %.3f mm\n",
                r.points.size(), r.look_spread_rad, r.two_dimensional ? "x and z" : "LOS",
                r.iterations, 1e3 * r.standard_error_m);
    EXPECT_TRUE(r.two_dimensional);
    EXPECT_GE(r.points.size(), 3u);
    EXPECT_TRUE(r.accepted);

    // Each component against the injected one, trend removed: within 3 standard errors
    // (the kernel's, rms of x and z; the error is about 1 of them: the 1 cm sway along
    // track, which the x-z solve cannot take, adds 0.5 mm in x at high SNR), the standard
    // error under a tenth of the injected sway, so a wrong solve fails.
    for (int c : { 0, 2 }) {
        std::vector<double> inj(M), est(M);
        for (unsigned n = 0; n < M; ++n) {
            inj[n] = nav_error(n)[c];
            est[n] = r.displacement_m[n][c];
        }
        const auto [err, inj_rms] = rms_detrended(est, inj);
        std::printf("%c: error %.3f mm rms against %.1f mm injected\n", c == 0 ? 'x' : 'z',
                    1e3 * err, 1e3 * inj_rms);
        EXPECT_LT(r.standard_error_m, 0.1 * inj_rms);
        EXPECT_LT(err, 3.0 * r.standard_error_m);
    }

    // The image (a residual of about one standard error costs 0.2-0.3 dB).
    expect_image_near_floor(pulses, clean, nav, img, HW);
}

TEST(bp_autofocus, targets_at_one_along_track_position)
{
    // The wide swath's targets all at y = 25 m: one Doppler history, so what each one's
    // range sidelobes put into the others' single-pulse pixels beats at their Doppler
    // difference, a fraction of a hertz, slower than the 17-pulse moving sum. The unwindowed
    // 2x oversampled Dirichlet's sidelobes (-18 to -32 dB) made that a 2.0 mm rms bias of x
    // on the true path (0.6 mm of z; 20 times the standard error at 40 dB); the histories
    // read from Hann-tapered pulses (sidelobes -32 to -74 dB) leave 0.047 mm of x at 60 dB
    // (docs/blocks/bp_focuser.md, "Range sidelobes").
    constexpr double HW = 950.0;
    const std::vector<vec3> one_y = { { 150.0, 25.0, 1.0 }, { 290.0, 25.0, 0.8 },
                                      { 430.0, 25.0, 0.9 } };
    const auto pulses = echo(N / 1e4, 61, one_y, HW); // 40 dB
    const auto tru = true_path(HW);
    std::vector<gr_complex> img(std::size_t(M) * K);
    auto x_error = [&](double band) {
        trajectory_autofocus_config cfg;
        cfg.significance = 0.0; // keep it, to measure it
        cfg.range_band_cycles = band;
        const auto r = trajectory_autofocus(pulses.data(), M, tru.data(), grid(HW), cfg,
                                            img.data());
        EXPECT_TRUE(r.two_dimensional);
        double x = 0.0;
        for (const auto& d : r.displacement_m)
            x += d[0] * d[0] / M;
        std::printf("one y, %s: x %.3f mm rms, standard error %.3f mm\n",
                    band == 0.0 ? "untapered" : "tapered", 1e3 * std::sqrt(x),
                    1e3 * r.standard_error_m);
        return std::sqrt(x) / r.standard_error_m;
    };
    // On the true path the estimate is noise, about 1 standard error (each draw's rms
    // scatters by 0.14: test above), plus the taper's residual bias (0.8 standard errors
    // at 40 dB), in quadrature: 1.6 at 3 of that scatter.
    EXPECT_LT(x_error(std::nan("")), 1.75);
    // Untapered (the old reading): the sidelobe bias, many standard errors.
    EXPECT_GT(x_error(0.0), 10.0);
}

TEST(bp_autofocus, leaves_a_focused_image_as_it_is)
{
    // On the true path the estimate is noise (0.27 mm standard error at this SNR, test
    // below): below 2 standard errors it is refused, and the image is the navigation's.
    const double sigma2 = N / 10.0;
    const auto pulses = echo(sigma2, 11);
    const auto tru = true_path();
    std::vector<gr_complex> img(std::size_t(M) * K);
    const auto r = trajectory_autofocus(
        pulses.data(), M, tru.data(), grid(), trajectory_autofocus_config(), img.data());
    EXPECT_FALSE(r.accepted);
    EXPECT_GT(r.standard_error_m, 0.0);
    for (std::size_t i = 0; i < r.antenna.size(); ++i)
        EXPECT_EQ(r.antenna[i], tru[i]);
    const auto before = bp_image(pulses, tru);
    const auto ref = bp_image(echo(0.0, 11), tru);
    EXPECT_EQ(nmse_db(img, ref), nmse_db(before, ref));
}

TEST(bp_autofocus, standard_error_is_the_scatter_of_the_estimate)
{
    // On the true path the whole estimate is noise: its rms over the pulses against the
    // standard error the kernel derives from the phase histories (sigma^2 / (2 L A^2)
    // per point, propagated through the least squares), at 10 dB and 0 dB per
    // range-compressed sample of the strongest target, three noise draws each; and at 10 dB
    // with both components solved (look_spread_rad below the targets' 0.009 rad spread: the
    // covariance G^-1 H G^-1, the component across the line of sight about 1 / spread
    // times the noise).
    const auto tru = true_path();
    std::vector<gr_complex> img(std::size_t(M) * K);
    const struct {
        double snr_db;
        bool two_d;
    } cases[] = { { 10.0, false }, { 0.0, false }, { 10.0, true } };
    for (const auto& [snr_db, two_d] : cases) {
        trajectory_autofocus_config cfg;
        cfg.significance = 0.0; // keep it, to measure it
        if (two_d)
            cfg.look_spread_rad = 0.001;
        double r2 = 0.0;
        for (unsigned seed : { 21u, 22u, 23u }) {
            const auto pulses = echo(N * std::pow(10.0, -snr_db / 10.0), seed);
            const auto r = trajectory_autofocus(pulses.data(), M, tru.data(), grid(), cfg,
                                                img.data());
            double rms = 0.0;
            for (const auto& d : r.displacement_m)
                rms += (d[0] * d[0] + d[2] * d[2]) / M;
            rms = std::sqrt(rms);
            std::printf("SNR %+.0f dB seed %u: estimate %.3f mm rms, standard error %.3f mm\n",
                        snr_db, seed, 1e3 * rms, 1e3 * r.standard_error_m);
            EXPECT_TRUE(r.accepted);
            EXPECT_EQ(r.two_dimensional, two_d);
            r2 += rms * rms / (r.standard_error_m * r.standard_error_m) / 3.0;
        }
        // About n / L = 400 / 17 = 24 independent values per draw, 71 over three: the
        // ratio's rms scatters by 1 / sqrt(2 * 71) = 0.08; +-0.25 is 3 of them.
        std::printf("SNR %+.0f dB%s: rms(estimate) / standard error = %.3f\n", snr_db,
                    two_d ? " (x and z)" : "", std::sqrt(r2));
        EXPECT_NEAR(std::sqrt(r2), 1.0, 0.25);
    }
}

TEST(bp_autofocus, does_no_harm_at_low_snr)
{
    // 0 dB per range-compressed sample of the strongest target.
    const double sigma2 = N;
    const auto tru = true_path();
    std::vector<gr_complex> img(std::size_t(M) * K);
    for (unsigned seed : { 31u, 32u, 33u }) {
        // A focused image: the correction is noise, so the navigation and its image are
        // returned as they are (bit for bit: the same back-projection).
        const auto pulses = echo(sigma2, seed);
        const auto r = trajectory_autofocus(pulses.data(), M, tru.data(), grid(),
                                            trajectory_autofocus_config(), img.data());
        EXPECT_FALSE(r.accepted);
        EXPECT_EQ(r.iterations, 1u);
        for (const auto& d : r.displacement_m)
            EXPECT_EQ(d[0] * d[0] + d[2] * d[2], 0.0);
        const auto nav_img = bp_image(pulses, tru);
        EXPECT_EQ(energy(img, nav_img), 0.0);
        // What keeping it would have cost (reported in docs/blocks/bp_focuser.md).
        trajectory_autofocus_config always;
        always.significance = 0.0;
        trajectory_autofocus(pulses.data(), M, tru.data(), grid(), always, img.data());
        const auto ref = bp_image(echo(0.0, seed), tru);
        std::printf("seed %u: kept noise correction %+.3f dB of NMSE\n", seed,
                    nmse_db(img, ref) - nmse_db(nav_img, ref));
    }

    // A path error of a few standard errors at the same SNR: sway along the targets' mean
    // line of sight, 3 mm at 1.1 Hz. A kept correction is larger than 2 standard errors
    // (se), so the error it leaves is about se: the image may be worse than the navigated
    // one by at most what a path error of rms se costs, phi^2 = (4 pi se / lambda)^2 of
    // the targets' energy E_t moved into the error E_e: 10 log10(1 + phi^2 E_t / E_e).
    const auto m = mean_los();
    std::vector<vec3> nav(M);
    for (unsigned n = 0; n < M; ++n) {
        const double e = 3e-3 * std::sin(2 * M_PI * 1.1 * n * T);
        nav[n] = { tru[n][0] + e * m[0], tru[n][1], tru[n][2] + e * m[1] };
    }
    for (unsigned seed : { 34u, 35u, 36u }) {
        const auto pulses = echo(sigma2, seed), clean = echo(0.0, seed);
        const auto r = trajectory_autofocus(pulses.data(), M, nav.data(), grid(),
                                            trajectory_autofocus_config(), img.data());
        const auto ref = bp_image(clean, tru);
        const double nav_db = nmse_db(bp_image(pulses, nav), ref), af_db = nmse_db(img, ref);
        const double phi = 4 * M_PI * r.standard_error_m / LAM;
        const double bound_db =
            10 * std::log10(1 + phi * phi * energy(ref, std::vector<gr_complex>(ref.size())) /
                                    energy(bp_image(pulses, tru), ref));
        std::printf("seed %u: se %.3f mm, %s; NMSE navigation %.2f dB, autofocus %.2f dB "
                    "(bound +%.2f dB)\n",
                    seed, 1e3 * r.standard_error_m, r.accepted ? "kept" : "refused", nav_db,
                    af_db, bound_db);
        EXPECT_LE(af_db, nav_db + bound_db);
    }
}

TEST(bp_autofocus, validates)
{
    const std::vector<gr_complex> pulses(std::size_t(M) * K);
    std::vector<vec3> ant(M, vec3{ 0.0, 0.0, H });
    std::vector<gr_complex> img(std::size_t(M) * K);
    auto run = [&](trajectory_autofocus_config c, unsigned n) {
        trajectory_autofocus(pulses.data(), n, ant.data(), grid(), c, img.data());
    };
    trajectory_autofocus_config c;
    c.points = 0;
    EXPECT_THROW(run(c, M), std::invalid_argument);
    c = {};
    c.points_db = 0.0;
    EXPECT_THROW(run(c, M), std::invalid_argument);
    c = {};
    c.max_iterations = 51;
    EXPECT_THROW(run(c, M), std::invalid_argument);
    c = {};
    c.smooth_pulses = M + 1;
    EXPECT_THROW(run(c, M), std::invalid_argument);
    c = {};
    c.tolerance_m = std::nan("");
    EXPECT_THROW(run(c, M), std::invalid_argument);
    c = {};
    c.significance = -1.0;
    EXPECT_THROW(run(c, M), std::invalid_argument);
    EXPECT_THROW(run({}, 1), std::invalid_argument);
    c = {};
    c.range_band_cycles = 1.5;
    EXPECT_THROW(run(c, M), std::invalid_argument);
    c = {};
    c.gcp.assign(trajectory_autofocus_config::max_gcp + 1, vec3{ 800.0, 25.0, 0.0 });
    EXPECT_THROW(run(c, M), std::invalid_argument);
    // refused with a message holding text
    auto refused = [&](const trajectory_autofocus_config& cfg, const bp_grid& g,
                       const std::string& text) {
        try {
            trajectory_autofocus(pulses.data(), M, ant.data(), g, cfg, img.data());
            ADD_FAILURE() << "accepted, expected: " << text;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
    };
    c = {};
    c.gcp = { { 800.0, 25.0, 0.0 }, { 800.0, std::nan(""), 0.0 } };
    refused(c, grid(), "gcp[1] = nan must be finite");
    c = {};
    c.look_spread_rad = -0.1;
    refused(c, grid(), "look_spread_rad = -0.1");
    c = {};
    c.gcp_along_track_se_m = 1.5;
    refused(c, grid(), "gcp_along_track_se_m = 1.5 must be in [0, 1]");
    c = {};
    c.gcp_speed_se_m = -0.01;
    refused(c, grid(), "gcp_speed_se_m = -0.01 must be in [0, 1]");
    // The automatic taper band, 2 |range_centre_cycles| + 1 / K, assumes subcarriers 0..N-1:
    // a spectrum centred near 0 would get a window of about one bin (1 / 64 + 0.002 here).
    bp_grid centred = grid();
    centred.range_centre_cycles = 0.001;
    refused({}, centred, "range_centre_cycles = 0.001 gives the automatic range_band_cycles 2 "
                         "|range_centre_cycles| + 1 / K = 0.017625, below 0.25");
    c = {};
    c.range_band_cycles = 0.5; // the band given: taken as it is
    EXPECT_NO_THROW(
        trajectory_autofocus(pulses.data(), M, ant.data(), centred, c, img.data()));
    // the tests' geometry, subcarriers 0..31 of a 64-point IFFT: 2 * 31 / 128 + 1 / 64 = 0.5
    EXPECT_NO_THROW(run({}, M));
}

TEST(bp_autofocus, ground_control_points_fix_the_trend)
{
    // The navigation error's constant and linear trend over the pulses (nav_error: 0.12 /
    // -0.15 / -0.20 m and 0.05 / 0 / -0.08 m/s, besides the sway) only move the image, so
    // focus leaves them; ground control points at surveyed positions fix them. Truth: each
    // GCP's range error |a_nav - q| - |a_true - q| per pulse, its least-squares constant
    // (at the middle pulse) and slope (the along-track error's part in it too: it moves the
    // GCP in Doppler like a drift); the image against the perfectly navigated one.
    std::vector<vec3> nav(M);
    const auto tru = true_path();
    for (unsigned n = 0; n < M; ++n)
        for (int c = 0; c < 3; ++c)
            nav[n][c] = tru[n][c] + nav_error(n)[c];
    const double tm = 0.5 * (M - 1.0);
    double stt = 0.0;
    for (unsigned n = 0; n < M; ++n)
        stt += (n - tm) * (n - tm);
    struct los {
        double ux, uz, c, s;
    };
    auto truth_of = [&](const vec3& q) {
        auto range = [&](const vec3& a) {
            return std::sqrt((a[0] - q[0]) * (a[0] - q[0]) + (a[1] - q[1]) * (a[1] - q[1]) +
                             a[2] * a[2]);
        };
        los t{ (tru[M / 2][0] - q[0]) / range(tru[M / 2]), tru[M / 2][2] / range(tru[M / 2]),
               0.0, 0.0 };
        for (unsigned n = 0; n < M; ++n) {
            const double e = range(nav[n]) - range(tru[n]);
            t.c += e / M;
            t.s += e * (n - tm) / stt;
        }
        return t;
    };
    const los t0 = truth_of(TGT[0]), t1 = truth_of(TGT[1]);
    const double sigma2 = N / 10.0; // 10 dB per range-compressed sample of the first target
    const auto pulses = echo(sigma2, 41);
    std::vector<gr_complex> img1(std::size_t(M) * K), img2(img1.size()), img0(img1.size());
    trajectory_autofocus_config cfg;
    const auto r0 = trajectory_autofocus(pulses.data(), M, nav.data(), grid(), cfg, img0.data());
    EXPECT_EQ(r0.gcp_used, 0u);

    // One GCP (the first target): the trend along its line of sight.
    cfg.gcp = { { TGT[0][0], TGT[0][1], 0.0 } };
    const auto r1 = trajectory_autofocus(pulses.data(), M, nav.data(), grid(), cfg, img1.data());
    ASSERT_EQ(r1.gcp_used, 1u);
    EXPECT_FALSE(r1.gcp_two_dimensional);
    const double c1 = r1.gcp_offset_m[0] * t0.ux + r1.gcp_offset_m[2] * t0.uz;
    const double s1 = r1.gcp_drift_m[0] * t0.ux + r1.gcp_drift_m[2] * t0.uz;
    // The constant's phase part (its distance to the lattice of the phase's period 1 / cs,
    // cs = 2 / lambda + fc_r / rho) and slope within 3 standard errors (0.07 mm, 0.6 um /
    // pulse: 1 / (2 pi cs sqrt(2 SNR n)) with the target's 10 dB over n = 400 pulses); the
    // lattice point from the range peak within +-1: the peak of the Hann-tapered pulses is
    // off by -8 mm, scattering by 17 mm (20 draws), so missing by 2 periods takes an error
    // past 1.5 P = 64 mm, over 3 of that scatter (untapered, the neighbours' range sidelobes
    // pulled it by +67 mm: +2 on this draw, on 12 of the 20).
    const double half = 1.0 / (2.0 / LAM + FCR / RHO), k = std::round((c1 - t0.c) / half);
    std::printf("1 GCP: constant %.2f mm (true %.2f, lattice %+.0f), se %.3f mm; slope %.4f "
                "mm / pulse (true %.4f), se %.4f\n",
                1e3 * c1, 1e3 * t0.c, k, 1e3 * r1.gcp_offset_se_m, 1e3 * s1, 1e3 * t0.s,
                1e3 * r1.gcp_drift_se_m);
    EXPECT_NEAR(c1 - k * half, t0.c, 3.0 * r1.gcp_offset_se_m);
    EXPECT_LE(std::abs(k), 1.0);
    EXPECT_NEAR(s1, t0.s, 3.0 * r1.gcp_drift_se_m);

    // Two GCPs 1 degree apart: x and z, so also the constant across the line of sight that
    // puts 4 pi (u_i - u_1) . e / lambda on the other targets' phases.
    cfg.gcp.push_back({ TGT[1][0], TGT[1][1], 0.0 });
    const auto r2 = trajectory_autofocus(pulses.data(), M, nav.data(), grid(), cfg, img2.data());
    ASSERT_EQ(r2.gcp_used, 2u);
    EXPECT_TRUE(r2.gcp_two_dimensional);
    // At one along-track position: e_y not solved (its standard error unbounded), y left.
    EXPECT_FALSE(r2.gcp_along_track);
    EXPECT_EQ(r2.gcp_offset_m[1], 0.0);
    // Each GCP's line-of-sight constant and slope as the solution gives them: the second's
    // integer is the first's (its lambda / 2 lattice point next to the first's prediction).
    for (const los& t : { t0, t1 }) {
        const double c = r2.gcp_offset_m[0] * t.ux + r2.gcp_offset_m[2] * t.uz;
        const double s = r2.gcp_drift_m[0] * t.ux + r2.gcp_drift_m[2] * t.uz;
        std::printf("2 GCPs: constant %.2f mm (true %.2f), slope %.4f mm / pulse (true %.4f)\n",
                    1e3 * c, 1e3 * t.c, 1e3 * s, 1e3 * t.s);
        EXPECT_NEAR(c - k * half, t.c, 3.0 * r1.gcp_offset_se_m * std::sqrt(2.0));
        EXPECT_NEAR(s, t.s, 3.0 * r1.gcp_drift_se_m * std::sqrt(2.0));
    }

    // The images against the perfectly navigated one's NMSE (the reference: the noise-free
    // echo along the truth).
    const auto ref = bp_image(echo(0.0, 41), tru);
    const double perfect_db = nmse_db(bp_image(pulses, tru), ref);
    const double af_db = nmse_db(img0, ref), gcp1_db = nmse_db(img1, ref);
    const double gcp2_db = nmse_db(img2, ref);
    std::printf("NMSE: perfect navigation %.2f dB, autofocus %.2f dB, with 1 GCP %.2f dB, "
                "2 GCPs %.2f dB\n",
                perfect_db, af_db, gcp1_db, gcp2_db);
    EXPECT_GT(af_db, perfect_db + 1.0);
    EXPECT_LT(gcp2_db, perfect_db + 0.5);
    // What the range peak's integer miss (k periods, 0.028 bin here) costs: the path moved
    // on by k periods along the first GCP's line of sight, where the constant is right,
    // against the same range shift of the perfectly navigated image (the truth moved by
    // k periods along that line of sight): the miss costs what that shift costs.
    std::vector<vec3> right = r2.antenna, shifted = tru;
    for (unsigned n = 0; n < M; ++n) {
        right[n][0] += k * half * t0.ux;
        right[n][2] += k * half * t0.uz;
        shifted[n][0] -= k * half * t0.ux;
        shifted[n][2] -= k * half * t0.uz;
    }
    const double right_db = nmse_db(bp_image(pulses, right), ref);
    const double shifted_db = nmse_db(bp_image(pulses, shifted), ref);
    std::printf("the integer right: %.2f dB (missed by %+.0f: %.2f dB); the perfect image "
                "shifted by as much: %.2f dB\n",
                right_db, k, gcp2_db, shifted_db);
    EXPECT_NEAR(gcp2_db - right_db, shifted_db - perfect_db, 0.05);
}

TEST(bp_autofocus, gcp_range_peak_is_not_pulled_by_sidelobes)
{
    // On the true path, noise-free, each target alone as GCP: its range peak is where the
    // target is, so the constant's integer is 0 (|constant| below half a period P). Read
    // from the unwindowed pulses the other targets' range sidelobes pulled the peaks by
    // +65 / -204 / -141 mm (integers +2 / -5 / -3); from the Hann-tapered pulses by -2.4 /
    // +7.6 / +4.6 mm.
    const auto tru = true_path();
    const auto pulses = echo(0.0, 1);
    const double half = 1.0 / (2.0 / LAM + FCR / RHO);
    std::vector<gr_complex> img(std::size_t(M) * K);
    for (const auto& q : TGT) {
        trajectory_autofocus_config cfg;
        cfg.gcp = { { q[0], q[1], 0.0 } };
        const auto r = trajectory_autofocus(pulses.data(), M, tru.data(), grid(), cfg,
                                            img.data());
        ASSERT_EQ(r.gcp_used, 1u);
        const double c = std::hypot(r.gcp_offset_m[0], r.gcp_offset_m[2]);
        std::printf("GCP at x = %.0f m: constant %.2f mm (P = %.2f mm)\n", q[0], 1e3 * c,
                    1e3 * half);
        EXPECT_LT(c, 0.5 * half);
    }
}


TEST(bp_autofocus, gcp_takes_out_an_along_track_offset)
{
    // A constant along-track navigation error e_y moves the image by e_y along track. To a
    // point q its history is (y_a - y_q) e_y / R, linear over the aperture with the slope
    // v T e_y / R per pulse, i.e. a line-of-sight drift (to 0.4 um rms: the hyperbola's
    // higher orders): the zero-Doppler time (the azimuth peak) and the phase slope are one
    // observable, which holds e_y and the line-of-sight velocity error as e_y + R u . d / v.
    // The GCP stage's slope takes it out, and R s / (v T) is the image's along-track shift:
    // here e_y itself (no drift injected), within 3 of the kernel's standard error, which is
    // held against the Cramer-Rao bound of a linear phase's slope (over 12 draws the estimate
    // scatters by 5.0 mm against 4.4-4.7 mm), and the target's azimuth peak back where the
    // perfectly navigated image has it (docs/blocks/bp_focuser.md, "The along-track offset").
    constexpr double ey = 0.30;
    const auto tru = true_path();
    std::vector<vec3> nav = tru;
    for (auto& a : nav)
        a[1] += ey;
    const double snr = 10.0; // per range-compressed sample of the first target
    const auto pulses = echo(N / snr, 43);
    trajectory_autofocus_config cfg;
    cfg.gcp = { { TGT[0][0], TGT[0][1], 0.0 } };
    std::vector<gr_complex> img(std::size_t(M) * K);
    const auto r = trajectory_autofocus(pulses.data(), M, nav.data(), grid(), cfg, img.data());
    ASSERT_EQ(r.gcp_used, 1u);
    EXPECT_FALSE(r.gcp_along_track); // one GCP: e_y stays in the drift
    const vec3 am = tru[M / 2];
    const double dx = am[0] - TGT[0][0], dy = am[1] - TGT[0][1], rm = std::hypot(dx, dy, H);
    const double s = r.gcp_drift_m[0] * dx / rm + r.gcp_drift_m[2] * H / rm;
    const double to_y = rm / (V * T), ey_hat = s * to_y, se = r.gcp_drift_se_m * to_y;
    // Cramer-Rao for the slope of a linear phase over n pulses at SNR g per pulse: 6 / (g n
    // (n^2 - 1)) rad^2 / pulse^2, in metres by 1 / (2 pi cs); the history is read from the
    // Hann-tapered pulses, which on noise white over all K bins keep 1 / 4 of the signal's
    // power and 3 / 16 of the noise's (half the bins, Hann's mean square 3 / 8): g = 4 / 3 of
    // the echo's SNR.
    const double cs = 2.0 / LAM + FCR / RHO;
    const double crb = std::sqrt(6.0 / (4.0 / 3.0 * snr * M * (double(M) * M - 1.0))) /
                       (2.0 * M_PI * cs) * to_y;

    // The azimuth peak (parabola through ln |.| at the strongest pixel near the target).
    auto azimuth_peak = [&](const std::vector<gr_complex>& im) {
        std::size_t best = 0;
        for (std::size_t i = 0; i < im.size(); ++i)
            if (std::norm(im[i]) > std::norm(im[best]))
                best = i;
        const unsigned j = unsigned(best / K), k = unsigned(best % K);
        auto l = [&](unsigned jj) { return std::log(double(std::norm(im[jj * K + k]))); };
        const double lm = l(j - 1), l0 = l(j), lp = l(j + 1);
        return (j + 0.5 * (lm - lp) / (lm - 2.0 * l0 + lp)) * V * T;
    };
    const double y_ref = azimuth_peak(bp_image(echo(0.0, 43), tru));
    const double y_nav = azimuth_peak(bp_image(pulses, nav)), y_gcp = azimuth_peak(img);
    std::printf("along-track offset %.1f mm: GCP slope gives %.1f mm, se %.2f mm (Cramer-Rao "
                "%.2f mm); azimuth peak off by %.1f mm along the navigation, %.1f mm after\n",
                1e3 * ey, 1e3 * ey_hat, 1e3 * se, 1e3 * crb, 1e3 * (y_nav - y_ref),
                1e3 * (y_gcp - y_ref));
    // 4.14 mm; 4.38-4.71 over 12 draws with sigma^2 from the moving mean's deviation (the
    // periodogram floor's scatters by about 6 %); without the taper's 4 / 3: +15 %
    EXPECT_NEAR(se, crb, 0.1 * crb);
    EXPECT_NEAR(ey_hat, ey, 3.0 * se);
    EXPECT_NEAR(y_nav - y_ref, ey, 3.0 * crb);
    EXPECT_NEAR(y_gcp - y_ref, 0.0, 3.0 * crb);
}

TEST(bp_autofocus, gcps_spread_along_track_solve_the_along_track_offset)
{
    // Each GCP's constant holds u_y e_y, u_y = (y_a - y_q) / R at the middle pulse: GCPs
    // spread along track tell e_y apart from x and z. Three GCPs (look angles 1 degree apart,
    // each alone in its range bins), the middle one 25 m along track from the outer two, so
    // u_y's pattern is not a linear function of the look angle that x and z would absorb.
    // Navigation = truth + e_y along track, then also + an (x, z) offset and drift. The
    // kernel's e_y within 3 of its standard error, which is held against the Cramer-Rao-type
    // one computed here: (G^-1)_yy of G = sum u u^T / var_c over the GCPs, var_c = 1 / ((2 pi
    // cs)^2 2 g n) the constant's (mean phase of n pulses at SNR g per pulse; g = 4 / 3 of
    // the echo's, the Hann-tapered history, as in gcp_takes_out_an_along_track_offset).
    const std::vector<vec3>& tg = SPREAD;
    constexpr double ey = 0.30, snr = 10.0;
    const auto pulses = echo(N / snr, 47, tg);
    const auto tru = true_path();
    const double cs = 2.0 / LAM + FCR / RHO;
    const double crb = crb_y(tg, snr, M);
    trajectory_autofocus_config cfg;
    for (const auto& q : tg)
        cfg.gcp.push_back({ q[0], q[1], 0.0 });
    const double half = 1.0 / cs;
    std::vector<gr_complex> img(std::size_t(M) * K);
    const auto ref = bp_image(echo(0.0, 47, tg), tru);
    const double perfect_db = nmse_db(bp_image(pulses, tru), ref);
    for (const bool drift : { false, true }) {
        std::vector<vec3> nav = tru;
        for (unsigned n = 0; n < M; ++n) {
            const double t = (n - 0.5 * (M - 1.0)) * T; // 0 at the middle pulse
            nav[n][0] += drift ? 0.12 + 0.05 * t : 0.0;
            nav[n][1] += ey;
            nav[n][2] += drift ? -0.20 - 0.08 * t : 0.0;
        }
        const auto r =
            trajectory_autofocus(pulses.data(), M, nav.data(), grid(), cfg, img.data());
        ASSERT_EQ(r.gcp_used, 3u);
        ASSERT_TRUE(r.gcp_along_track);
        EXPECT_TRUE(r.gcp_two_dimensional);
        std::printf("%s: e_y %.1f mm (true %.1f), se %.2f mm (Cramer-Rao %.2f mm); offset "
                    "(%.1f, %.1f) mm, se %.2f mm; drift (%.4f, %.4f) mm / pulse, se %.4f\n",
                    drift ? "with drift" : "e_y alone", 1e3 * r.gcp_offset_m[1], 1e3 * ey,
                    1e3 * r.gcp_offset_y_se_m, 1e3 * crb, 1e3 * r.gcp_offset_m[0],
                    1e3 * r.gcp_offset_m[2], 1e3 * r.gcp_offset_se_m, 1e3 * r.gcp_drift_m[0],
                    1e3 * r.gcp_drift_m[2], 1e3 * r.gcp_drift_se_m);
        EXPECT_NEAR(r.gcp_offset_y_se_m, crb, 0.1 * crb);
        EXPECT_NEAR(r.gcp_offset_m[1], ey, 3.0 * r.gcp_offset_y_se_m);
        // (the speed gate is open too: d_y, 0 here, solved and taken off with its noise)
        EXPECT_NEAR(r.antenna[M / 2][1],
                    tru[M / 2][1] + ey - r.gcp_offset_m[1] - 0.5 * r.gcp_drift_m[1], 1e-9);
        // (x, z): the drift within 3 standard errors (rms of x, z); the offset less the
        // integer k of periods along the GCPs' mean line of sight (|k| <= 1, "The integer").
        const double dx = drift ? 0.05 * T : 0.0, dz = drift ? -0.08 * T : 0.0;
        EXPECT_LT(std::hypot(r.gcp_drift_m[0] - dx, r.gcp_drift_m[2] - dz),
                  3.0 * r.gcp_drift_se_m);
        const double ox = r.gcp_offset_m[0] - (drift ? 0.12 : 0.0);
        const double oz = r.gcp_offset_m[2] - (drift ? -0.20 : 0.0);
        const auto m = mean_los(); // TGT's look angles are tg's
        const double k = std::round((ox * m[0] + oz * m[1]) / half);
        EXPECT_LE(std::abs(k), 1.0);
        EXPECT_LT(std::hypot(ox - k * half * m[0], oz - k * half * m[1]),
                  3.0 * r.gcp_offset_se_m);
        // The image against the perfectly navigated one's NMSE; and with e_y left in the
        // drift (gate closed) for comparison.
        trajectory_autofocus_config closed = cfg;
        closed.gcp_along_track_se_m = 0.0;
        std::vector<gr_complex> img0(img.size());
        const auto r0 =
            trajectory_autofocus(pulses.data(), M, nav.data(), grid(), closed, img0.data());
        EXPECT_FALSE(r0.gcp_along_track);
        EXPECT_EQ(r0.gcp_offset_m[1], 0.0);
        const double got_db = nmse_db(img, ref), closed_db = nmse_db(img0, ref);
        std::printf("NMSE: perfect navigation %.2f dB, e_y solved %.2f dB, left in the "
                    "drift %.2f dB\n",
                    perfect_db, got_db, closed_db);
        EXPECT_LT(got_db, perfect_db + 0.5);
    }
}

TEST(bp_autofocus, gcps_spread_along_track_solve_the_along_track_speed)
{
    // Each GCP's slope holds u_y d_y as its constant u_y e_y (d_y the along-track speed
    // error per pulse): the GCPs of gcps_spread_along_track_solve_the_along_track_offset
    // solve it as a fourth unknown. Navigation = truth + (x, z) offset and drift + e_y +
    // d_y (t - t_mid). The kernel's d_y within 3 of its standard error, held against the
    // Cramer-Rao-type one computed here as e_y's: (G^-1)_yy of G = sum u u^T / var_s,
    // var_s = 1 / ((2 pi cs)^2 2 g sum (n - n_mid)^2) the slope's (a linear phase over n
    // pulses at SNR g per pulse, g = 4 / 3 of the echo's). The image against the perfectly
    // navigated one: with d_y solved, and with the speed gate shut (d_y left: the image
    // stretched by d_y / v); shut, every output is the one before d_y was an unknown (the
    // y path is nav - e_y: no trend).
    const std::vector<vec3>& tg = SPREAD;
    constexpr double ey = 0.30, dy = 0.10, snr = 10.0; // dy [m/s]: a GNSS class's
    const auto pulses = echo(N / snr, 47, tg);
    const auto tru = true_path();
    const double cs = 2.0 / LAM + FCR / RHO, tm = 0.5 * (M - 1.0);
    double stt = 0.0;
    for (unsigned n = 0; n < M; ++n)
        stt += (n - tm) * (n - tm);
    const double crb = crb_y(tg, snr, stt) / T; // [m/s]
    const std::vector<vec3> nav = nav_with_speed_error(ey, dy);
    trajectory_autofocus_config cfg;
    for (const auto& q : tg)
        cfg.gcp.push_back({ q[0], q[1], 0.0 });
    std::vector<gr_complex> img(std::size_t(M) * K), img0(img.size());
    const auto r = trajectory_autofocus(pulses.data(), M, nav.data(), grid(), cfg, img.data());
    ASSERT_EQ(r.gcp_used, 3u);
    ASSERT_TRUE(r.gcp_along_track);
    ASSERT_TRUE(r.gcp_along_track_speed);
    const double dy_hat = r.gcp_drift_m[1] / T, se = r.gcp_drift_y_se_m / T;
    std::printf("d_y %.2f mm/s (true %.2f), se %.2f mm/s (Cramer-Rao %.2f mm/s, n se %.1f mm); "
                "e_y %.1f mm (true %.1f), se %.2f mm; drift (%.2f, %.2f) mm/s (true (50, -80)), "
                "se %.2f mm/s\n",
                1e3 * dy_hat, 1e3 * dy, 1e3 * se, 1e3 * crb, 1e3 * M * r.gcp_drift_y_se_m,
                1e3 * r.gcp_offset_m[1], 1e3 * ey, 1e3 * r.gcp_offset_y_se_m,
                1e3 * r.gcp_drift_m[0] / T, 1e3 * r.gcp_drift_m[2] / T,
                1e3 * r.gcp_drift_se_m / T);
    EXPECT_NEAR(se, crb, 0.1 * crb);
    EXPECT_NEAR(dy_hat, dy, 3.0 * se);
    EXPECT_NEAR(r.gcp_offset_m[1], ey, 3.0 * r.gcp_offset_y_se_m);
    EXPECT_LT(std::hypot(r.gcp_drift_m[0] - 0.05 * T, r.gcp_drift_m[2] + 0.08 * T),
              3.0 * r.gcp_drift_se_m);
    // the path's y: nav less e_y and d_y's trend, bit for bit
    for (unsigned n = 0; n < M; n += M - 1)
        EXPECT_EQ(r.antenna[n][1], nav[n][1] - (r.gcp_offset_m[1] + r.gcp_drift_m[1] * (n - tm)));

    trajectory_autofocus_config shut = cfg;
    shut.gcp_speed_se_m = 0.0;
    const auto r0 = trajectory_autofocus(pulses.data(), M, nav.data(), grid(), shut, img0.data());
    EXPECT_FALSE(r0.gcp_along_track_speed);
    EXPECT_EQ(r0.gcp_drift_m[1], 0.0);
    EXPECT_EQ(r0.gcp_drift_y_se_m, 0.0);
    EXPECT_EQ(r0.gcp_offset_m[1], r.gcp_offset_m[1]); // e_y from the constants alone
    for (unsigned n = 0; n < M; ++n)
        ASSERT_EQ(r0.antenna[n][1], nav[n][1] - r0.gcp_offset_m[1]);
    // d_y only with e_y (e_y left in the slopes would bias it by about 10 mm/s here)
    trajectory_autofocus_config no_ey = cfg;
    no_ey.gcp_along_track_se_m = 0.0;
    std::vector<gr_complex> img1(img.size());
    const auto r1 = trajectory_autofocus(pulses.data(), M, nav.data(), grid(), no_ey, img1.data());
    EXPECT_FALSE(r1.gcp_along_track_speed);
    EXPECT_EQ(r1.gcp_drift_m[1], 0.0);
    // The images against the perfectly navigated one, same noise (error energy over its
    // energy, one complex scale fitted): what the navigation left, not the noise.
    const auto perfect = bp_image(pulses, tru);
    auto rel_db = [&](const std::vector<gr_complex>& im) {
        cd num(0.0, 0.0);
        double den = 0.0;
        for (std::size_t i = 0; i < im.size(); ++i) {
            num += std::conj(cd(perfect[i])) * cd(im[i]);
            den += std::norm(cd(perfect[i]));
        }
        double e = 0.0;
        for (std::size_t i = 0; i < im.size(); ++i)
            e += std::norm(cd(im[i]) - num / den * cd(perfect[i]));
        return 10.0 * std::log10(e / den);
    };
    // The GCPs' constant may miss its lambda / 2 integer (k periods along their mean line
    // of sight, |k| <= 1; ground_control_points_fix_the_trend): a range shift the path
    // moved on by k periods takes out, so that what the along-track error leaves shows.
    const auto m = mean_los();
    const double k = std::round(((r.gcp_offset_m[0] - 0.12) * m[0] +
                                 (r.gcp_offset_m[2] + 0.20) * m[1]) * cs);
    EXPECT_LE(std::abs(k), 1.0);
    auto right_db = [&](std::vector<vec3> path) {
        for (auto& v : path) {
            v[0] += k / cs * m[0];
            v[2] += k / cs * m[1];
        }
        return rel_db(bp_image(pulses, path));
    };
    const double got_db = rel_db(img), shut_db = rel_db(img0);
    const double got_k_db = right_db(r.antenna), shut_k_db = right_db(r0.antenna);
    std::printf("against the perfectly navigated image: d_y solved %.2f dB, left %.2f dB; the "
                "integer (%+.0f) right: %.2f / %.2f dB\n",
                got_db, shut_db, k, got_k_db, shut_k_db);
    EXPECT_LT(got_db, shut_db);
    EXPECT_LT(got_k_db, shut_k_db - 3.0);
}



TEST(bp_autofocus, gcp_standard_errors_are_the_scatter_over_draws)
{
    // The GCP solve's standard errors against its estimates' scatter over D noise draws (the
    // echo's noise-free part once, a fresh draw added each time), the navigation of
    // gcps_spread_along_track_solve_the_along_track_speed, 10 dB: e_y, d_y and the (x, z)
    // drift, for SPREAD (each GCP alone in its range bins) and for two GCPs in one range bin
    // 25 m apart along track (each one's history carries the other's echo, a line at 0.07
    // cycles a pulse, which the deviation from the moving mean counted as noise: e_y's se 5.7
    // times its scatter, d_y's gate shut). Per quantity, the deviations from the mean over
    // the draws in units of each draw's se: their rms is 1 where the se is right, with a
    // relative scatter of 1 / sqrt(2 dof), dof = D - 1 (the drift's x and z, whose se is
    // sqrt(var x + var z), err together along d_y's fit: no more); asserted within 3 of that.
    // The one-bin pair over 192 draws (1 +- 0.153): with the floor read after its neighbours'
    // echoes were taken out (with the noise within 1 / L of their line) e_y 1.18 (failed),
    // d_y 1.12, the drift 1.11 (docs/blocks/bp_focuser.md, "The noise floor of a GCP with
    // neighbours").
    constexpr double snr = 10.0;
    const std::vector<vec3> nav = nav_with_speed_error(0.30, 0.10);
    const std::vector<vec3> one_bin = { { 800.0, 12.53, 1.0 }, { 800.0, 37.53, 1.0 } };
    std::vector<gr_complex> img(std::size_t(M) * K);
    for (const auto* tg : { &SPREAD, &one_bin }) {
        const unsigned D = tg == &SPREAD ? 32 : 192, seed0 = tg == &SPREAD ? 200 : 5000;
        const auto clean = echo(0.0, 1, *tg);
        trajectory_autofocus_config cfg;
        for (const auto& q : *tg)
            cfg.gcp.push_back({ q[0], q[1], 0.0 });
        struct draw {
            double ey, dy, dx, dz, ey_se, dy_se, drift_se;
        };
        std::vector<draw> dr;
        for (unsigned d = 0; d < D; ++d) {
            std::mt19937 rng(seed0 + d);
            std::normal_distribution<double> gauss(0.0, std::sqrt(N / snr / 2.0));
            auto pulses = clean;
            for (auto& v : pulses)
                v += gr_complex(float(gauss(rng)), float(gauss(rng)));
            const auto r =
                trajectory_autofocus(pulses.data(), M, nav.data(), grid(), cfg, img.data());
            ASSERT_EQ(r.gcp_used, tg->size());
            ASSERT_TRUE(r.gcp_along_track_speed);
            dr.push_back({ r.gcp_offset_m[1], r.gcp_drift_m[1], r.gcp_drift_m[0],
                           r.gcp_drift_m[2], r.gcp_offset_y_se_m, r.gcp_drift_y_se_m,
                           r.gcp_drift_se_m });
        }
        draw mean{};
        for (const draw& d : dr) {
            mean.ey += d.ey / D;
            mean.dy += d.dy / D;
            mean.dx += d.dx / D;
            mean.dz += d.dz / D;
        }
        double zy = 0.0, zd = 0.0, zxz = 0.0, sy = 0.0, sd = 0.0, sy2 = 0.0, sd2 = 0.0;
        for (const draw& d : dr) {
            zy += std::pow((d.ey - mean.ey) / d.ey_se, 2) / (D - 1);
            zd += std::pow((d.dy - mean.dy) / d.dy_se, 2) / (D - 1);
            zxz += (std::pow(d.dx - mean.dx, 2) + std::pow(d.dz - mean.dz, 2)) /
                   std::pow(d.drift_se, 2) / (D - 1);
            sy += std::pow(d.ey - mean.ey, 2) / (D - 1);
            sd += std::pow(d.dy - mean.dy, 2) / (D - 1);
            sy2 += d.ey_se * d.ey_se / D;
            sd2 += d.dy_se * d.dy_se / D;
        }
        const double bound = 3.0 / std::sqrt(2.0 * (D - 1));
        std::printf("%s, %u draws: e_y %.1f mm, scatter %.2f mm, se %.2f mm (rms); d_y %.1f "
                    "mm/s, scatter %.2f mm/s, se %.2f mm/s; rms deviation / se: e_y %.3f, d_y "
                    "%.3f, drift (x, z) %.3f (bound 1 +- %.3f)\n",
                    tg == &SPREAD ? "GCPs spread" : "two GCPs in one range bin", D,
                    1e3 * mean.ey, 1e3 * std::sqrt(sy), 1e3 * std::sqrt(sy2),
                    1e3 * mean.dy / T, 1e3 * std::sqrt(sd) / T, 1e3 * std::sqrt(sd2) / T,
                    std::sqrt(zy), std::sqrt(zd), std::sqrt(zxz), bound);
        EXPECT_NEAR(std::sqrt(zy), 1.0, bound);
        EXPECT_NEAR(std::sqrt(zd), 1.0, bound);
        EXPECT_NEAR(std::sqrt(zxz), 1.0, bound);
    }
}

TEST(bp_autofocus, gcp_neighbours_echoes_are_taken_out)
{
    // GCPs within the Hann-tapered main lobe hold each other's echoes in their histories, a
    // beat at their along-track separation that biased d_y: two GCPs in one range bin 25 m
    // apart along track, and three at slant R0, R0 + D, R0 + 2 D, y 12.53 / 37.53 / 12.53 m:
    // nrsar-sim's layout, D its 1.7 bins in units of the main lobe's half-width 2 / band
    // (band 0.81 there: 0.69; here 0.5, D = 2.75 bins). Noise-free, navigation = truth +
    // (x, z) offset and drift + e_y + d_y (t - t_mid), and perfect: d_y and e_y against the
    // injected ones. Before the neighbours were modelled: d_y +18.4 / +7.5 mm/s off, with
    // perfect navigation +7.6 mm/s (the GCPs alone in their bins, SPREAD: -0.23 mm/s).
    constexpr double ey = 0.30, dy = 0.10; // [m], [m/s]
    const auto tru = true_path();
    const std::vector<vec3> nav = nav_with_speed_error(ey, dy);
    auto ground = [](double slant) { return std::sqrt(slant * slant - H * H); };
    constexpr double D = 2.75 * RHO;
    const std::vector<vec3> one_bin = { { 800.0, 12.53, 1.0 }, { 800.0, 37.53, 1.0 } };
    const std::vector<vec3> sim_like = { { ground(1000.0), 12.53, 1.0 },
                                         { ground(1000.0 + D), 37.53, 1.0 },
                                         { ground(1000.0 + 2.0 * D), 12.53, 1.0 } };
    std::vector<gr_complex> img(std::size_t(M) * K);
    struct layout {
        const char* name;
        const std::vector<vec3>* tg;
        const std::vector<vec3>* path;
        double dy, ey;
    };
    for (const layout& c : { layout{ "two GCPs in one range bin", &one_bin, &nav, dy, ey },
                             layout{ "nrsar-sim's layout", &sim_like, &nav, dy, ey },
                             layout{ "nrsar-sim's layout, perfect navigation", &sim_like, &tru,
                                     0.0, 0.0 } }) {
        const auto pulses = echo(0.0, 1, *c.tg);
        trajectory_autofocus_config cfg;
        for (const auto& q : *c.tg)
            cfg.gcp.push_back({ q[0], q[1], 0.0 });
        const auto r =
            trajectory_autofocus(pulses.data(), M, c.path->data(), grid(), cfg, img.data());
        ASSERT_EQ(r.gcp_used, c.tg->size());
        ASSERT_TRUE(r.gcp_along_track_speed);
        const double dy_hat = r.gcp_drift_m[1] / T;
        std::printf("%s, noise-free: d_y %.3f mm/s (true %.1f, se %.3f), e_y %.3f mm (true "
                    "%.1f, se %.4f)\n",
                    c.name, 1e3 * dy_hat, 1e3 * c.dy, 1e3 * r.gcp_drift_y_se_m / T,
                    1e3 * r.gcp_offset_m[1], 1e3 * c.ey, 1e3 * r.gcp_offset_y_se_m);
        EXPECT_NEAR(dy_hat, c.dy, 0.3e-3);
        EXPECT_NEAR(r.gcp_offset_m[1], c.ey, 0.7e-3);
    }
}

TEST(bp_autofocus, gcp_neighbours_in_a_cut_profile)
{
    // nrsar-sim's GCPs (docs/blocks/bp_focuser.md, "The neighbours' echoes modelled"): its
    // K bins cut from a longer range IFFT (here 64 of 512, 256 subcarriers: the profile is
    // not K-periodic), the GCPs 3.4 bins apart (nrsar-sim's 1.7 at twice the band), and its
    // presummer's first two outputs at 0.62 and 0.95 of the echo. Noise-free, perfect
    // navigation and the d_y test's: d_y and e_y against the injected ones, and with perfect
    // navigation the (x, z) drift against 0. Before (the outer pair's sidelobes, 6.8 bins
    // apart, unmodelled, the point response K-periodic, the window's leak taken off the weak
    // first pulses, no line-of-sight turn of x over the window): perfect navigation d_y
    // +0.257 mm/s, e_y -0.060 mm, drift x / z +1.91 / +2.57 mm/s; now -0.038, +0.008,
    // +0.045 / +0.060.
    constexpr unsigned sub = 256, fft = 512;
    constexpr double ey = 0.30, dy = 0.10;
    const auto tru = true_path();
    const std::vector<vec3> nav = nav_with_speed_error(ey, dy);
    auto ground = [](double slant) { return std::sqrt(slant * slant - H * H); };
    constexpr double D = 3.4 * RHO;
    const std::vector<vec3> tg = { { ground(1000.0), 12.53, 1.0 },
                                   { ground(1000.0 + D), 37.53, 1.0 },
                                   { ground(1000.0 + 2.0 * D), 12.53, 1.0 } };
    auto pulses = echo(0.0, 1, tg, H, sub, fft);
    for (unsigned k = 0; k < K; ++k) {
        pulses[k] *= 0.62f;
        pulses[K + k] *= 0.95f;
    }
    bp_grid g = grid();
    g.range_centre_cycles = (sub - 1) / (2.0 * fft);
    std::vector<gr_complex> img(std::size_t(M) * K);
    for (const auto* path : { &tru, &nav }) {
        const double dy_true = path == &nav ? dy : 0.0, ey_true = path == &nav ? ey : 0.0;
        trajectory_autofocus_config cfg;
        for (const auto& q : tg)
            cfg.gcp.push_back({ q[0], q[1], 0.0 });
        const auto r = trajectory_autofocus(pulses.data(), M, path->data(), g, cfg, img.data());
        ASSERT_EQ(r.gcp_used, tg.size());
        ASSERT_TRUE(r.gcp_along_track_speed);
        const double dy_hat = r.gcp_drift_m[1] / T;
        std::printf("cut profile, %s: d_y %.3f mm/s (true %.1f), e_y %.3f mm (true %.1f), "
                    "drift x %.3f z %.3f mm/s\n",
                    path == &nav ? "navigation error" : "perfect navigation", 1e3 * dy_hat,
                    1e3 * dy_true, 1e3 * r.gcp_offset_m[1], 1e3 * ey_true,
                    1e3 * r.gcp_drift_m[0] / T, 1e3 * r.gcp_drift_m[2] / T);
        EXPECT_NEAR(dy_hat, dy_true, path == &nav ? 0.3e-3 : 0.1e-3);
        EXPECT_NEAR(r.gcp_offset_m[1], ey_true, path == &nav ? 0.7e-3 : 0.03e-3);
        if (path == &tru) {
            EXPECT_NEAR(r.gcp_drift_m[0] / T, 0.0, 0.2e-3);
            EXPECT_NEAR(r.gcp_drift_m[2] / T, 0.0, 0.2e-3);
        }
    }
}
