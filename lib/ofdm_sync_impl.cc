/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "ofdm_sync_impl.h"
#include "param_check.h"
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
      d_backoff(backoff),
      d_backoff_samples(std::llround(backoff * num.cp_samples)),
      d_acq(num.fft_size,
            num.cp_samples,
            threshold,
            std::size_t(dmrs.symbols.front()) * (num.cp_samples + num.fft_size) +
                num.cp_samples + num.fft_size / 2 + std::size_t(std::llround(backoff * num.cp_samples)) + 2)
{
    // The other DMRS symbols of the slot refine the CFO estimate.
    std::vector<std::int64_t> repeats;
    for (std::size_t k = 1; k < dmrs.symbols.size(); k++)
        repeats.push_back(std::int64_t(dmrs.symbols[k] - dmrs.symbols[0]) *
                          (num.cp_samples + num.fft_size));
    d_acq.set_repeats(repeats);
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
    // Searching eats whatever arrives; draining needs no input; tracking is 1:1.
    ninput_items_required[0] =
        d_state == state::track ? noutput_items : (d_state == state::search ? 1 : 0);
}

void ofdm_sync_impl::on_lock()
{
    const auto& r = d_acq.get();
    const std::int64_t len = d_num.cp_samples + d_num.fft_size;
    d_next = r.symbol_start - std::int64_t(d_first_dmrs) * len - d_backoff_samples;
    d_timing = std::int64_t(d_in_origin) + r.symbol_start;
    d_start = std::int64_t(d_in_origin) + d_next;
    d_cfo_hz = r.cfo * d_num.sample_rate_hz();
    d_metric = r.metric;
    d_rot.set_frequency(-r.cfo);
    d_rot.set_phase(0.0);
    d_out_origin = nitems_written(0);
    d_next_slot = 0;
    d_sync_tag_pending = true;
    d_state = state::drain;
    d_logger->info("locked: DMRS symbol at input sample {}, CFO {:.1f} Hz, metric {:.3f}, "
                   "output starts at input sample {}",
                   d_timing,
                   d_cfo_hz,
                   d_metric,
                   d_start);
}

void ofdm_sync_impl::tag_slots(std::uint64_t out_begin, std::uint64_t out_end)
{
    const std::uint64_t slot_len = std::uint64_t(d_num.cp_samples + d_num.fft_size) *
                                   d_num.symbols_per_slot;
    while (true) {
        const std::uint64_t at = d_out_origin + d_next_slot * slot_len;
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

int ofdm_sync_impl::general_work(int noutput_items,
                                 gr_vector_int& ninput_items,
                                 gr_vector_const_void_star& input_items,
                                 gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto in = static_cast<const gr_complex*>(input_items[0]);
    auto out = static_cast<gr_complex*>(output_items[0]);
    int consumed = 0;
    int produced = 0;

    if (d_reset_pending) {
        d_reset_pending = false;
        d_acq.reset();
        d_state = state::search;
        d_in_origin = nitems_read(0);
        d_timing = -1;
        d_cfo_hz = 0.0;
        d_metric = 0.0;
    }

    if (d_state == state::search) {
        const int n = ninput_items[0];
        std::size_t bad = 0;
        const gr_complex* x = d_guard.guard(in, n, bad);
        if (bad > 0)
            d_nonfinite.note(d_logger, bad, nitems_read(0));
        consumed = n;
        if (d_acq.push(x, n))
            on_lock();
    }

    if (d_state == state::drain) {
        const std::int64_t bstart = d_acq.buffer_start();
        const std::int64_t bend = bstart + std::int64_t(d_acq.buffered());
        while (produced < noutput_items && d_next < bend) {
            gr_complex* o = out + produced;
            std::int64_t k;
            if (d_next < bstart) {
                // Before the first buffered sample (before the stream began): zeros.
                k = std::min<std::int64_t>(bstart - d_next, noutput_items - produced);
                std::fill_n(o, k, gr_complex(0.0f, 0.0f));
            } else {
                k = std::min<std::int64_t>(bend - d_next, noutput_items - produced);
                std::memcpy(o, d_acq.buffer() + (d_next - bstart), sizeof(gr_complex) * k);
            }
            d_rot.rotate(o, o, std::size_t(k));
            produced += int(k);
            d_next += k;
        }
        if (d_next >= bend) {
            d_acq.discard_before(bend); // frees the history
            d_state = state::track;
        }
    }

    if (d_state == state::track) {
        const int n = std::min(ninput_items[0] - consumed, noutput_items - produced);
        if (n > 0) {
            std::size_t bad = 0;
            const gr_complex* x = d_guard.guard(in + consumed, n, bad);
            d_rot.rotate(x, out + produced, std::size_t(n));
            if (bad > 0) {
                const std::uint64_t item = nitems_written(0) + produced;
                add_item_tag(0, d_nonfinite.tag(d_logger, bad, item, item, alias_pmt()));
            }
            consumed += n;
            produced += n;
        }
    }

    if (produced > 0) {
        if (d_sync_tag_pending) {
            pmt::pmt_t info = pmt::make_dict();
            info = pmt::dict_add(info, pmt::mp("cfo_hz"), pmt::from_double(d_cfo_hz));
            info = pmt::dict_add(info, pmt::mp("timing"), pmt::from_long(d_timing));
            info = pmt::dict_add(info, pmt::mp("start"), pmt::from_long(d_start));
            info = pmt::dict_add(info, pmt::mp("metric"), pmt::from_double(d_metric));
            add_item_tag(0, d_out_origin, tags::sync_key(), info);
            d_sync_tag_pending = false;
        }
        tag_slots(nitems_written(0), nitems_written(0) + produced);
    }
    consume_each(consumed);
    return produced;
}

} // namespace nrsar
} // namespace gr
