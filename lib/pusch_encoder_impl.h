/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_PUSCH_ENCODER_IMPL_H
#define INCLUDED_NRSAR_PUSCH_ENCODER_IMPL_H

#include <gnuradio/nrsar/kernel/transport_block.h>
#include <gnuradio/nrsar/pusch_encoder.h>
#include <atomic>
#include <deque>
#include <vector>

namespace gr {
namespace nrsar {

class pusch_encoder_impl : public pusch_encoder
{
private:
    pusch_config d_cfg;
    kernel::transport_block_codec d_codec;
    std::uint64_t d_max_queued;

    std::deque<std::vector<std::uint8_t>> d_pdus;
    std::size_t d_pdu_offset = 0;
    std::uint64_t d_slot;                  // absolute index of the next slot
    std::uint8_t d_sn = 0;                 // RLC SN of the next segmented PDU (6 bits)

    std::vector<std::uint8_t> d_tb;        // the MAC PDU of the current TB
    std::vector<std::uint8_t> d_tb_bits;   // G unpacked bits of the current slot
    std::vector<std::uint8_t> d_last_tb;   // the TB, rv and c_init d_tb_bits were made of
    unsigned d_last_rv = 0;
    std::uint32_t d_last_c_init = 0;
    bool d_last_valid = false;
    std::vector<std::uint8_t> d_out;       // packed bytes ready for the output, from d_out_head
    std::size_t d_out_head = 0;
    std::uint8_t d_acc = 0;                // partial byte
    unsigned d_acc_bits = 0;

    std::atomic<std::uint64_t> d_tbs{ 0 };
    std::atomic<std::uint64_t> d_filler{ 0 };
    std::atomic<std::uint64_t> d_payload_bytes{ 0 };
    std::atomic<std::uint64_t> d_dropped{ 0 };
    std::atomic<std::uint64_t> d_queued_bytes{ 0 };

    void handle_pdu(const pmt::pmt_t& msg);
    void drop_pdu(const std::string& why);
    void next_tb();
    void push_bit(std::uint8_t b);
    void encode_slot();

public:
    explicit pusch_encoder_impl(const pusch_config& cfg);

    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;

    std::uint64_t tbs_sent() const override { return d_tbs; }
    std::uint64_t filler_tbs_sent() const override { return d_filler; }
    std::uint64_t payload_bytes_sent() const override { return d_payload_bytes; }
    std::uint64_t pdus_dropped() const override { return d_dropped; }
    std::uint64_t queued_bytes() const override { return d_queued_bytes; }
    double code_rate() const override { return d_codec.code_rate(); }
    std::uint64_t payload_bits_per_slot() const override
    {
        return 8 * d_codec.payload_bytes();
    }
    std::uint64_t tbs_bits() const override { return d_codec.tbs_bits(); }
    unsigned code_blocks() const override { return d_codec.code_blocks(); }
    std::uint64_t slot_bits() const override { return d_codec.slot_bits(); }
    double throughput_bps() const override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PUSCH_ENCODER_IMPL_H */
