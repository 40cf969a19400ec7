/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "../azimuth_window.h"
#include "param_check.h"
#include <gnuradio/nrsar/kernel/aperture_focuser.h>
#include <gnuradio/nrsar/kernel/fft_size.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
// Bin 0 of an uncropped range IFFT is at 0 m: allowed.
void check_first_range(double r)
{
    if (!std::isfinite(r) || r < 0.0)
        throw_param("first_range_m", r, "must be finite and >= 0");
}

template <typename... A>
std::string format(const char* fmt, A... a)
{
    char buf[256];
    std::snprintf(buf, sizeof buf, fmt, a...);
    return buf;
}
} // namespace

aperture_focuser::aperture_focuser(const numerology& num,
                                   const geometry& geo,
                                   const scene& scn,
                                   unsigned num_range_bins,
                                   const focuser_config& cfg,
                                   double pulse_interval_s,
                                   double first_range_m,
                                   double range_bin_m,
                                   const trajectory& nav)
    : d_num(num), d_geo(geo), d_scn(scn), d_cfg(cfg), d_K(num_range_bins)
{
    check_at_least("num_range_bins", num_range_bins, 1u);
    d_geo.validate();
    d_scn.validate();
    d_cfg.validate();
    double y_ref = 0.0;
    los_reference::scene_centre(d_geo, d_scn, y_ref, d_los_range);
    d_los = std::make_shared<const los_reference>(d_geo, nav, y_ref);
    check_first_range(first_range_m);
    configure(pulse_interval_s, first_range_m, range_bin_m);
}

void aperture_focuser::configure(double T, double first_range, double range_bin)
{
    check_finite_positive("pulse_interval_s", T);
    check_first_range(first_range);
    check_finite_positive("range_bin_m", range_bin);
    d_T = T;
    d_first_range = first_range;
    d_range_bin = range_bin;

    if (d_cfg.lines_per_aperture > 0) {
        d_M = d_cfg.lines_per_aperture;
    } else {
        const double m = std::round(d_geo.aperture_s / T);
        if (!(m >= 2.0 && m < 1e9))
            throw_param("lines_per_aperture (round(aperture_s / T))", m, "must be in [2, 1e9)");
        d_M = static_cast<unsigned>(m);
    }
    check_at_least("lines_per_aperture", d_M, 2u);

    // The scene band with margin and the output window's shift: one computation with
    // bp_focuser (azimuth_window.h), so that both image the same lines.
    const azimuth_window w =
        scene_azimuth_window(d_geo, d_scn, d_cfg.band_margin_hz, T, first_range, range_bin, d_K);
    d_scene_lo_hz = w.band_lo_hz;
    d_scene_hi_hz = w.band_hi_hz;
    const double prf = 1.0 / T;
    if (d_scene_hi_hz - d_scene_lo_hz > prf)
        d_warnings.push_back(format("scene Doppler band [%.1f, %.1f] Hz (with margin) is wider "
                                    "than the pulse rate %.1f Hz: the azimuth spectrum aliases",
                                    d_scene_lo_hz,
                                    d_scene_hi_hz,
                                    prf));
    d_line_shift = w.line_shift;
    const double e_hi = w.e_hi, e_lo = w.e_lo;
    if (d_cfg.overlap_lines < 0) {
        // Overlap-save: image line t0 needs the pulses [t0 - e_hi, t0 - e_lo], so the block
        // of the window [iM + s, iM + s + M) starts `before` = e_hi pulses ahead of it and
        // ends `after` = -e_lo pulses past its end (each at least 0); 2 % and 2 lines of slack
        // cover the hyperbolic range history and the RCMC kernel.
        d_before = static_cast<unsigned>(std::ceil(std::max(0.0, e_hi) * 1.02 + 2.0));
        d_after = static_cast<unsigned>(std::ceil(std::max(0.0, -e_lo) * 1.02 + 2.0));
        // Along-track resampling reads each line up to the path's lag |y_nav - y| / (v T)
        // plus half the interpolator away: the block reaches that much further both ways.
        if (d_cfg.moco_resample && d_cfg.moco != moco_order::OFF && !d_los->ideal()) {
            const trajectory& nav = d_los->path();
            double lag = 0.0;
            for (double t = nav.start_s(); t <= nav.end_s(); t += 0.01)
                lag = std::max(lag, std::abs(nav.position(t)[1] - d_geo.track_start_m -
                                             d_geo.velocity_mps * t));
            const unsigned extra = static_cast<unsigned>(
                std::ceil(lag / (d_geo.velocity_mps * T) + 0.5 * d_cfg.rcmc_taps));
            d_before += extra;
            d_after += extra;
        }
    } else {
        d_before = d_after = static_cast<unsigned>(d_cfg.overlap_lines);
    }
    if (d_lines_in == 0) {
        // A strip's task starts at the first line of its first aperture's block (or at
        // the flight's start): the flight's lines before it are another task's.
        const std::uint64_t a0 = d_cfg.first_aperture;
        if (a0 > 0 && a0 > (std::uint64_t(1) << 62) / d_M)
            throw_param("first_aperture", a0, "times lines_per_aperture must stay below 2^62");
        d_aperture_start = a0 * d_M;
        const long long first_block = static_cast<long long>(d_aperture_start) + block_offset();
        d_line0 = a0 == 0 ? 0u : static_cast<std::uint64_t>(std::max(0ll, first_block));
        d_next_y = d_geo.track_start_m +
                   (static_cast<double>(d_aperture_start) + d_line_shift) * d_geo.velocity_mps * T;
    }
    d_kernel.reset(); // rebuilt lazily for the new block
}

long long aperture_focuser::block_offset() const
{
    return (d_before + d_after == 0) ? 0 : d_line_shift - static_cast<long long>(d_before);
}

rd_block aperture_focuser::make_block() const
{
    rd_block blk;
    blk.num_range_bins = d_K;
    blk.num_lines = d_before + d_M + d_after;
    blk.pulse_interval_s = d_T;
    blk.velocity_mps = d_geo.velocity_mps;
    blk.wavelength_m = d_geo.wavelength_m();
    blk.first_range_m = d_first_range;
    blk.range_bin_m = d_range_bin;
    blk.band_lo_hz = d_scene_lo_hz;
    blk.band_hi_hz = d_scene_hi_hz;
    // Without overlap the aperture is focused circularly and rotated by the shift; with
    // overlap the block's input framing carries it.
    blk.line_shift = (d_before + d_after == 0) ? d_line_shift : 0;
    blk.range_centre_cycles = std::isnan(d_cfg.range_centre_cycles)
                                  ? std::remainder((d_num.num_subcarriers - 1.0) *
                                                       d_num.subcarrier_spacing_hz *
                                                       d_range_bin / speed_of_light,
                                                   1.0)
                                  : d_cfg.range_centre_cycles;
    return blk;
}

bool aperture_focuser::differs(double a, double b)
{
    return std::abs(a - b) > 1e-9 * std::max(1.0, std::abs(b));
}

aperture_focuser::axes_change
aperture_focuser::set_axes(double T, double first_range, double range_bin)
{
    if (!differs(T, d_T) && !differs(first_range, d_first_range) &&
        !differs(range_bin, d_range_bin)) {
        d_pending = false;
        return axes_change::NONE;
    }
    if (d_lines_in == 0) {
        // Nothing buffered yet: applies from the first line, with a fresh block framing.
        configure(T, first_range, range_bin);
        d_block.clear();
        d_fill = d_written = d_shift = 0;
        d_skip = d_lead = 0;
        d_pending = false;
        return axes_change::APPLIED;
    }
    d_pending = true;
    d_pending_T = T;
    d_pending_first_range = first_range;
    d_pending_range_bin = range_bin;
    return axes_change::PENDING;
}

void aperture_focuser::prepare()
{
    if (d_kernel && !d_block.empty())
        return;
    const rd_block blk = make_block();
    if (!d_kernel) {
        // Aperture buffer, output queue and the band matrix (at most the FFT size);
        // ESTIMATE also keeps every spectrum.
        const double fft = fast_fft_size(blk.num_lines);
        const double gib = 8.0 * d_K *
                           (blk.num_lines + d_M +
                            fft * (d_cfg.band == doppler_band::ESTIMATE ? 2.0 : 1.0)) /
                           (1 << 30);
        if (gib > 2.0)
            d_warnings.push_back(format("processing blocks of %u lines x %u bins need about "
                                        "%.1f GiB; presum or crop the range window to reduce it",
                                        blk.num_lines,
                                        d_K,
                                        gib));
        d_kernel = std::make_unique<rd_focuser>(d_cfg, blk);
        d_kernel->set_motion(d_los,
                             d_geo.carrier_hz + 0.5 * (d_num.num_subcarriers - 1.0) *
                                                    d_num.subcarrier_spacing_hz,
                             d_los_range);
    }
    apply_shift();

    // Resize the input block (range-major: row k holds the P lines of range bin k, the
    // kernel's own layout), keeping the most recent lines (history and look-ahead).
    const unsigned P = blk.num_lines;
    decltype(d_block) fresh(static_cast<size_t>(P) * d_K); // zeros (calloc)
    if (d_fill > 0 && !d_block.empty()) {
        // Old layout: [history | look-ahead], d_fill lines. Keep the look-ahead (lines past
        // the aperture start) and as much history as the new block wants.
        const unsigned old_before = d_layout_before;
        const unsigned lookahead = d_fill > old_before ? d_fill - old_before : 0u;
        const unsigned history = d_fill - lookahead;
        const unsigned keep_hist = std::min(history, d_before);
        const unsigned keep_look = std::min(lookahead, P - d_before);
        for (unsigned k = 0; k < d_K; ++k)
            std::memcpy(&fresh[static_cast<size_t>(k) * P + d_before - keep_hist],
                        &d_block[static_cast<size_t>(k) * d_layout_lines + history - keep_hist],
                        sizeof(gr_complex) * (keep_hist + keep_look));
        d_fill = d_written = d_before + keep_look;
    } else {
        // The first block starts at the flight's line o = a0 M + shift - before (overlap)
        // or a0 M (circular): lines before the flight's start are zero, pulses between the
        // stream's first line and o are skipped.
        const long long o = static_cast<long long>(d_aperture_start) + block_offset();
        // A window far ahead of the flight can start more than a block before it: the
        // lines that do not fit enter as zeros before the stream's first line (d_lead).
        const long long zeros = std::max(0ll, -o);
        d_fill = static_cast<unsigned>(std::min<long long>(zeros, P));
        d_lead = static_cast<std::uint64_t>(zeros) - d_fill;
        d_skip = static_cast<std::uint64_t>(std::max(0ll, o - static_cast<long long>(d_line0)));
        d_written = 0;
    }
    d_block.swap(fresh);
    d_layout_before = d_before;
    d_layout_lines = P;
    // Grown only: the last aperture's lines stay readable until the next focus().
    if (d_out.size() < static_cast<size_t>(d_M) * d_K)
        d_out.resize(static_cast<size_t>(d_M) * d_K);
}

aperture_focuser::ingest_result aperture_focuser::ingest(const gr_complex* lines, unsigned n)
{
    ingest_result res;
    if (d_skip > 0) { // pulses whose energy focuses before the first output line
        const unsigned drop = static_cast<unsigned>(std::min<std::uint64_t>(d_skip, n));
        d_skip -= drop;
        d_lines_in += drop;
        lines += static_cast<size_t>(drop) * d_K;
        n -= drop;
        if (n == 0)
            return res;
    }
    apply_shift();
    const unsigned P = d_layout_lines;
    if (d_lead > 0) { // zero lines before the stream's first line (room() left them space)
        const unsigned z = static_cast<unsigned>(std::min<std::uint64_t>(d_lead, P - d_fill));
        for (unsigned k = 0; k < d_K; ++k)
            std::fill_n(&d_block[static_cast<size_t>(k) * P + d_fill], z, gr_complex(0.0f, 0.0f));
        d_fill += z;
        d_written = std::max(d_written, d_fill);
        d_lead -= z;
    }
    // Straight into the range-major block: the transpose happens while the lines are hot.
    transpose(lines, d_K, &d_block[d_fill], P, n, d_K);
    const size_t count = static_cast<size_t>(n) * d_K;
    // Non-finite check: x - x is 0 for finite x and NaN otherwise; one branch-free pass.
    const float* f = reinterpret_cast<const float*>(lines);
    // Eight independent accumulators so the loop vectorises without -ffast-math.
    float part[8] = { 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f };
    const size_t nf = 2 * count;
    size_t i = 0;
    for (; i + 8 <= nf; i += 8)
        for (int j = 0; j < 8; ++j)
            part[j] += f[i + j] - f[i + j];
    float acc = 0.0f;
    for (; i < nf; ++i)
        acc += f[i] - f[i];
    for (float p : part)
        acc += p;
    size_t first_bad = 0;
    if (acc != 0.0f) { // NaN (or a NaN sum): find and zero the offenders
        for (size_t j = 0; j < count; ++j) {
            if (!(std::isfinite(lines[j].real()) && std::isfinite(lines[j].imag()))) {
                d_block[(j % d_K) * P + d_fill + j / d_K] = gr_complex(0.0f, 0.0f);
                if (res.nonfinite++ == 0)
                    first_bad = j;
            }
        }
    }
    // The input line of the first bad sample, not the chunk's first line.
    res.first_bad_line = d_lines_in + first_bad / d_K;
    d_fill += n;
    d_written = std::max(d_written, d_fill);
    d_lines_in += n;
    return res;
}

void aperture_focuser::focus(bool with_rd_map)
{
    apply_shift();
    const unsigned P = d_before + d_M + d_after;
    // Zero padding for a partial (flushed) block: lines past d_written are zero already.
    if (d_written > d_fill) {
        for (unsigned k = 0; k < d_K; ++k)
            std::fill(&d_block[static_cast<size_t>(k) * P + d_fill],
                      &d_block[static_cast<size_t>(k) * P + d_written],
                      gr_complex(0.0f, 0.0f));
        d_written = d_fill;
    }
    // Slow time of the block's first line (motion compensation): aperture i's block starts
    // at input line i M + (shift - before) with overlap, at i M without.
    d_kernel->set_block_start_s((static_cast<double>(d_aperture_start) + block_offset()) * d_T);
    // Only lines [before, before + M) of the block are valid output (overlap-save).
    if (with_rd_map) {
        // The map of this block: band bins x K (at most the FFT size).
        d_rd.resize(static_cast<size_t>(d_kernel->fft_size()) * d_K);
        d_kernel->focus_range_major(d_block.data(), P, d_out.data(), d_before, d_M, d_rd.data());
        d_rd_lines = d_kernel->band_bins();
        d_rd_f0 = d_kernel->rd_doppler_first_hz();
        d_rd_df = 1.0 / (d_kernel->fft_size() * d_T);
    } else {
        d_kernel->focus_range_major(d_block.data(), P, d_out.data(), d_before, d_M);
        d_rd_lines = 0;
    }
    d_image_lines = d_M;
    d_image_y0 = d_next_y;
    d_image_dy = d_geo.velocity_mps * d_T;

    d_next_y += d_M * d_image_dy;
    d_aperture_start += d_M;
    ++d_focused;
    // Shift: the next block starts M lines later; keep before + after lines. Done when the
    // next lines come (apply_shift): after the stream's last block it is not needed.
    const unsigned keep = std::min(d_fill, P) > d_M ? std::min(d_fill, P) - d_M : 0u;
    d_shift = keep > 0 ? d_M : 0u;
    d_fill = keep;
    if (d_pending) {
        apply_shift();
        d_pending = false;
        configure(d_pending_T, d_pending_first_range, d_pending_range_bin);
        prepare();
    }
}

void aperture_focuser::apply_shift()
{
    if (d_shift == 0)
        return;
    const size_t P = d_layout_lines;
    for (unsigned k = 0; k < d_K; ++k)
        std::memmove(&d_block[k * P], &d_block[k * P + d_shift], sizeof(gr_complex) * d_fill);
    d_shift = 0;
}

void aperture_focuser::release()
{
    decltype(d_block)().swap(d_block);
    volk::vector<gr_complex>().swap(d_out);
    volk::vector<gr_complex>().swap(d_rd);
    d_fill = d_written = d_shift = d_layout_lines = 0;
    d_image_lines = d_rd_lines = 0;
}

// guard: lines of K bins -> lines of the K - 2 g inner bins (one copy when g = 0).
void aperture_focuser::copy_inner(gr_complex* dst, const gr_complex* src, unsigned lines) const
{
    const unsigned g = d_cfg.guard_bins;
    if (g == 0) {
        std::memcpy(dst, src, sizeof(gr_complex) * lines * d_K);
        return;
    }
    const unsigned ko = d_K - 2 * g;
    for (unsigned m = 0; m < lines; ++m)
        std::memcpy(dst + static_cast<size_t>(m) * ko,
                    src + static_cast<size_t>(m) * d_K + g,
                    sizeof(gr_complex) * ko);
}

void aperture_focuser::read_image(gr_complex* dst, unsigned first, unsigned n) const
{
    copy_inner(dst, &d_out[static_cast<size_t>(first) * d_K], n);
}

void aperture_focuser::read_rd_map(gr_complex* dst, unsigned first, unsigned n) const
{
    copy_inner(dst, &d_rd[static_cast<size_t>(first) * d_K], n);
}

std::vector<std::string> aperture_focuser::take_warnings()
{
    std::vector<std::string> w;
    w.swap(d_warnings);
    return w;
}

unsigned aperture_focuser::fft_size() const
{
    const unsigned P = d_before + d_M + d_after;
    return d_cfg.fast_fft_size ? fast_fft_size(P) : P;
}
double aperture_focuser::band_lo_hz() const
{
    // Before the first block: the band a kernel of the current parameters processes (the
    // probe's theory and weights are configured then).
    return d_kernel ? d_kernel->band_lo_hz()
                    : rd_focuser::configured_band(d_cfg, d_scene_lo_hz, d_scene_hi_hz, 1.0 / d_T)
                          .first;
}
double aperture_focuser::band_hi_hz() const
{
    return d_kernel ? d_kernel->band_hi_hz()
                    : rd_focuser::configured_band(d_cfg, d_scene_lo_hz, d_scene_hi_hz, 1.0 / d_T)
                          .second;
}
unsigned aperture_focuser::band_bins() const
{
    if (d_kernel)
        return d_kernel->band_bins();
    // Before the first block (e.g. to size a display of the rd_map port): the band of a
    // kernel built for the current parameters, without building one (FFT plans, tables).
    return rd_focuser::configured_band_bins(d_cfg, make_block());
}
double aperture_focuser::max_migration_bins() const
{
    return d_kernel ? d_kernel->max_migration_bins() : 0.0;
}
bool aperture_focuser::rcmc_applied() const { return d_kernel && d_kernel->rcmc_applied(); }

} // namespace kernel
} // namespace nrsar
} // namespace gr
