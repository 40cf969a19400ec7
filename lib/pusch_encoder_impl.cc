/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "pusch_encoder_impl.h"
#include "message_ports.h"
#include "param_check.h"
#include "kernel/bit_pack.h"
#include <gnuradio/io_signature.h>
#include <algorithm>

namespace gr {
namespace nrsar {

pusch_encoder::sptr pusch_encoder::make(const pusch_config& cfg)
{
    return gnuradio::make_block_sptr<pusch_encoder_impl>(cfg);
}

pusch_encoder_impl::pusch_encoder_impl(const pusch_config& cfg)
    : gr::block("pusch_encoder",
                gr::io_signature::make(0, 0, 0),
                gr::io_signature::make(1, 1, sizeof(std::uint8_t))),
      d_cfg(cfg),
      d_codec(cfg),
      d_max_queued(cfg.max_queued_bytes),
      d_slot(cfg.first_slot)
{
    d_tb.resize(d_codec.tb_bytes());
    d_tb_bits.resize(d_codec.slot_bits());
    message_port_register_in(pdus_port());
    set_msg_handler(pdus_port(), [this](const pmt::pmt_t& msg) { handle_pdu(msg); });
}

double pusch_encoder_impl::throughput_bps() const
{
    return static_cast<double>(payload_bits_per_slot()) /
           (d_cfg.repetitions * d_cfg.num.symbols_per_slot * d_cfg.num.symbol_s());
}

void pusch_encoder_impl::drop_pdu(const std::string& why)
{
    const std::uint64_t n = ++d_dropped;
    // every drop is counted; the log is rate-limited to drops 1, 2, 4, 8, ...
    if ((n & (n - 1)) == 0)
        d_logger->warn("dropped PDU ({}); {} dropped so far (pdus_dropped())", why, n);
}

void pusch_encoder_impl::handle_pdu(const pmt::pmt_t& msg)
{
    gr::thread::scoped_lock guard(d_setlock);
    if (!pmt::is_pair(msg) || !pmt::is_u8vector(pmt::cdr(msg))) {
        drop_pdu("not a PDU: expected pmt pair (meta . u8vector)");
        return;
    }
    std::size_t len = 0;
    const std::uint8_t* data = pmt::u8vector_elements(pmt::cdr(msg), len);
    if (len == 0)
        return;
    if (len > 65535) {
        drop_pdu("PDU of " + std::to_string(len) +
                 " bytes > 65535 (the RLC segment offset has 16 bits)");
        return;
    }
    if (d_queued_bytes + len > d_max_queued) {
        drop_pdu("queue full: " + std::to_string(d_queued_bytes.load()) + " + " +
                 std::to_string(len) + " bytes > max_queued_bytes = " +
                 std::to_string(d_max_queued));
        return;
    }
    d_pdus.emplace_back(data, data + len);
    d_queued_bytes += len;
}

void pusch_encoder_impl::next_tb()
{
    using kernel::mac_sdu;
    mac_sdu sdu;
    if (d_pdus.empty()) {
        d_filler++;
        sdu.write(d_tb.data(), d_tb.size());
        return;
    }
    // RLC UM segmentation (38.322 5.2.2.1): SN only on segmented SDUs, SO on all but the first
    const auto& front = d_pdus.front();
    const std::size_t rest = front.size() - d_pdu_offset;
    sdu.filler = false;
    if (d_pdu_offset == 0)
        sdu.si = rest <= mac_sdu::capacity(d_tb.size(), mac_sdu::complete) ? mac_sdu::complete
                                                                            : mac_sdu::first;
    else
        sdu.si = rest <= mac_sdu::capacity(d_tb.size(), mac_sdu::last) ? mac_sdu::last
                                                                        : mac_sdu::middle;
    const std::size_t len = std::min(rest, mac_sdu::capacity(d_tb.size(), sdu.si));
    sdu.sn = d_sn;
    sdu.so = static_cast<std::uint16_t>(d_pdu_offset);
    sdu.data.assign(front.begin() + static_cast<std::ptrdiff_t>(d_pdu_offset),
                    front.begin() + static_cast<std::ptrdiff_t>(d_pdu_offset + len));
    sdu.write(d_tb.data(), d_tb.size());
    d_pdu_offset += len;
    d_payload_bytes += len;
    d_queued_bytes -= len;
    if (d_pdu_offset == front.size()) {
        if (sdu.si != mac_sdu::complete)
            d_sn = static_cast<std::uint8_t>((d_sn + 1) & 0x3f);
        d_pdus.pop_front();
        d_pdu_offset = 0;
    }
}

void pusch_encoder_impl::encode_slot()
{
    // a new TB every repetitions slots (and in the first slot, which may lie inside a TB's
    // repetitions: first_slot); each slot sends it with the rv of its position
    const auto pos = static_cast<unsigned>(d_slot % d_cfg.repetitions);
    if (pos == 0 || d_slot == d_cfg.first_slot) {
        next_tb();
        d_tbs++;
    }
    // A TB, rv and c_init equal to the last slot's give its bits again: every padding-only
    // slot under the standard scrambler, i.e. most of a radar aperture.
    const unsigned rv = d_cfg.rv_of(pos);
    const std::uint32_t c_init = d_codec.c_init(d_slot);
    if (!(d_last_valid && rv == d_last_rv && c_init == d_last_c_init && d_tb == d_last_tb)) {
        d_codec.encode(d_tb.data(), rv, d_slot, d_tb_bits.data());
        d_last_tb = d_tb;
        d_last_rv = rv;
        d_last_c_init = c_init;
        d_last_valid = true;
    }
    // continuous MSB-first bit stream; whole bytes 8 bits at a time (G is a multiple of
    // the modulation order, so after a byte-aligned slot the next one is aligned too)
    const std::size_t g = d_tb_bits.size();
    std::size_t i = 0;
    for (; i < g && d_acc_bits != 0; i++)
        push_bit(d_tb_bits[i]);
    const std::size_t whole = (g - i) / 8;
    const std::size_t at = d_out.size();
    d_out.resize(at + whole);
    for (std::size_t k = 0; k < whole; k++, i += 8)
        d_out[at + k] = kernel::pack8(&d_tb_bits[i]);
    for (; i < g; i++)
        push_bit(d_tb_bits[i]);
    d_slot++;
}

void pusch_encoder_impl::push_bit(std::uint8_t b)
{
    d_acc = static_cast<std::uint8_t>((d_acc << 1) | (b & 1u));
    if (++d_acc_bits == 8) {
        d_out.push_back(d_acc);
        d_acc = 0;
        d_acc_bits = 0;
    }
}

int pusch_encoder_impl::general_work(int noutput_items,
                                     gr_vector_int& /*ninput_items*/,
                                     gr_vector_const_void_star& /*input_items*/,
                                     gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    auto out = static_cast<std::uint8_t*>(output_items[0]);
    const auto want = static_cast<std::size_t>(noutput_items);
    std::size_t done = 0;
    while (done < want) {
        if (d_out_head == d_out.size()) {
            d_out.clear();
            d_out_head = 0;
            encode_slot();
            continue;
        }
        const std::size_t n = std::min(want - done, d_out.size() - d_out_head);
        std::copy_n(d_out.data() + d_out_head, n, out + done);
        d_out_head += n;
        done += n;
    }
    return noutput_items;
}

} /* namespace nrsar */
} /* namespace gr */
