/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "rd_focuser_impl.h"
#include "azimuth_window.h"
#include "focuser_stream.h"
#include "param_check.h"
#include <gnuradio/block_detail.h>
#include <gnuradio/buffer_reader.h>
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace gr {
namespace nrsar {

rd_focuser::sptr rd_focuser::make(const numerology& num,
                                  const geometry& geo,
                                  const scene& scn,
                                  unsigned num_range_bins,
                                  double first_range_m,
                                  double range_bin_m,
                                  const focuser_config& cfg)
{
    check_at_least("num_range_bins", num_range_bins, 1u); // before the io_signatures
    return gnuradio::make_block_sptr<rd_focuser_impl>(
        num, geo, scn, num_range_bins, first_range_m, range_bin_m, cfg);
}

namespace {
double default_range_bin(const numerology& num, double range_bin_m)
{
    num.validate();
    if (range_bin_m == 0.0)
        return num.range_bin_m(num.fft_size);
    check_finite_positive("range_bin_m", range_bin_m);
    return range_bin_m;
}

// Bin 0 of an uncropped range IFFT is at 0 m: allowed.
void check_first_range(double r)
{
    if (!std::isfinite(r) || r < 0.0)
        throw_param("first_range_m", r, "must be finite and >= 0");
}

// guard: K - 2 guard_bins output bins, at least one.
unsigned output_vlen(unsigned k, const focuser_config& cfg)
{
    if (2ull * cfg.guard_bins >= k)
        throw_param("guard_bins", cfg.guard_bins, "must be below num_range_bins / 2 (" +
                                                     std::to_string(k) + " / 2)");
    return k - 2 * cfg.guard_bins;
}

bool differs(double a, double b) { return std::abs(a - b) > 1e-9 * std::max(1.0, std::abs(b)); }
} // namespace

rd_focuser_impl::rd_focuser_impl(const numerology& num,
                                 const geometry& geo,
                                 const scene& scn,
                                 unsigned num_range_bins,
                                 double first_range_m,
                                 double range_bin_m,
                                 const focuser_config& cfg)
    : gr::block("rd_focuser",
                gr::io_signature::make(1, 1, sizeof(gr_complex) * num_range_bins),
                // out: the image; optional rd_map: the range-Doppler map after RCMC.
                gr::io_signature::make(
                    1, 2, sizeof(gr_complex) * output_vlen(num_range_bins, cfg))),
      d_num(num),
      d_geo(geo),
      d_scn(scn),
      d_cfg(cfg),
      d_K(num_range_bins),
      d_ctor_first_range(first_range_m),
      d_ctor_range_bin(default_range_bin(num, range_bin_m))
{
    d_geo.validate();
    d_scn.validate();
    d_cfg.validate();
    check_first_range(first_range_m);
    configure(d_num.symbol_s() * d_cfg.symbols_per_pulse, first_range_m, d_ctor_range_bin);
    // The output is a different domain (azimuth lines); the block places its own tags.
    set_tag_propagation_policy(TPP_DONT);
    set_relative_rate(1.0);
    // Whole apertures come out at once: an output buffer of about 2 MiB instead of GNU Radio's
    // default (16 items of 2 KiB at K = 256) cuts the scheduler round trips downstream.
    set_min_output_buffer(std::max<long>(64, (2l << 20) / (sizeof(gr_complex) * d_K)));
}

rd_focuser_impl::~rd_focuser_impl() {}

void rd_focuser_impl::configure(double T, double first_range, double range_bin)
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

    const azimuth_window win = scene_azimuth_window(
        d_geo, d_scn, d_cfg.band_margin_hz, T, first_range, range_bin, d_K);
    d_scene_lo_hz = win.band_lo_hz;
    d_scene_hi_hz = win.band_hi_hz;
    const double prf = 1.0 / T;
    if (d_scene_hi_hz - d_scene_lo_hz > prf)
        d_logger->warn("scene Doppler band [{:.1f}, {:.1f}] Hz (with margin) is wider than the "
                       "pulse rate {:.1f} Hz: the azimuth spectrum aliases",
                       d_scene_lo_hz,
                       d_scene_hi_hz,
                       prf);
    const double v = d_geo.velocity_mps;
    const double e_hi = win.e_hi, e_lo = win.e_lo;
    d_line_shift = win.line_shift;
    if (d_cfg.overlap_lines < 0) {
        // Overlap-save: image line t0 needs the pulses [t0 - e_hi, t0 - e_lo], so the block
        // of the window [iM + s, iM + s + M) starts `before` = e_hi pulses ahead of it and
        // ends `after` = -e_lo pulses past its end (each at least 0); 2 % and 2 lines of slack
        // cover the hyperbolic range history and the RCMC kernel.
        d_before = static_cast<unsigned>(std::ceil(std::max(0.0, e_hi) * 1.02 + 2.0));
        d_after = static_cast<unsigned>(std::ceil(std::max(0.0, -e_lo) * 1.02 + 2.0));
    } else {
        d_before = d_after = static_cast<unsigned>(d_cfg.overlap_lines);
    }
    if (d_lines_in == 0 && d_apertures == 0)
        d_next_y = d_geo.track_start_m + d_line_shift * v * T;
    d_kernel.reset(); // rebuilt lazily for the new block
}

kernel::rd_block rd_focuser_impl::make_block() const
{
    kernel::rd_block blk;
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

void rd_focuser_impl::ensure_kernel()
{
    if (d_kernel)
        return;
    const kernel::rd_block blk = make_block();
    // Aperture buffer, output queue and the band matrix (at most the FFT size); ESTIMATE
    // also keeps every spectrum.
    const double fft = kernel::fast_fft_size(blk.num_lines);
    const double gib = 8.0 * d_K *
                       (blk.num_lines + d_M +
                        fft * (d_cfg.band == doppler_band::ESTIMATE ? 2.0 : 1.0)) /
                       (1 << 30);
    if (gib > 2.0)
        d_logger->warn("processing blocks of {} lines x {} bins need about {:.1f} GiB; "
                       "presum or crop the range window to reduce it",
                       blk.num_lines,
                       d_K,
                       gib);
    d_kernel = std::make_unique<kernel::rd_focuser>(d_cfg, blk);

    // Resize the input block (range-major: row k holds the P lines of range bin k, the
    // kernel's own layout), keeping the most recent lines (history and look-ahead).
    const unsigned P = blk.num_lines;
    volk::vector<gr_complex> fresh(static_cast<size_t>(P) * d_K, gr_complex(0.0f, 0.0f));
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
        d_fill = d_before + keep_look;
    } else {
        // The first block starts at input line o = shift - before (overlap) or 0 (circular):
        // lines before the stream start are zero, pulses before o are skipped.
        const long long o = (d_before + d_after == 0) ? 0 : d_line_shift - d_before;
        d_fill = static_cast<unsigned>(std::max(0ll, -o));
        d_skip = static_cast<std::uint64_t>(std::max(0ll, o));
    }
    d_block.swap(fresh);
    d_layout_before = d_before;
    d_layout_lines = P;
    d_out.resize(static_cast<size_t>(d_M) * d_K);
}

void rd_focuser_impl::handle_tag(const tag_t& tag)
{
    double T = d_pending ? d_pending_T : d_T;
    double r0 = d_pending ? d_pending_first_range : d_first_range;
    double rho = d_pending ? d_pending_range_bin : d_range_bin;
    if (pmt::eq(tag.key, tags::pulse_interval_key())) {
        if (!parse_pulse_interval(tag.value, T)) {
            d_logger->warn("ignoring pulse_interval tag with value {}", pmt::write_string(tag.value));
            return;
        }
    } else if (pmt::eq(tag.key, tags::range_axis_key())) {
        double first = 0.0, step = 0.0;
        uint64_t k = 0;
        if (!parse_range_axis(tag.value, first, step, k)) {
            d_logger->warn("ignoring malformed range_axis tag {}", pmt::write_string(tag.value));
            return;
        }
        if (k != d_K || !(first >= 0.0) || !(step > 0.0) || !std::isfinite(first + step)) {
            d_logger->warn("ignoring range_axis tag ({}, {}, {}): the block has {} bins",
                           first,
                           step,
                           k,
                           d_K);
            return;
        }
        if (differs(first, d_ctor_first_range) || differs(step, d_ctor_range_bin))
            d_logger->warn("range_axis tag ({} m, {} m) differs from the constructor's "
                           "({} m, {} m): using the tag",
                           first,
                           step,
                           d_ctor_first_range,
                           d_ctor_range_bin);
        r0 = first;
        rho = step;
    } else {
        return;
    }
    if (!differs(T, d_T) && !differs(r0, d_first_range) && !differs(rho, d_range_bin)) {
        d_pending = false;
        return;
    }
    if (d_lines_in == 0) {
        // Nothing buffered yet: applies from the first line, with a fresh block framing.
        configure(T, r0, rho);
        d_block.clear();
        d_fill = 0;
        d_skip = 0;
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

void rd_focuser_impl::ingest(const gr_complex* lines, unsigned n)
{
    if (d_skip > 0) { // pulses whose energy focuses before the first output line
        const unsigned drop = static_cast<unsigned>(std::min<std::uint64_t>(d_skip, n));
        d_skip -= drop;
        d_lines_in += drop;
        lines += static_cast<size_t>(drop) * d_K;
        n -= drop;
        if (n == 0)
            return;
    }
    // Straight into the range-major block: the transpose happens while the lines are hot.
    const unsigned P = d_layout_lines;
    kernel::transpose(lines, d_K, &d_block[d_fill], P, n, d_K);
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
    std::uint64_t bad = 0;
    size_t first_bad = 0;
    if (acc != 0.0f) { // NaN (or a NaN sum): find and zero the offenders
        for (size_t j = 0; j < count; ++j) {
            if (!(std::isfinite(lines[j].real()) && std::isfinite(lines[j].imag()))) {
                d_block[(j % d_K) * P + d_fill + j / d_K] = gr_complex(0.0f, 0.0f);
                if (bad++ == 0)
                    first_bad = j;
            }
        }
    }
    if (bad) {
        // The log names the input line of the first bad sample, not the chunk's first line.
        d_nonfinite.note(d_logger, bad, d_lines_in + first_bad / d_K);
        d_nonfinite_pending += bad;
    }
    d_fill += n;
    d_lines_in += n;
}

void rd_focuser_impl::process_block()
{
    const unsigned P = d_before + d_M + d_after;
    // Zero padding for a partial (flushed) block.
    for (unsigned k = 0; k < d_K; ++k)
        std::fill(&d_block[static_cast<size_t>(k) * P + d_fill],
                  &d_block[static_cast<size_t>(k) * P] + P,
                  gr_complex(0.0f, 0.0f));
    // Only lines [before, before + M) of the block are valid output (overlap-save).
    if (d_want_rd) {
        // The map of this block: band bins x K (at most the FFT size), queued for port 1.
        d_rd.resize(static_cast<size_t>(d_kernel->fft_size()) * d_K);
        d_kernel->focus_range_major(d_block.data(), P, d_out.data(), d_before, d_M, d_rd.data());
        d_rd_pos = 0;
        d_rd_len = d_kernel->band_bins();
        d_rd_tags_due = true;
        d_rd_f0 = d_kernel->rd_doppler_first_hz();
        d_rd_df = 1.0 / (d_kernel->fft_size() * d_T);
    } else {
        d_kernel->focus_range_major(d_block.data(), P, d_out.data(), d_before, d_M);
    }
    d_out_pos = 0;
    d_out_len = d_M;
    d_out_tags_due = true;
    d_out_y0 = d_next_y;
    d_out_dy = d_geo.velocity_mps * d_T;

    d_next_y += d_M * d_out_dy;
    d_aperture_start += d_M;
    // Shift: the next block starts M lines later; keep before + after lines.
    const unsigned keep = std::min(d_fill, P) > d_M ? std::min(d_fill, P) - d_M : 0u;
    for (unsigned k = 0; k < d_K; ++k)
        std::memmove(&d_block[static_cast<size_t>(k) * P],
                     &d_block[static_cast<size_t>(k) * P + d_M],
                     sizeof(gr_complex) * keep);
    d_fill = keep;
    if (d_pending) {
        d_pending = false;
        configure(d_pending_T, d_pending_first_range, d_pending_range_bin);
        ensure_kernel();
    }
}

void rd_focuser_impl::add_aperture_tags(int port,
                                        uint64_t item,
                                        uint64_t index,
                                        const pmt::pmt_t& axis_key,
                                        double first,
                                        double step,
                                        uint64_t lines)
{
    add_item_tag(port, item, tags::aperture_key(), pmt::from_uint64(index));
    add_item_tag(port,
                 item,
                 axis_key,
                 pmt::make_tuple(
                     pmt::from_double(first), pmt::from_double(step), pmt::from_uint64(lines)));
    add_item_tag(port,
                 item,
                 tags::range_axis_key(),
                 pmt::make_tuple(pmt::from_double(d_first_range + d_cfg.guard_bins * d_range_bin),
                                 pmt::from_double(d_range_bin),
                                 pmt::from_uint64(num_output_bins())));
}

// guard: lines of K bins -> lines of the K - 2 g inner bins (one copy when g = 0).
void rd_focuser_impl::copy_inner(gr_complex* dst, const gr_complex* src, unsigned lines) const
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

unsigned rd_focuser_impl::num_output_bins() const { return d_K - 2 * d_cfg.guard_bins; }

int rd_focuser_impl::drain(gr_complex* out, int noutput, int produced)
{
    while (d_out_pos < d_out_len && produced < noutput) {
        const uint64_t item = nitems_written(0) + produced;
        if (d_out_tags_due && d_out_pos == 0) {
            add_aperture_tags(
                0, item, d_apertures, tags::azimuth_axis_key(), d_out_y0, d_out_dy, d_out_len);
            if (d_nonfinite_pending) {
                add_item_tag(0, item, tags::nonfinite_key(), pmt::from_uint64(d_nonfinite_pending));
                d_nonfinite_pending = 0;
            }
            d_out_tags_due = false;
            ++d_apertures;
            d_nonfinite.rearm();
        }
        const unsigned n = std::min<unsigned>(d_out_len - d_out_pos, noutput - produced);
        copy_inner(out + static_cast<size_t>(produced) * num_output_bins(),
                   &d_out[static_cast<size_t>(d_out_pos) * d_K],
                   n);
        d_out_pos += n;
        produced += n;
    }
    return produced;
}

int rd_focuser_impl::drain_rd(gr_complex* out, int noutput, int produced)
{
    while (d_rd_pos < d_rd_len && produced < noutput) {
        if (d_rd_tags_due && d_rd_pos == 0) {
            const uint64_t item = nitems_written(1) + produced;
            add_aperture_tags(
                1, item, d_rd_apertures, tags::doppler_axis_key(), d_rd_f0, d_rd_df, d_rd_len);
            d_rd_tags_due = false;
            ++d_rd_apertures;
        }
        const unsigned n = std::min<unsigned>(d_rd_len - d_rd_pos, noutput - produced);
        copy_inner(out + static_cast<size_t>(produced) * num_output_bins(),
                   &d_rd[static_cast<size_t>(d_rd_pos) * d_K],
                   n);
        d_rd_pos += n;
        produced += n;
    }
    return produced;
}

void rd_focuser_impl::forecast(int, gr_vector_int& ninput_items_required)
{
    // One input item is always held back until the upstream is done, so that the
    // scheduler calls us once more at the end of the stream to flush the last apertures.
    const bool done = detail() && detail()->input(0)->done();
    ninput_items_required[0] = done ? 1 : 2;
}

int rd_focuser_impl::general_work(int noutput_items,
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
    ensure_kernel();
    // The map is computed only while its port is connected (otherwise no extra work).
    d_want_rd = output_items.size() > 1;
    auto* rd_out = d_want_rd ? static_cast<gr_complex*>(output_items[1]) : nullptr;

    int produced = drain(out, noutput_items, 0);
    int produced_rd = d_want_rd ? drain_rd(rd_out, noutput_items, 0) : 0;
    // The tags of everything not yet ingested, in offset order.
    std::vector<tag_t> tags;
    get_tags_in_range(tags, 0, d_lines_in, nread + navail);
    std::sort(tags.begin(), tags.end(), tag_t::offset_compare);
    size_t next_tag = 0;
    while (produced < noutput_items && queues_empty()) {
        const uint64_t next = d_lines_in; // absolute index of the next line to ingest
        const int i = static_cast<int>(next - nread);
        if (i < navail) {
            while (next_tag < tags.size() && tags[next_tag].offset <= next)
                handle_tag(tags[next_tag++]);
            ensure_kernel();
            // Ingest up to the next tag, the end of the input or a full block.
            uint64_t end = nread + navail;
            if (next_tag < tags.size())
                end = std::min<uint64_t>(end, tags[next_tag].offset);
            const unsigned room = d_before + d_M + d_after - d_fill;
            const unsigned n = static_cast<unsigned>(std::min<uint64_t>(end - next, room));
            ingest(in + static_cast<size_t>(i) * d_K, n);
            if (d_fill == d_before + d_M + d_after)
                process_block();
        } else if (upstream_done && !d_flush_done) {
            // End of stream: emit, zero padded, every aperture whose own pulses
            // [iM, iM + M) were (partly) received.
            if (d_aperture_start < d_lines_in) {
                process_block();
            } else {
                d_flush_done = true;
            }
        } else {
            break;
        }
        produced = drain(out, noutput_items, produced);
        if (d_want_rd)
            produced_rd = drain_rd(rd_out, noutput_items, produced_rd);
    }

    // Consume what was ingested, holding the last item back until the stream ends and
    // everything is flushed.
    int consume = static_cast<int>(d_lines_in - nread);
    if (!(upstream_done && d_flush_done && queues_empty()))
        consume = std::min(consume, navail - 1);
    consume_each(std::max(consume, 0));
    if (!d_want_rd)
        return produced;
    produce(0, produced);
    produce(1, produced_rd);
    return WORK_CALLED_PRODUCE;
}

bool rd_focuser_impl::stop()
{
    gr::thread::scoped_lock guard(d_setlock);
    const uint64_t emitted = d_aperture_start;
    if (d_lines_in > emitted || d_out_pos < d_out_len)
        d_logger->warn("stopped with {} input lines not yet emitted as focused lines and {} "
                       "focused lines not delivered (the flowgraph stopped before the input "
                       "ended)",
                       d_lines_in > emitted ? d_lines_in - emitted : 0,
                       d_out_len - d_out_pos);
    return true;
}

unsigned rd_focuser_impl::lines_per_aperture() const { return d_M; }
unsigned rd_focuser_impl::overlap_before() const { return d_before; }
long long rd_focuser_impl::line_shift() const { return d_line_shift; }
unsigned rd_focuser_impl::overlap_after() const { return d_after; }
unsigned rd_focuser_impl::fft_size() const
{
    const unsigned P = d_before + d_M + d_after;
    return d_cfg.fast_fft_size ? kernel::fast_fft_size(P) : P;
}
double rd_focuser_impl::pulse_interval_s() const { return d_T; }
double rd_focuser_impl::first_range_m() const { return d_first_range; }
double rd_focuser_impl::range_bin_m() const { return d_range_bin; }
double rd_focuser_impl::band_lo_hz() const
{
    return d_kernel ? d_kernel->band_lo_hz() : d_scene_lo_hz;
}
double rd_focuser_impl::band_hi_hz() const
{
    return d_kernel ? d_kernel->band_hi_hz() : d_scene_hi_hz;
}
unsigned rd_focuser_impl::band_bins() const
{
    if (d_kernel)
        return d_kernel->band_bins();
    // Before the first block (e.g. to size a display of the rd_map port): the band of a
    // kernel built for the current parameters (ESTIMATE: the scene band it falls back to).
    return kernel::rd_focuser(d_cfg, make_block()).band_bins();
}
double rd_focuser_impl::max_migration_bins() const
{
    return d_kernel ? d_kernel->max_migration_bins() : 0.0;
}
bool rd_focuser_impl::rcmc_applied() const { return d_kernel && d_kernel->rcmc_applied(); }
std::uint64_t rd_focuser_impl::apertures() const { return d_apertures; }
std::uint64_t rd_focuser_impl::nonfinite_count() const { return d_nonfinite.count(); }

} // namespace nrsar
} // namespace gr
