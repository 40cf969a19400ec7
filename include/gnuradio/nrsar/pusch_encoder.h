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
#include <gnuradio/nrsar/pusch_config.h>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * \brief PUSCH transport-block encoder of the UAV backhaul: PDUs in, the scrambled (and
 * NR LDPC coded) data bits of every slot out, as the packed byte stream that nr_isac_tx
 * (same num, mod, dmrs, tx_mode DATA) consumes on its input 0.
 * \ingroup nrsar
 *
 * One transport block (TB) per PUSCH transmission fills the slot's G = (symbols_per_slot -
 * DMRS symbols) N Qm data bits (kernel::transport_block_codec: the UL-SCH of TS 38.212 6.2
 * with the TBS of 38.214 5.1.3.2, or CRC24A only with coding NONE; scrambling of 38.211
 * 6.3.1.1). The TB's bytes are a MAC PDU (kernel::mac_sdu: a 38.321 subheader, a 38.322
 * RLC UM header that segments a PDU over as many TBs as it needs, padding); with no PDU
 * queued a padding-only TB (filler) keeps the radar grid full. With repetitions > 1 each TB
 * goes out in that many consecutive slots, rv 0, 2, 3, 1 (38.214 6.1.2.1).
 *
 * Ports: message in "pdus" (pmt pair (meta . u8vector), 1 .. 65535 bytes; queued while the
 * queued bytes stay <= max_queued_bytes, otherwise dropped, counted and logged);
 * output 0: bytes, MSB first, G bits per slot as one continuous bit stream (G need not be a
 * multiple of 8), slot cfg.first_slot first (0: the stream's start; later, with the PDUs from
 * that slot's TB on, the rest of that stream: nr_isac_tx's start_symbol with input 0).
 */
class NRSAR_API pusch_encoder : virtual public gr::block
{
public:
    typedef std::shared_ptr<pusch_encoder> sptr;

    //! cfg: the PUSCH (validated; its receiver fields are not used here)
    static sptr make(const pusch_config& cfg = pusch_config());

    virtual std::uint64_t tbs_sent() const = 0;          //!< TBs (slots) encoded, filler included
    virtual std::uint64_t filler_tbs_sent() const = 0;   //!< filler TBs
    virtual std::uint64_t payload_bytes_sent() const = 0; //!< PDU bytes encoded
    virtual std::uint64_t pdus_dropped() const = 0;      //!< PDUs refused (queue full / malformed)
    virtual std::uint64_t queued_bytes() const = 0;      //!< PDU bytes waiting
    //! (A + TB CRC) / G: the effective code rate
    virtual double code_rate() const = 0;
    //! 8 x the largest PDU bytes one TB carries whole (one TB per `repetitions` slots)
    virtual std::uint64_t payload_bits_per_slot() const = 0;
    virtual std::uint64_t tbs_bits() const = 0;          //!< A, TBS of 38.214
    virtual unsigned code_blocks() const = 0;            //!< C (0 with coding NONE)
    virtual std::uint64_t slot_bits() const = 0;         //!< G
    //! payload_bits_per_slot / (repetitions slot durations, symbols_per_slot Tsym) [bit/s]
    virtual double throughput_bps() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PUSCH_ENCODER_H */
