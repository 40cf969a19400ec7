/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "ofdm_sync_impl.h"
#include "param_check.h"
#include "rx_time_tag.h"
#include <gnuradio/nrsar/kernel/rx_time_aligner.h>
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace gr {
namespace nrsar {

namespace {

void check_threshold(double threshold)
{
    check_finite("threshold", threshold);
    if (!(threshold > 0.0 && threshold < 1.0))
        throw_param("threshold", threshold, "must be in (0, 1) (the metric M is in [0, 1])");
}

} // namespace

ofdm_sync::sptr
ofdm_sync::make(const numerology& num, const dmrs_config& dmrs, double threshold, double backoff)
{
    num.validate();
    dmrs.validate(num);
    if (!dmrs.enabled())
        throw_param("dmrs symbols",
                    0,
                    "(none): ofdm_sync needs at least one DMRS symbol per slot to acquire on");
    if (num.fft_size % 2 != 0)
        throw_param("fft_size",
                    num.fft_size,
                    "must be even for ofdm_sync (the DMRS symbol repeats every fft_size / 2)");
    check_threshold(threshold);
    check_finite("backoff", backoff);
    if (!(backoff >= 0.0 && backoff < 1.0))
        throw_param("backoff", backoff, "must be in [0, 1) (a fraction of the cyclic prefix)");
    return gnuradio::make_block_sptr<ofdm_sync_impl>(num, dmrs, threshold, backoff);
}

ofdm_sync_impl::ofdm_sync_impl(const numerology& num,
                               const dmrs_config& dmrs,
                               double threshold,
                               double backoff)
    : gr::block("ofdm_sync",
                gr::io_signature::make(1, 1, sizeof(gr_complex)),
                gr::io_signature::make(1, 1, sizeof(gr_complex))),
      d_num(num),
      d_first_dmrs(dmrs.symbols.front()),
      d_num_dmrs(unsigned(dmrs.symbols.size())),
      d_backoff(backoff),
      d_backoff_samples(std::llround(backoff * num.cp_samples)),
      d_acq(num.fft_size,
            num.cp_samples,
            threshold,
            std::size_t(d_first_dmrs) * (num.cp_samples + num.fft_size) + num.cp_samples +
                num.fft_size / 2 + std::size_t(d_backoff_samples) + 2),
      d_tracker(num.fft_size,
                num.cp_samples,
                num.symbols_per_slot,
                std::uint64_t(d_first_dmrs) * (num.cp_samples + num.fft_size) +
                    std::uint64_t(d_backoff_samples),
                // the backoff is the FFT window's margin against late timing (at least cp/8)
                std::max<unsigned>(unsigned(d_backoff_samples), num.cp_samples / 8)),
      d_matcher(num, dmrs),
      d_rx_time_key(pmt::mp("rx_time"))
{
    d_check.resize(d_tracker.check_length());
    // The other DMRS symbols of the slot refine the CFO estimate.
    std::vector<std::int64_t> repeats;
    for (std::size_t k = 1; k < dmrs.symbols.size(); k++)
        repeats.push_back(std::int64_t(dmrs.symbols[k] - dmrs.symbols[0]) *
                          (num.cp_samples + num.fft_size));
    d_acq.set_repeats(repeats);
    d_tracker.set_repeats(repeats);
    set_tag_propagation_policy(TPP_DONT);
    message_port_register_in(pmt::mp("reset"));
    set_msg_handler(pmt::mp("reset"), [this](const pmt::pmt_t&) { this->reset(); });
}

void ofdm_sync_impl::set_threshold(double threshold)
{
    check_threshold(threshold);
    gr::thread::scoped_lock guard(d_setlock);
    d_acq.set_threshold(threshold);
}

void ofdm_sync_impl::reset()
{
    gr::thread::scoped_lock guard(d_setlock);
    d_reset_pending = true;
}

void ofdm_sync_impl::forecast(int noutput_items, gr_vector_int& ninput_items_required)
{
    // Searching eats whatever arrives; draining and padding need no input; dropping takes
    // what comes; tracking is 1:1.
    int need = 1;
    if (d_state == state::drain || (d_state == state::track && (d_pad > 0 || d_search_pending)))
        need = 0;
    else if (d_state == state::track && d_drop == 0)
        need = noutput_items;
    ninput_items_required[0] = need;
}

void ofdm_sync_impl::jump_grid(std::uint64_t to)
{
    // The derotator's phase follows the grid (the radio's time), skipped samples included.
    const double skipped = double(std::int64_t(to - d_grid_out));
    d_rot.set_phase(d_rot.phase() + 2.0 * M_PI * d_rot.frequency() * skipped);
    d_grid_out = to;
}

bool ofdm_sync_impl::output_checked(const gr_complex* out, std::size_t n)
{
    const auto c = d_tracker.check(out, d_grid_out, n, d_matcher, d_num.slots_per_frame);
    d_grid_out += n;
    if (c.lost) {
        d_logger->warn("slot {}: DMRS rho {:.3f} (threshold {:.3f}), offset {:.1f} samples",
                       c.slot,
                       c.match.rho,
                       d_matcher.threshold(),
                       c.match.offset);
        lose_lock("DMRS check");
    }
    return c.lost;
}

void ofdm_sync_impl::lose_lock(const char* why)
{
    d_lock_losses++;
    d_pad = d_tracker.pad_to_symbol(d_grid_out);
    d_gap_tag_pending = true;
    d_gap_samples = 0;
    d_search_pending = true;
    d_logger->warn("lock lost ({}) at output grid sample {} (slot {}): searching again",
                   why,
                   d_grid_out,
                   d_grid_out / d_tracker.slot_length());
}

const gr_complex* ofdm_sync_impl::lock_window(std::int64_t symbol_start, double cfo)
{
    // The DMRS test's window of the found symbol, CFO removed (its common phase is irrelevant).
    const std::int64_t at = symbol_start + d_matcher.window_delay() - d_acq.buffer_start();
    if (at < 0 || at + std::int64_t(d_check.size()) > std::int64_t(d_acq.buffered()))
        return nullptr;
    // The house rotator: a sincos per 512 samples instead of per sample, phase error below
    // 5e-5 rad over the window (test_ofdm_modem: phase_rotator.lock_window_matches_polar).
    kernel::phase_rotator derotate(-cfo);
    derotate.rotate(d_acq.buffer() + at, d_check.data(), d_check.size());
    return d_check.data();
}

void ofdm_sync_impl::acquire(const gr_complex* x, std::size_t n, std::uint64_t out_item)
{
    bool found = d_acq.push(x, n);
    while (found && !on_lock(out_item))
        found = d_acq.push(nullptr, 0);
}

bool ofdm_sync_impl::on_lock(std::uint64_t out_item)
{
    const auto& r = d_acq.get();
    const std::int64_t len = d_num.cp_samples + d_num.fft_size;
    const std::int64_t L = std::int64_t(d_tracker.slot_length());
    // Which DMRS symbol of its slot the search found, and the slot's number within the frame:
    // the DMRS sequence that fits it best (which also refines the plateau's timing: its start
    // scatters by 15-19 samples rms at 3-5 dB). A crossing no sequence passes is rejected;
    // where the test window is not buffered, the later DMRS symbols in the buffer tell the
    // symbol (lock waits for them), and a fresh lock takes the first DMRS symbol of slot 0.
    unsigned j = d_fresh ? 0
                         : d_tracker.found_dmrs(d_acq.buffer(),
                                                d_acq.buffer_start(),
                                                d_acq.buffered(),
                                                r.symbol_start,
                                                d_acq.threshold());
    kernel::dmrs_matcher::match m;
    int frame_slot = -1;
    if (const gr_complex* w = lock_window(r.symbol_start, d_fresh ? r.cfo : -d_rot.frequency())) {
        for (unsigned k = 0; k < d_num_dmrs; k++) {
            kernel::dmrs_matcher::match mk;
            const unsigned s = d_matcher.identify(w, k, mk);
            if (mk.rho >= d_matcher.threshold() && mk.rho > m.rho) {
                m = mk;
                frame_slot = int(s);
                j = k;
            }
        }
        // No DMRS sequence fits: noise or data crossed the threshold (likely where H is
        // short: exp(-t H) per position, 4% at `tiny`). The search goes on after it.
        if (frame_slot < 0) {
            d_acq.reject();
            return false;
        }
    }
    const std::int64_t symbol_start =
        r.symbol_start + (frame_slot >= 0 ? std::llround(m.offset) : 0);
    d_timing = std::int64_t(d_in_origin) + symbol_start;
    // acquirer index of the found DMRS's slot start
    const std::int64_t found_slot_start =
        symbol_start - d_tracker.repeat_offset(j) - std::int64_t(d_first_dmrs) * len -
        d_backoff_samples;
    std::uint64_t slot0 = 0;
    if (d_fresh) {
        slot0 = frame_slot >= 0 ? std::uint64_t(frame_slot) : 0;
        d_next = found_slot_start;
        if (j > 0 && d_next < d_acq.buffer_start()) { // its start is gone: the next slot
            d_next += L;
            slot0++;
        }
        d_grid_start = std::int64_t(d_in_origin) + d_next - std::int64_t(slot0) * L;
        d_grid_out = slot0 * std::uint64_t(L);
        d_rot.set_phase(0.0);
    } else {
        // A re-acquisition: the new DMRS goes on the old grid, and the slots in between are
        // skipped (the output resumes at the new DMRS's slot, or the next one where the
        // slot's start is no longer buffered).
        const auto r2 = d_tracker.relock_at(
            d_timing - d_grid_start, d_grid_out, j, frame_slot, d_num.slots_per_frame);
        d_grid_start -= r2.shift;
        if (r2.shift > 0)
            d_lost_samples += std::uint64_t(r2.shift);
        slot0 = r2.slot;
        if (std::int64_t(slot0) * L + d_grid_start - std::int64_t(d_in_origin) <
            d_acq.buffer_start())
            slot0++;
        d_skipped_slots += slot0 - d_grid_out / std::uint64_t(L);
        d_skipped_symbols += slot0 * d_num.symbols_per_slot - d_grid_out / std::uint64_t(len);
        d_next = std::int64_t(slot0) * L + d_grid_start - std::int64_t(d_in_origin);
        jump_grid(slot0 * std::uint64_t(L));
        d_reacquisitions++;
    }
    d_start = d_grid_start + std::int64_t(d_grid_out);
    d_out_minus_grid = std::int64_t(out_item) - std::int64_t(d_grid_out);
    d_next_slot = slot0;
    d_metric = r.metric;
    if (d_fresh) { // a gap leaves the oscillators' offset as it was: the CFO is kept
        d_cfo_hz = r.cfo * d_num.sample_rate_hz();
        d_rot.set_frequency(-r.cfo);
    }
    d_sync_tag_pending = true;
    d_sync_tag_item = out_item;
    d_state = state::drain;
    // The drained slots are checked too: a false or shifted lock is noticed there.
    d_tracker.start_check(d_grid_out);
    d_logger->info("{}: DMRS symbol at input sample {}, CFO {:.1f} Hz, metric {:.3f}, "
                   "DMRS rho {:.3f} (symbol {} of slot {} of the frame), slot {} starts at input "
                   "sample {}",
                   d_fresh ? "locked" : "re-acquired",
                   d_timing,
                   d_cfo_hz,
                   d_metric,
                   m.rho,
                   j,
                   frame_slot,
                   slot0,
                   d_start);
    d_fresh = false;
    return true;
}

void ofdm_sync_impl::tag_slots(std::uint64_t out_begin, std::uint64_t out_end)
{
    const std::uint64_t slot_len = d_tracker.slot_length();
    while (true) {
        const std::uint64_t at = std::uint64_t(std::int64_t(d_next_slot * slot_len) + d_out_minus_grid);
        if (at >= out_end)
            break;
        if (at >= out_begin) {
            add_item_tag(0,
                         at,
                         tags::symbol_key(),
                         pmt::from_uint64(d_next_slot * d_num.symbols_per_slot));
            add_item_tag(0, at, tags::slot_key(), pmt::from_uint64(d_next_slot));
            if (d_next_slot % d_num.slots_per_frame == 0)
                add_item_tag(0,
                             at,
                             tags::frame_key(),
                             pmt::from_uint64(d_next_slot / d_num.slots_per_frame));
        }
        d_next_slot++;
    }
}

void ofdm_sync_impl::handle_stamp(const gr::tag_t& tag, std::uint64_t out_item)
{
    std::uint64_t full;
    double frac;
    if (!parse_rx_time(tag.value, full, frac)) {
        d_logger->warn("rx_time tag at input sample {} is not (uint64 s, double s); ignored",
                       tag.offset);
        return;
    }
    if (!d_have_stamp) {
        d_have_stamp = true;
        d_stamp_abs = tag.offset;
        d_stamp_full = full;
        d_stamp_frac = frac;
        return;
    }
    // Samples the radio's clock says passed since the last stamp, against those that came.
    const kernel::rx_time_aligner clock(d_num.sample_rate_hz(), 1, d_stamp_full, d_stamp_frac);
    const std::int64_t lost =
        -clock.samples_until_start(full, frac) - std::int64_t(tag.offset - d_stamp_abs);
    d_stamp_abs = tag.offset;
    d_stamp_full = full;
    d_stamp_frac = frac;
    if (lost == 0)
        return;
    d_gaps++;
    if (lost < 0) {
        d_logger->warn("rx_time at input sample {} goes back {} samples", tag.offset, -lost);
        if (d_state == state::track && !d_search_pending)
            lose_lock("rx_time went back");
        return;
    }
    d_lost_samples += std::uint64_t(lost);
    d_grid_start -= lost; // the grid of the samples after the gap (search: for the re-acquisition)
    if (d_state == state::search) {
        d_acq.reset(); // its history would straddle the gap
        d_in_origin = tag.offset;
        d_logger->warn("rx_time gap of {} samples at input sample {} while searching",
                       lost,
                       tag.offset);
        return;
    }
    // Tracking: the grid sample the stamped sample would have had without the gap.
    const std::uint64_t g = std::uint64_t(std::int64_t(tag.offset) - d_grid_start) - lost;
    const auto p = d_tracker.plan_gap(g, std::uint64_t(lost));
    // Output stands at the stamped sample unless samples after an earlier gap (or a
    // re-acquisition's start) are still being dropped: then the slots from the one output
    // resumes at are the ones not counted yet.
    const bool normal = !d_resume && d_drop == 0;
    const std::uint64_t from =
        d_resume ? d_resume_slot : (normal ? p.first_slot : d_grid_out / d_tracker.slot_length());
    const std::uint64_t resume = std::max(p.resume_slot, from);
    d_skipped_slots += resume - from;
    d_skipped_symbols += normal ? p.skipped_symbols : (resume - from) * d_num.symbols_per_slot;
    if (normal) {
        d_pad = p.pad;
        d_gap_tag_pending = true;
        d_gap_samples = std::uint64_t(lost);
        d_reacquisitions++;
    }
    d_drop = resume * d_tracker.slot_length() - (g + std::uint64_t(lost));
    d_resume = true;
    d_resume_slot = resume;
    d_logger->warn("rx_time gap of {} samples at input sample {} (output item {}): slots {} .. {} "
                   "skipped, resuming at slot {}",
                   lost,
                   tag.offset,
                   out_item,
                   from,
                   resume - 1,
                   resume);
}

int ofdm_sync_impl::general_work(int noutput_items,
                                 gr_vector_int& ninput_items,
                                 gr_vector_const_void_star& input_items,
                                 gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto in = static_cast<const gr_complex*>(input_items[0]);
    auto out = static_cast<gr_complex*>(output_items[0]);
    const std::uint64_t r0 = nitems_read(0), w0 = nitems_written(0);
    const int avail = ninput_items[0];
    int consumed = 0;
    int produced = 0;

    if (d_reset_pending) {
        d_reset_pending = false;
        d_acq.reset();
        d_state = state::search;
        d_fresh = true;
        d_pad = d_drop = 0;
        d_resume = d_search_pending = d_gap_tag_pending = false;
        d_rest.clear();
        d_in_origin = r0;
        d_timing = -1;
        d_cfo_hz = 0.0;
        d_metric = 0.0;
    }

    std::vector<gr::tag_t> stamps;
    get_tags_in_window(stamps, 0, 0, std::uint64_t(avail), d_rx_time_key);
    std::stable_sort(stamps.begin(), stamps.end(), gr::tag_t::offset_compare);
    std::size_t si = 0;
    // Input items up to the next stamp not handled yet (all of them without one).
    auto until_stamp = [&]() {
        while (si < stamps.size() && stamps[si].offset < r0 + std::uint64_t(consumed))
            si++; // consumed in an earlier call (search or drop)
        return si < stamps.size() ? int(stamps[si].offset - r0) - consumed : avail - consumed;
    };

    while (true) {
        if (d_state == state::search) {
            if (consumed == avail)
                break;
            const int n = until_stamp();
            if (n == 0) {
                handle_stamp(stamps[si++], w0 + produced);
                continue;
            }
            std::size_t bad = 0;
            const gr_complex* x = d_guard.guard(in + consumed, n, bad);
            if (bad > 0)
                d_nonfinite.note(d_logger, bad, r0 + consumed);
            consumed += n;
            acquire(x, n, w0 + produced);
            continue;
        }

        if (d_state == state::drain) {
            const std::int64_t bstart = d_acq.buffer_start();
            const std::int64_t bend = bstart + std::int64_t(d_acq.buffered());
            bool lost = false;
            while (!lost && produced < noutput_items && d_next < bend) {
                gr_complex* o = out + produced;
                // Stop at the end of a slot's check window, to look at it before going on.
                std::int64_t k = std::min<std::int64_t>(
                    noutput_items - produced, std::int64_t(d_tracker.until_check_end(d_grid_out)));
                if (d_next < bstart) {
                    // Before the first buffered sample (before the stream began): zeros.
                    k = std::min<std::int64_t>(bstart - d_next, k);
                    std::fill_n(o, k, gr_complex(0.0f, 0.0f));
                } else {
                    k = std::min<std::int64_t>(bend - d_next, k);
                    std::memcpy(o, d_acq.buffer() + (d_next - bstart), sizeof(gr_complex) * k);
                }
                d_rot.rotate(o, o, std::size_t(k));
                produced += int(k);
                d_next += k;
                lost = output_checked(o, std::size_t(k));
            }
            if (!lost && d_next < bend && produced == noutput_items)
                break;
            // A re-acquisition may resume at a slot that starts after the buffer: drop to it.
            // A lost lock leaves the rest of the buffer to the new search.
            d_drop = lost ? 0 : std::uint64_t(std::max<std::int64_t>(d_next - bend, 0));
            if (lost)
                d_rest.assign(d_acq.buffer() + (d_next - bstart), d_acq.buffer() + (bend - bstart));
            d_acq.discard_before(bend); // frees the history
            d_state = state::track;
            continue;
        }

        // Tracking.
        if (d_pad > 0) { // zeros complete the symbol a gap or lost lock cut
            const std::uint64_t k = std::min<std::uint64_t>(d_pad, noutput_items - produced);
            if (k == 0)
                break;
            if (d_gap_tag_pending) { // the slot may now look whole: mark it cut
                add_item_tag(0, w0 + produced, tags::gap_key(), pmt::from_uint64(d_gap_samples));
                d_gap_tag_pending = false;
            }
            std::fill_n(out + produced, k, gr_complex(0.0f, 0.0f));
            jump_grid(d_grid_out + k);
            d_pad -= k;
            produced += int(k);
            continue;
        }
        if (d_search_pending) {
            d_search_pending = false;
            d_resume = false;
            d_drop = 0;
            d_acq.reset();
            d_state = state::search;
            // The input ends at r0 + consumed, after the rest of a drained buffer (if any).
            d_in_origin = r0 + consumed - d_rest.size();
            if (!d_rest.empty())
                acquire(d_rest.data(), d_rest.size(), w0 + produced);
            d_rest.clear();
            continue;
        }
        const int to_stamp = until_stamp();
        if (to_stamp == 0 && si < stamps.size()) {
            handle_stamp(stamps[si++], w0 + produced);
            continue;
        }
        if (d_drop > 0) { // received samples of the last slot a gap cut
            const int k = int(std::min<std::uint64_t>(d_drop, std::uint64_t(to_stamp)));
            if (k == 0)
                break;
            consumed += k;
            d_drop -= std::uint64_t(k);
            continue;
        }
        if (d_resume) {
            d_resume = false;
            jump_grid(d_resume_slot * d_tracker.slot_length());
            d_out_minus_grid = std::int64_t(w0 + produced) - std::int64_t(d_grid_out);
            d_next_slot = d_resume_slot;
            d_tracker.start_check(d_grid_out);
        }
        // Stop at the end of the slot's check window, to look at it before going on.
        const int n = int(std::min<std::uint64_t>(
            std::uint64_t(std::min(to_stamp, noutput_items - produced)),
            d_tracker.until_check_end(d_grid_out)));
        if (n <= 0)
            break;
        std::size_t bad = 0;
        const gr_complex* x = d_guard.guard(in + consumed, n, bad);
        d_rot.rotate(x, out + produced, std::size_t(n));
        if (bad > 0) {
            const std::uint64_t item = w0 + produced;
            add_item_tag(0, d_nonfinite.tag(d_logger, bad, item, item, alias_pmt()));
        }
        consumed += n;
        output_checked(out + produced, std::size_t(n)); // derotated: the test needs no CFO
        produced += n;
    }

    if (produced > 0) {
        if (d_sync_tag_pending) {
            pmt::pmt_t info = pmt::make_dict();
            info = pmt::dict_add(info, pmt::mp("cfo_hz"), pmt::from_double(d_cfo_hz));
            info = pmt::dict_add(info, pmt::mp("timing"), pmt::from_long(d_timing));
            info = pmt::dict_add(info, pmt::mp("start"), pmt::from_long(d_start));
            info = pmt::dict_add(info, pmt::mp("metric"), pmt::from_double(d_metric));
            add_item_tag(0, d_sync_tag_item, tags::sync_key(), info);
            d_sync_tag_pending = false;
        }
        tag_slots(w0, w0 + produced);
    }
    consume_each(consumed);
    return produced;
}

} // namespace nrsar
} // namespace gr
