/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_PUSCH_ENCODER_H
#define INCLUDED_NRSAR_PUSCH_ENCODER_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <cstdint>
#include <string>

namespace gr {
namespace nrsar {

/*!
 * \brief PUSCH transport-block encoder of the UAV backhaul: PDUs in, the scrambled (and
 * optionally LDPC coded) data bits of every slot out, as the packed byte stream that
 * nr_isac_tx (same num, mod, dmrs, tx_mode DATA) consumes on its input 0.
 * \ingroup nrsar
 *
 * One transport block per slot fills the slot's G = (symbols_per_slot - DMRS symbols) N k
 * data bits (kernel::transport_block_codec: 5-byte header {payload_len, seq, flags} +
 * payload + CRC24A, LDPC, scrambling of TS 38.211 6.3.1.1). A PDU is segmented over as many
 * TBs as it needs (a TB carries bytes of one PDU only; flags pdu_start / pdu_end mark its
 * first and last TB). When no PDU is queued a filler TB (flag filler, no payload) is sent,
 * so the radar grid stays full of random-looking REs.
 *
 * Ports: message in "pdus" (pmt pair (meta . u8vector), any length >= 1; queued while the
 * queued bytes stay <= max_queued_bytes, otherwise dropped, counted and logged);
 * output 0: bytes, MSB first, G bits per slot as one continuous bit stream (G need not be a
 * multiple of 8), slot 0 first.
 */
class NRSAR_API pusch_encoder : virtual public gr::block
{
public:
    typedef std::shared_ptr<pusch_encoder> sptr;

    /*!
     * \param num              numerology (validated)
     * \param mod              QPSK, QAM16, QAM64 or QAM256 (what pusch_receiver demaps)
     * \param dmrs             DMRS layout, as given to nr_isac_tx (may be none for a
     *                         radar-only grid, but then no pusch_receiver can decode it)
     * \param ldpc_alist       alist file of an LDPC code (e.g.
     *                         /usr/share/gnuradio/fec/ldpc/n_1800_k_0902_gap_28.alist);
     *                         "" = uncoded
     * \param scrambling_id    0 .. 65535 (c_init of the data scrambling)
     * \param max_queued_bytes bound of the PDU queue in bytes (>= 1)
     */
    static sptr make(const numerology& num = numerology(),
                     modulation mod = modulation::QAM256,
                     const dmrs_config& dmrs = dmrs_config::preset("pusch2"),
                     const std::string& ldpc_alist = "",
                     unsigned scrambling_id = 0,
                     std::uint64_t max_queued_bytes = 1u << 20);

    virtual std::uint64_t tbs_sent() const = 0;          //!< TBs (slots) encoded, filler included
    virtual std::uint64_t filler_tbs_sent() const = 0;   //!< filler TBs
    virtual std::uint64_t payload_bytes_sent() const = 0; //!< PDU bytes encoded
    virtual std::uint64_t pdus_dropped() const = 0;      //!< PDUs refused (queue full / malformed)
    virtual std::uint64_t queued_bytes() const = 0;      //!< PDU bytes waiting
    virtual double code_rate() const = 0;                //!< LDPC k / n (1 uncoded)
    virtual std::uint64_t payload_bits_per_slot() const = 0; //!< 8 payload bytes of a TB
    virtual std::uint64_t slot_bits() const = 0;         //!< G
    //! payload_bits_per_slot / slot duration (symbols_per_slot Tsym) [bit/s]
    virtual double throughput_bps() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PUSCH_ENCODER_H */
