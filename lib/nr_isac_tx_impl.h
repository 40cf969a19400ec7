/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_NR_ISAC_TX_IMPL_H
#define INCLUDED_NRSAR_NR_ISAC_TX_IMPL_H

#include <gnuradio/nrsar/kernel/gold_sequence.h>
#include <gnuradio/nrsar/kernel/nr_grid.h>
#include <gnuradio/nrsar/nr_isac_tx.h>
#include <atomic>
#include <deque>
#include <vector>

namespace gr {
namespace nrsar {

class nr_isac_tx_impl : public nr_isac_tx
{
private:
    kernel::nr_grid d_grid;
    kernel::gold_sequence d_prbs;
    bool d_stream_input = false;

    // Packed MSB-first bits waiting to be mapped: d_stage[0..) from bit d_stage_bit on.
    std::vector<std::uint8_t> d_stage;
    std::size_t d_stage_bit = 0;

    std::deque<std::vector<std::uint8_t>> d_pdus;
    std::size_t d_pdu_offset = 0; // bytes of d_pdus.front() already staged

    const std::uint64_t d_start;  // absolute index of output item 0
    std::uint64_t d_symbol;       // absolute index of the next output symbol
    std::size_t d_skip_bits = 0;  // input bits of the start slot's symbols before d_start
    // Counters read by the getters from other threads without d_setlock.
    std::atomic<std::uint64_t> d_payload_bytes{ 0 };
    std::atomic<std::uint64_t> d_pdus_dropped{ 0 };
    std::atomic<std::uint64_t> d_prbs_symbols{ 0 };
    std::atomic<unsigned> d_queued{ 0 };
    bool d_warned_drop = false;

    std::size_t staged_bits() const { return 8 * d_stage.size() - d_stage_bit; }
    void handle_pdu(const pmt::pmt_t& msg);
    void drop_pdu(const char* why);
    // Stages bits for need bits from the PDU queue, then the PRBS. Returns true if PRBS used.
    bool stage_from_pdus_and_prbs(std::size_t need);
    void compact_stage();
    void tag_symbol(std::uint64_t m);

public:
    nr_isac_tx_impl(const numerology& num,
                    modulation mod,
                    tx_mode mode,
                    const srs_config& srs,
                    std::uint64_t seed,
                    const dmrs_config& dmrs,
                    std::uint64_t start_symbol);

    bool check_topology(int ninputs, int noutputs) override;
    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;

    std::uint64_t payload_bytes_sent() const override;
    std::uint64_t pdus_dropped() const override;
    std::uint64_t prbs_symbols() const override;
    unsigned queued_pdus() const override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_NR_ISAC_TX_IMPL_H */
