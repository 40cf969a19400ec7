/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "pusch_receiver_impl.h"
#include "message_ports.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cmath>

namespace gr {
namespace nrsar {

namespace {

int checked_itemsize(const numerology& num)
{
    num.validate();
    return static_cast<int>(num.num_subcarriers * sizeof(gr_complex));
}
} // namespace

pusch_receiver::sptr pusch_receiver::make(const pusch_config& cfg)
{
    return gnuradio::make_block_sptr<pusch_receiver_impl>(cfg);
}

pusch_receiver_impl::pusch_receiver_impl(const pusch_config& cfg)
    : gr::block("pusch_receiver",
                gr::io_signature::make(1, 1, checked_itemsize(cfg.num)),
                gr::io_signature::make(0, 1, sizeof(gr_complex))),
      d_num(cfg.num),
      d_rx(cfg),
      d_repetitions(cfg.repetitions)
{
    set_tag_propagation_policy(TPP_DONT);
    // Room for two slots of equalised REs: a slot is only finished when its REs all fit
    // (see general_work), so none are left behind when the input ends.
    set_min_output_buffer(0, 2 * static_cast<long>(d_rx.data_res()));
    d_slot_buf.resize(static_cast<std::size_t>(d_num.symbols_per_slot) * d_num.num_subcarriers);
    message_port_register_out(pdus_port());
}

bool pusch_receiver_impl::check_topology(int /*ninputs*/, int noutputs)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_eq_output = noutputs > 0;
    return true;
}

void pusch_receiver_impl::forecast(int /*noutput_items*/, gr_vector_int& ninput_items_required)
{
    // Output 0 runs behind the input by up to one slot: any input symbol makes progress.
    ninput_items_required[0] = 1;
}


void pusch_receiver_impl::finish_slot()
{
    if (d_cut) { // completed with zeros after a gap: lost, not decoded
        d_cut = false;
        if (d_eq_output) {
            std::fill(d_eq.begin(), d_eq.end(), gr_complex(0.0f, 0.0f));
            d_eq_pos = 0;
        }
        report_lost(d_slot);
        d_slot++;
        d_fill = 0;
        return;
    }
    const auto res = d_rx.process(d_slot_buf.data(), d_slot, d_eq_output ? d_eq.data() : nullptr);
    if (d_eq_output)
        d_eq_pos = 0;
    d_snr = res.snr_db;
    d_evm = res.evm_db;
    const auto& tb = res.tb;
    if (res.transmissions > 0 && tb.code_blocks > 0) {
        d_decodes++;
        d_iterations_sum = d_iterations_sum + tb.mean_iterations;
    }
    if (!res.tb_final) {
        d_slot++;
        d_fill = 0;
        return;
    }
    const bool ok = tb.header_ok;
    const bool filler = ok && tb.sdu.filler;
    const auto si = tb.sdu.si;
    if (ok) {
        d_ok++;
        if (filler)
            d_filler++;
        if (res.transmissions > 1)
            d_harq_ok++;
        d_bytes += tb.sdu.data.size();
    } else {
        d_failed++;
    }
    // A TB that failed after a gap cut one of its repetitions is lost, not a channel failure.
    const bool lost = !ok && res.tb_index == d_cut_tb;
    if (lost)
        d_lost++;
    const bool data = ok && !filler;
    const long payload_len = data ? static_cast<long>(tb.sdu.data.size()) : 0;
    pdu_meta m;
    m.slot = res.tb_index * d_repetitions;
    m.seq = ok ? static_cast<long>(res.tb_index & 0xffffu) : -1;
    m.crc_ok = ok;
    m.filler = filler;
    m.payload_len = payload_len;
    m.pdu_start = data && (si == kernel::mac_sdu::complete || si == kernel::mac_sdu::first);
    m.pdu_end = data && (si == kernel::mac_sdu::complete || si == kernel::mac_sdu::last);
    m.sn = data ? tb.sdu.sn : -1;
    m.so = data ? tb.sdu.so : -1;
    m.transmissions = res.transmissions;
    m.ldpc_iterations = tb.mean_iterations;
    m.code_blocks = tb.code_blocks;
    m.cb_crc_ok = tb.cb_crc_ok;
    m.snr_db = res.snr_db;
    m.evm_db = res.evm_db;
    m.lost = lost;
    const pmt::pmt_t bytes = data ? pmt::init_u8vector(tb.sdu.data.size(), tb.sdu.data)
                                  : pmt::make_u8vector(0, 0);
    publish(m, bytes, res.tb_index);
    d_slot++;
    d_fill = 0;
}

void pusch_receiver_impl::publish(const pdu_meta& m, const pmt::pmt_t& bytes, std::uint64_t tb)
{
    pmt::pmt_t meta = pmt::make_dict();
    auto add = [&meta](const char* key, const pmt::pmt_t& v) {
        meta = pmt::dict_add(meta, pmt::mp(key), v);
    };
    add("slot", pmt::from_uint64(m.slot));
    add("seq", pmt::from_long(m.seq));
    add("crc_ok", pmt::from_bool(m.crc_ok));
    add("filler", pmt::from_bool(m.filler));
    add("payload_len", pmt::from_long(m.payload_len));
    add("pdu_start", pmt::from_bool(m.pdu_start));
    add("pdu_end", pmt::from_bool(m.pdu_end));
    add("sn", pmt::from_long(m.sn));
    add("so", pmt::from_long(m.so));
    add("lost", pmt::from_bool(m.lost));
    add("transmissions", pmt::from_long(m.transmissions));
    add("ldpc_iterations", pmt::from_double(m.ldpc_iterations));
    add("code_blocks", pmt::from_long(m.code_blocks));
    add("cb_crc_ok", pmt::from_long(m.cb_crc_ok));
    add("snr_db", pmt::from_double(m.snr_db));
    add("evm_db", pmt::from_double(m.evm_db));
    d_reported_tb = tb;
    message_port_pub(pdus_port(), pmt::cons(meta, bytes));
}

void pusch_receiver_impl::report_lost(std::uint64_t slot)
{
    // A TB is lost when its last transmission is and it has not been reported (decoded) yet;
    // one whose earlier repetition is cut is lost if the rest do not decode (finish_slot).
    const std::uint64_t tb = slot / d_repetitions;
    d_cut_tb = tb;
    if (slot % d_repetitions != d_repetitions - 1 || tb == d_reported_tb)
        return;
    d_failed++;
    d_lost++;
    pdu_meta m; // the defaults: nothing received
    m.slot = tb * d_repetitions;
    m.lost = true;
    publish(m, pmt::make_u8vector(0, 0), tb);
}

int pusch_receiver_impl::general_work(int noutput_items,
                                      gr_vector_int& ninput_items,
                                      gr_vector_const_void_star& input_items,
                                      gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const unsigned n = d_num.num_subcarriers;
    const unsigned sps = d_num.symbols_per_slot;
    int produced = 0;

    // Drain equalised REs of the last slot first.
    auto drain = [&]() {
        if (!d_eq_output)
            return;
        auto out = static_cast<gr_complex*>(output_items[0]);
        const std::size_t take = std::min<std::size_t>(
            static_cast<std::size_t>(noutput_items - produced), d_eq.size() - d_eq_pos);
        std::copy(d_eq.begin() + static_cast<std::ptrdiff_t>(d_eq_pos),
                  d_eq.begin() + static_cast<std::ptrdiff_t>(d_eq_pos + take),
                  out + produced);
        d_eq_pos += take;
        produced += static_cast<int>(take);
    };
    if (d_eq_output && d_eq.empty()) {
        d_eq.resize(d_rx.data_res());
        d_eq_pos = d_eq.size();
    }
    drain();

    const auto in = static_cast<const gr_complex*>(input_items[0]);
    const int avail = ninput_items[0];
    const std::uint64_t base = nitems_read(0);
    std::vector<gr::tag_t> slot_tags, gap_tags;
    get_tags_in_window(slot_tags, 0, 0, static_cast<std::uint64_t>(avail), tags::slot_key());
    get_tags_in_window(gap_tags, 0, 0, static_cast<std::uint64_t>(avail), tags::gap_key());
    std::sort(gap_tags.begin(), gap_tags.end(), gr::tag_t::offset_compare);
    std::size_t next_tag = 0, next_gap = 0;

    int used = 0;
    while (used < avail) {
        if (d_eq_output && d_eq_pos < d_eq.size())
            break; // output 0 must take the previous slot first
        // The slot's last symbol finishes it: take it only when all its equalised REs fit,
        // so the scheduler calls again while input is left (at the end of the stream a
        // remainder held back here would be lost).
        // (A max_noutput_items below one slot falls back to draining across calls.)
        if (d_eq_output && d_fill + 1 == sps &&
            static_cast<std::size_t>(noutput_items - produced) < d_rx.data_res() &&
            !(is_set_max_noutput_items() &&
              static_cast<std::size_t>(max_noutput_items()) < d_rx.data_res()))
            break;
        const std::uint64_t abs = base + static_cast<std::uint64_t>(used);
        while (next_tag < slot_tags.size() && slot_tags[next_tag].offset < abs)
            next_tag++;
        if (next_tag < slot_tags.size() && slot_tags[next_tag].offset == abs &&
            (pmt::is_uint64(slot_tags[next_tag].value) ||
             pmt::is_integer(slot_tags[next_tag].value))) {
            const std::uint64_t slot = pmt::to_uint64(slot_tags[next_tag].value);
            if (d_fill != 0) {
                d_partial++;
                d_logger->warn("slot tag at item {} inside slot {}: {} symbols discarded",
                               abs,
                               d_slot,
                               d_fill);
            }
            // Slots numbered ahead of the one expected never arrived whole (a gap upstream;
            // a number going back is a new acquisition): their TBs are reported lost.
            if (d_seen_slot_tag && slot > d_slot) {
                if (slot - d_slot <= max_lost_report) {
                    for (std::uint64_t s = d_slot; s < slot; s++)
                        report_lost(s);
                } else { // bounded messages: a jump this long is a new burst, not a gap
                    d_logger->warn("slot number jumps from {} to {}: taken as a new burst, "
                                   "the slots between are not reported lost",
                                   d_slot,
                                   slot);
                }
            }
            d_seen_slot_tag = true;
            d_cut = false;
            d_fill = 0;
            d_slot = slot;
        }
        for (; next_gap < gap_tags.size() && gap_tags[next_gap].offset <= abs; next_gap++)
            if (gap_tags[next_gap].offset == abs)
                d_cut = true;
        std::size_t bad = 0;
        const gr_complex* src = d_guard.guard(in + static_cast<std::size_t>(used) * n, n, bad);
        std::copy(src, src + n, d_slot_buf.data() + static_cast<std::size_t>(d_fill) * n);
        if (bad) {
            d_nonfinite.note(d_logger, bad, abs);
            d_nonfinite_count += bad;
        }
        used++;
        if (++d_fill == sps) {
            finish_slot();
            drain();
        }
    }
    consume(0, used);
    return produced;
}

} /* namespace nrsar */
} /* namespace gr */
