/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "bp_focuser_impl.h"
#include "azimuth_window.h"
#include "focuser_stream.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/kernel/bp_autofocus.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace gr {
namespace nrsar {

bp_focuser::sptr bp_focuser::make(const numerology& num,
                                  const geometry& geo,
                                  const scene& scn,
                                  unsigned num_range_bins,
                                  double first_range_m,
                                  double range_bin_m,
                                  const bp_config& cfg,
                                  const trajectory& nav)
{
    check_at_least("num_range_bins", num_range_bins, 2u); // before the io_signatures
    return gnuradio::make_block_sptr<bp_focuser_impl>(
        num, geo, scn, num_range_bins, first_range_m, range_bin_m, cfg, nav);
}

bp_focuser_impl::bp_focuser_impl(const numerology& num,
                                 const geometry& geo,
                                 const scene& scn,
                                 unsigned num_range_bins,
                                 double first_range_m,
                                 double range_bin_m,
                                 const bp_config& cfg,
                                 const trajectory& nav)
    : gr::block("bp_focuser",
                gr::io_signature::make(1, 1, sizeof(gr_complex) * num_range_bins),
                gr::io_signature::make(1, 1, sizeof(gr_complex) * num_range_bins)),
      d_num(num),
      d_geo(geo),
      d_scn(scn),
      d_cfg(cfg),
      d_nav(nav.empty() ? trajectory::ideal(geo) : nav),
      d_K(num_range_bins),
      d_ctor_first_range(first_range_m),
      d_ctor_range_bin(default_range_bin(num, range_bin_m))
{
    d_geo.validate();
    d_scn.validate();
    d_cfg.validate();
    if (!std::isfinite(first_range_m) || first_range_m < 0.0)
        throw_param("first_range_m", first_range_m, "must be finite and >= 0");
    // A sampled path must at least cover the first aperture (later ones are checked per
    // pulse, naming the time).
    d_nav.check_covers(0.0, d_geo.aperture_s);
    configure(d_num.symbol_s() * d_cfg.symbols_per_pulse, first_range_m, d_ctor_range_bin);
    // A strip's task starts at aperture a0 (pulse a0 M): its slow time and first line the
    // products the whole flight's run forms there, so the images are bit-identical.
    if (d_cfg.first_aperture > (std::uint64_t(1) << 32) / d_M)
        throw_param("first_aperture", d_cfg.first_aperture,
                    "times lines_per_aperture must stay below 2^32");
    d_pulse = d_cfg.first_aperture * d_M;
    d_next_y = d_y0 + static_cast<double>(d_pulse - d_p0) * (d_geo.velocity_mps * d_T);
    d_apertures = d_cfg.first_aperture;
    set_tag_propagation_policy(TPP_DONT);
    set_relative_rate(1, d_cfg.line_step);
    // Whole apertures come out at once (as rd_focuser).
    set_min_output_buffer(std::max<long>(64, (2l << 20) / (sizeof(gr_complex) * d_K)));
}

bp_focuser_impl::~bp_focuser_impl() {}

void bp_focuser_impl::configure(double T, double first_range, double range_bin)
{
    check_finite_positive("pulse_interval_s", T);
    check_finite_positive("range_bin_m", range_bin);
    if (d_T > 0.0) { // a new T from the next pulse (an aperture's first) on
        d_t0 += static_cast<double>(d_pulse - d_p0) * d_T;
        d_y0 = d_next_y;
        d_p0 = d_pulse;
    }
    d_T = T;
    d_first_range = first_range;
    d_range_bin = range_bin;
    if (d_cfg.lines_per_aperture > 0) {
        d_M = d_cfg.lines_per_aperture;
    } else {
        const double m = std::round(d_geo.aperture_s / T);
        if (!(m >= 1.0 && m < 1e8))
            throw_param("lines_per_aperture (round(aperture_s / T))", m, "must be in [1, 1e8)");
        d_M = static_cast<unsigned>(m);
    }
    if (d_M % d_cfg.line_step)
        throw_param("line_step", d_cfg.line_step,
                    "must divide the lines per aperture M = " + std::to_string(d_M) +
                        " (the image lines of every aperture on one grid)");
    d_lines = d_M / d_cfg.line_step;
    const azimuth_window win = scene_azimuth_window(
        d_geo, d_scn, d_cfg.band_margin_hz, T, first_range, range_bin, d_K);
    d_line_shift = win.line_shift;
    d_band_lo_hz = win.band_lo_hz;
    d_band_hi_hz = win.band_hi_hz;
    const double dy = d_geo.velocity_mps * T;
    if (d_lines_in == 0 && d_apertures == 0)
        d_next_y = d_y0 = d_geo.track_start_m + d_line_shift * dy;

    kernel::bp_grid g;
    g.num_range_bins = d_K;
    g.first_range_m = first_range;
    g.range_bin_m = range_bin;
    g.wavelength_m = d_geo.wavelength_m();
    g.range_centre_cycles =
        std::isnan(d_cfg.range_centre_cycles)
            ? std::remainder((d_num.num_subcarriers - 1.0) * d_num.subcarrier_spacing_hz *
                                 range_bin / speed_of_light,
                             1.0)
            : d_cfg.range_centre_cycles;
    g.upsample = d_cfg.upsample;
    g.num_lines = d_lines;
    g.line_step = d_cfg.line_step;
    g.first_y_m = d_next_y;
    g.line_spacing_m = dy;
    g.reference_height_m = d_geo.height_m;
    if (d_cfg.grid == image_grid::GROUND) {
        // The plane at ground_height_m: x of the first bin and the projected bin spacing.
        const double dz = d_geo.height_m - d_cfg.ground_height_m;
        if (!(dz > 0.0))
            throw_param("ground_height_m", d_cfg.ground_height_m,
                        "must be below the platform height " + std::to_string(d_geo.height_m));
        const double r_mid = first_range + 0.5 * (d_K - 1) * range_bin;
        if (std::isnan(d_cfg.ground_first_x_m) && !(first_range > dz))
            throw_param("first_range_m (ground grid)", first_range,
                        "must exceed the height above the grid " + std::to_string(dz) +
                            " m (or set ground_first_x_m)");
        if (d_cfg.ground_spacing_m == 0.0 && !(r_mid > dz))
            throw_param("mid range (ground grid)", r_mid,
                        "must exceed the height above the grid " + std::to_string(dz) +
                            " m (or set ground_spacing_m)");
        g.ground = true;
        g.ground_height_m = d_cfg.ground_height_m;
        g.first_x_m = std::isnan(d_cfg.ground_first_x_m)
                          ? std::sqrt((first_range - dz) * (first_range + dz))
                          : d_cfg.ground_first_x_m;
        g.x_spacing_m = d_cfg.ground_spacing_m > 0.0
                            ? d_cfg.ground_spacing_m
                            : range_bin * r_mid / std::sqrt((r_mid - dz) * (r_mid + dz));
    }
    g.sinc_taps = d_cfg.sinc_taps;
    g.subaperture = d_cfg.ffbp_subaperture;
    g.beam_oversample = d_cfg.ffbp_beam_oversample;
    g.levels = d_cfg.ffbp_levels;
    g.merge_factor = d_cfg.ffbp_merge_factor;
    d_kernel = std::make_unique<kernel::bp_focuser>(g, d_cfg.num_threads);
    d_pulses.resize(static_cast<size_t>(d_M) * d_K);
    d_antenna.resize(d_M);
    d_out.resize(static_cast<size_t>(d_lines) * d_K);
}

void bp_focuser_impl::handle_tag(const tag_t& tag)
{
    double T = d_pending ? d_pending_T : d_T;
    double r0 = d_pending ? d_pending_first_range : d_first_range;
    double rho = d_pending ? d_pending_range_bin : d_range_bin;
    if (!axes_from_tag(tag, d_K, d_ctor_first_range, d_ctor_range_bin, d_logger, T, r0, rho))
        return;
    using kernel::aperture_focuser;
    if (!aperture_focuser::differs(T, d_T) && !aperture_focuser::differs(r0, d_first_range) &&
        !aperture_focuser::differs(rho, d_range_bin)) {
        d_pending = false;
        return;
    }
    if (d_fill == 0) {
        configure(T, r0, rho);
        d_pending = false;
    } else {
        d_pending = true;
        d_pending_T = T;
        d_pending_first_range = r0;
        d_pending_range_bin = rho;
        d_logger->info("axis change at input line {} applies from aperture {}",
                       tag.offset,
                       d_apertures + 1);
    }
}

void bp_focuser_impl::ingest(const gr_complex* lines, unsigned n)
{
    std::size_t zeroed = 0;
    const gr_complex* clean = d_guard.guard(lines, static_cast<size_t>(n) * d_K, zeroed);
    if (zeroed) {
        d_nonfinite.note(d_logger, zeroed, d_lines_in);
        d_nonfinite_pending += zeroed;
    }
    std::memcpy(&d_pulses[static_cast<size_t>(d_fill) * d_K],
                clean,
                sizeof(gr_complex) * n * d_K);
    for (unsigned p = 0; p < n; ++p) {
        const double t = d_t0 + static_cast<double>(d_pulse - d_p0) * d_T;
        d_antenna[d_fill + p] = d_nav.position(t); // throws past the path's end
        ++d_pulse;
    }
    d_fill += n;
    d_lines_in += n;
}

void bp_focuser_impl::process_aperture()
{
    if (d_cfg.trajectory_autofocus && d_fill >= 2) {
        kernel::bp_grid g = d_kernel->grid();
        g.first_y_m = d_next_y;
        // Phase histories smoothed over 40 ms (16 pulses at 400 Hz): the GNSS error's sway
        // reaches 2 Hz, which a 40 ms moving sum keeps to 0.989 (docs/blocks/bp_focuser.md).
        kernel::trajectory_autofocus_config tc;
        tc.max_iterations = d_cfg.autofocus_iterations;
        tc.points = d_cfg.autofocus_points;
        tc.tolerance_m = d_cfg.autofocus_tolerance_m;
        tc.significance = d_cfg.autofocus_significance;
        tc.gcp = d_cfg.autofocus_gcp;
        tc.gcp_along_track_se_m = d_cfg.autofocus_gcp_along_track_se_m;
        // the kernel gates n se(d_y), the stretch over the aperture (at most 1 m)
        tc.gcp_speed_se_m = std::min(1.0, d_cfg.autofocus_gcp_speed_se_mps * d_fill * d_T);
        tc.smooth_pulses = static_cast<unsigned>(
            std::clamp(std::round(0.04 / d_T), 1.0, static_cast<double>(d_fill)));
        const auto r = kernel::trajectory_autofocus(
            d_pulses.data(), d_fill, d_antenna.data(), g, tc, d_out.data(), d_cfg.num_threads);
        double ss = 0.0;
        for (double v : r.los_m)
            ss += v * v;
        d_los_rms = std::sqrt(ss / r.los_m.size());
        d_los_se = r.standard_error_m;
        // the GCPs' trend, the drift per second (NaN without a GCP used)
        d_gcp_used = r.gcp_used;
        const double unused = r.gcp_used ? 1.0 : std::numeric_limits<double>::quiet_NaN();
        for (int c = 0; c < 3; ++c) {
            d_gcp_offset[c] = unused * r.gcp_offset_m[c];
            d_gcp_drift[c] = unused * r.gcp_drift_m[c] / d_T;
        }
        d_gcp_se = { unused * r.gcp_offset_se_m, unused * r.gcp_drift_se_m / d_T,
                     r.gcp_along_track ? r.gcp_offset_y_se_m : s_nan,
                     r.gcp_along_track_speed ? r.gcp_drift_y_se_m / d_T : s_nan };
    } else {
        d_kernel->reset(d_next_y);
        d_kernel->add(d_pulses.data(), d_fill, d_antenna.data());
        d_kernel->image(d_out.data());
    }
    d_out_pos = 0;
    d_out_len = d_lines;
    d_out_y0 = d_next_y;
    d_next_y = d_y0 + static_cast<double>(d_pulse - d_p0) * (d_geo.velocity_mps * d_T);
    d_fill = 0;
    ++d_apertures_imaged;
    if (d_pending) {
        d_pending = false;
        configure(d_pending_T, d_pending_first_range, d_pending_range_bin);
    }
}

int bp_focuser_impl::drain(gr_complex* out, int noutput, int produced)
{
    while (d_out_pos < d_out_len && produced < noutput) {
        const uint64_t item = nitems_written(0) + produced;
        if (d_out_pos == 0) {
            add_item_tag(0, item, tags::aperture_key(), pmt::from_uint64(d_apertures));
            add_item_tag(0,
                         item,
                         tags::azimuth_axis_key(),
                         pmt::make_tuple(pmt::from_double(d_out_y0),
                                         pmt::from_double(d_geo.velocity_mps * d_T *
                                                          d_cfg.line_step),
                                         pmt::from_uint64(d_out_len)));
            const auto& g = d_kernel->grid();
            // The columns' axis: slant range, or ground x (ground_range_axis).
            add_item_tag(0,
                         item,
                         g.ground ? tags::ground_range_axis_key() : tags::range_axis_key(),
                         pmt::make_tuple(pmt::from_double(g.ground ? g.first_x_m : g.first_range_m),
                                         pmt::from_double(g.ground ? g.x_spacing_m : g.range_bin_m),
                                         pmt::from_uint64(d_K)));
            if (d_nonfinite_pending) {
                add_item_tag(0,
                             item,
                             tags::nonfinite_key(),
                             pmt::from_uint64(d_nonfinite_pending),
                             alias_pmt());
                d_nonfinite_pending = 0;
            }
            ++d_apertures;
            d_nonfinite.rearm();
        }
        const unsigned n = std::min<unsigned>(d_out_len - d_out_pos, noutput - produced);
        std::memcpy(out + static_cast<size_t>(produced) * d_K,
                    &d_out[static_cast<size_t>(d_out_pos) * d_K],
                    sizeof(gr_complex) * n * d_K);
        d_out_pos += n;
        produced += n;
    }
    return produced;
}

void bp_focuser_impl::forecast(int, gr_vector_int& ninput_items_required)
{
    ninput_items_required[0] = items_until_flush(detail());
}

int bp_focuser_impl::general_work(int noutput_items,
                                  gr_vector_int& ninput_items,
                                  gr_vector_const_void_star& input_items,
                                  gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const uint64_t nread = nitems_read(0);
    const int navail = ninput_items[0];
    const bool upstream_done = input_ended(detail(), navail);

    std::vector<tag_t> tags;
    get_tags_in_range(tags, 0, d_lines_in, nread + navail);
    std::sort(tags.begin(), tags.end(), tag_t::offset_compare);
    // The block's side of the shared input loop (focuser_stream.h).
    struct side {
        bp_focuser_impl& b;
        gr_complex* out;
        int noutput;
        int produced = 0;
        uint64_t lines_in() const { return b.d_lines_in; }
        void handle_tag(const tag_t& t) { b.handle_tag(t); }
        unsigned room() const { return b.d_M - b.d_fill; }
        void ingest(const gr_complex* lines, unsigned n) { b.ingest(lines, n); }
        bool block_full() const { return b.d_fill == b.d_M; }
        // End of stream: the partial aperture from the pulses received.
        bool flush_due() const { return b.d_fill > 0 && !b.done(); }
        void focus() { b.process_aperture(); }
        bool queues_empty() const { return b.d_out_pos >= b.d_out_len; }
        bool wants_input() const
        {
            return produced < noutput && queues_empty() && !b.done();
        }
        void drain() { produced = b.drain(out, noutput, produced); }
    } s{ *this, out, noutput_items };
    consume_each(
        focuser_stream_loop(s, tags, in, d_K, nread, navail, upstream_done, d_flush_done));
    // cfg.apertures imaged and delivered: done (a strip's task stops its graph here)
    if (s.produced == 0 && done() && s.queues_empty())
        return WORK_DONE;
    return s.produced;
}

bool bp_focuser_impl::stop()
{
    gr::thread::scoped_lock guard(d_setlock);
    if ((d_fill > 0 && !done()) || d_out_pos < d_out_len)
        d_logger->warn("stopped with {} pulses not yet imaged and {} image lines not delivered "
                       "(the flowgraph stopped before the input ended)",
                       d_fill,
                       d_out_len - d_out_pos);
    return true;
}

} // namespace nrsar
} // namespace gr
