/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "ofdm_demod_impl.h"
#include "param_check.h"
#include "rx_time_tag.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cmath>

namespace gr {
namespace nrsar {

namespace {
void check_tx_start_time(double t)
{
    if (std::isnan(t) || std::isinf(t))
        throw_param("tx_start_time",
                    t,
                    "must be a finite time in seconds (negative turns the rx_time alignment off)");
}

} // namespace

ofdm_demod::sptr ofdm_demod::make(const numerology& num, int fft_start, double tx_start_time)
{
    num.validate();
    if (fft_start > int(num.cp_samples))
        throw_param("fft_start",
                    fft_start,
                    "must be at most cp_samples = " + std::to_string(num.cp_samples) +
                        " (a later FFT window reaches into the next symbol; < 0 means cp_samples)");
    check_tx_start_time(tx_start_time);
    const unsigned start = fft_start < 0 ? num.cp_samples : unsigned(fft_start);
    return gnuradio::make_block_sptr<ofdm_demod_impl>(
        kernel::ofdm_demodulator(
            num.num_subcarriers, num.fft_size, num.cp_samples, num.dc_subcarrier(), start),
        num,
        tx_start_time);
}

ofdm_demod_impl::ofdm_demod_impl(kernel::ofdm_demodulator&& kern,
                                 const numerology& num,
                                 double tx_start_time)
    : gr::block("ofdm_demod",
                gr::io_signature::make(1, 1, sizeof(gr_complex)),
                gr::io_signature::make(1, 1, sizeof(gr_complex) * kern.n())),
      d_kernel(std::move(kern)),
      d_fs(num.sample_rate_hz()),
      d_symbols_per_slot(std::max(1u, num.symbols_per_slot)),
      d_slots_per_frame(std::max(1u, num.slots_per_frame)),
      d_rx_time_key(pmt::mp("rx_time")),
      d_tx_start_time(-1.0)
{
    // Tags are mapped by hand to the symbol they fall in (floor), not rounded.
    set_tag_propagation_policy(TPP_DONT);
    set_tx_start_time(tx_start_time);
}

void ofdm_demod_impl::set_tx_start_time(double t)
{
    check_tx_start_time(t);
    gr::thread::scoped_lock guard(d_setlock);
    d_tx_start_time = t;
    if (t < 0.0) {
        d_aligner.reset();
        d_aligned = false;
        d_skip = 0;
        d_fill = 0;
        return;
    }
    std::uint64_t full;
    double frac;
    kernel::rx_time_aligner::split_seconds(t, full, frac);
    d_aligner = std::make_unique<kernel::rx_time_aligner>(
        d_fs, d_kernel.symbol_length(), full, frac);
    // Already stamped: recompute the TX start sample from the last stamp at the next work().
    d_reapply = d_aligned;
}

void ofdm_demod_impl::forecast(int noutput_items, gr_vector_int& ninput_items_required)
{
    ninput_items_required[0] = noutput_items * int(d_kernel.symbol_length());
}

void ofdm_demod_impl::demod_one(const gr_complex* in, gr_complex* out, std::uint64_t item)
{
    if (d_kernel.execute_if_finite(in, out))
        return;
    std::size_t bad = 0; // a NaN / Inf, or a sum that overflowed: the guarded pass
    const gr_complex* x = d_guard.guard(in, d_kernel.symbol_length(), bad);
    d_kernel.execute(x, out);
    if (bad > 0)
        add_item_tag(0, d_nonfinite.tag(d_logger, bad, item, item, alias_pmt()));
}

int ofdm_demod_impl::work_plain(int noutput_items,
                                int ninput,
                                const gr_complex* in,
                                gr_complex* out)
{
    const std::uint64_t len = d_kernel.symbol_length();
    const int n = std::min<int>(noutput_items, int(ninput / len));
    const std::uint64_t r0 = nitems_read(0), w0 = nitems_written(0);
    get_tags_in_range(d_tags, 0, r0, r0 + std::uint64_t(n) * len);
    for (auto t : d_tags) {
        t.offset = w0 + (t.offset - r0) / len;
        add_item_tag(0, t);
    }
    for (int i = 0; i < n; i++)
        demod_one(in + i * len, out + i * d_kernel.n(), w0 + i);
    consume(0, n * len);
    return n;
}

void ofdm_demod_impl::apply_offset(std::uint64_t abs, std::int64_t tx_start_offset, const char* why)
{
    const auto len = d_kernel.symbol_length();
    // The symbol the output stream is at, zero symbols still owed included.
    const std::uint64_t expected = d_aligned ? d_next_symbol + d_fill : 0;
    const auto r = kernel::rx_time_aligner::align_offset(tx_start_offset, len, expected);
    if (r.lost_symbols > 0) {
        d_lost += std::uint64_t(r.lost_symbols);
        d_logger->warn("{} at input sample {}: symbols {} .. {} lost ({} so far), output as "
                       "zeros; symbol {} follows",
                       why,
                       abs,
                       expected,
                       r.next_symbol - 1,
                       d_lost,
                       r.next_symbol);
    } else if (r.lost_symbols < 0) {
        d_logger->warn("{} at input sample {} goes back in time: the next output is symbol {} "
                       "(expected {})",
                       why,
                       abs,
                       r.next_symbol,
                       expected);
    } else {
        d_logger->info("{} at input sample {}: TX start at input sample {}, {} samples dropped "
                       "before symbol {}",
                       why,
                       abs,
                       std::int64_t(abs) + tx_start_offset,
                       r.skip,
                       r.next_symbol);
    }
    d_s0 = std::int64_t(abs) + tx_start_offset;
    d_skip = r.skip;
    // Lost symbols are output as zero vectors, so output item k stays symbol k (the radar's
    // reference grid and slow time go on); a stamp that goes back in time restarts there.
    if (r.lost_symbols > 0) {
        d_next_symbol = expected - d_fill;
        d_fill += std::uint64_t(r.lost_symbols);
    } else {
        d_next_symbol = r.next_symbol;
        d_fill = 0;
    }
    d_aligned = true;
    d_tag_next = true;
}

void ofdm_demod_impl::apply_stamp(std::uint64_t abs, std::uint64_t full, double frac)
{
    d_stamp_abs = abs;
    d_stamp_full = full;
    d_stamp_frac = frac;
    apply_offset(abs, d_aligner->samples_until_start(full, frac), "rx_time");
}

void ofdm_demod_impl::count_stamp(std::uint64_t offset)
{
    // A stamp left unconsumed (the output filled up behind it) is seen again next call.
    if (d_stamps == 0 || offset > d_last_stamp)
        d_stamps++;
    d_last_stamp = offset;
}

void ofdm_demod_impl::tag_symbol(std::uint64_t item)
{
    const std::uint64_t sym = d_next_symbol;
    const bool slot_start = sym % d_symbols_per_slot == 0;
    if (d_tag_next || slot_start)
        add_item_tag(0, item, tags::symbol_key(), pmt::from_uint64(sym), alias_pmt());
    if (slot_start) {
        const std::uint64_t slot = sym / d_symbols_per_slot;
        add_item_tag(0, item, tags::slot_key(), pmt::from_uint64(slot), alias_pmt());
        if (slot % d_slots_per_frame == 0)
            add_item_tag(0,
                         item,
                         tags::frame_key(),
                         pmt::from_uint64(slot / d_slots_per_frame),
                         alias_pmt());
    }
    d_tag_next = false;
}

int ofdm_demod_impl::work_aligned(int noutput_items,
                                  int ninput,
                                  const gr_complex* in,
                                  gr_complex* out)
{
    const std::uint64_t len = d_kernel.symbol_length();
    const std::uint64_t r0 = nitems_read(0), w0 = nitems_written(0);
    const std::uint64_t avail = std::uint64_t(ninput);

    if (d_reapply) { // new T0 at run time: from the last stamp, relative to this position
        d_reapply = false;
        const std::int64_t s0 =
            std::int64_t(d_stamp_abs) + d_aligner->samples_until_start(d_stamp_full, d_stamp_frac);
        apply_offset(r0, s0 - std::int64_t(r0), "new tx_start_time");
    }

    auto& tags = d_tags;
    get_tags_in_range(tags, 0, r0, r0 + avail);
    std::stable_sort(tags.begin(), tags.end(), gr::tag_t::offset_compare);
    auto& stamps = d_stamps_at; // indices into tags of rx_time tags
    stamps.clear();
    for (std::size_t i = 0; i < tags.size(); i++)
        if (pmt::eq(tags[i].key, d_rx_time_key))
            stamps.push_back(i);

    std::size_t si = 0; // next stamp not applied yet
    std::uint64_t pos = 0;
    int produced = 0;
    // (relative input start, output item) of each demodulated symbol
    auto& starts = d_starts;
    starts.clear();

    // Next stamp that changes the timeline, skipping malformed and consistent ones.
    auto next_stamp = [&]() -> std::uint64_t {
        while (si < stamps.size()) {
            const auto& t = tags[stamps[si]];
            std::uint64_t full;
            double frac;
            if (!parse_rx_time(t.value, full, frac)) {
                d_logger->warn("rx_time tag at input sample {} is not (uint64 s, double s); "
                               "ignored",
                               t.offset);
                count_stamp(t.offset);
                si++;
                continue;
            }
            if (d_aligned) {
                const std::int64_t s0 =
                    std::int64_t(t.offset) + d_aligner->samples_until_start(full, frac);
                if (s0 == d_s0) { // the same timeline: nothing to do
                    count_stamp(t.offset);
                    si++;
                    continue;
                }
            }
            return t.offset - r0;
        }
        return avail; // none in this window
    };

    std::uint64_t stamp_at = next_stamp();
    while (pos < avail || d_fill > 0) {
        if (d_fill > 0) { // a lost symbol: zeros in its place
            if (produced == noutput_items)
                break;
            tag_symbol(w0 + produced);
            std::fill_n(out + std::size_t(produced) * d_kernel.n(), d_kernel.n(), gr_complex(0));
            d_next_symbol++;
            produced++;
            d_tag_next = --d_fill == 0; // the first received symbol after the gap
            continue;
        }
        if (stamp_at == pos) {
            const auto& t = tags[stamps[si]];
            std::uint64_t full;
            double frac;
            parse_rx_time(t.value, full, frac); // checked by next_stamp()
            count_stamp(t.offset);
            apply_stamp(t.offset, full, frac);
            si++;
            stamp_at = next_stamp();
            continue;
        }
        const std::uint64_t limit = stamp_at; // <= avail
        if (!d_aligned) { // time unknown: drop up to the first stamp
            if (!d_warned_unstamped) {
                d_logger->warn("rx_time alignment on but no rx_time tag yet: dropping input "
                               "samples until one arrives");
                d_warned_unstamped = true;
            }
            d_dropped += limit - pos;
            pos = limit;
            continue;
        }
        if (d_skip > 0) {
            const std::uint64_t n = std::min(d_skip, limit - pos);
            d_skip -= n;
            d_dropped += n;
            pos += n;
            continue;
        }
        if (pos + len > limit) {
            if (limit < avail) { // a partial symbol before a re-aligning stamp
                d_dropped += limit - pos;
                pos = limit;
                continue;
            }
            break; // wait for the rest of the symbol
        }
        if (produced == noutput_items)
            break;
        const std::uint64_t item = w0 + produced;
        tag_symbol(item);
        demod_one(in + pos, out + std::size_t(produced) * d_kernel.n(), item);
        starts.emplace_back(pos, produced);
        d_next_symbol++;
        produced++;
        pos += len;
    }

    // Tags of the consumed samples: to the item whose symbol holds them, or (dropped
    // samples) to the next item produced, now or in a later call.
    if (produced > 0 && !d_pending.empty()) { // from earlier calls: before this call's tags
        for (auto t : d_pending) {
            t.offset = w0;
            add_item_tag(0, t);
        }
        d_pending.clear();
    }
    std::size_t j = 0;
    for (auto t : tags) {
        const std::uint64_t rel = t.offset - r0;
        if (rel >= pos)
            break;
        while (j < starts.size() && starts[j].first + len <= rel)
            j++;
        if (j < starts.size()) {
            t.offset = w0 + std::uint64_t(starts[j].second);
            add_item_tag(0, t);
        } else {
            d_pending.push_back(t);
        }
    }
    consume(0, int(pos));
    return produced;
}

int ofdm_demod_impl::general_work(int noutput_items,
                                  gr_vector_int& ninput_items,
                                  gr_vector_const_void_star& input_items,
                                  gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto in = static_cast<const gr_complex*>(input_items[0]);
    auto out = static_cast<gr_complex*>(output_items[0]);
    if (d_aligner)
        return work_aligned(noutput_items, ninput_items[0], in, out);
    return work_plain(noutput_items, ninput_items[0], in, out);
}

} // namespace nrsar
} // namespace gr
