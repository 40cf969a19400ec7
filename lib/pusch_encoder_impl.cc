/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "pusch_encoder_impl.h"
#include "message_ports.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/kernel/soft_demapper.h>
#include <algorithm>

namespace gr {
namespace nrsar {

namespace {

std::size_t checked_slot_bits(const numerology& num,
                              modulation mod,
                              const dmrs_config& dmrs,
                              std::uint64_t max_queued_bytes)
{
    num.validate();
    dmrs.validate(num);
    if (!kernel::soft_demapper::supported(mod))
        throw_param("mod",
                    static_cast<int>(mod),
                    "is not decodable by pusch_receiver (QPSK, QAM16, QAM64, QAM256 only)");
    check_at_least("max_queued_bytes", max_queued_bytes, std::uint64_t{ 1 });
    return kernel::pusch_slot_bits(num, mod, dmrs);
}
} // namespace

pusch_encoder::sptr pusch_encoder::make(const numerology& num,
                                        modulation mod,
                                        const dmrs_config& dmrs,
                                        const std::string& ldpc_alist,
                                        unsigned scrambling_id,
                                        std::uint64_t max_queued_bytes)
{
    return gnuradio::make_block_sptr<pusch_encoder_impl>(
        num, mod, dmrs, ldpc_alist, scrambling_id, max_queued_bytes);
}

pusch_encoder_impl::pusch_encoder_impl(const numerology& num,
                                       modulation mod,
                                       const dmrs_config& dmrs,
                                       const std::string& ldpc_alist,
                                       unsigned scrambling_id,
                                       std::uint64_t max_queued_bytes)
    : gr::block("pusch_encoder",
                gr::io_signature::make(0, 0, 0),
                gr::io_signature::make(1, 1, sizeof(std::uint8_t))),
      d_num(num),
      d_codec(checked_slot_bits(num, mod, dmrs, max_queued_bytes), ldpc_alist, scrambling_id),
      d_max_queued(max_queued_bytes)
{
    d_tb_bits.resize(d_codec.slot_bits());
    message_port_register_in(pdus_port());
    set_msg_handler(pdus_port(), [this](const pmt::pmt_t& msg) { handle_pdu(msg); });
}

double pusch_encoder_impl::throughput_bps() const
{
    return static_cast<double>(payload_bits_per_slot()) /
           (d_num.symbols_per_slot * d_num.symbol_s());
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
    if (d_queued_bytes + len > d_max_queued) {
        drop_pdu("queue full: " + std::to_string(d_queued_bytes.load()) + " + " +
                 std::to_string(len) + " bytes > max_queued_bytes = " +
                 std::to_string(d_max_queued));
        return;
    }
    d_pdus.emplace_back(data, data + len);
    d_queued_bytes += len;
}

void pusch_encoder_impl::encode_slot()
{
    kernel::tb_header h;
    h.seq = d_seq++;
    const std::uint8_t* payload = nullptr;
    std::size_t len = 0;
    if (d_pdus.empty()) {
        h.flags = kernel::tb_header::filler;
        d_filler++;
    } else {
        const auto& front = d_pdus.front();
        len = std::min(d_codec.payload_bytes(), front.size() - d_pdu_offset);
        payload = front.data() + d_pdu_offset;
        if (d_pdu_offset == 0)
            h.flags |= kernel::tb_header::pdu_start;
        if (d_pdu_offset + len == front.size())
            h.flags |= kernel::tb_header::pdu_end;
    }
    d_codec.encode(h, payload, len, d_slot, d_tb_bits.data());
    if (len > 0) {
        d_pdu_offset += len;
        d_payload_bytes += len;
        d_queued_bytes -= len;
        if (d_pdu_offset == d_pdus.front().size()) {
            d_pdus.pop_front();
            d_pdu_offset = 0;
        }
    }
    // continuous MSB-first bit stream
    for (std::uint8_t b : d_tb_bits) {
        d_acc = static_cast<std::uint8_t>((d_acc << 1) | (b & 1u));
        if (++d_acc_bits == 8) {
            d_out.push_back(d_acc);
            d_acc = 0;
            d_acc_bits = 0;
        }
    }
    d_slot++;
    d_tbs++;
}

int pusch_encoder_impl::general_work(int noutput_items,
                                     gr_vector_int& /*ninput_items*/,
                                     gr_vector_const_void_star& /*input_items*/,
                                     gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    auto out = static_cast<std::uint8_t*>(output_items[0]);
    const auto want = static_cast<std::size_t>(noutput_items);
    while (d_out.size() < want)
        encode_slot();
    std::copy(d_out.begin(), d_out.begin() + static_cast<std::ptrdiff_t>(want), out);
    d_out.erase(d_out.begin(), d_out.begin() + static_cast<std::ptrdiff_t>(want));
    return noutput_items;
}

} /* namespace nrsar */
} /* namespace gr */
