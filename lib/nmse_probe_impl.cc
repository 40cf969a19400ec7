/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "nmse_probe_impl.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/kernel/filter_theory.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cmath>
#include <limits>

namespace gr {
namespace nrsar {

namespace {
constexpr double nan_v = std::numeric_limits<double>::quiet_NaN();
// One aperture is buffered (twice with the reference input): refuse more than 2^28 pixels.
constexpr std::uint64_t max_pixels = std::uint64_t(1) << 28;

const pmt::pmt_t& metrics_port()
{
    static const pmt::pmt_t port = pmt::mp("metrics");
    return port;
}

bool read_axis(const pmt::pmt_t& value, double& first, double& step, std::uint64_t& count)
{
    if (!pmt::is_tuple(value) || pmt::length(value) < 3)
        return false;
    const auto a = pmt::tuple_ref(value, 0), b = pmt::tuple_ref(value, 1),
               c = pmt::tuple_ref(value, 2);
    if (!pmt::is_number(a) || !pmt::is_number(b) || !pmt::is_number(c))
        return false;
    first = pmt::to_double(a);
    step = pmt::to_double(b);
    const double n = pmt::is_integer(c) || pmt::is_uint64(c) ? static_cast<double>(pmt::to_uint64(c))
                                                               : pmt::to_double(c);
    count = n > 0.0 ? static_cast<std::uint64_t>(std::llround(n)) : 0;
    return std::isfinite(first) && std::isfinite(step) && step != 0.0;
}
} // namespace

nmse_probe::sptr nmse_probe::make(const numerology& num,
                                  const geometry& geo,
                                  const scene& scn,
                                  const std::vector<gr_complex>& constellation,
                                  filter_type filter,
                                  double snr_in_db,
                                  unsigned vlen,
                                  const probe_config& cfg)
{
    return gnuradio::make_block_sptr<nmse_probe_impl>(
        num, geo, scn, constellation, filter, snr_in_db, vlen, cfg);
}

void probe_config::validate() const
{
    const auto nonneg = [](const char* name, double v) {
        if (!std::isfinite(v) || v < 0.0)
            throw_param(name, v, "must be finite and >= 0");
    };
    nonneg("range_resolution_m", range_resolution_m);
    nonneg("azimuth_resolution_m", azimuth_resolution_m);
    nonneg("noise_guard_cells", noise_guard_cells);
    nonneg("sidelobe_window_cells", sidelobe_window_cells);
    if (sidelobe_window_cells > 0.0 && sidelobe_window_cells < 2.0)
        throw_param("sidelobe_window_cells", sidelobe_window_cells, "must be 0 (whole cut) or >= 2");
    if (!noise_box.empty()) {
        if (noise_box.size() != 4)
            throw_param("noise_box size", noise_box.size(), "must be 0 or 4 (r_min, r_max, y_min, y_max)");
        for (double v : noise_box)
            check_finite("noise_box value", v);
        if (!(noise_box[1] > noise_box[0]))
            throw_param("noise_box r_max", noise_box[1], "must be > r_min = " + std::to_string(noise_box[0]));
        if (!(noise_box[3] > noise_box[2]))
            throw_param("noise_box y_max", noise_box[3], "must be > y_min = " + std::to_string(noise_box[2]));
    }
    if (block_lines > 0 && block_lines < lines_per_aperture)
        throw_param("block_lines", block_lines,
                    "must be 0 or >= lines_per_aperture = " + std::to_string(lines_per_aperture));
    check_finite("band_lo_hz", band_lo_hz);
    check_finite("band_hi_hz", band_hi_hz);
    if ((band_lo_hz != 0.0 || band_hi_hz != 0.0) && !(band_hi_hz > band_lo_hz))
        throw_param("band_hi_hz", band_hi_hz,
                    "must be > band_lo_hz = " + std::to_string(band_lo_hz) + " (both 0: unknown)");
}

namespace {
// Validates before anything is stored (member initialiser).
const probe_config& validated(const probe_config& cfg)
{
    cfg.validate();
    return cfg;
}

double closest_range(const geometry& geo, const point_target& t)
{
    return t.slant_range_m(geo, t.y_m); // sqrt(x^2 + H^2), eq. (8) abeam
}
} // namespace

nmse_probe_impl::nmse_probe_impl(const numerology& num,
                                 const geometry& geo,
                                 const scene& scn,
                                 const std::vector<gr_complex>& constellation,
                                 filter_type filter,
                                 double snr_in_db,
                                 unsigned vlen,
                                 const probe_config& cfg)
    : gr::sync_block(
          "nmse_probe",
          gr::io_signature::make(cfg.reference_input ? 2 : 1,
                                 cfg.reference_input ? 2 : 1,
                                 sizeof(gr_complex) * check_at_least("vlen", vlen, 4u)),
          gr::io_signature::make(0, 0, 0)),
      d_num(num),
      d_geo(geo),
      d_scene(scn),
      d_constellation(constellation),
      d_filter(filter),
      d_snr_in_db(snr_in_db),
      d_vlen(vlen),
      d_cfg(validated(cfg)),
      d_nm(static_cast<double>(cfg.num_subcarriers ? cfg.num_subcarriers : num.num_subcarriers) *
           static_cast<double>(cfg.symbols_per_aperture ? cfg.symbols_per_aperture
                                                        : geo.symbols_per_aperture(num))),
      d_subcarriers(cfg.num_subcarriers ? cfg.num_subcarriers : num.num_subcarriers)
{
    num.validate();
    geo.validate();
    scn.validate();
    if (!(scn.targets.front().rcs > 0.0))
        throw_param("reference target rcs", scn.targets.front().rcs, "must be > 0");
    check_finite("snr_in_db", snr_in_db);
    // Validates the constellation (non-empty, finite, no zero point) with the theory itself.
    kernel::nmse_theory_db(d_constellation, d_filter, d_snr_in_db);
    if (!(d_nm >= 1.0))
        throw_param("symbols_per_aperture", geo.symbols_per_aperture(num), "must be at least 1");
    if (cfg.lines_per_aperture && std::uint64_t(cfg.lines_per_aperture) * vlen > max_pixels)
        throw_param("lines_per_aperture * vlen",
                    std::uint64_t(cfg.lines_per_aperture) * vlen,
                    "must be at most 2^28 (one aperture is buffered)");
    // B_target: the reference target's Doppler over the aperture, Ka Ta for a target seen
    // all along the track (eq. (8) exactly, as compute_extent takes the scene's band).
    d_target_band_hz =
        compute_extent(geo, scene{ { scn.targets.front() } }).doppler_bandwidth_hz();

    message_port_register_out(metrics_port());
    set_tag_propagation_policy(TPP_DONT);
}

nmse_probe_impl::~nmse_probe_impl() {}

void nmse_probe_impl::set_snr_in_db(double snr_in_db)
{
    check_finite("snr_in_db", snr_in_db);
    gr::thread::scoped_lock guard(d_setlock);
    d_snr_in_db = snr_in_db;
}

double nmse_probe_impl::snr_in_db() const { return d_snr_in_db; }

void nmse_probe_impl::set_filter(filter_type filter)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_filter = filter;
}

filter_type nmse_probe_impl::filter() const { return d_filter; }

double nmse_probe_impl::metric(const char* key) const
{
    std::lock_guard<std::mutex> lock(d_result_lock);
    const auto it = d_metrics.find(key);
    return it == d_metrics.end() ? nan_v : it->second;
}

std::map<std::string, double> nmse_probe_impl::metrics() const
{
    std::lock_guard<std::mutex> lock(d_result_lock);
    return d_metrics;
}

std::uint64_t nmse_probe_impl::apertures() const
{
    std::lock_guard<std::mutex> lock(d_result_lock);
    return d_apertures;
}

std::uint64_t nmse_probe_impl::nonfinite_count() const
{
    std::lock_guard<std::mutex> lock(d_result_lock);
    return d_nonfinite;
}

void nmse_probe_impl::open_aperture(std::uint64_t index)
{
    // Without a new azimuth tag the aperture continues where the previous one ended.
    if (!d_aaxis_fresh && d_capacity)
        d_aaxis.first += static_cast<double>(d_capacity) * d_aaxis.step;
    d_aaxis_fresh = false;
    d_ap_raxis = d_raxis;
    d_ap_aaxis = d_aaxis;
    d_capacity = d_cfg.lines_per_aperture ? d_cfg.lines_per_aperture : d_aaxis.count;
    d_aperture = index;
    d_lines_in = 0;
    d_nonfinite_ap = 0;
    d_open = true;
    const std::size_t n = d_capacity * d_vlen;
    if (d_img.size() < n)
        d_img.resize(n);
    if (d_ref.size() < n)
        d_ref.resize(n);
}

void nmse_probe_impl::finish_aperture(bool partial)
{
    d_open = false;
    const std::size_t lines = d_lines_in, bins = d_vlen;
    if (lines == 0)
        return;
    const auto& target = d_scene.targets.front();
    const double dr = d_ap_raxis.step, r0 = d_ap_raxis.first;
    const double dy = d_ap_aaxis.step, y0 = d_ap_aaxis.first;
    const double R0 = closest_range(d_geo, target);
    // Resolution cells: c / (2 N Delta f) (48) and lambda R0 / (2 v Ta) = v / Ba (49).
    const double rho_r = d_cfg.range_resolution_m > 0.0
                             ? d_cfg.range_resolution_m
                             : speed_of_light / (2.0 * d_subcarriers * d_num.subcarrier_spacing_hz);
    const double rho_a = d_cfg.azimuth_resolution_m > 0.0 ? d_cfg.azimuth_resolution_m
                                               : d_geo.wavelength_m() * R0 /
                                                     (2.0 * d_geo.velocity_mps * d_geo.aperture_s);

    kernel::metrics_config cfg;
    cfg.nm_factor = d_nm;
    cfg.range_res_bins = rho_r / std::abs(dr);
    cfg.azimuth_res_lines = rho_a / std::abs(dy);
    cfg.sidelobe_window_cells = d_cfg.sidelobe_window_cells;
    cfg.reference_rcs_m2 = target.rcs;
    cfg.pixel_area_m2 = std::abs(dr * dy);
    // Other targets on a cut through the reference (within 2 cells across it) bound that
    // cut's sidelobe window at half their distance: their main lobes are not sidelobes.
    for (std::size_t q = 1; q < d_scene.targets.size(); ++q) {
        const auto& t = d_scene.targets[q];
        const double d_range = std::abs(closest_range(d_geo, t) - R0) / rho_r;
        const double d_azimuth = std::abs(t.y_m - target.y_m) / rho_a;
        if (d_azimuth < 2.0 && d_range >= 2.0)
            cfg.range_window_limit_cells = std::min(cfg.range_window_limit_cells, d_range / 2);
        if (d_range < 2.0 && d_azimuth >= 2.0)
            cfg.azimuth_window_limit_cells =
                std::min(cfg.azimuth_window_limit_cells, d_azimuth / 2);
    }
    const double exp_bin = (R0 - r0) / dr;
    const double exp_line = (target.y_m - y0) / dy;

    if (!d_cfg.reference_input) {
        // eq. (47) with chi = 1 at the true position; ramps of off-centre bands from the data.
        const auto pk = kernel::find_peak(d_img.data(), lines, bins, exp_line, exp_bin,
                                          cfg.search_cells * cfg.azimuth_res_lines,
                                          cfg.search_cells * cfg.range_res_bins);
        const auto ramps = kernel::estimate_phase_ramps(d_img.data(), lines, bins,
                                                        static_cast<double>(pk.first),
                                                        static_cast<double>(pk.second),
                                                        cfg.azimuth_res_lines,
                                                        cfg.range_res_bins);
        const double az_band = static_cast<double>(d_capacity) / cfg.azimuth_res_lines;
        kernel::psf_model(d_ref.data(), lines, bins, exp_line, exp_bin, cfg.azimuth_res_lines,
                          std::max(1.0, az_band), cfg.range_res_bins, d_subcarriers,
                          ramps.first, ramps.second);
    }

    // Noise region: a given box, or range bins away from every target.
    d_bin_mask.assign(bins, 1);
    d_line_mask.assign(lines, 1);
    for (std::size_t k = 0; k < bins; ++k) {
        const double r = r0 + k * dr;
        if (!d_cfg.noise_box.empty()) {
            d_bin_mask[k] = r >= d_cfg.noise_box[0] && r <= d_cfg.noise_box[1];
        } else {
            for (const auto& t : d_scene.targets)
                if (std::abs(r - closest_range(d_geo, t)) <= d_cfg.noise_guard_cells * rho_r)
                    d_bin_mask[k] = 0;
        }
    }
    if (!d_cfg.noise_box.empty())
        for (std::size_t m = 0; m < lines; ++m) {
            const double y = y0 + m * dy;
            d_line_mask[m] = y >= d_cfg.noise_box[2] && y <= d_cfg.noise_box[3];
        }

    // SPEC 8: the NMSE's mean over pixels that each carry a whole correlation window's noise
    // and data randomness. A zero-padded aperture's pixels hold fewer pulses near its ends,
    // and far bins (longer windows) fewer than near ones: normalise each pixel. Aperture i's
    // pulses span track_start + [i, i + 1) M dy.
    const bool band_known = d_cfg.band_hi_hz > d_cfg.band_lo_hz;
    const bool weighted = band_known && d_cfg.zero_padded;
    if (weighted) {
        const double span = static_cast<double>(d_capacity) * dy;
        const double data0 = d_geo.track_start_m + static_cast<double>(d_aperture) * span;
        kernel::strip_pixel_weights_into(d_weights, lines, bins, y0, dy, r0, dr,
                                         std::min(data0, data0 + span),
                                         std::max(data0, data0 + span), d_cfg.band_lo_hz,
                                         d_cfg.band_hi_hz, d_geo.wavelength_m(),
                                         d_geo.velocity_mps,
                                         d_cfg.block_lines * std::abs(dy));
    }
    const auto res = d_kernel.compute(d_img.data(), d_ref.data(), lines, bins, exp_line,
                                      exp_bin, cfg, d_bin_mask.data(), d_line_mask.data(),
                                      weighted ? d_weights.data() : nullptr);
    // SPEC 8's theory is for one target. In a scene, every target's data-randomness
    // pedestal (rcs_q Var(chi)) and the noise (SNR_in is defined against the total RCS)
    // count against the reference target's peak: add 10 log10(total RCS / reference RCS).
    const double theory = kernel::nmse_theory_db(d_constellation, d_filter, d_snr_in_db) +
                          10.0 * std::log10(d_scene.total_rcs() / target.rcs);
    // Band occupancy: noise and data randomness fill the processed band B_p, the target's
    // energy only its own B_t; the reference (same band) peaks with min(B_p, B_t), so the
    // NMSE rises by B_p / B_t for a wider band and by B_t / B_p for a narrower one.
    const double band_hz = d_cfg.band_hi_hz - d_cfg.band_lo_hz;
    const double theory_band =
        band_known && d_target_band_hz > 0.0
            ? theory + std::abs(10.0 * std::log10(band_hz / d_target_band_hz))
            : nan_v;

    // Peak position: slant range -> ground range on the target's side of the track.
    const double r_pk = r0 + res.peak_bin * dr;
    const double y_pk = y0 + res.peak_line * dy;
    const double h = d_geo.height_m;
    const double x_pk = std::copysign(std::sqrt(std::max(0.0, r_pk * r_pk - h * h)), target.x_m);
    const double err = std::hypot(x_pk - target.x_m, y_pk - target.y_m);

    std::map<std::string, double> m;
    m["aperture"] = static_cast<double>(d_aperture);
    m["lines"] = static_cast<double>(lines);
    m["partial"] = partial ? 1.0 : 0.0;
    m["nonfinite"] = static_cast<double>(d_nonfinite_ap);
    m["nmse_db"] = res.nmse_db;
    m["nmse_theory_db"] = theory;
    m["nmse_theory_band_db"] = theory_band;
    m["nmse_pixels"] = static_cast<double>(res.nmse_pixels);
    m["processed_band_hz"] = band_known ? band_hz : nan_v;
    m["target_band_hz"] = d_target_band_hz;
    m["pel_db"] = res.pel_db;
    m["c_hat_re"] = res.c_hat.real();
    m["c_hat_im"] = res.c_hat.imag();
    m["snr_out_db"] = res.snr_out_db;
    m["peak_power"] = res.peak_power;
    m["noise_power"] = res.noise_power;
    m["noise_pixels"] = static_cast<double>(res.noise_pixels);
    m["islr_db"] = res.islr_db;
    m["pslr_db"] = res.pslr_db;
    m["islr_range_db"] = res.range.islr_db;
    m["islr_azimuth_db"] = res.azimuth.islr_db;
    m["pslr_range_db"] = res.range.pslr_db;
    m["pslr_azimuth_db"] = res.azimuth.pslr_db;
    m["irw_range_m"] = res.range.irw * std::abs(dr);
    m["irw_azimuth_m"] = res.azimuth.irw * std::abs(dy);
    m["peak_range_m"] = r_pk;
    m["peak_azimuth_m"] = y_pk;
    m["peak_x_m"] = x_pk;
    m["peak_error_range_m"] = r_pk - R0;
    m["peak_error_azimuth_m"] = y_pk - target.y_m;
    m["peak_error_m"] = err;
    m["image_entropy"] = res.image_entropy;
    m["epi"] = res.epi;
    m["nesz_db"] = res.nesz_db;

    if (d_nonfinite_ap)
        d_logger->warn("aperture {}: {} non-finite samples zeroed", d_aperture, d_nonfinite_ap);
    if (partial)
        d_logger->info("aperture {} partial: {} of {} lines", d_aperture, lines, d_capacity);
    if (res.noise_pixels == 0)
        d_logger->warn("aperture {}: empty noise region, snr_out_db is NaN", d_aperture);

    pmt::pmt_t dict = pmt::make_dict();
    for (const auto& kv : m) {
        pmt::pmt_t v;
        if (kv.first == "aperture" || kv.first == "lines" || kv.first == "nonfinite" ||
            kv.first == "noise_pixels" || kv.first == "nmse_pixels")
            v = pmt::from_uint64(static_cast<std::uint64_t>(kv.second));
        else if (kv.first == "partial")
            v = pmt::from_bool(partial);
        else
            v = pmt::from_double(kv.second);
        dict = pmt::dict_add(dict, pmt::mp(kv.first), v);
    }
    {
        std::lock_guard<std::mutex> lock(d_result_lock);
        d_metrics = std::move(m);
        ++d_apertures;
    }
    message_port_pub(metrics_port(), dict);
    d_lines_in = 0;
}

bool nmse_probe_impl::stop()
{
    gr::thread::scoped_lock guard(d_setlock);
    if (d_open && d_lines_in > 0)
        finish_aperture(true); // the stream ended mid-aperture: report what arrived
    return true;
}

int nmse_probe_impl::work(int noutput_items,
                          gr_vector_const_void_star& input_items,
                          gr_vector_void_star& /*output_items*/)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto* img = static_cast<const gr_complex*>(input_items[0]);
    const auto* ref = d_cfg.reference_input ? static_cast<const gr_complex*>(input_items[1]) : nullptr;
    const std::uint64_t base = nitems_read(0);

    auto& tags = d_tags;
    get_tags_in_range(tags, 0, base, base + noutput_items);
    std::sort(tags.begin(), tags.end(), gr::tag_t::offset_compare);
    std::size_t ti = 0;

    for (int i = 0; i < noutput_items; ++i) {
        bool new_aperture = false;
        std::uint64_t index = d_open ? d_aperture + 1 : d_aperture;
        for (; ti < tags.size() && tags[ti].offset == base + i; ++ti) {
            const auto& t = tags[ti];
            if (pmt::eq(t.key, tags::aperture_key())) {
                new_aperture = true;
                if (pmt::is_number(t.value))
                    index = pmt::to_uint64(t.value);
            } else if (pmt::eq(t.key, tags::range_axis_key())) {
                axis a;
                if (read_axis(t.value, a.first, a.step, a.count)) {
                    a.known = true;
                    if (a.count && a.count != d_vlen)
                        d_logger->warn("range axis has {} bins, the input {}: using {}",
                                       a.count, d_vlen, d_vlen);
                    d_raxis = a;
                } else {
                    d_logger->warn("ignoring malformed range_axis tag at item {}", t.offset);
                }
            } else if (pmt::eq(t.key, tags::azimuth_axis_key())) {
                axis a;
                if (read_axis(t.value, a.first, a.step, a.count)) {
                    a.known = true;
                    d_aaxis = a;
                    d_aaxis_fresh = true;
                } else {
                    d_logger->warn("ignoring malformed azimuth_axis tag at item {}", t.offset);
                }
            }
        }
        if (new_aperture && d_open)
            finish_aperture(true); // an aperture tag before the previous one was complete
        if (!d_open) {
            const std::uint64_t lines = d_cfg.lines_per_aperture ? d_cfg.lines_per_aperture : d_aaxis.count;
            const bool ready = d_raxis.known && d_aaxis.known && lines > 0 &&
                               lines * d_vlen <= max_pixels;
            if (!ready) {
                ++d_skipped;
                if (!d_warned_skip) {
                    d_logger->warn("skipping lines until the range and azimuth axes and the "
                                   "aperture length are known (tags or lines_per_aperture)");
                    d_warned_skip = true;
                }
                continue;
            }
            open_aperture(new_aperture ? index : (d_apertures ? d_aperture + 1 : 0));
        }
        gr_complex* dst = d_img.data() + d_lines_in * d_vlen;
        std::copy(img + i * d_vlen, img + (i + 1) * d_vlen, dst);
        std::size_t bad = kernel::zero_nonfinite(dst, d_vlen);
        if (ref) {
            gr_complex* rdst = d_ref.data() + d_lines_in * d_vlen;
            std::copy(ref + i * d_vlen, ref + (i + 1) * d_vlen, rdst);
            bad += kernel::zero_nonfinite(rdst, d_vlen);
        }
        if (bad) {
            d_nonfinite_ap += bad;
            std::lock_guard<std::mutex> lock(d_result_lock);
            d_nonfinite += bad;
        }
        if (++d_lines_in == d_capacity)
            finish_aperture(false);
    }
    return noutput_items;
}

} /* namespace nrsar */
} /* namespace gr */
