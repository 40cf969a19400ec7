/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "../param_check.h"
#include <gnuradio/nrsar/kernel/fft_plans.h>
#include <gnuradio/nrsar/kernel/image_metrics.h>
#include <volk/volk.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
constexpr double nan_v = std::numeric_limits<double>::quiet_NaN();
constexpr double pi = 3.14159265358979323846;

double db10(double x) { return (x > 0.0 && std::isfinite(x)) ? 10.0 * std::log10(x) : nan_v; }
} // namespace

// Band-limited interpolation of a cut by zero-padding its spectrum.
struct image_metrics::upsampler {
    std::size_t n = 0;
    unsigned factor = 0;
    fft_fwd fwd;
    fft_rev rev;

    void plan(std::size_t len, unsigned u)
    {
        if (len == n && u == factor)
            return;
        n = len;
        factor = u;
        fwd = make_fft_fwd(static_cast<int>(n));
        rev = make_fft_rev(static_cast<int>(n * u));
    }

    // in: n samples (already gathered); out: n * factor interpolated samples of the band
    // centred at centre_cycles (cycles per sample): the zeros go opposite that centre.
    // A cut's band need not be centred on 0: a range IFFT of subcarriers 0..N-1 puts a range
    // cut's band at [0, N / nfft) cycles per bin, across Nyquist, and zeros inserted at
    // Nyquist split it and add a false sidelobe (range PSLR -5.4 dB instead of -13.8 dB on a
    // focused paper-geometry target, docs/blocks/nmse_probe.md).
    const gr_complex* run(const gr_complex* in, double centre_cycles)
    {
        std::copy(in, in + n, fwd->get_inbuf());
        fwd->execute();
        const gr_complex* X = fwd->get_outbuf();
        gr_complex* Y = rev->get_inbuf();
        const std::size_t m = n * factor;
        std::fill(Y, Y + m, gr_complex(0.0f, 0.0f));
        const float scale = 1.0f / static_cast<float>(n); // gr::fft is unnormalised
        // Band centre c0 opposite the gap; bin k sits at c0 + d, d in [-n/2, n/2).
        // A centre within 1/8 cycle of 0 keeps the zeros exactly at Nyquist: the estimate
        // scatters by about a bin with noise, and a band centred near 0 (or a full band,
        // one sample per cell) is then split where the textbook puts it.
        const double centre_bins =
            (centre_cycles - std::round(centre_cycles)) * static_cast<double>(n);
        const long c = std::abs(centre_bins) < 0.125 * static_cast<double>(n)
                           ? 0L
                           : std::lround(centre_bins);
        const std::size_t c0 = static_cast<std::size_t>(((c % static_cast<long>(n)) +
                                                         static_cast<long>(n)) %
                                                        static_cast<long>(n));
        const std::size_t half = n / 2;
        for (std::size_t k = 0; k < n; ++k) {
            const long d = static_cast<long>((k + n - c0 + half) % n) - static_cast<long>(half);
            const std::size_t idx =
                static_cast<std::size_t>((static_cast<long>(c0) + d + static_cast<long>(m)) %
                                         static_cast<long>(m));
            if (n % 2 == 0 && d == -static_cast<long>(half)) {
                // the gap bin of an even length is split so the result stays exact
                Y[idx] += X[k] * (0.5f * scale);
                Y[(c0 + half) % m] += X[k] * (0.5f * scale);
            } else {
                Y[idx] = X[k] * scale;
            }
        }
        rev->execute();
        return rev->get_outbuf();
    }
};

image_metrics::image_metrics()
{
    d_up[0] = std::make_unique<upsampler>();
    d_up[1] = std::make_unique<upsampler>();
}
image_metrics::~image_metrics() = default;
image_metrics::image_metrics(image_metrics&&) noexcept = default;
image_metrics& image_metrics::operator=(image_metrics&&) noexcept = default;

std::complex<double>
calibration_factor(const gr_complex* img, const gr_complex* ref, std::size_t lines, std::size_t bins)
{
    std::complex<double> cross(0.0, 0.0);
    double rr = 0.0;
    for (std::size_t m = 0; m < lines; ++m) {
        const gr_complex* x = img + m * bins;
        const gr_complex* r = ref + m * bins;
        lv_32fc_t c, p;
        // float sums over one line (<= a few thousand terms), double across lines
        volk_32fc_x2_conjugate_dot_prod_32fc(&c, x, r, static_cast<unsigned>(bins));
        volk_32fc_x2_conjugate_dot_prod_32fc(&p, r, r, static_cast<unsigned>(bins));
        cross += std::complex<double>(c.real(), c.imag());
        rr += p.real();
    }
    if (!(rr > 0.0))
        return { 0.0, 0.0 };
    return cross / rr;
}

double dirichlet(double u, double res, double band)
{
    const double a = pi * u / res;
    const double den = band * std::sin(a / band);
    if (std::abs(den) < 1e-12 * band)
        // at u = 0 (and multiples of the period band*res) the limit is +-1
        return std::cos(a) / std::cos(a / band);
    return std::sin(a) / den;
}

void psf_model(gr_complex* out,
               std::size_t lines,
               std::size_t bins,
               double line0,
               double bin0,
               double azimuth_res,
               double azimuth_band,
               double range_res,
               double range_band,
               double phase_per_line,
               double phase_per_bin)
{
    // eq. (47) with chi = 1 is separable: R(k, m) = D_N(k - k_q) D_M(m - m_q).
    std::vector<std::complex<double>> rk(bins);
    for (std::size_t k = 0; k < bins; ++k) {
        const double u = static_cast<double>(k) - bin0;
        rk[k] = std::polar(dirichlet(u, range_res, range_band), phase_per_bin * u);
    }
    for (std::size_t m = 0; m < lines; ++m) {
        const double w = static_cast<double>(m) - line0;
        const auto am = std::polar(dirichlet(w, azimuth_res, azimuth_band), phase_per_line * w);
        gr_complex* row = out + m * bins;
        for (std::size_t k = 0; k < bins; ++k) {
            const auto v = am * rk[k];
            row[k] = gr_complex(static_cast<float>(v.real()), static_cast<float>(v.imag()));
        }
    }
}

std::pair<double, double> estimate_phase_ramps(const gr_complex* img,
                                               std::size_t lines,
                                               std::size_t bins,
                                               double peak_line,
                                               double peak_bin,
                                               double azimuth_res,
                                               double range_res)
{
    // Pairs within 0.45 cells of the peak stay inside the main lobe (first null at 1 cell),
    // where the real Dirichlet kernel has one sign, so their phase step is the ramp alone.
    const double rl = std::max(1.0, 0.45 * azimuth_res);
    const double rb = std::max(1.0, 0.45 * range_res);
    auto lo = [](double c, double r) { return static_cast<long>(std::floor(c - r)); };
    auto hi = [](double c, double r) { return static_cast<long>(std::ceil(c + r)); };
    const long l0 = std::max(0L, lo(peak_line, rl)), l1 = std::min<long>(lines - 1, hi(peak_line, rl));
    const long b0 = std::max(0L, lo(peak_bin, rb)), b1 = std::min<long>(bins - 1, hi(peak_bin, rb));
    std::complex<double> acc_l(0.0, 0.0), acc_b(0.0, 0.0);
    for (long m = l0; m <= l1; ++m)
        for (long k = b0; k <= b1; ++k) {
            const std::complex<double> x(img[m * bins + k].real(), img[m * bins + k].imag());
            const bool in_l = std::abs(m - peak_line) <= rl, in_b = std::abs(k - peak_bin) <= rb;
            if (k + 1 <= b1 && in_l && in_b && std::abs(k + 1 - peak_bin) <= rb) {
                const auto& y = img[m * bins + k + 1];
                acc_b += std::complex<double>(y.real(), y.imag()) * std::conj(x);
            }
            if (m + 1 <= l1 && in_l && in_b && std::abs(m + 1 - peak_line) <= rl) {
                const auto& y = img[(m + 1) * bins + k];
                acc_l += std::complex<double>(y.real(), y.imag()) * std::conj(x);
            }
        }
    return { std::abs(acc_l) > 0.0 ? std::arg(acc_l) : 0.0,
             std::abs(acc_b) > 0.0 ? std::arg(acc_b) : 0.0 };
}

std::pair<std::size_t, std::size_t> find_peak(const gr_complex* img,
                                              std::size_t lines,
                                              std::size_t bins,
                                              double line,
                                              double bin,
                                              double half_lines,
                                              double half_bins)
{
    auto box = [](double c, double half, std::size_t n, long& lo, long& hi) {
        half = std::max(2.0, half);
        const double nd = static_cast<double>(n);
        lo = 1;
        hi = 0;
        if (std::isfinite(c) && std::isfinite(half) && c + half >= 0.0 && c - half <= nd - 1.0) {
            lo = static_cast<long>(std::max(0.0, std::floor(c - half)));
            hi = static_cast<long>(std::min(nd - 1.0, std::ceil(c + half)));
        }
        if (lo > hi) { // the target is outside the image: search it all
            lo = 0;
            hi = static_cast<long>(n) - 1;
        }
    };
    long l0, l1, b0, b1;
    box(line, half_lines, lines, l0, l1);
    box(bin, half_bins, bins, b0, b1);
    std::size_t ml = l0, kb = b0;
    float pmax = -1.0f;
    for (long m = l0; m <= l1; ++m)
        for (long k = b0; k <= b1; ++k) {
            const float v = std::norm(img[m * bins + k]);
            if (v > pmax) {
                pmax = v;
                ml = m;
                kb = k;
            }
        }
    return { ml, kb };
}

void strip_pixel_weights_into(std::vector<float>& w,
                              std::size_t lines,
                              std::size_t bins,
                              double y0_m,
                              double dy_m,
                              double r0_m,
                              double dr_m,
                              double data_lo_m,
                              double data_hi_m,
                              double band_lo_hz,
                              double band_hi_hz,
                              double wavelength_m,
                              double velocity_mps,
                              double period_m)
{
    check_finite_positive("wavelength_m", wavelength_m);
    check_finite_positive("velocity_mps", velocity_mps);
    check_finite("y0_m", y0_m);
    check_finite("dy_m", dy_m);
    check_finite("r0_m", r0_m);
    check_finite("dr_m", dr_m);
    check_finite("band_lo_hz", band_lo_hz);
    check_finite("band_hi_hz", band_hi_hz);
    if (!(band_hi_hz > band_lo_hz))
        throw_param("band_hi_hz", band_hi_hz, "must be > band_lo_hz = " + std::to_string(band_lo_hz));
    if (!(data_hi_m > data_lo_m) || !std::isfinite(data_lo_m) || !std::isfinite(data_hi_m))
        throw_param("data_hi_m", data_hi_m, "must be finite and > data_lo_m = " + std::to_string(data_lo_m));
    if (!(period_m >= 0.0) || !std::isfinite(period_m))
        throw_param("period_m", period_m, "must be finite and >= 0");
    const double span = data_hi_m - data_lo_m;
    if (period_m > 0.0 && period_m < span)
        throw_param("period_m", period_m, "must be 0 or >= the data span " + std::to_string(span));
    // Data under (-inf, u]: the data in every copy of the block (period_m > 0) or once.
    const auto data_below = [&](double u) {
        if (period_m == 0.0)
            return std::clamp(u - data_lo_m, 0.0, span);
        const double n = std::floor((u - data_lo_m) / period_m);
        return n * span + std::min(u - data_lo_m - n * period_m, span);
    };
    // (y - y_p) / r of Doppler f: f = 2 v d / (lambda sqrt(r^2 + d^2)) solved for d. A band
    // reaching (fl / (2 v))^2 >= 0.99 (towards endfire, e.g. the full PRF) maps parabolically,
    // eq. (40), as the focuser's migration does there.
    const double f_max = 2.0 * velocity_mps / wavelength_m; // Doppler of a target at endfire
    const double a_edge = std::max(std::abs(band_lo_hz), std::abs(band_hi_hz)) / f_max;
    const bool hyperbolic = a_edge * a_edge < 0.99;
    const auto c = [&](double f) {
        const double a = f / f_max;
        return f * wavelength_m / (2.0 * velocity_mps) / (hyperbolic ? std::sqrt(1.0 - a * a) : 1.0);
    };
    const double c_lo = c(band_lo_hz), c_hi = c(band_hi_hz);
    w.assign(lines * bins, 0.0f);
    for (std::size_t k = 0; k < bins; ++k) {
        const double r = r0_m + static_cast<double>(k) * dr_m;
        const double u_lo = r * c_lo, u_hi = r * c_hi, window = u_hi - u_lo;
        if (!(window > 0.0))
            continue; // a bin at slant range <= 0 (a crop's guard at the radar) holds no echo
        const double wraps = period_m > 0.0 ? std::floor(window / period_m) : 0.0;
        const double best = wraps * span + std::min(window - wraps * period_m, span);
        for (std::size_t m = 0; m < lines; ++m) {
            const double y = y0_m + static_cast<double>(m) * dy_m;
            const double s = data_below(y - u_lo) - data_below(y - u_hi);
            if (s >= 0.5 * best)
                w[m * bins + k] = static_cast<float>(window / s);
        }
    }
}

double image_entropy(const gr_complex* img, std::size_t n)
{
    // Two passes: the total energy, then -sum D ln D (pixels with D = 0 contribute 0).
    double S = 0.0;
    for (std::size_t i = 0; i < n; ++i)
        S += std::norm(std::complex<double>(img[i]));
    if (!(S > 0.0))
        return 0.0;
    double E = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double D = std::norm(std::complex<double>(img[i])) / S;
        if (D > 0.0)
            E -= D * std::log(D);
    }
    return E;
}

double edge_preservation_index(const gr_complex* x,
                               const gr_complex* y,
                               std::size_t lines,
                               std::size_t bins)
{
    std::vector<double> scratch;
    return edge_preservation_index(x, y, lines, bins, scratch);
}

double edge_preservation_index(const gr_complex* x,
                               const gr_complex* y,
                               std::size_t lines,
                               std::size_t bins,
                               std::vector<double>& scratch)
{
    if (lines < 3 || bins < 3)
        throw_param("image size (lines x bins)", lines * bins, "must be at least 3 x 3");
    // Amplitudes once per pixel (the Laplacians below read each one 5 times per pass: the
    // hypot calls were most of nmse_probe's CPU time, issue 16); same values, same sums.
    const std::size_t n_px = lines * bins;
    if (scratch.size() < 2 * n_px)
        scratch.resize(2 * n_px);
    double* const ax = scratch.data();
    double* const ay = ax + n_px;
    for (std::size_t i = 0; i < n_px; ++i) {
        ax[i] = std::abs(std::complex<double>(x[i]));
        ay[i] = std::abs(std::complex<double>(y[i]));
    }
    const auto lap = [bins](const double* amp, std::size_t m, std::size_t k) {
        const double* A = amp + m * bins + k;
        return A[-std::ptrdiff_t(bins)] + A[bins] + A[-1] + A[1] - 4.0 * A[0];
    };
    const double n = static_cast<double>((lines - 2) * (bins - 2));
    double sx = 0.0, sy = 0.0;
    for (std::size_t m = 1; m + 1 < lines; ++m)
        for (std::size_t k = 1; k + 1 < bins; ++k) {
            sx += lap(ax, m, k);
            sy += lap(ay, m, k);
        }
    const double mx = sx / n, my = sy / n;
    double sxy = 0.0, sxx = 0.0, syy = 0.0;
    for (std::size_t m = 1; m + 1 < lines; ++m)
        for (std::size_t k = 1; k + 1 < bins; ++k) {
            const double dx = lap(ax, m, k) - mx, dy = lap(ay, m, k) - my;
            sxy += dx * dy;
            sxx += dx * dx;
            syy += dy * dy;
        }
    return sxx > 0.0 && syy > 0.0 ? sxy / std::sqrt(sxx * syy) : nan_v;
}

double nesz_db(double noise_power, double target_energy, double rcs_m2, double pixel_area_m2)
{
    const auto ok = [](double v) { return std::isfinite(v) && v > 0.0; };
    if (!(ok(noise_power) && ok(target_energy) && ok(rcs_m2) && ok(pixel_area_m2)))
        return nan_v;
    return 10.0 * std::log10(noise_power * rcs_m2 / (target_energy * pixel_area_m2));
}

std::size_t zero_nonfinite(gr_complex* data, std::size_t n)
{
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (!std::isfinite(data[i].real()) || !std::isfinite(data[i].imag())) {
            data[i] = gr_complex(0.0f, 0.0f);
            ++count;
        }
    return count;
}

namespace {
// Centre of a cut's band [cycles per sample] from the phase step between neighbours within
// 0.45 cells of the peak sample: there the kernel (Dirichlet times a linear phase) has one
// sign, so arg(x[i+1] conj(x[i])) is 2 pi times the band centre (the same estimate as
// estimate_phase_ramps). 0 when the cut holds no usable pair.
double band_centre_cycles(const gr_complex* x, std::size_t n, std::size_t peak, double res)
{
    const long w = std::max(1L, static_cast<long>(std::ceil(0.45 * res)));
    const long lo = std::max(0L, static_cast<long>(peak) - w);
    const long hi = std::min(static_cast<long>(n) - 1, static_cast<long>(peak) + w);
    std::complex<double> acc(0.0, 0.0);
    for (long i = lo; i < hi; ++i)
        acc += std::complex<double>(x[i + 1].real(), x[i + 1].imag()) *
               std::conj(std::complex<double>(x[i].real(), x[i].imag()));
    return std::abs(acc) > 0.0 ? std::arg(acc) / (2.0 * pi) : 0.0;
}
} // namespace

cut_metrics image_metrics::analyse_cut(const gr_complex* cut,
                                       std::size_t n,
                                       std::size_t stride,
                                       std::size_t around,
                                       double res_samples,
                                       double window_cells,
                                       int slot)
{
    cut_metrics r;
    r.irw = r.islr_db = r.pslr_db = nan_v;
    if (n < 3 || !(res_samples > 0.0))
        return r;
    // >= 16 interpolated samples per resolution cell keeps the -3 dB and null positions
    // within a few thousandths of a cell.
    const unsigned u =
        static_cast<unsigned>(std::clamp(std::ceil(16.0 / res_samples), 1.0, 64.0));
    r.upsample = u;
    if (d_line.size() < n)
        d_line.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        d_line[i] = cut[i * stride];
    const std::size_t m = n * u;
    const gr_complex* y = d_line.data();
    if (u > 1) {
        auto& up = *d_up[slot & 1];
        up.plan(n, u);
        y = up.run(d_line.data(), band_centre_cycles(d_line.data(), n, around, res_samples));
    }
    if (d_power.size() < m)
        d_power.resize(m);
    float* p = d_power.data();
    volk_32fc_magnitude_squared_32f(p, y, static_cast<unsigned>(m));

    // Peak within +-1 original sample of the pixel peak, then a parabola through the top 3.
    const long c = static_cast<long>(around) * u;
    long ipk = c;
    for (long i = std::max(0L, c - static_cast<long>(u));
         i <= std::min<long>(m - 1, c + static_cast<long>(u));
         ++i)
        if (p[i] > p[ipk])
            ipk = i;
    const double ppk = p[ipk];
    if (!(ppk > 0.0))
        return r;
    double frac = 0.0, pref = ppk;
    if (ipk > 0 && ipk + 1 < static_cast<long>(m)) {
        const double a = p[ipk - 1], b = p[ipk + 1];
        const double den = a - 2.0 * ppk + b;
        if (den < 0.0) {
            frac = std::clamp(0.5 * (a - b) / den, -0.5, 0.5);
            pref = ppk - 0.25 * (a - b) * frac;
        }
    }
    r.peak_pos = (ipk + frac) / u;
    r.peak_power = pref;

    // -3 dB (half power) crossings, linear in power between interpolated samples.
    const double half = 0.5 * pref;
    double left = nan_v, right = nan_v;
    for (long i = ipk; i > 0; --i)
        if (p[i - 1] < half) {
            left = (i - 1) + (half - p[i - 1]) / (p[i] - p[i - 1]);
            break;
        }
    for (long i = ipk; i + 1 < static_cast<long>(m); ++i)
        if (p[i + 1] < half) {
            right = i + (p[i] - half) / (p[i] - p[i + 1]);
            break;
        }
    r.irw = (right - left) / u;

    // Main lobe: down to the first minimum on each side.
    long jl = ipk, jr = ipk;
    while (jl > 0 && p[jl - 1] < p[jl])
        --jl;
    while (jr + 1 < static_cast<long>(m) && p[jr + 1] < p[jr])
        ++jr;
    long lo = 0, hi = static_cast<long>(m) - 1;
    if (window_cells > 0.0) {
        const long w = static_cast<long>(std::ceil(window_cells * res_samples * u));
        lo = std::max(lo, ipk - w);
        hi = std::min(hi, ipk + w);
    }
    jl = std::max(jl, lo);
    jr = std::min(jr, hi);
    double main = 0.0, side = 0.0, sidemax = 0.0;
    for (long i = lo; i <= hi; ++i) {
        if (i >= jl && i <= jr) {
            main += p[i];
        } else {
            side += p[i];
            sidemax = std::max<double>(sidemax, p[i]);
        }
    }
    r.mainlobe_energy = main;
    r.sidelobe_energy = side;
    r.islr_db = db10(side / main);
    r.pslr_db = (lo < jl || hi > jr) ? db10(sidemax / pref) : nan_v;
    r.valid = std::isfinite(r.irw);
    return r;
}

metrics_result image_metrics::compute(const gr_complex* img,
                                      const gr_complex* ref,
                                      std::size_t lines,
                                      std::size_t bins,
                                      double expected_line,
                                      double expected_bin,
                                      const metrics_config& cfg,
                                      const std::uint8_t* bin_mask,
                                      const std::uint8_t* line_mask,
                                      const float* pixel_weight)
{
    metrics_result res;
    if (lines == 0 || bins == 0) {
        res.pel_db = res.nmse = res.nmse_db = res.snr_out_db = res.islr_db = res.pslr_db = nan_v;
        res.epi = res.nesz_db = nan_v;
        return res;
    }

    // Calibration factor c_hat and max |ref|^2 (SPEC section 8).
    res.c_hat = calibration_factor(img, ref, lines, bins);
    if (d_power.size() < bins)
        d_power.resize(bins);
    if (d_line.size() < bins)
        d_line.resize(bins);
    float* pw = d_power.data();
    double ref_max = 0.0;
    for (std::size_t mline = 0; mline < lines; ++mline) {
        volk_32fc_magnitude_squared_32f(pw, ref + mline * bins, static_cast<unsigned>(bins));
        ref_max = std::max<double>(ref_max, *std::max_element(pw, pw + bins));
    }
    const double cabs2 = std::norm(res.c_hat);
    res.pel_db = cabs2 > 0.0 ? -10.0 * std::log10(cabs2) : nan_v;

    // e = img / c_hat - ref, once per pixel: its mean power is the NMSE numerator and,
    // times |c_hat|^2, the residual img - c_hat ref whose mean over the noise region is
    // the noise power (the reference's own sidelobes removed).
    double err_all = 0.0, err_region = 0.0;
    std::size_t region_pixels = 0, nmse_pixels = 0;
    if (cabs2 > 0.0) {
        const std::complex<double> inv = 1.0 / res.c_hat;
        const lv_32fc_t invf(static_cast<float>(inv.real()), static_cast<float>(inv.imag()));
        gr_complex* e = d_line.data();
        for (std::size_t mline = 0; mline < lines; ++mline) {
            volk_32fc_s32fc_multiply_32fc(e, img + mline * bins, invf, static_cast<unsigned>(bins));
            volk_32f_x2_subtract_32f(reinterpret_cast<float*>(e),
                                     reinterpret_cast<const float*>(e),
                                     reinterpret_cast<const float*>(ref + mline * bins),
                                     static_cast<unsigned>(2 * bins));
            volk_32fc_magnitude_squared_32f(pw, e, static_cast<unsigned>(bins));
            const bool line_in = !line_mask || line_mask[mline];
            double s_all = 0.0, s_reg = 0.0;
            std::size_t n_reg = 0;
            const float* wl = pixel_weight ? pixel_weight + mline * bins : nullptr;
            for (std::size_t k = 0; k < bins; ++k) {
                if (!wl) {
                    s_all += pw[k];
                } else if (wl[k] > 0.0f) {
                    s_all += static_cast<double>(wl[k]) * pw[k];
                    ++nmse_pixels;
                }
                if (line_in && (!bin_mask || bin_mask[k])) {
                    s_reg += pw[k];
                    ++n_reg;
                }
            }
            err_all += s_all;
            if (!wl)
                nmse_pixels += bins;
            err_region += s_reg;
            region_pixels += n_reg;
        }
        res.nmse = nmse_pixels ? cfg.nm_factor * (err_all / nmse_pixels) / ref_max : nan_v;
    } else {
        res.nmse = nan_v;
    }
    res.nmse_pixels = nmse_pixels;
    res.nmse_db = db10(res.nmse);
    if (cabs2 > 0.0 && ref_max > 0.0 && res.nmse == 0.0)
        res.nmse_db = -std::numeric_limits<double>::infinity();

    // Pixel peak within the search box around where the target should be.
    const auto pk = find_peak(img, lines, bins, expected_line, expected_bin,
                              cfg.search_cells * cfg.azimuth_res_lines,
                              cfg.search_cells * cfg.range_res_bins);
    const long ml = static_cast<long>(pk.first), kb = static_cast<long>(pk.second);
    const double pmax = std::norm(img[ml * bins + kb]);

    // Cuts through the peak pixel (SPEC section 8: ISLR, PSLR, IRW from 1-D cuts).
    const auto window = [&cfg](double limit) {
        return cfg.sidelobe_window_cells > 0.0 ? std::min(cfg.sidelobe_window_cells, limit)
               : std::isfinite(limit)          ? limit
                                               : 0.0;
    };
    res.range = analyse_cut(img + ml * bins, bins, 1, kb, cfg.range_res_bins,
                            window(cfg.range_window_limit_cells), 0);
    res.azimuth = analyse_cut(img + kb, lines, bins, ml, cfg.azimuth_res_lines,
                              window(cfg.azimuth_window_limit_cells), 1);
    res.peak_bin = res.range.peak_power > 0.0 ? res.range.peak_pos : static_cast<double>(kb);
    res.peak_line = res.azimuth.peak_power > 0.0 ? res.azimuth.peak_pos : static_cast<double>(ml);
    // A separable PSF peaks at p_r p_a / p_pixel: each cut misses the peak by the other
    // direction's straddle loss only.
    res.peak_power = pmax > 0.0 ? res.range.peak_power * res.azimuth.peak_power / pmax : 0.0;
    res.islr_db = db10((res.range.sidelobe_energy + res.azimuth.sidelobe_energy) /
                       (res.range.mainlobe_energy + res.azimuth.mainlobe_energy));
    res.pslr_db = std::isnan(res.range.pslr_db) ? res.azimuth.pslr_db
                  : std::isnan(res.azimuth.pslr_db)
                      ? res.range.pslr_db
                      : std::max(res.range.pslr_db, res.azimuth.pslr_db);

    res.noise_pixels = region_pixels;
    res.noise_power = region_pixels ? cabs2 * err_region / region_pixels : nan_v;
    res.snr_out_db = db10(res.peak_power / res.noise_power);

    // Extended-scene figures (second paper, section 3.2.1). The target's energy is that of
    // the calibrated reference, |c_hat|^2 <ref, ref>.
    res.image_entropy = image_entropy(img, lines * bins);
    res.epi =
        lines >= 3 && bins >= 3 ? edge_preservation_index(ref, img, lines, bins, d_amp) : nan_v;
    // Kept for the next aperture (a per-aperture free fragments glibc's arenas) unless above
    // glibc's largest mmap threshold (32 MiB on 64 bits): such a block is unmapped on free,
    // fragmenting nothing, and a paper aperture's 43 MB would otherwise stay resident.
    if (d_amp.capacity() * sizeof(double) > (std::size_t(32) << 20))
        std::vector<double>().swap(d_amp);
    double ref_energy = 0.0;
    for (std::size_t i = 0; i < lines * bins; ++i)
        ref_energy += std::norm(std::complex<double>(ref[i]));
    res.nesz_db = nesz_db(res.noise_power, cabs2 * ref_energy, cfg.reference_rcs_m2, cfg.pixel_area_m2);
    return res;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
