/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_NR_ISAC_TX_H
#define INCLUDED_NRSAR_NR_ISAC_TX_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * \brief The UAV's NR transmit grid: one vector of N = num.num_subcarriers gr_complex per
 * OFDM symbol (column S[:, m], SPEC section 3), both backhaul data and radar reference.
 * \ingroup nrsar
 *
 * Data bits, MSB first, come from (in this order of preference):
 * - input 0 (packed bytes, optional): when connected, the only source; the block waits for it;
 * - PDUs on message port "pdus" (pmt pair, cdr u8vector), queued (at most 64 PDUs; when full
 *   the newest PDU is dropped and counted);
 * - otherwise the seeded Gold sequence c(n) of 3GPP TS 38.211 5.2.1 with c_init = seed,
 *   one continuous sequence across symbols.
 * Bits carry over between symbols (bits per symbol need not be a multiple of 8).
 * Data REs are mapped with kernel::constellation (TS 38.211 5.1, unit average power);
 * DMRS symbols (dmrs) carry the PUSCH DMRS of TS 38.211 6.4.1.1 (kernel::nr_grid).
 * SRS REs (tx_mode SRS, DATA_SRS) carry the low-PAPR Zadoff-Chu sequence of TS 38.211
 * 5.2.2 (u = v = 0, alpha = 0) on the comb of srs; in SRS mode every other RE is 0.
 *
 * Output tags at the first symbol of every slot: tags::symbol_key() (absolute symbol
 * index, uint64) and tags::slot_key() (absolute slot index); at every frame start also
 * tags::frame_key() (frame index). Input tags are not propagated.
 *
 * start_symbol > 0: output item 0 is symbol start_symbol of the stream from symbol 0, and
 * every later item and tag is that stream's, bit for bit (tag values stay absolute, offsets
 * move by start_symbol): the PRBS jumps past the bits the symbols before it map
 * (kernel::gold_sequence::discard). With input 0 connected, the input's first bit is the
 * first data bit of the slot holding start_symbol (pusch_encoder's stream from that slot,
 * pusch_config::first_slot): the data bits of the slot's symbols before start_symbol are read
 * and dropped, so the grid is the tail of the one from symbol 0 whenever the input is the tail
 * of its bit stream. PDUs are dropped and counted (their bits' place is defined from symbol 0
 * only).
 */
class NRSAR_API nr_isac_tx : virtual public gr::block
{
public:
    typedef std::shared_ptr<nr_isac_tx> sptr;

    //! Maximum number of queued PDUs; more are dropped (pdus_dropped()).
    static constexpr unsigned max_queued_pdus = 64;

    /*!
     * \param num   OFDM numerology (validated); output vlen = num.num_subcarriers.
     * \param mod   constellation of the data REs (QPSK, QAM16/64/256, PSK8, PSK16).
     * \param mode  DATA (all REs data), SRS (pilot only), DATA_SRS (data + pilot).
     * \param srs   SRS comb layout (validated against num when mode is SRS or DATA_SRS;
     *              comb_offset must also lie inside the num_rb * 12 band).
     * \param seed  c_init of the PRBS, 0 .. 2^31 - 1.
     * \param dmrs  PUSCH DMRS layout (kernel/dmrs.h): its symbols carry the DMRS on the even
     *              subcarriers, 0 on the odd ones, and no data. Default: none (bit-identical
     *              to the grid without DMRS).
     * \param start_symbol  absolute index of the first output symbol (default 0).
     */
    static sptr make(const numerology& num = numerology(),
                     modulation mod = modulation::QAM256,
                     tx_mode mode = tx_mode::DATA,
                     const srs_config& srs = srs_config(),
                     std::uint64_t seed = 0,
                     const dmrs_config& dmrs = dmrs_config(),
                     std::uint64_t start_symbol = 0);

    //! Payload bytes (stream or PDU) taken into the grid so far.
    virtual std::uint64_t payload_bytes_sent() const = 0;
    //! PDUs dropped (queue full, wrong type, stream input connected, or start_symbol > 0).
    virtual std::uint64_t pdus_dropped() const = 0;
    //! Output symbols for which PRBS bits were drawn.
    virtual std::uint64_t prbs_symbols() const = 0;
    //! PDUs waiting in the queue.
    virtual unsigned queued_pdus() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_NR_ISAC_TX_H */
