/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Kernel tests of autofocus and of the extended-scene image metrics. The images are built
// here in double precision from their definition (explicit DFT sums, not FFTW): a few
// point targets whose azimuth spectra occupy a band of Doppler bins that wraps across DFT
// bin 0, defocused by a known phase error; every expected value comes from that model.

#include <gnuradio/nrsar/kernel/autofocus.h>
#include <gnuradio/nrsar/kernel/image_metrics.h>
#include "test_util.h"
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <functional>
#include <random>
#include <vector>

using namespace gr::nrsar;
using cd = std::complex<double>;

namespace {
constexpr double pi = 3.14159265358979323846;
constexpr std::size_t M = 256, K = 16, B = 128; // lines, range bins, band (Doppler bins)
constexpr long band_centre = 20;                // band = bins 20 - 64 .. 20 + 63 (wraps)

struct target {
    double line;
    std::size_t bin;
    double amp;
};
const std::vector<target> scatterers = { { 100.0, 5, 1.0 }, { 180.0, 9, 0.7 }, { 40.0, 12, 0.5 } };

// Centred band coordinate u in [-1/2, 1/2) of DFT bin p, or NaN outside the band.
double band_u(std::size_t p)
{
    const long d = ((static_cast<long>(p) - band_centre + 3 * static_cast<long>(M) / 2) %
                    static_cast<long>(M)) -
                   static_cast<long>(M) / 2;
    return (d >= -static_cast<long>(B) / 2 && d < static_cast<long>(B) / 2)
               ? static_cast<double>(d) / B
               : std::nan("");
}

// Image (lines x bins, row-major) of the scatterers, moved by `shift` lines, with
// exp(j phi(p)) on their spectra and complex Gaussian noise of power noise_power per
// pixel: the unitary inverse DFT written out,
// g(m, k) = M^-1/2 sum_p G(p, k) exp(j phi(p)) exp(j 2 pi p m / M),
// G(p, k) = amp exp(-j 2 pi f (line + shift) / M) on the band of the target's range bin,
// f the alias of p nearest the band centre (a fractional shift is a band-limited one).
std::vector<gr_complex>
make_image(const std::vector<double>& phi, double noise_power, unsigned seed, double shift = 0.0)
{
    std::vector<cd> img(M * K, cd(0.0, 0.0));
    for (const auto& t : scatterers)
        for (std::size_t p = 0; p < M; ++p) {
            if (std::isnan(band_u(p)))
                continue;
            const double f = band_centre + band_u(p) * B;
            const cd G = t.amp * std::polar(1.0, -2.0 * pi * f * (t.line + shift) / M + phi[p]);
            for (std::size_t m = 0; m < M; ++m)
                img[m * K + t.bin] += G * std::polar(1.0 / std::sqrt(double(M)), 2.0 * pi * double(p * m % M) / M);
        }
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, std::sqrt(noise_power / 2.0));
    const auto draw = [&] { return noise_power > 0.0 ? g(rng) : 0.0; };
    std::vector<gr_complex> out(M * K);
    for (std::size_t i = 0; i < M * K; ++i) {
        const double re = img[i].real() + draw();
        out[i] = gr_complex(static_cast<float>(re), static_cast<float>(img[i].imag() + draw()));
    }
    return out;
}

std::vector<double> phase_of(const std::function<double(double)>& f)
{
    std::vector<double> phi(M, 0.0);
    for (std::size_t p = 0; p < M; ++p)
        if (!std::isnan(band_u(p)))
            phi[p] = f(band_u(p));
    return phi;
}

// rms over the band of (estimate - truth) after the least-squares constant and linear
// terms in u (which autofocus cannot see) are removed, in double.
double residual_rms(const std::vector<double>& est, const std::vector<double>& truth)
{
    double s0 = 0, s1 = 0, s2 = 0, t0 = 0, t1 = 0;
    for (std::size_t p = 0; p < M; ++p) {
        const double u = band_u(p);
        if (std::isnan(u))
            continue;
        const double e = est[p] - truth[p];
        s0 += 1;
        s1 += u;
        s2 += u * u;
        t0 += e;
        t1 += u * e;
    }
    const double det = s0 * s2 - s1 * s1;
    const double a = (s2 * t0 - s1 * t1) / det, b = (s0 * t1 - s1 * t0) / det;
    double acc = 0.0;
    for (std::size_t p = 0; p < M; ++p) {
        const double u = band_u(p);
        if (!std::isnan(u)) {
            const double r = est[p] - truth[p] - a - b * u;
            acc += r * r;
        }
    }
    return std::sqrt(acc / s0);
}

// Band-limited interpolation of the azimuth cut of range bin `bin`, 16 points per line
// over the whole cut: the cut's DFT written out, evaluated at fractional lines with each
// bin at its alias nearest the band centre. Returns |g(x)|^2.
std::vector<double> fine_cut(const std::vector<gr_complex>& img, std::size_t bin)
{
    constexpr int up = 16;
    std::vector<cd> c(M);
    for (std::size_t p = 0; p < M; ++p)
        for (std::size_t m = 0; m < M; ++m)
            c[p] += cd(img[m * K + bin]) * std::polar(1.0, -2.0 * pi * double(p * m % M) / M);
    // exp(j 2 pi alias x / M) with x = i / up: a table over (alias i) mod (M up).
    std::vector<cd> w(M * up);
    for (std::size_t j = 0; j < M * up; ++j)
        w[j] = std::polar(1.0, 2.0 * pi * double(j) / double(M * up));
    std::vector<double> out(M * up);
    for (std::size_t i = 0; i < M * up; ++i) {
        cd acc(0.0, 0.0);
        for (std::size_t p = 0; p < M; ++p) {
            const long a = long(p) - band_centre;
            const long alias = ((a + 3 * long(M) / 2) % long(M)) - long(M) / 2 + band_centre;
            const long n = long(M * up);
            acc += c[p] * w[static_cast<std::size_t>(((alias * long(i)) % n + n) % n)];
        }
        out[i] = std::norm(acc / double(M));
    }
    return out;
}

// Interpolated peak power and half-power width [lines] of that cut.
std::pair<double, double> peak_irw(const std::vector<gr_complex>& img, std::size_t bin)
{
    const auto f = fine_cut(img, bin);
    const long n = long(f.size());
    const long at = long(std::max_element(f.begin(), f.end()) - f.begin());
    const double best = f[at];
    double w = 0.0;
    for (int dir : { -1, 1 }) {
        long i = at;
        while (f[((i + dir) % n + n) % n] > best / 2)
            i += dir;
        const double a = f[((i % n) + n) % n], b = f[(((i + dir) % n) + n) % n];
        w += std::abs(i - at) + (a - best / 2) / (a - b);
    }
    return { best, w / 16.0 };
}

// Phase noise bound: the estimate's error at one Doppler bin is about the phase noise of
// the strongest scatterer's spectrum there, 1 / sqrt(2 SNR_bin), SNR_bin = amp^2 / noise
// power per bin (the unitary DFT keeps the per-pixel noise power); three times that.
double phase_tolerance(double noise_power) { return 3.0 / std::sqrt(2.0 / noise_power); }

struct case_result {
    double residual_rms, peak_ratio, irw_ratio, entropy_focused, entropy_before, entropy_after;
};

case_result run_case(const autofocus_config& cfg, const std::vector<double>& truth, double noise_power)
{
    const auto focused = make_image(std::vector<double>(M, 0.0), noise_power, 7);
    auto img = make_image(truth, noise_power, 7);
    kernel::autofocus af(cfg);
    const auto r = af.focus(img.data(), M, K);
    EXPECT_EQ(r.phase_rad.size(), M);
    case_result c;
    c.residual_rms = residual_rms(r.phase_rad, truth);
    const auto pf = peak_irw(focused, 5), pc = peak_irw(img, 5);
    c.peak_ratio = pc.first / pf.first;
    c.irw_ratio = pc.second / pf.second;
    c.entropy_focused = kernel::image_entropy(focused.data(), M * K);
    c.entropy_before = r.entropy_before;
    c.entropy_after = r.entropy_after;
    return c;
}

autofocus_config config_of(autofocus_method m, unsigned order = 0)
{
    autofocus_config c;
    c.method = m;
    c.entropy_order = order;
    c.max_iterations = 100;
    return c;
}

const double noise = 0.01; // SNR_bin 20 dB for the strongest scatterer

void expect_refocused(const case_result& c, double tol)
{
    EXPECT_LT(c.residual_rms, tol);
    // A residual error of rms e keeps exp(-e^2) of the peak power (the Strehl ratio,
    // e = tol: 0.956); the width within 5 % of the focused image's (both interpolated);
    // the entropy falls, and at least 90 % of what the error added is taken back.
    EXPECT_GT(c.peak_ratio, std::exp(-tol * tol) - 0.03);
    EXPECT_LT(c.peak_ratio, 1.05);
    EXPECT_NEAR(c.irw_ratio, 1.0, 0.05);
    EXPECT_LT(c.entropy_after, c.entropy_before);
    EXPECT_LT(c.entropy_after - c.entropy_focused, 0.1 * (c.entropy_before - c.entropy_focused));
}
} // namespace

TEST(Autofocus, PgaQuadratic)
{
    // 4 pi at the band edges: the image defocuses over ~ 8 resolution cells.
    const auto truth = phase_of([](double u) { return 16.0 * pi * u * u; });
    const auto c = run_case(config_of(autofocus_method::PGA), truth, noise);
    expect_refocused(c, phase_tolerance(noise));
}

TEST(Autofocus, PgaSinusoidal)
{
    const auto truth = phase_of([](double u) { return 2.5 * std::sin(2.0 * pi * 3.0 * u + 0.5); });
    const auto c = run_case(config_of(autofocus_method::PGA), truth, noise);
    expect_refocused(c, phase_tolerance(noise));
}

TEST(Autofocus, PgaRandomLowPass)
{
    // Gaussian noise through a 9-bin moving average, scaled to 2 rad rms.
    std::mt19937 rng(3);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<double> w(B + 8), lp(B);
    for (auto& v : w)
        v = g(rng);
    double ms = 0.0;
    for (std::size_t i = 0; i < B; ++i) {
        for (std::size_t j = 0; j < 9; ++j)
            lp[i] += w[i + j] / 9.0;
        ms += lp[i] * lp[i] / B;
    }
    const auto truth = phase_of([&](double u) {
        return 2.0 / std::sqrt(ms) * lp[static_cast<std::size_t>(std::lround((u + 0.5) * B)) % B];
    });
    const auto c = run_case(config_of(autofocus_method::PGA), truth, noise);
    expect_refocused(c, phase_tolerance(noise));
}

TEST(Autofocus, PgaEstimateDoesNotDependOnTheSubLinePosition)
{
    // The noise-free image moved by a fraction of a line (a linear phase over the band,
    // which autofocus cannot see) must give the same estimate: measured 0.043 / 0.042 /
    // 0.003 rad rms at 0.25 / 0.5 / 0.75 lines; 0.108 / 0.060 / 0.179 rad with the window's
    // hard edges at whole lines around the brightest line (docs/blocks/autofocus.md,
    // "Sub-line position"). Each estimate within the noisy cases' bound of the truth
    // (measured 0.050 rad).
    const auto truth = phase_of([](double u) { return 2.5 * std::sin(2.0 * pi * 3.0 * u + 0.5); });
    const auto estimate = [&](double shift) {
        auto img = make_image(truth, 0.0, 7, shift);
        kernel::autofocus af(config_of(autofocus_method::PGA));
        return af.focus(img.data(), M, K).phase_rad;
    };
    const auto ref = estimate(0.0);
    EXPECT_LT(residual_rms(ref, truth), phase_tolerance(noise));
    for (double s : { 0.25, 0.5, 0.75 })
        EXPECT_LT(residual_rms(estimate(s), ref), 0.05) << "shift " << s << " lines";
}

TEST(Autofocus, EntropyQuadraticPolynomial)
{
    const auto truth = phase_of([](double u) { return 16.0 * pi * u * u; });
    const auto c = run_case(config_of(autofocus_method::ENTROPY, 2), truth, noise);
    expect_refocused(c, phase_tolerance(noise));
}

TEST(Autofocus, EntropyPerBinSinusoidal)
{
    const auto truth = phase_of([](double u) { return 2.5 * std::sin(2.0 * pi * 3.0 * u + 0.5); });
    const auto c = run_case(config_of(autofocus_method::ENTROPY), truth, noise);
    expect_refocused(c, phase_tolerance(noise));
}

TEST(Autofocus, FocusedImageStaysFocused)
{
    // No error: the estimate is noise only, and the image keeps its peak.
    const std::vector<double> truth(M, 0.0);
    for (auto m : { autofocus_method::PGA, autofocus_method::ENTROPY }) {
        const auto c = run_case(config_of(m), truth, noise);
        EXPECT_LT(c.residual_rms, phase_tolerance(noise));
        EXPECT_NEAR(c.peak_ratio, 1.0, 0.05);
    }
}

TEST(Autofocus, NonePassesThrough)
{
    auto img = make_image(phase_of([](double u) { return 10.0 * u * u; }), noise, 1);
    const auto copy = img;
    kernel::autofocus af(config_of(autofocus_method::NONE));
    const auto r = af.focus(img.data(), M, K);
    EXPECT_EQ(img, copy);
    EXPECT_EQ(r.phase_rms_rad, 0.0);
    EXPECT_EQ(r.entropy_before, r.entropy_after);
}

TEST(Autofocus, RemoveLinearPhaseUnwrapsFromStart)
{
    // a + b u on bins [start, start + 8) (u = 0..7, wrapping past bin 0) plus a parabola:
    // what remains is the parabola's own residual from its least-squares line.
    const std::size_t n = 10, start = 6;
    std::vector<double> phi(n), w(n, 0.0), expect(n);
    double q[8], s = 0.0;
    for (int u = 0; u < 8; ++u)
        q[u] = (u - 3.5) * (u - 3.5) - 5.25; // mean zero over u = 0..7, odd moment zero
    for (int u = 0; u < 8; ++u) {
        const std::size_t p = (start + u) % n;
        phi[p] = 1.5 - 0.3 * u + q[u];
        w[p] = 1.0;
        expect[p] = q[u];
        s += q[u];
    }
    EXPECT_NEAR(s, 0.0, 1e-12);
    kernel::remove_linear_phase(phi.data(), w.data(), n, start);
    for (int u = 0; u < 8; ++u)
        EXPECT_NEAR(phi[(start + u) % n], expect[(start + u) % n], 1e-12);
}

TEST(Autofocus, RefusesBadConfig)
{
    using nrsar_test::error_of;
    auto c = config_of(autofocus_method::PGA);
    c.max_iterations = 0;
    EXPECT_EQ(error_of([&] { kernel::autofocus a(c); }), "max_iterations = 0 must be in [1, 1000]");
    c = config_of(autofocus_method::ENTROPY, 1);
    EXPECT_EQ(error_of([&] { kernel::autofocus a(c); }),
              "entropy_order = 1 must be 0 (per bin) or in [2, 8]");
    c = config_of(autofocus_method::PGA);
    c.tolerance_rad = 0.0;
    EXPECT_EQ(error_of([&] { kernel::autofocus a(c); }), "tolerance_rad = 0 must be in (0, 1)");
    kernel::autofocus a(config_of(autofocus_method::PGA));
    std::vector<gr_complex> tiny(3 * 2);
    EXPECT_EQ(error_of([&] { a.focus(tiny.data(), 3, 2); }), "lines = 3 must be at least 4");
}

// ---- image metrics of the second paper (section 3.2.1), against their formulas ----

TEST(ImageMetrics, EntropyOfKnownImages)
{
    // One bright pixel: 0; n equal pixels: ln n; two pixels of powers 1 and 3: the sum.
    std::vector<gr_complex> img(64, gr_complex(0, 0));
    img[10] = gr_complex(3.0f, -4.0f);
    EXPECT_NEAR(kernel::image_entropy(img.data(), img.size()), 0.0, 1e-12);
    for (auto& v : img)
        v = gr_complex(0.0f, 2.0f);
    EXPECT_NEAR(kernel::image_entropy(img.data(), img.size()), std::log(64.0), 1e-9);
    std::vector<gr_complex> two = { gr_complex(1, 0), gr_complex(0, std::sqrt(3.0f)) };
    EXPECT_NEAR(kernel::image_entropy(two.data(), 2), -(0.25 * std::log(0.25) + 0.75 * std::log(0.75)), 1e-7);
    std::vector<gr_complex> zero(5);
    EXPECT_EQ(kernel::image_entropy(zero.data(), 5), 0.0);
}

TEST(ImageMetrics, EdgePreservationIndex)
{
    // 1 against itself and a scaled copy; against independent noise near 0 (|EPI| below
    // 4 / sqrt(pixels)); the Laplacian written out in double for a defocused copy.
    const std::size_t L = 40, N = 30;
    auto x = nrsar_test::gaussian_samples(L * N, 1);
    auto y = x;
    for (auto& v : y)
        v *= 2.5f;
    EXPECT_NEAR(kernel::edge_preservation_index(x.data(), x.data(), L, N), 1.0, 1e-12);
    EXPECT_NEAR(kernel::edge_preservation_index(x.data(), y.data(), L, N), 1.0, 1e-6);
    const auto z = nrsar_test::gaussian_samples(L * N, 2);
    EXPECT_LT(std::abs(kernel::edge_preservation_index(x.data(), z.data(), L, N)),
              4.0 / std::sqrt(double((L - 2) * (N - 2))));
    std::vector<gr_complex> w(L * N);
    for (std::size_t i = 0; i < L * N; ++i)
        w[i] = 0.6f * x[i] + 0.8f * z[i];
    std::vector<double> lx, lw;
    for (std::size_t m = 1; m + 1 < L; ++m)
        for (std::size_t k = 1; k + 1 < N; ++k) {
            const auto lap = [&](const std::vector<gr_complex>& a) {
                const auto A = [&](std::size_t mm, std::size_t kk) { return std::abs(cd(a[mm * N + kk])); };
                return A(m - 1, k) + A(m + 1, k) + A(m, k - 1) + A(m, k + 1) - 4 * A(m, k);
            };
            lx.push_back(lap(x));
            lw.push_back(lap(w));
        }
    double mx = 0, mw = 0;
    for (std::size_t i = 0; i < lx.size(); ++i) {
        mx += lx[i] / lx.size();
        mw += lw[i] / lw.size();
    }
    double sxy = 0, sxx = 0, syy = 0;
    for (std::size_t i = 0; i < lx.size(); ++i) {
        sxy += (lx[i] - mx) * (lw[i] - mw);
        sxx += (lx[i] - mx) * (lx[i] - mx);
        syy += (lw[i] - mw) * (lw[i] - mw);
    }
    EXPECT_NEAR(kernel::edge_preservation_index(x.data(), w.data(), L, N), sxy / std::sqrt(sxx * syy), 1e-9);
    EXPECT_EQ(nrsar_test::error_of([&] { kernel::edge_preservation_index(x.data(), w.data(), 2, N); }),
              "image size (lines x bins) = 60 must be at least 3 x 3");
}

TEST(ImageMetrics, NeszIntegralMethod)
{
    // Noise power 1e-3 per pixel, a 10 m^2 target of energy 50 on 0.5 m x 2 m pixels:
    // 1e-3 * 10 / (50 * 1) = 2e-4, -36.99 dB.
    EXPECT_NEAR(kernel::nesz_db(1e-3, 50.0, 10.0, 1.0), 10 * std::log10(2e-4), 1e-12);
    EXPECT_TRUE(std::isnan(kernel::nesz_db(0.0, 50.0, 10.0, 1.0)));
    EXPECT_TRUE(std::isnan(kernel::nesz_db(1e-3, 50.0, std::nan(""), 1.0)));
}
