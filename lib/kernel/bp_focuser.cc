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
#include <cstdint>
#include <cstring>
#include <map>
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

// Recursive FFBP: 1..8 levels, more than one only with FFBP, merging 2..16 at a time.
void check_ffbp_levels(unsigned levels,
                       unsigned factor,
                       unsigned subaperture,
                       const char* levels_name,
                       const char* factor_name,
                       const char* subaperture_name)
{
    check_range(levels_name, levels, 1u, 8u);
    if (levels == 1)
        return;
    if (subaperture < 2)
        throw_param(levels_name, levels, std::string("must be 1 without FFBP (") +
                                             subaperture_name + " < 2)");
    check_range(factor_name, factor, 2u, 16u);
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
    check_ffbp_levels(ffbp_levels, ffbp_merge_factor, ffbp_subaperture, "ffbp_levels",
                      "ffbp_merge_factor", "ffbp_subaperture");
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
    check_ffbp_levels(levels, merge_factor, subaperture, "levels", "merge_factor", "subaperture");
}

// Per-thread FFT plans and scratch.
struct bp_focuser::worker {
    fft_fwd fwd;
    fft_rev rev;
    std::vector<int> idx, beam;
    std::vector<float> mu, nu, frac, sine;
    std::vector<double> r, h; // the exact BP's distances from one line to the next
    std::vector<gr_complex> demod; // K: exp(-j 2 pi fc_r k) / K (inverse-FFT scale folded in)
    // FFBP: the plans of the polar subimages' rows, per row length (K + 2 E bins).
    std::map<unsigned, std::pair<fft_fwd, fft_rev>> sub_plans;

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

// FFBP: a polar subimage's interpolation job for worker w (its rows, beams and centre).
template <typename W, typename N>
bp_detail::merge_job polar_job(const bp_grid& g, W& w, const N& nd)
{
    const unsigned U = g.upsample;
    bp_detail::merge_job m;
    m.l = range_job(g, U, w);
    m.l.ax = nd.ctr[0];
    m.l.pos_offset = U * nd.first_p / g.range_bin_m; // the polar rows start E bins earlier
    m.l.profile = nd.up.data();
    m.l.last = static_cast<int>(U * (nd.Kp - 1)) - 1;
    m.u0 = nd.u0;
    m.inv_du = 1.0 / nd.du;
    m.last_beam = static_cast<int>(nd.B) - 2;
    m.row = static_cast<size_t>(nd.Kp) * U;
    m.beam = w.beam.data();
    m.nu = w.nu.data();
    return m;
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

// One polar subimage of FFBP: its subaperture, centre, beams and range rows, the points of
// the imaged surface at (r_i, u_b), the subimage (summed modulated) and its upsampled rows.
struct bp_focuser::polar_node {
    unsigned s0 = 0, c = 0; // pulses s0 .. s0 + c - 1 of the add() call
    std::array<double, 3> ctr{};
    double dz = 0.0, u0 = 0.0, du = 0.0, first_p = 0.0;
    unsigned B = 0, Kp = 0;
    std::vector<double> px, py;
    std::vector<float> pvalid;
    std::vector<gr_complex> sub, up;
};

// The subimage's centre, beams and polar points, its sum zeroed. Its beams span the
// pixels' direction cosines along track as seen from the centre and, for a subimage merged
// into a larger one (parent), those of the parent's first and last beams. False: no pixel
// on the surface.
bool bp_focuser::plan_node(polar_node& nd,
                           const std::array<double, 3>* antenna,
                           const polar_node* parent)
{
    const unsigned K = d_grid.num_range_bins;
    const double rho = d_grid.range_bin_m, first = d_grid.first_range_m;
    const double cs = 2.0 / d_grid.wavelength_m + d_grid.range_centre_cycles / rho;
    const unsigned M = d_grid.num_lines;
    const double y0 = line_y(0), y1 = line_y(M - 1);
    nd.ctr = antenna[nd.s0 + nd.c / 2];
    const std::array<double, 3>& ctr = nd.ctr;
    const double dz = d_surface_z - ctr[2];
    nd.dz = dz;
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
    if (parent)
        for (unsigned b : { 0u, parent->B - 1 })
            for (unsigned i = 0; i < parent->Kp; ++i) {
                const size_t o = static_cast<size_t>(b) * parent->Kp + i;
                if (parent->pvalid[o] == 0.0f)
                    continue;
                const double dx = parent->px[o] - ctr[0], dy = parent->py[o] - ctr[1];
                const double u = dy / std::sqrt(dx * dx + dy * dy + dz * dz);
                umin = std::min(umin, u);
                umax = std::max(umax, u);
            }
    if (umin > umax)
        return false;
    // Nyquist beam spacing of the subaperture: the baseband phase 2 pi cs (R_p - r)
    // changes with u by at most cs D / sqrt(1 - u^2) cycles per unit.
    double dmax = 0.0;
    for (unsigned p = 0; p < nd.c; ++p) {
        const auto& a = antenna[nd.s0 + p];
        dmax = std::max(dmax, std::hypot(a[0] - ctr[0], a[1] - ctr[1], a[2] - ctr[2]));
    }
    const double umag = std::min(0.999, std::max(std::abs(umin), std::abs(umax)));
    const double band = 2.0 * cs * dmax / std::sqrt(1.0 - umag * umag);
    const double span = std::max(umax - umin, 1e-9);
    const double du = band > 0.0 ? std::min(span, 1.0 / (band * d_grid.beam_oversample)) : span;
    nd.B = static_cast<unsigned>(std::ceil(span / du)) + 3;
    nd.u0 = umin - du;
    nd.du = du;

    // Polar points: range r_i x beam u_b on the imaged surface. The ranges are the
    // input bins and E more on either side: a pixel up to D beyond the input window
    // still sees pulses inside it.
    const unsigned E = static_cast<unsigned>(std::ceil(dmax / rho)) + 1;
    nd.Kp = K + 2 * E;
    nd.first_p = first - E * rho;
    const size_t BK = static_cast<size_t>(nd.B) * nd.Kp;
    nd.px.resize(BK);
    nd.py.resize(BK);
    nd.pvalid.resize(BK);
    for (unsigned b = 0; b < nd.B; ++b) {
        const double u = nd.u0 + b * du;
        for (unsigned i = 0; i < nd.Kp; ++i) {
            const double r = nd.first_p + i * rho;
            const double g2 = r * r * (1.0 - u * u) - dz * dz;
            const size_t o = static_cast<size_t>(b) * nd.Kp + i;
            nd.px[o] = ctr[0] + std::sqrt(std::max(g2, 0.0));
            nd.py[o] = ctr[1] + u * r;
            nd.pvalid[o] = g2 > 0.0 && r > 0.0 ? 1.0f : 0.0f;
        }
    }
    nd.sub.assign(BK, gr_complex(0.0f, 0.0f));
    nd.up.resize(BK * d_grid.upsample);
    prepare_workers(nd.Kp);
    return true;
}

// The workers' plans of Kp-bin polar rows and their scratch for Kp points.
void bp_focuser::prepare_workers(unsigned Kp)
{
    const unsigned U = d_grid.upsample;
    for (auto& w : d_workers) {
        auto& plans = w->sub_plans[Kp];
        if (!plans.first) {
            plans.first = make_fft_fwd(Kp, 1);
            plans.second = make_fft_rev(Kp * U, 1);
        }
        const size_t n = std::max<size_t>(Kp, w->idx.size());
        for (auto* v : { &w->mu, &w->nu, &w->frac, &w->sine })
            v->resize(n);
        w->idx.resize(n);
        w->beam.resize(n);
    }
}

// Pulses per subimage at this depth of the tree (0: those merged onto the image), at most n.
unsigned bp_focuser::node_pulses(unsigned depth, unsigned n) const
{
    std::uint64_t p = d_grid.subaperture;
    for (unsigned l = depth + 1; l < d_grid.levels && p < n; ++l)
        p *= d_grid.merge_factor;
    return static_cast<unsigned>(std::min<std::uint64_t>(p, n));
}

void bp_focuser::add_ffbp(const gr_complex* pulses,
                          unsigned n,
                          const std::array<double, 3>* antenna)
{
    const unsigned top = node_pulses(0, n); // the subapertures merged onto the image
    while (d_nodes.size() < d_grid.levels)
        d_nodes.push_back(std::make_unique<polar_node>());
    polar_node& root = *d_nodes[0];
    for (unsigned s0 = 0; s0 < n; s0 += top) {
        root.s0 = s0;
        root.c = std::min(top, n - s0);
        if (!plan_node(root, antenna, nullptr))
            return; // no pixel on the surface
        d_beams = root.B;
        build_node(0, pulses, antenna);
        merge_onto_image(root);
    }
}

// The subimage at this depth of the tree: the last level back-projects its pulses, the
// others merge the next level's subimages, built one after the other into one node.
void bp_focuser::build_node(unsigned depth,
                            const gr_complex* pulses,
                            const std::array<double, 3>* antenna)
{
    polar_node& nd = *d_nodes[depth];
    if (depth + 1 == d_grid.levels) {
        back_project_leaf(nd, pulses, antenna);
    } else {
        const unsigned span = node_pulses(depth + 1, nd.c);
        polar_node& ch = *d_nodes[depth + 1];
        for (unsigned s = 0; s < nd.c; s += span) {
            ch.s0 = nd.s0 + s;
            ch.c = std::min(span, nd.c - s);
            if (!plan_node(ch, antenna, &nd))
                continue;
            build_node(depth + 1, pulses, antenna);
            merge_child(nd, ch);
        }
    }
    upsample_node(nd);
}

// Stage 1: the subaperture's pulses onto the beams (the threads split the beams).
void bp_focuser::back_project_leaf(polar_node& nd,
                                   const gr_complex* pulses,
                                   const std::array<double, 3>* antenna)
{
    const unsigned K = d_grid.num_range_bins;
    const unsigned U = d_grid.upsample;
    const size_t L = static_cast<size_t>(K) * U;
    const double zs = d_surface_z;
    d_prof.resize(L * nd.c);
    upsample_pulses(pulses + static_cast<size_t>(nd.s0) * K, nd.c, d_prof.data());
    split(d_threads, nd.B, [&](unsigned t, unsigned lo, unsigned hi) {
        worker& w = *d_workers[t];
        bp_detail::line_job j = range_job(d_grid, U, w);
        j.K = nd.Kp; // the polar points, read from the pulses' K bins
        for (unsigned b = lo; b < hi; ++b) {
            const size_t o = static_cast<size_t>(b) * nd.Kp;
            j.ground = &nd.px[o];
            j.py = &nd.py[o];
            j.valid = &nd.pvalid[o];
            j.acc = &nd.sub[o];
            for (unsigned p = 0; p < nd.c; ++p) {
                const auto& a = antenna[nd.s0 + p];
                j.ax = a[0];
                j.ay = a[1];
                j.c = (zs - a[2]) * (zs - a[2]);
                j.profile = &d_prof[p * L];
                if (d_simd)
                    bp_detail::project_line_avx2(j);
                else
                    bp_detail::project_line_body(j);
            }
        }
    });
}

// Recursive FFBP: every point of the parent's subimage takes the child's at its own (r, u)
// (the threads split the parent's beams), remodulated like a pulse's sample.
void bp_focuser::merge_child(polar_node& P, const polar_node& ch)
{
    split(d_threads, P.B, [&](unsigned t, unsigned lo, unsigned hi) {
        worker& w = *d_workers[t];
        bp_detail::merge_job m = polar_job(d_grid, w, ch);
        m.l.K = P.Kp;
        m.l.ay = ch.ctr[1];
        m.l.c = ch.dz * ch.dz;
        for (unsigned b = lo; b < hi; ++b) {
            const size_t o = static_cast<size_t>(b) * P.Kp;
            m.l.ground = &P.px[o];
            m.l.py = &P.py[o];
            m.l.valid = &P.pvalid[o];
            m.l.acc = &P.sub[o];
            if (d_simd)
                bp_detail::merge_line_avx2(m);
            else
                bp_detail::merge_line_body(m);
        }
    });
}

// Each beam to baseband (exp(-j 2 pi (cs r_i - co)) removed, the phase in double) and
// upsampled U times in range (the threads split the beams).
void bp_focuser::upsample_node(polar_node& nd)
{
    const double rho = d_grid.range_bin_m, first = d_grid.first_range_m;
    const double fcr = d_grid.range_centre_cycles;
    const double cs = 2.0 / d_grid.wavelength_m + fcr / rho;
    const double co = fcr * first / rho;
    const size_t Lp = static_cast<size_t>(nd.Kp) * d_grid.upsample;
    d_base.resize(nd.Kp); // the same for every beam
    for (unsigned i = 0; i < nd.Kp; ++i) {
        const double cyc = cs * (nd.first_p + i * rho) - co;
        const double ph = -2.0 * M_PI * (cyc - std::nearbyint(cyc));
        d_base[i] =
            gr_complex(static_cast<float>(std::cos(ph)), static_cast<float>(std::sin(ph)));
    }
    split(d_threads, nd.B, [&](unsigned t, unsigned lo, unsigned hi) {
        auto& plans = d_workers[t]->sub_plans[nd.Kp];
        for (unsigned b = lo; b < hi; ++b) {
            const size_t o = static_cast<size_t>(b) * nd.Kp;
            for (unsigned i = 0; i < nd.Kp; ++i)
                nd.sub[o + i] *= d_base[i];
            upsample_row(*plans.first, *plans.second, &nd.sub[o], nullptr, &nd.up[b * Lp]);
        }
    });
}

// Stage 2: every pixel takes the subimage at its own (r, u) (the threads split the lines).
void bp_focuser::merge_onto_image(const polar_node& nd)
{
    const unsigned K = d_grid.num_range_bins;
    split(d_threads, d_grid.num_lines, [&](unsigned t, unsigned lo, unsigned hi) {
        worker& w = *d_workers[t];
        bp_detail::merge_job m = polar_job(d_grid, w, nd);
        m.l.ground = d_ground.data();
        m.l.valid = d_valid.data();
        for (unsigned line = lo; line < hi; ++line) {
            m.dy = line_y(line) - nd.ctr[1];
            m.l.c = m.dy * m.dy + nd.dz * nd.dz;
            m.l.acc = &d_image[static_cast<size_t>(line) * K];
            if (d_simd)
                bp_detail::merge_line_avx2(m);
            else
                bp_detail::merge_line_body(m);
        }
    });
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
