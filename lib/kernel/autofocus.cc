/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "../param_check.h"
#include "small_solve.h"
#include <gnuradio/nrsar/kernel/autofocus.h>
#include <gnuradio/nrsar/kernel/image_metrics.h>
#include <algorithm>
#include <cmath>
#include <complex>

namespace gr {
namespace nrsar {

void autofocus_config::validate() const
{
    if (method != autofocus_method::NONE && method != autofocus_method::PGA &&
        method != autofocus_method::ENTROPY)
        throw_param("method", static_cast<int>(method), "must be NONE, PGA or ENTROPY");
    check_range("max_iterations", max_iterations, 1u, 1000u);
    if (!(std::isfinite(tolerance_rad) && tolerance_rad > 0.0 && tolerance_rad < 1.0))
        throw_param("tolerance_rad", tolerance_rad, "must be in (0, 1)");
    if (!(std::isfinite(pga_bins_db) && pga_bins_db >= 0.0 && pga_bins_db <= 100.0))
        throw_param("pga_bins_db", pga_bins_db, "must be in [0, 100]");
    if (!(std::isfinite(pga_window_db) && pga_window_db > 0.0 && pga_window_db <= 60.0))
        throw_param("pga_window_db", pga_window_db, "must be in (0, 60]");
    check_at_least("pga_min_window", pga_min_window, 2u);
    if (!(std::isfinite(support_db) && support_db > 0.0 && support_db <= 100.0))
        throw_param("support_db", support_db, "must be in (0, 100]");
    if (!(std::isfinite(wavelength_m) && wavelength_m >= 0.0))
        throw_param("wavelength_m", wavelength_m, "must be finite and >= 0 (0: no deramp)");
    if (entropy_order == 1 || entropy_order > 8)
        throw_param("entropy_order", entropy_order, "must be 0 (per bin) or in [2, 8]");
}

namespace kernel {

void remove_linear_phase(double* phi, const double* w, std::size_t n, std::size_t start);

namespace {
using cd = std::complex<double>;
constexpr double pi = 3.14159265358979323846;

// Circular moving sum of w over L bins, centred: smooth[p] sums w[p - L/2 ..].
std::vector<double> smoothed(const std::vector<double>& w, std::size_t L)
{
    const std::size_t M = w.size();
    L = std::max<std::size_t>(1, std::min(L, M));
    std::vector<double> out(M);
    double run = 0.0;
    for (std::size_t i = 0; i < L; ++i)
        run += w[i];
    for (std::size_t i = 0; i < M; ++i) {
        out[(i + L / 2) % M] = run;
        run += w[(i + L) % M] - w[i];
    }
    return out;
}

// Centre of the weakest stretch of w (the moving sum, so a spectral null inside a band
// does not count): integrations of a phase gradient and the frequency axis of every fit
// start there, so a signal band that wraps across DFT bin 0 is one piece.
std::size_t weakest(const std::vector<double>& w)
{
    const auto s = smoothed(w, w.size() / 32);
    return static_cast<std::size_t>(std::min_element(s.begin(), s.end()) - s.begin());
}

// The equivalent width (sum w)^2 / sum w^2 of w in bins: B for a flat band of B bins.
double equivalent_width(const std::vector<double>& w)
{
    double s1 = 0.0, s2 = 0.0;
    for (double v : w) {
        s1 += v;
        s2 += v * v;
    }
    return s2 > 0.0 ? s1 * s1 / s2 : 1.0;
}

// Outside the band (w = 0) phi takes the value of the nearest bin inside it: the fit's
// ramp continued there would turn the band's skirts (the focused response's edge
// diffraction) and re-enter PGA's next estimate through its window; held, a focused
// image stays as it is.
void hold_outside(std::vector<double>& phi, const std::vector<double>& w)
{
    const std::size_t M = phi.size();
    std::vector<std::size_t> dist(M, M);
    std::vector<double> val(phi);
    for (int pass = 0; pass < 2; ++pass) // forward, then backward, around the circle
        for (std::size_t i = 0; i < 2 * M; ++i) {
            const std::size_t p = pass == 0 ? i % M : (2 * M - 1 - i) % M;
            const std::size_t q = pass == 0 ? (p + M - 1) % M : (p + 1) % M;
            if (w[p] > 0.0)
                dist[p] = 0;
            else if (dist[q] + 1 < dist[p]) {
                dist[p] = dist[q] + 1;
                val[p] = val[q];
            }
        }
    for (std::size_t p = 0; p < M; ++p)
        if (dist[p] < M)
            phi[p] = val[p];
}

// Brings phi to the form the result reports: phi is known modulo 2 pi per bin and up to
// a constant and a circular shift, so an estimate may hold a ramp that wraps (a focused
// image shifted by whole lines). Removes the weighted mean wrapped phase difference of
// neighbouring bins, unwraps along the frequency from the weakest stretch, then removes
// the weighted least-squares constant and slope.
void canonical_phase(std::vector<double>& phi, const std::vector<double>& w)
{
    const std::size_t M = phi.size(), s = weakest(w);
    std::complex<double> mean_step(0.0, 0.0);
    for (std::size_t i = 1; i < M; ++i) {
        const std::size_t p = (s + i) % M, q = (s + i - 1) % M;
        mean_step += std::sqrt(w[p] * w[q]) * std::polar(1.0, phi[p] - phi[q]);
    }
    const double b = std::arg(mean_step);
    std::vector<double> out(M);
    out[s] = 0.0;
    for (std::size_t i = 1; i < M; ++i) {
        const std::size_t p = (s + i) % M, q = (s + i - 1) % M;
        out[p] = out[q] + std::remainder(phi[p] - phi[q] - b, 2.0 * pi);
    }
    phi.swap(out);
    remove_linear_phase(phi.data(), w.data(), M, s);
    hold_outside(phi, w);
}

double weighted_rms(const std::vector<double>& phi, const std::vector<double>& w)
{
    double num = 0.0, den = 0.0;
    for (std::size_t p = 0; p < phi.size(); ++p) {
        num += w[p] * phi[p] * phi[p];
        den += w[p];
    }
    return den > 0.0 ? std::sqrt(num / den) : 0.0;
}

// Legendre polynomials P_0..P_order at t in [-1, 1] (well conditioned up to order 8).
void legendre(double t, unsigned order, double* P)
{
    P[0] = 1.0;
    if (order >= 1)
        P[1] = t;
    for (unsigned n = 2; n <= order; ++n)
        P[n] = ((2.0 * n - 1.0) * t * P[n - 1] - (n - 1.0) * P[n - 2]) / n;
}

// Weighted least-squares projection of phi onto Legendre polynomials of orders
// 0..order in the frequency unwrapped from bin `start` (t = -1 .. 1).
void project_polynomial(std::vector<double>& phi,
                        const std::vector<double>& w,
                        unsigned order,
                        std::size_t start)
{
    const std::size_t M = phi.size(), n = order + 1;
    std::vector<double> A(n * n, 0.0), b(n, 0.0), P(n);
    std::vector<double> basis(M * n);
    for (std::size_t i = 0; i < M; ++i) {
        const std::size_t p = (start + i) % M;
        legendre(2.0 * (i + 0.5) / static_cast<double>(M) - 1.0, order, &basis[p * n]);
        for (std::size_t r = 0; r < n; ++r) {
            b[r] += w[p] * basis[p * n + r] * phi[p];
            for (std::size_t c = 0; c < n; ++c)
                A[r * n + c] += w[p] * basis[p * n + r] * basis[p * n + c];
        }
    }
    std::vector<double> x; // A symmetric positive definite: a zero pivot leaves its 0
    solve_small(A, b, n, 0.0, x);
    for (std::size_t p = 0; p < M; ++p) {
        double s = 0.0;
        for (std::size_t r = 0; r < n; ++r)
            s += x[r] * basis[p * n + r];
        phi[p] = s;
    }
}
} // namespace

void remove_linear_phase(double* phi, const double* w, std::size_t n, std::size_t start)
{
    // Abscissa u = (p - start) mod n, centred, so the 2 x 2 normal equations stay well
    // conditioned.
    const double c = 0.5 * (static_cast<double>(n) - 1.0);
    const auto u_of = [n, start, c](std::size_t p) {
        return static_cast<double>((p + n - start % n) % n) - c;
    };
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, t0 = 0.0, t1 = 0.0;
    for (std::size_t p = 0; p < n; ++p) {
        const double u = u_of(p);
        s0 += w[p];
        s1 += w[p] * u;
        s2 += w[p] * u * u;
        t0 += w[p] * phi[p];
        t1 += w[p] * u * phi[p];
    }
    if (!(s0 > 0.0))
        return;
    const double det = s0 * s2 - s1 * s1;
    const double a = det > 0.0 ? (s2 * t0 - s1 * t1) / det : t0 / s0;
    const double b = det > 0.0 ? (s0 * t1 - s1 * t0) / det : 0.0;
    for (std::size_t p = 0; p < n; ++p)
        phi[p] -= a + b * u_of(p);
}

autofocus::autofocus(const autofocus_config& cfg) : d_cfg(cfg) { d_cfg.validate(); }
autofocus::~autofocus() = default;
autofocus::autofocus(autofocus&&) noexcept = default;
autofocus& autofocus::operator=(autofocus&&) noexcept = default;

void autofocus::plan(std::size_t lines, std::size_t bins)
{
    if (lines != d_M) {
        d_fwd = make_fft_fwd(static_cast<int>(lines));
        d_rev = make_fft_rev(static_cast<int>(lines));
    }
    d_M = lines;
    d_K = bins;
    d_spec.resize(lines * bins);
    d_work.resize(lines * bins);
    d_phi.assign(lines, 0.0);
    d_weight.assign(lines, 0.0);
}

void autofocus::image_of(const double* phi)
{
    const std::size_t M = d_M;
    const float scale = 1.0f / static_cast<float>(M); // unitary DFT pair: 1 / M in total
    std::vector<gr_complex> rot(M);
    for (std::size_t p = 0; p < M; ++p)
        rot[p] = gr_complex(static_cast<float>(std::cos(phi[p]) * scale),
                            static_cast<float>(-std::sin(phi[p]) * scale));
    for (std::size_t k = 0; k < d_K; ++k) {
        const gr_complex* G = &d_spec[k * M];
        gr_complex* in = d_rev->get_inbuf();
        for (std::size_t p = 0; p < M; ++p)
            in[p] = G[p] * rot[p];
        d_rev->execute();
        std::copy(d_rev->get_outbuf(), d_rev->get_outbuf() + M, &d_work[k * M]);
    }
}

double autofocus::entropy_of_work() const { return image_entropy(d_work.data(), d_M * d_K); }

autofocus_result
autofocus::focus(gr_complex* img, std::size_t lines, std::size_t bins, const image_axes& axes)
{
    check_at_least("lines", lines, std::size_t(4));
    check_at_least("bins", bins, std::size_t(1));
    plan(lines, bins);
    d_axes = axes;
    const std::size_t M = lines, K = bins;
    // Azimuth spectrum per range bin, range-major; spectra of the unitary DFT times sqrt(M)
    // (image_of divides by M once).
    for (std::size_t k = 0; k < K; ++k) {
        gr_complex* in = d_fwd->get_inbuf();
        for (std::size_t m = 0; m < M; ++m)
            in[m] = img[m * K + k];
        d_fwd->execute();
        const gr_complex* out = d_fwd->get_outbuf();
        std::copy(out, out + M, &d_spec[k * M]);
        for (std::size_t p = 0; p < M; ++p)
            d_weight[p] += std::norm(out[p]) / static_cast<double>(M);
    }
    // The targets' band: only there is the phase estimated, fitted and counted. The
    // moving sum bridges the Fresnel dips of a band but must stay shorter than the band:
    // a sixteenth of its equivalent width.
    // Wider (M / 32 = 750 bins for a 50-bin band at 24 k lines) it took in the band's
    // skirts, the finite aperture's edge diffraction, whose phase is the focuser's
    // azimuth chirp, not the phase history's: both methods "focused" them.
    {
        const auto sm =
            smoothed(d_weight, static_cast<std::size_t>(equivalent_width(d_weight) / 16.0));
        const double floor_v = *std::max_element(sm.begin(), sm.end()) *
                               std::pow(10.0, -d_cfg.support_db / 10.0);
        for (std::size_t p = 0; p < M; ++p)
            if (!(sm[p] >= floor_v && sm[p] > 0.0))
                d_weight[p] = 0.0;
    }
    autofocus_result r;
    r.entropy_before = image_entropy(img, M * K);
    if (d_cfg.method == autofocus_method::PGA)
        r.iterations = run_pga();
    else if (d_cfg.method == autofocus_method::ENTROPY)
        r.iterations = run_entropy();
    if (d_cfg.method != autofocus_method::NONE) {
        canonical_phase(d_phi, d_weight);
        image_of(d_phi.data());
        for (std::size_t k = 0; k < K; ++k)
            for (std::size_t m = 0; m < M; ++m)
                img[m * K + k] = d_work[k * M + m];
    }
    r.entropy_after = image_entropy(img, M * K);
    r.phase_rad = d_phi;
    r.weight = d_weight;
    r.phase_rms_rad = weighted_rms(d_phi, d_weight);
    return r;
}

// A range bin at r != r0 of a target at slant range r0 (its range sidelobe) holds the
// target's pulses, deramped at r, with the phase k u^2 (1 / r - 1 / r0) / 2 per pulse at
// offset u: the range-azimuth coupling of a focused response (0.33 rad at the band edge
// one 9.8 m bin away on nrsar-sim's 1 s aperture), which PGA would take for an error.
// In the deramped spectrum u = -2 pi r f / k, i.e. the phase (2 pi f)^2 r (r0 - r) /
// (2 k r0); removed here. r0: the range of the brightest bin near k on the same line
// (the target's), refined by a parabola through its neighbours' peak powers.
void autofocus::undo_range_coupling(gr_complex* G,
                                    std::size_t k,
                                    double r,
                                    const std::vector<double>& peak,
                                    const std::vector<std::size_t>& at,
                                    double kw) const
{
    const std::size_t M = d_M, K = d_K;
    const auto same_line = [&](std::size_t j) {
        const std::size_t d = (at[j] + M - at[k]) % M;
        return std::min(d, M - d) <= 2;
    };
    std::size_t j = k;
    for (;;) {
        if (j + 1 < K && peak[j + 1] > peak[j] && same_line(j + 1))
            ++j;
        else if (j > 0 && peak[j - 1] > peak[j] && same_line(j - 1))
            --j;
        else
            break;
    }
    double off = 0.0;
    if (j > 0 && j + 1 < K) {
        const double a = peak[j - 1], b = peak[j], c = peak[j + 1];
        const double den = a - 2.0 * b + c;
        if (den < 0.0)
            off = std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
    }
    const double r0 =
        d_axes.range_first_m + (static_cast<double>(j) + off) * d_axes.range_step_m;
    const double c2 = r * (r0 - r) / (2.0 * kw * r0);
    for (std::size_t p = 0; p < M; ++p) {
        const double pa = p < (M + 1) / 2 ? static_cast<double>(p)
                                          : static_cast<double>(p) - static_cast<double>(M);
        const double w = 2.0 * pi * pa / (static_cast<double>(M) * d_axes.line_spacing_m);
        const double ph = -c2 * w * w;
        G[p] *= gr_complex(static_cast<float>(std::cos(ph)), static_cast<float>(std::sin(ph)));
    }
}

// Phase gradient autofocus (Wahl et al. 1994, with Jakowatz's linear unbiased minimum
// variance gradient): per iteration, the strongest range bins are circularly shifted so
// each one's brightest line is line 0, windowed around it (the window narrows as the
// image focuses), transformed, and the phase difference of neighbouring DFT bins,
// arg sum_k G_k(p) conj(G_k(p - 1)), is integrated into the residual error.
unsigned autofocus::run_pga()
{
    const std::size_t M = d_M, K = d_K;
    std::vector<double> peak(K), profile(M), z_energy(M), dphi(M);
    std::vector<std::size_t> at(K);
    std::vector<cd> z(M);
    std::size_t window = M;
    const double band_bins = equivalent_width(d_weight);
    unsigned it = 0;
    while (it < d_cfg.max_iterations) {
        ++it;
        image_of(d_phi.data());
        for (std::size_t k = 0; k < K; ++k) {
            const gr_complex* g = &d_work[k * M];
            std::size_t best = 0;
            double bp = -1.0;
            for (std::size_t m = 0; m < M; ++m) {
                const double e = std::norm(g[m]);
                if (e > bp) {
                    bp = e;
                    best = m;
                }
            }
            peak[k] = bp;
            at[k] = best;
        }
        const double strongest = *std::max_element(peak.begin(), peak.end());
        if (!(strongest > 0.0))
            break;
        const double keep = strongest * std::pow(10.0, -d_cfg.pga_bins_db / 10.0);
        std::fill(profile.begin(), profile.end(), 0.0);
        for (std::size_t k = 0; k < K; ++k)
            if (peak[k] >= keep)
                for (std::size_t m = 0; m < M; ++m)
                    profile[m] += std::norm(d_work[k * M + (at[k] + m) % M]);
        // Window: twice the extent, either side of line 0, over which the centred
        // profile stays within pga_window_db of its peak; it only narrows.
        const double floor_v = profile[0] * std::pow(10.0, -d_cfg.pga_window_db / 10.0);
        // The outermost lines above that level count, not the first null: a sinusoidal
        // error spreads a target into paired echoes with nulls between them.
        std::size_t right = M / 2, left = M / 2;
        while (right > 0 && profile[right] < floor_v)
            --right;
        while (left > 0 && profile[M - left] < floor_v)
            --left;
        // Never narrower than 4 resolution cells (M / B lines for a band of B bins): a
        // window that cuts into a focused main lobe biases the estimate (0.02 rad at 8
        // lines on a 7-line lobe; 8 cells cost the GNSS study's seed 1 10 dB of NMSE,
        // docs/blocks/autofocus.md).
        const auto cells = static_cast<std::size_t>(4.0 * static_cast<double>(M) / band_bins);
        window = std::min(window,
                          std::max({ static_cast<std::size_t>(d_cfg.pga_min_window),
                                     cells,
                                     2 * (left + right + 1) }));
        // The window is tapered and centred on each range bin's peak interpolated between
        // lines (a parabola through the magnitudes): flat over a quarter of its half-width,
        // a raised-cosine skirt out to 1.5 times the half-width of the 2 (window / 2) + 1
        // lines. A window with hard edges at whole lines around the brightest whole line
        // weights a target by where it sits between lines: a half-line shift of the image
        // moved the estimate by 0.12 rad rms (GNSS study, seed 1, noise-free), by up to
        // 0.56 rad at line_step 4; tapered and centred by 0.005 / 0.073 rad. A Hann taper
        // (no flat part) does as well there but lost 0.07 rad on a random error
        // (docs/blocks/autofocus.md, "Sub-line position").
        const double taper_half = 1.5 * (static_cast<double>(window / 2) + 0.5);
        const std::size_t half = std::min(M / 2, static_cast<std::size_t>(taper_half + 0.5));
        const bool whole = window >= M; // the circle has no edges: no window at all
        const auto taper = [taper_half, whole](double c) {
            const double a = std::abs(c) / taper_half;
            if (whole || a <= 0.25)
                return 1.0;
            return a < 1.0 ? 0.5 + 0.5 * std::cos(pi * (a - 0.25) / 0.75) : 0.0;
        };
        // Deramp: a pulse at along-track offset u from a target at range r adds the chirp
        // exp(j k sqrt(r^2 + (y - u)^2)) to the image (k = 4 pi / lambda); times
        // exp(-j k sqrt(r^2 + y^2)) it becomes the tone exp(-j k u y / r) of constant phase
        // (up to (u y)^2 / r^3 terms), so the windowed target's spectrum is the window's
        // transform swept over one pulse per frequency: real where no error acts. Without
        // it the focused response carries the finite aperture's Fresnel phase ripple
        // (+-0.27 rad on a 50-bin band) and the estimate flattens it.
        const bool deramp = d_cfg.wavelength_m > 0.0 && d_axes.range_first_m > 0.0 &&
                            d_axes.range_step_m > 0.0 && d_axes.line_spacing_m > 0.0;
        const double kw = deramp ? 4.0 * pi / d_cfg.wavelength_m : 0.0;
        std::fill(z.begin(), z.end(), cd(0.0, 0.0));
        std::fill(z_energy.begin(), z_energy.end(), 0.0);
        for (std::size_t k = 0; k < K; ++k) {
            if (peak[k] < keep)
                continue;
            gr_complex* in = d_fwd->get_inbuf();
            std::fill(in, in + M, gr_complex(0.0f, 0.0f));
            const double r = d_axes.range_first_m + static_cast<double>(k) * d_axes.range_step_m;
            const gr_complex* g = &d_work[k * M];
            const double before = std::abs(g[(at[k] + M - 1) % M]), top = std::abs(g[at[k]]),
                         after = std::abs(g[(at[k] + 1) % M]);
            const double curv = before - 2.0 * top + after;
            const double centre =
                curv < 0.0 ? std::clamp(0.5 * (before - after) / curv, -0.5, 0.5) : 0.0;
            for (std::size_t c = 0; c <= half && c < M; ++c) {
                gr_complex rot(1.0f, 0.0f);
                if (deramp) {
                    const double y = static_cast<double>(c) * d_axes.line_spacing_m;
                    const double ph = -kw * y * y / (std::sqrt(r * r + y * y) + r);
                    rot = gr_complex(static_cast<float>(std::cos(ph)),
                                     static_cast<float>(std::sin(ph)));
                }
                const double x = static_cast<double>(c);
                in[c] = g[(at[k] + c) % M] * rot * static_cast<float>(taper(x - centre));
                if (c > 0 && c < M - c)
                    in[M - c] =
                        g[(at[k] + M - c) % M] * rot * static_cast<float>(taper(x + centre));
            }
            d_fwd->execute();
            gr_complex* G = d_fwd->get_outbuf();
            if (deramp)
                undo_range_coupling(G, k, r, peak, at, kw);
            for (std::size_t p = 0; p < M; ++p) {
                const cd a(G[p]), b(G[(p + M - 1) % M]);
                z[p] += a * std::conj(b);
                z_energy[p] += std::norm(a);
            }
        }
        // The deramped estimate resolves the phase to the window's Doppler resolution,
        // M / window bins; finer structure in it is the window's leakage, which the
        // correction (in the image's spectrum) does not feed back into the next estimate,
        // so it would add up over the iterations: the gradients are averaged over that
        // resolution (triangular weights).
        if (deramp && window < M) {
            const std::size_t h = M / window;
            std::vector<cd> zs(M, cd(0.0, 0.0));
            for (std::size_t p = 0; p < M; ++p)
                for (std::size_t j = 0; j <= 2 * h; ++j)
                    zs[p] += static_cast<double>(h + 1 - (j > h ? j - h : h - j)) *
                             z[(p + M + j - h) % M];
            z.swap(zs);
        }
        // Outside the band the gradient is noise: the phase is held there. So it is
        // where the windowed (deramped) targets' spectrum lies support_db below its peak:
        // beyond the aperture's Doppler edge only the window's leakage is left.
        const double z_floor = *std::max_element(z_energy.begin(), z_energy.end()) *
                               std::pow(10.0, -d_cfg.support_db / 10.0);
        std::vector<bool> weak(M);
        for (std::size_t p = 0; p < M; ++p)
            weak[p] = d_weight[p] == 0.0 || z_energy[p] < z_floor;
        for (std::size_t p = 0; p < M; ++p)
            if (weak[p] || weak[(p + M - 1) % M]) {
                z[p] = cd(1.0, 0.0);
                z_energy[p] = 0.0;
            }
        const std::size_t s = weakest(d_weight);
        dphi[s] = 0.0;
        for (std::size_t i = 1; i < M; ++i) {
            const std::size_t p = (s + i) % M, q = (s + i - 1) % M;
            dphi[p] = dphi[q] + std::arg(z[p]);
        }
        remove_linear_phase(dphi.data(), z_energy.data(), M, s);
        hold_outside(dphi, z_energy);
        for (std::size_t p = 0; p < M; ++p)
            d_phi[p] += dphi[p];
        if (weighted_rms(dphi, z_energy) < d_cfg.tolerance_rad)
            break;
    }
    return it;
}

// Minimum entropy (entropy as in the second paper's section 3.2.1, [33]): with the image
// g = IDFT(G exp(-j phi)) and D = |g|^2 / S, the entropy E = -sum D ln D has the gradient
// dE/dphi(p) = -(2 / S) Im q(p), q(p) = sum_k G'(p, k) conj(W(p, k)), G' = G exp(-j phi),
// W = DFT(g ln D) (S is constant: the correction keeps the energy). Each iteration takes
// the preconditioned descent step Im q(p) / (lambda h(p)), h(p) = max(w(p), mean w): a
// Doppler bin's curvature scales with its energy w(p), and the floor keeps bins of noise
// alone from being tuned to it (bins outside the band, support_db, stay as they are).
// entropy_order >= 2: the step projected, with weights w (the band),
// onto Legendre polynomials of that order (the Gauss-Newton step of their coefficients).
// lambda grows fourfold when a step fails to lower the entropy and halves when it
// succeeds (a trust region: E never rises).
unsigned autofocus::run_entropy()
{
    const std::size_t M = d_M, K = d_K;
    const std::size_t start = weakest(d_weight);
    double mean_w = 0.0;
    for (double v : d_weight)
        mean_w += v / static_cast<double>(M);
    std::vector<double> h(M), trial(M), step(M);
    for (std::size_t p = 0; p < M; ++p)
        h[p] = std::max(d_weight[p], mean_w);
    std::vector<bool> frozen(M, false);
    if (d_cfg.entropy_order == 0)
        for (std::size_t p = 0; p < M; ++p)
            frozen[p] = d_weight[p] == 0.0;
    std::vector<cd> q(M);
    image_of(d_phi.data());
    double E = entropy_of_work();
    double lambda = 1.0;
    unsigned it = 0;
    bool fresh = true; // q belongs to the current phi
    while (it < d_cfg.max_iterations && lambda < 1e12) {
        ++it;
        if (fresh) {
            double S = 0.0;
            for (std::size_t i = 0; i < M * K; ++i)
                S += std::norm(d_work[i]);
            if (!(S > 0.0))
                break;
            std::fill(q.begin(), q.end(), cd(0.0, 0.0));
            for (std::size_t k = 0; k < K; ++k) {
                const gr_complex* g = &d_work[k * M];
                gr_complex* in = d_fwd->get_inbuf();
                for (std::size_t m = 0; m < M; ++m) {
                    const double D = std::norm(g[m]) / S;
                    in[m] = g[m] * static_cast<float>(D > 0.0 ? std::log(D) : 0.0);
                }
                d_fwd->execute();
                const gr_complex* W = d_fwd->get_outbuf();
                const gr_complex* G = &d_spec[k * M];
                for (std::size_t p = 0; p < M; ++p)
                    q[p] += cd(G[p]) * std::polar(1.0, -d_phi[p]) * std::conj(cd(W[p]));
            }
            // d_spec and W are each sqrt(M) times unitary: q carries a factor M, as w(p).
            fresh = false;
        }
        for (std::size_t p = 0; p < M; ++p)
            step[p] = frozen[p] ? 0.0 : q[p].imag() / (lambda * h[p] * static_cast<double>(M));
        if (d_cfg.entropy_order >= 2)
            project_polynomial(step, d_weight, d_cfg.entropy_order, start);
        for (std::size_t p = 0; p < M; ++p)
            trial[p] = d_phi[p] + step[p];
        image_of(trial.data());
        const double E_new = entropy_of_work();
        if (E_new < E) {
            E = E_new;
            d_phi.swap(trial);
            lambda = std::max(0.5 * lambda, 1e-6);
            fresh = true;
            if (weighted_rms(step, d_weight) < d_cfg.tolerance_rad)
                break;
        } else {
            lambda *= 4.0;
        }
    }
    image_of(d_phi.data());
    return it;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
