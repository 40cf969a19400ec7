/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "../param_check.h"
#include "bp_focuser_impl.h"
#include "gaussian_noise_impl.h" // noise_detail::avx2_available
#include <gnuradio/nrsar/bp_config.h>
#include <gnuradio/nrsar/kernel/bp_autofocus.h>
#include <gnuradio/nrsar/kernel/bp_focuser.h>
#include <gnuradio/nrsar/kernel/fft_plans.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>

namespace gr {
namespace nrsar {

namespace {
// The short sinc: 0 (off) or an even 2..32, not with FFBP (its subimages are upsampled).
void check_sinc_taps(unsigned taps, unsigned subaperture, const char* subaperture_name)
{
    if (taps == 0)
        return;
    check_range("sinc_taps", taps, 2u, 32u);
    if (taps % 2)
        throw_param("sinc_taps", taps, "must be even (0: upsampled linear)");
    if (subaperture > 1)
        throw_param("sinc_taps", taps, std::string("must be 0 with FFBP (") + subaperture_name +
                                           " > 1)");
}
} // namespace

void bp_config::validate() const
{
    check_at_least("symbols_per_pulse", symbols_per_pulse, 1u);
    check_range("line_step", line_step, 1u, 4096u);
    if (line_step > 1 && trajectory_autofocus)
        throw_param("line_step", line_step,
                    "must be 1 with trajectory_autofocus (it estimates on one line per pulse)");
    check_range("upsample", upsample, 1u, 64u);
    if (!std::isfinite(band_margin_hz))
        throw_param("band_margin_hz", band_margin_hz, "must be finite (< 0: automatic)");
    if (!std::isnan(range_centre_cycles))
        check_range("range_centre_cycles", range_centre_cycles, -1.0, 1.0);
    check_range("num_threads", num_threads, 1u, 2u);
    check_finite("ground_height_m", ground_height_m);
    if (!std::isnan(ground_first_x_m))
        check_finite("ground_first_x_m", ground_first_x_m);
    if (!(ground_spacing_m >= 0.0 && std::isfinite(ground_spacing_m)))
        throw_param("ground_spacing_m", ground_spacing_m, "must be finite and >= 0 (0: automatic)");
    check_range("ffbp_beam_oversample", ffbp_beam_oversample, 1.0, 64.0);
    check_sinc_taps(sinc_taps, ffbp_subaperture, "ffbp_subaperture");
    check_range("autofocus_iterations", autofocus_iterations, 1u, 50u);
    check_range("autofocus_points", autofocus_points, 1u, 64u);
    if (!(std::isfinite(autofocus_tolerance_m) && autofocus_tolerance_m > 0.0 &&
          autofocus_tolerance_m < 1.0))
        throw_param("autofocus_tolerance_m", autofocus_tolerance_m, "must be in (0, 1)");
    check_range("autofocus_significance", autofocus_significance, 0.0, 100.0);
    check_finite_points(
        "autofocus_gcp", autofocus_gcp, kernel::trajectory_autofocus_config::max_gcp);
    check_range("autofocus_gcp_along_track_se_m", autofocus_gcp_along_track_se_m, 0.0, 1.0);
    check_range("autofocus_gcp_speed_se_mps", autofocus_gcp_speed_se_mps, 0.0, 1.0);
}

namespace kernel {

void bp_grid::validate() const
{
    check_at_least("num_range_bins", num_range_bins, 2u);
    if (!std::isfinite(first_range_m) || first_range_m < 0.0)
        throw_param("first_range_m", first_range_m, "must be finite and >= 0");
    check_finite_positive("range_bin_m", range_bin_m);
    check_finite_positive("wavelength_m", wavelength_m);
    check_range("range_centre_cycles", range_centre_cycles, -1.0, 1.0);
    check_range("upsample", upsample, 1u, 64u);
    check_at_least("num_lines", num_lines, 1u);
    check_finite("first_y_m", first_y_m);
    check_finite_positive("line_spacing_m", line_spacing_m);
    check_range("line_step", line_step, 1u, 4096u);
    check_finite_positive("reference_height_m", reference_height_m);
    if (ground) {
        check_finite("first_x_m", first_x_m);
        check_finite_positive("x_spacing_m", x_spacing_m);
        check_finite("ground_height_m", ground_height_m);
    }
    check_range("beam_oversample", beam_oversample, 1.0, 64.0);
    check_sinc_taps(sinc_taps, subaperture, "subaperture");
}

// Per-thread FFT plans and scratch.
struct bp_focuser::worker {
    fft_fwd fwd;
    fft_rev rev;
    std::vector<int> idx, beam;
    std::vector<float> mu, nu, frac, sine;
    std::vector<double> r, h; // the exact BP's distances from one line to the next
    std::vector<gr_complex> demod; // K: exp(-j 2 pi fc_r k) / K (inverse-FFT scale folded in)
    // FFBP: the plans of the polar subimage's rows (K + 2 E bins), made when E changes.
    fft_fwd sub_fwd;
    fft_rev sub_rev;

    worker(const bp_grid& g)
        : fwd(make_fft_fwd(g.num_range_bins, 1)),
          rev(make_fft_rev(g.num_range_bins * g.upsample, 1)),
          idx(g.num_range_bins),
          beam(g.num_range_bins),
          mu(g.num_range_bins),
          nu(g.num_range_bins),
          frac(g.num_range_bins),
          sine(g.num_range_bins),
          r(g.num_range_bins),
          h(g.num_range_bins),
          demod(g.num_range_bins)
    {
        for (unsigned k = 0; k < g.num_range_bins; ++k) {
            const double ph = -2.0 * M_PI * g.range_centre_cycles * k;
            demod[k] = gr_complex(static_cast<float>(std::cos(ph) / g.num_range_bins),
                                  static_cast<float>(std::sin(ph) / g.num_range_bins));
        }
    }
};

namespace {
constexpr unsigned chunk_pulses = 64; // pulses upsampled at once (U K x 64 samples)

// A job on the pulses' range axis, U samples per bin: position and phase scales, the last
// interpolation start, K, and the worker's scratch.
template <typename W>
bp_detail::line_job range_job(const bp_grid& g, unsigned U, W& w)
{
    bp_detail::line_job j;
    j.pos_scale = U / g.range_bin_m;
    j.pos_offset = U * g.first_range_m / g.range_bin_m;
    j.cyc_scale = 2.0 / g.wavelength_m + g.range_centre_cycles / g.range_bin_m;
    j.cyc_offset = g.range_centre_cycles * g.first_range_m / g.range_bin_m;
    j.last = static_cast<int>(U * (g.num_range_bins - 1)) - 1;
    j.K = g.num_range_bins;
    j.idx = w.idx.data();
    j.mu = w.mu.data();
    j.frac = w.frac.data();
    j.sine = w.sine.data();
    return j;
}

// fn(t, lo, hi) on [0, n) split over the threads (t = 0 runs on the caller's).
template <typename F>
void split(unsigned threads, unsigned n, F&& fn)
{
    if (threads == 1 || n < 2) {
        fn(0u, 0u, n);
        return;
    }
    std::thread other([&] { fn(1u, n / 2, n); });
    fn(0u, 0u, n / 2);
    other.join();
}
} // namespace

bp_focuser::bp_focuser(const bp_grid& grid, unsigned num_threads, bool allow_simd)
    : d_grid(grid),
      d_threads(num_threads),
      d_simd(allow_simd && noise_detail::avx2_available())
{
    d_grid.validate();
    check_range("num_threads", num_threads, 1u, 2u);
    const unsigned K = grid.num_range_bins;
    d_ground.resize(K);
    d_valid.resize(K);
    const double h = grid.reference_height_m;
    d_surface_z = grid.ground ? grid.ground_height_m : 0.0;
    for (unsigned k = 0; k < K; ++k) {
        const double r0 = grid.first_range_m + k * grid.range_bin_m;
        const bool ok = grid.ground || r0 > h;
        d_ground[k] = grid.ground ? grid.first_x_m + k * grid.x_spacing_m
                                  : (ok ? std::sqrt((r0 - h) * (r0 + h)) : 0.0);
        d_valid[k] = ok ? 1.0f : 0.0f;
    }
    d_image.assign(static_cast<size_t>(grid.num_lines) * K, gr_complex(0.0f, 0.0f));
    if (grid.sinc_taps)
        d_sinc = std::make_unique<sinc_interpolator>(grid.sinc_taps);
    d_stride = grid.sinc_taps ? K + grid.sinc_taps : static_cast<size_t>(K) * grid.upsample;
    for (unsigned t = 0; t < num_threads; ++t)
        d_workers.push_back(std::make_unique<worker>(d_grid));
}

bp_focuser::~bp_focuser() = default;

void bp_focuser::reset(double first_y_m)
{
    check_finite("first_y_m", first_y_m);
    d_grid.first_y_m = first_y_m;
    std::fill(d_image.begin(), d_image.end(), gr_complex(0.0f, 0.0f));
    d_pulses = 0;
}

namespace {
// K-point FFT of in (times demod[k], or 1 / K without), zero padding in the middle (the
// spectrum is centred at 0), U K-point inverse FFT: out[U k] = in[k] (demod[k] K).
void upsample_row(gr::fft::fft_complex_fwd& fwd,
                  gr::fft::fft_complex_rev& rev,
                  const gr_complex* in,
                  const gr_complex* demod,
                  gr_complex* out)
{
    const unsigned K = fwd.inbuf_length();
    const unsigned L = rev.inbuf_length();
    gr_complex* ib = fwd.get_inbuf();
    const float scale = 1.0f / K;
    for (unsigned k = 0; k < K; ++k)
        ib[k] = demod ? in[k] * demod[k] : in[k] * scale;
    fwd.execute();
    const gr_complex* spec = fwd.get_outbuf();
    gr_complex* rb = rev.get_inbuf();
    const unsigned pos = (K + 1) / 2, neg = K / 2;
    std::memcpy(rb, spec, sizeof(gr_complex) * pos);
    std::fill(rb + pos, rb + L - neg, gr_complex(0.0f, 0.0f));
    std::memcpy(rb + L - neg, spec + K - neg, sizeof(gr_complex) * neg);
    rev.execute();
    std::memcpy(out, rev.get_outbuf(), sizeof(gr_complex) * L);
}
} // namespace

// Demodulated by exp(-j 2 pi fc_r k) (the spectrum to 0) and upsampled; for the short sinc
// demodulated only, between taps / 2 zeros on either side.
void bp_focuser::upsample(worker& w, const gr_complex* pulse, gr_complex* out)
{
    if (!d_sinc) {
        upsample_row(*w.fwd, *w.rev, pulse, w.demod.data(), out);
        return;
    }
    const unsigned K = d_grid.num_range_bins, half = d_grid.sinc_taps / 2;
    std::fill(out, out + half, gr_complex(0.0f, 0.0f));
    for (unsigned k = 0; k < K; ++k)
        out[half + k] = pulse[k] * w.demod[k] * static_cast<float>(K); // demod carries 1 / K
    std::fill(out + half + K, out + 2 * half + K, gr_complex(0.0f, 0.0f));
}

void bp_focuser::project_lines(worker& w,
                               unsigned line0,
                               unsigned line1,
                               const gr_complex* profiles,
                               unsigned n,
                               const std::array<double, 3>* antenna)
{
    const unsigned K = d_grid.num_range_bins;
    const unsigned U = d_sinc ? 1 : d_grid.upsample; // the sinc reads the input bins
    const size_t L = d_stride;
    bp_detail::line_job j = range_job(d_grid, U, w);
    if (d_sinc) {
        j.sinc_table = d_sinc->phase_taps(0.0);
        j.sinc_taps = d_sinc->taps();
        j.sinc_phases = static_cast<float>(d_sinc->phases());
    }
    j.ground = d_ground.data();
    j.valid = d_valid.data();
    j.r = w.r.data();
    j.h = w.h.data();
    // Tiles of lines: a pulse's profile (U K samples, K + taps) is read for every line of the tile
    // while it is in L1, and the tile's accumulators stay in L2.
    const unsigned tile = std::max(1u, 16384u / K);
    for (unsigned t0 = line0; t0 < line1; t0 += tile) {
        const unsigned t1 = std::min(line1, t0 + tile);
        for (unsigned p = 0; p < n; ++p) {
            j.ax = antenna[p][0];
            j.profile = profiles + p * L;
            j.c_last = -1.0; // the pulse's first line: r and h from sqrt
            for (unsigned line = t0; line < t1; ++line) {
                const double dy = line_y(line) - antenna[p][1];
                const double dz = d_surface_z - antenna[p][2];
                j.c = dy * dy + dz * dz;
                j.acc = &d_image[static_cast<size_t>(line) * K];
                if (d_simd)
                    bp_detail::project_line_avx2(j);
                else
                    bp_detail::project_line_body(j);
                j.c_last = j.c;
            }
        }
    }
}

void bp_focuser::add(const gr_complex* pulses, unsigned n, const std::array<double, 3>* antenna)
{
    for (unsigned p = 0; p < n; ++p)
        for (int ax = 0; ax < 3; ++ax)
            check_finite("antenna position", antenna[p][ax]);
    if (d_grid.subaperture > 1)
        add_ffbp(pulses, n, antenna);
    else
        add_bp(pulses, n, antenna);
    d_pulses += n;
}

// The n pulses' upsampled profiles into prof (n x U K), the threads taking every other one.
void bp_focuser::upsample_pulses(const gr_complex* pulses, unsigned n, gr_complex* prof)
{
    const unsigned K = d_grid.num_range_bins;
    const size_t L = d_stride;
    auto part = [&](unsigned t) {
        for (unsigned p = t; p < n; p += d_threads)
            upsample(*d_workers[t], pulses + static_cast<size_t>(p) * K, prof + p * L);
    };
    if (d_threads == 1 || n < 2) {
        part(0);
        return;
    }
    std::thread other(part, 1u);
    part(0);
    other.join();
}

void bp_focuser::add_bp(const gr_complex* pulses, unsigned n, const std::array<double, 3>* antenna)
{
    const unsigned K = d_grid.num_range_bins;
    const size_t L = d_stride;
    d_prof.resize(L * std::min(n, chunk_pulses));
    for (unsigned p0 = 0; p0 < n; p0 += chunk_pulses) {
        const unsigned c = std::min(chunk_pulses, n - p0);
        upsample_pulses(pulses + static_cast<size_t>(p0) * K, c, d_prof.data());
        // Each thread projects the chunk onto its half of the lines.
        split(d_threads, d_grid.num_lines, [&](unsigned t, unsigned lo, unsigned hi) {
            project_lines(*d_workers[t], lo, hi, d_prof.data(), c, antenna + p0);
        });
    }
}

void bp_focuser::add_ffbp(const gr_complex* pulses,
                          unsigned n,
                          const std::array<double, 3>* antenna)
{
    const unsigned K = d_grid.num_range_bins;
    const unsigned U = d_grid.upsample;
    const size_t L = static_cast<size_t>(K) * U;
    const double rho = d_grid.range_bin_m, first = d_grid.first_range_m;
    const double fcr = d_grid.range_centre_cycles;
    const double cs = 2.0 / d_grid.wavelength_m + fcr / rho; // cycles per metre of range
    const double zs = d_surface_z;
    const unsigned M = d_grid.num_lines;
    const double y0 = line_y(0), y1 = line_y(M - 1);
    for (unsigned s0 = 0; s0 < n; s0 += d_grid.subaperture) {
        const unsigned c = std::min(d_grid.subaperture, n - s0);
        const std::array<double, 3>& ctr = antenna[s0 + c / 2];
        const double dz = zs - ctr[2];
        // The pixels' direction cosines along track as seen from the centre.
        double umin = 1.0, umax = -1.0;
        for (double y : { y0, y1 })
            for (unsigned k = 0; k < K; ++k) {
                if (d_valid[k] == 0.0f)
                    continue;
                const double dx = d_ground[k] - ctr[0], dy = y - ctr[1];
                const double u = dy / std::sqrt(dx * dx + dy * dy + dz * dz);
                umin = std::min(umin, u);
                umax = std::max(umax, u);
            }
        if (umin > umax)
            return; // no pixel on the surface
        // Nyquist beam spacing of the subaperture: the baseband phase 2 pi cs (R_p - r)
        // changes with u by at most cs D / sqrt(1 - u^2) cycles per unit.
        double dmax = 0.0;
        for (unsigned p = 0; p < c; ++p) {
            const auto& a = antenna[s0 + p];
            dmax = std::max(dmax, std::hypot(a[0] - ctr[0], a[1] - ctr[1], a[2] - ctr[2]));
        }
        const double umag = std::min(0.999, std::max(std::abs(umin), std::abs(umax)));
        const double band = 2.0 * cs * dmax / std::sqrt(1.0 - umag * umag);
        const double span = std::max(umax - umin, 1e-9);
        const double du = band > 0.0 ? std::min(span, 1.0 / (band * d_grid.beam_oversample)) : span;
        const unsigned B = static_cast<unsigned>(std::ceil(span / du)) + 3;
        const double u0 = umin - du;
        d_beams = B;

        // Polar points: range r_i x beam u_b on the imaged surface. The ranges are the
        // input bins and E more on either side: a pixel up to D beyond the input window
        // still sees pulses inside it.
        const unsigned E = static_cast<unsigned>(std::ceil(dmax / rho)) + 1;
        const unsigned Kp = K + 2 * E;
        const size_t Lp = static_cast<size_t>(Kp) * U;
        const double first_p = first - E * rho;
        const size_t BK = static_cast<size_t>(B) * Kp;
        d_px.resize(BK);
        d_py.resize(BK);
        d_pvalid.resize(BK);
        for (unsigned b = 0; b < B; ++b) {
            const double u = u0 + b * du;
            for (unsigned i = 0; i < Kp; ++i) {
                const double r = first_p + i * rho;
                const double g2 = r * r * (1.0 - u * u) - dz * dz;
                const size_t o = static_cast<size_t>(b) * Kp + i;
                d_px[o] = ctr[0] + std::sqrt(std::max(g2, 0.0));
                d_py[o] = ctr[1] + u * r;
                d_pvalid[o] = g2 > 0.0 && r > 0.0 ? 1.0f : 0.0f;
            }
        }
        for (auto& w : d_workers) {
            if (!w->sub_fwd || static_cast<unsigned>(w->sub_fwd->inbuf_length()) != Kp) {
                w->sub_fwd = make_fft_fwd(Kp, 1);
                w->sub_rev = make_fft_rev(Kp * U, 1);
            }
            for (auto* v : { &w->mu, &w->nu, &w->frac, &w->sine })
                v->resize(std::max(Kp, K));
            w->idx.resize(std::max(Kp, K));
            w->beam.resize(std::max(Kp, K));
        }
        d_sub.assign(BK, gr_complex(0.0f, 0.0f));
        d_sub_up.resize(static_cast<size_t>(B) * Lp);
        d_prof.resize(L * c);
        upsample_pulses(pulses + static_cast<size_t>(s0) * K, c, d_prof.data());

        // Stage 1: the subaperture's pulses onto the beams (the threads split the beams),
        // then each beam to baseband and upsampled.
        const double co = fcr * first / rho;
        split(d_threads, B, [&](unsigned t, unsigned lo, unsigned hi) {
            worker& w = *d_workers[t];
            bp_detail::line_job j = range_job(d_grid, U, w);
            j.K = Kp; // the polar points, read from the pulses' K bins
            for (unsigned b = lo; b < hi; ++b) {
                const size_t o = static_cast<size_t>(b) * Kp;
                j.ground = &d_px[o];
                j.py = &d_py[o];
                j.valid = &d_pvalid[o];
                j.acc = &d_sub[o];
                for (unsigned p = 0; p < c; ++p) {
                    const auto& a = antenna[s0 + p];
                    j.ax = a[0];
                    j.ay = a[1];
                    j.c = (zs - a[2]) * (zs - a[2]);
                    j.profile = &d_prof[p * L];
                    if (d_simd)
                        bp_detail::project_line_avx2(j);
                    else
                        bp_detail::project_line_body(j);
                }
                // Baseband: remove exp(j 2 pi (cs r_i - co)), the phase in double.
                for (unsigned i = 0; i < Kp; ++i) {
                    const double cyc = cs * (first_p + i * rho) - co;
                    const double ph = -2.0 * M_PI * (cyc - std::nearbyint(cyc));
                    d_sub[o + i] *= gr_complex(static_cast<float>(std::cos(ph)),
                                               static_cast<float>(std::sin(ph)));
                }
                upsample_row(*w.sub_fwd, *w.sub_rev, &d_sub[o], nullptr, &d_sub_up[b * Lp]);
            }
        });

        // Stage 2: every pixel takes the subimage at its own (r, u) (the threads split the
        // lines).
        split(d_threads, M, [&](unsigned t, unsigned lo, unsigned hi) {
            worker& w = *d_workers[t];
            bp_detail::merge_job m;
            m.l = range_job(d_grid, U, w);
            m.l.ground = d_ground.data();
            m.l.valid = d_valid.data();
            m.l.ax = ctr[0];
            m.l.pos_offset = U * first_p / rho; // the polar rows start E bins earlier
            m.l.profile = d_sub_up.data();
            m.l.last = static_cast<int>(U * (Kp - 1)) - 1;
            m.u0 = u0;
            m.inv_du = 1.0 / du;
            m.last_beam = static_cast<int>(B) - 2;
            m.row = Lp;
            m.beam = w.beam.data();
            m.nu = w.nu.data();
            for (unsigned line = lo; line < hi; ++line) {
                m.dy = line_y(line) - ctr[1];
                m.l.c = m.dy * m.dy + dz * dz;
                m.l.acc = &d_image[static_cast<size_t>(line) * K];
                if (d_simd)
                    bp_detail::merge_line_avx2(m);
                else
                    bp_detail::merge_line_body(m);
            }
        });
    }
}

void bp_focuser::image(gr_complex* out) const
{
    const float s = static_cast<float>(
        1.0 / std::sqrt(static_cast<double>(d_grid.num_lines) * d_grid.line_step));
    for (size_t i = 0; i < d_image.size(); ++i)
        out[i] = d_image[i] * s;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
