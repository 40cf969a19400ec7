/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "fmod_two_pi.h"
#include "param_check.h"
#include "bessel_i0.h"
#include "gaussian_noise_impl.h" // noise_detail::avx2_available()
#include "td_echo_impl.h"
#include <gnuradio/nrsar/kernel/td_echo.h>
#include <volk/volk.h>
#include <algorithm>
#include <cmath>

namespace gr {
namespace nrsar {
namespace kernel {

multipath_fir::multipath_fir(unsigned taps, double kaiser_beta, unsigned max_lag)
    : d_simd(noise_detail::avx2_available()),
      d_avx512(d_simd && td_detail::avx512_available()),
      d_taps(taps),
      d_beta(kaiser_beta),
      d_max_lag(max_lag)
{
    if (taps < 2 || taps > 256 || taps % 2 != 0)
        throw_param("taps", taps, "must be even and in [2, 256]");
    check_range("kaiser_beta", kaiser_beta, 0.0, 50.0);
    check_at_least("max_lag", max_lag, taps);
    d_i0_beta = bessel_i0(kaiser_beta);
    d_acc.resize(max_lag + 1);
    d_grev.resize(max_lag + 1);
    d_tail.resize(max_lag + 4);
}

double multipath_fir::default_beta(unsigned taps, double band_edge)
{
    // Kaiser's formulas (Oppenheim & Schafer 7.6): attenuation A [dB] reachable with
    // L - 1 = (A - 7.95) / (14.36 dF), dF the transition width in cycles/sample.
    const double df = std::max(0.0, 2.0 * (0.5 - band_edge));
    const double a = std::min(150.0, 14.36 * df * (double(taps) - 1.0) + 7.95);
    if (a > 50.0)
        return 0.1102 * (a - 8.7);
    if (a >= 21.0)
        return 0.5842 * std::pow(a - 21.0, 0.4) + 0.07886 * (a - 21.0);
    return 0.0;
}

double multipath_fir::kernel(double t) const
{
    const double half = d_taps / 2.0;
    if (std::abs(t) >= half)
        return 0.0;
    const double s = (t == 0.0) ? 1.0 : std::sin(M_PI * t) / (M_PI * t);
    const double u = t / half;
    return s * bessel_i0(d_beta * std::sqrt(std::max(0.0, 1.0 - u * u))) / d_i0_beta;
}

std::size_t multipath_fir::set_paths(const echo_path* paths, std::size_t n)
{
    const int half = static_cast<int>(d_taps / 2);
    const int max_lag = static_cast<int>(d_max_lag);
    int lo = max_lag + 1, hi = -1;
    std::size_t dropped = 0;
    double w[256];
    for (std::size_t p = 0; p < n; p++) {
        const double d = paths[p].delay_samples;
        const std::complex<double> a = paths[p].gain;
        if (!(std::isfinite(d) && d >= 0.0 && d <= max_lag - half) ||
            !(std::isfinite(a.real()) && std::isfinite(a.imag()))) {
            dropped++;
            continue;
        }
        const double fl = std::floor(d);
        const double mu = d - fl;
        const int D = static_cast<int>(fl);
        if (mu < 1e-9 || mu > 1.0 - 1e-9) { // integer delay: one exact tap
            const int l = mu < 0.5 ? D : D + 1;
            d_acc[l] += a;
            lo = std::min(lo, l);
            hi = std::max(hi, l);
            continue;
        }
        // lags l = D - L/2 + 1 .. D + L/2, weight h(l - d), normalised to unit DC gain.
        const int l0 = D - half + 1;
        double sum = 0.0;
        for (unsigned j = 0; j < d_taps; j++) {
            w[j] = kernel(l0 + int(j) - d);
            sum += w[j];
        }
        for (unsigned j = 0; j < d_taps; j++) {
            const int l = l0 + int(j);
            if (l < 0) // causal: no look-ahead (delays below L/2 samples)
                continue;
            d_acc[l] += a * (w[j] / sum);
            lo = std::min(lo, l);
            hi = std::max(hi, l);
        }
    }
    d_lag_lo = lo;
    d_lag_hi = hi;
    for (int l = lo; l <= hi; l++) {
        d_grev[hi - l] =
            gr_complex(static_cast<float>(d_acc[l].real()), static_cast<float>(d_acc[l].imag()));
        d_acc[l] = 0.0;
    }
    return dropped;
}

void multipath_fir::filter(const gr_complex* x, gr_complex* y, std::size_t n) const
{
    if (d_lag_lo > d_lag_hi) {
        std::fill(y, y + n, gr_complex(0.0f, 0.0f));
        return;
    }
    const unsigned span = static_cast<unsigned>(d_lag_hi - d_lag_lo + 1);
    if (span == 1) { // one integer delay: a scaled copy
        volk_32fc_s32fc_multiply_32fc(y, x - d_lag_hi, d_grev[0], n);
        return;
    }
    const gr_complex* g = d_grev.data();
    const gr_complex* xs = x - d_lag_hi;
    if (d_simd) {
        (d_avx512 ? td_detail::fir_avx512 : td_detail::fir_avx2)(xs, g, span, y, n, d_tail.data());
        return;
    }
    for (std::size_t i = 0; i < n; i++)
        volk_32fc_x2_dot_prod_32fc(y + i, xs + i, g, span);
}

void multipath_fir::set_simd(bool allow)
{
    d_simd = allow && noise_detail::avx2_available();
    d_avx512 = d_simd && td_detail::avx512_available();
}

void multipath_fir::set_avx512(bool allow)
{
    d_avx512 = allow && d_simd && td_detail::avx512_available();
}

td_echo::td_echo(const numerology& num,
                 const geometry& geo,
                 const scene& scn,
                 unsigned taps,
                 double kaiser_beta,
                 const antenna_beam& beam,
                 const trajectory& path)
    : d_num(num),
      d_geo(geo),
      d_beam(beam),
      d_path(path),
      d_line(flies_ideal_line(path, geo)),
      d_sym(num.cp_samples + num.fft_size),
      d_fir(taps,
            kaiser_beta < 0.0
                ? multipath_fir::default_beta(
                      taps,
                      double(std::max(num.dc_subcarrier(),
                                      num.num_subcarriers - num.dc_subcarrier())) /
                          num.fft_size)
                : kaiser_beta,
            num.cp_samples + num.fft_size + taps / 2)
{
    d_num.validate();
    d_geo.validate();
    d_beam.validate();
    set_scene(scn);
    d_z.resize(d_sym);
}

double td_echo::band_edge() const
{
    const unsigned k0 = d_num.dc_subcarrier();
    return double(std::max(k0, d_num.num_subcarriers - k0)) / d_num.fft_size;
}

void td_echo::set_scene(const scene& scn)
{
    scn.validate();
    d_scene = scn;
    d_paths.clear();
    d_cur_m = ~std::uint64_t(0); // rebuild the filter at the next sample
}

std::vector<echo_path> td_echo::paths(std::uint64_t m) const
{
    // eq. (8): y_p = track_start + v t_m, t_m = m Tsym, all in double.
    const double yp = d_geo.track_start_m +
                      d_geo.velocity_mps * (static_cast<double>(m) * d_num.symbol_s());
    antenna_pose pose;
    if (!d_line)
        pose = antenna_pose::of(d_path, static_cast<double>(m) * d_num.symbol_s());
    const vec3& p = pose.position;
    const double fs = d_num.sample_rate_hz();
    const double f_rf = d_geo.carrier_hz + d_num.dc_subcarrier() * d_num.subcarrier_spacing_hz;
    std::vector<echo_path> out;
    out.reserve(d_scene.targets.size());
    for (const auto& t : d_scene.targets) {
        if (!(t.rcs > 0.0))
            continue;
        double R = t.slant_range_m(d_geo, yp); // eq. (8)
        if (!d_line) {                         // the true path: exact range from p(t_m)
            const double dx = t.x_m - p[0], dy = p[1] - t.y_m;
            R = std::sqrt(dx * dx + p[2] * p[2] + dy * dy);
        }
        // two-way beam amplitude, eqs. (1)-(3) (1 for WHOLE_BLOCK)
        const double g = d_line ? d_beam.azimuth_gain(d_geo, t.y_m - yp, R) *
                                      d_beam.elevation_gain(d_geo, t.x_m)
                                : d_beam.gain(d_geo, pose, t.x_m, t.y_m, R);
        if (g == 0.0)
            continue; // outside the beam
        const double tau = 2.0 * R / speed_of_light;
        // carrier term e^{-j 2 pi (fc + k0 Delta f) tau}: the phase is ~1.5e5 rad, so it
        // is reduced modulo 2 pi in double before the sincos.
        const double phi = t.phase_rad - fmod_two_pi(2.0 * M_PI * f_rf * tau);
        echo_path p;
        p.delay_samples = tau * fs;
        p.gain = std::polar(g * std::sqrt(t.rcs), phi);
        out.push_back(p);
    }
    return out;
}

std::uint64_t td_echo::process(std::uint64_t s0,
                               const gr_complex* x,
                               gr_complex* y,
                               std::size_t n,
                               const gaussian_noise* noise,
                               float sigma)
{
    const bool with_noise = noise && sigma > 0.0f;
    std::size_t i = 0;
    while (i < n) {
        const std::uint64_t s = s0 + i;
        const std::uint64_t m = s / d_sym;
        const std::size_t off = static_cast<std::size_t>(s - m * d_sym);
        const std::size_t len = std::min<std::size_t>(n - i, d_sym - off);
        if (m != d_cur_m) { // stop-and-go: one set of delays per symbol
            d_paths = paths(m);
            d_dropped += d_fir.set_paths(d_paths.data(), d_paths.size());
            d_cur_m = m;
        }
        d_fir.filter(x + i, y + i, len);
        if (with_noise) {
            if (off == 0 && len == d_sym) {
                noise->add(m, sigma, y + i, len);
            } else {
                // Partial symbol (a work() call boundary): the whole symbol's noise is drawn
                // once and kept, so small calls do not redraw it.
                if (d_z_m != m || d_z_sigma != sigma || d_z_seed != noise->seed()) {
                    noise->generate(m, sigma, d_z.data(), d_sym);
                    d_z_m = m;
                    d_z_sigma = sigma;
                    d_z_seed = noise->seed();
                }
                volk_32f_x2_add_32f(reinterpret_cast<float*>(y + i),
                                    reinterpret_cast<const float*>(y + i),
                                    reinterpret_cast<const float*>(d_z.data() + off),
                                    2 * len);
            }
        }
        i += len;
    }
    return d_dropped;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
