/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_PUSCH_RECEIVER_H
#define INCLUDED_NRSAR_PUSCH_RECEIVER_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/pusch_config.h>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * \brief The base station's PUSCH receiver on the frequency-domain grid: DMRS channel
 * estimation, equalisation, soft demapping, UL-SCH decoding with HARQ soft combining of
 * repetitions, CB CRC24B / TB CRC24A checks, MAC PDU parse (kernel::pusch_rx).
 * \ingroup nrsar
 *
 * Input 0: one vector of N = num.num_subcarriers gr_complex per OFDM symbol, the first item
 * is symbol 0 of slot 0. A tags::slot_key() tag re-aligns the slot counter (the tagged item
 * starts slot = tag value; a partial slot before it is discarded and counted).
 *
 * Message output "pdus": one PDU per TB (per slot without repetitions), (meta . u8vector)
 * with meta a dict {slot (uint64, the TB's first slot), seq (int, TB index mod 2^16, -1 when
 * failed), crc_ok (bool), filler (bool), payload_len (int), pdu_start (bool), pdu_end (bool),
 * sn (int, RLC SN), so (int, RLC SO), transmissions (int), ldpc_iterations (double),
 * code_blocks (int), cb_crc_ok (int), snr_db (double), evm_db (double)}; the u8vector holds
 * the payload only when crc_ok (TB CRC matched, LDPC parity held and the MAC PDU parsed),
 * otherwise it is empty (a failed TB is reported, never delivered as data).
 *
 * Output 0 (optional): the equalised data REs of every slot (gr_complex stream, data symbols
 * in time order, subcarriers in order; (symbols_per_slot - DMRS symbols) N per slot), e.g.
 * for a QT constellation sink.
 */
class NRSAR_API pusch_receiver : virtual public gr::block
{
public:
    typedef std::shared_ptr<pusch_receiver> sptr;

    //! cfg: the transmitter's PUSCH; its freq_window and max_iterations are the receiver's
    static sptr make(const pusch_config& cfg = pusch_config());

    virtual std::uint64_t blocks_ok() const = 0;       //!< TBs with CRC ok (filler included)
    virtual std::uint64_t blocks_failed() const = 0;   //!< TBs with CRC / header failure, lost ones included
    //! TBs whose slots never arrived whole (a gap upstream: a partial slot, or slot numbers
    //! skipped), reported crc_ok False, lost True without decoding, or, with repetitions, whose
    //! other transmissions did not decode them; also in blocks_failed()
    virtual std::uint64_t blocks_lost() const = 0;
    virtual std::uint64_t filler_blocks() const = 0;   //!< CRC-ok filler TBs
    virtual std::uint64_t payload_bytes_ok() const = 0; //!< payload bytes delivered
    virtual double last_snr_db() const = 0;            //!< SNR estimate of the last slot
    virtual double last_evm_db() const = 0;            //!< EVM of the last slot
    virtual std::uint64_t partial_slots() const = 0;   //!< slots cut short by a slot tag
    virtual std::uint64_t nonfinite_samples() const = 0; //!< non-finite inputs zeroed
    virtual double code_rate() const = 0;                //!< as pusch_encoder
    virtual std::uint64_t payload_bits_per_slot() const = 0; //!< as pusch_encoder
    virtual std::uint64_t tbs_bits() const = 0;          //!< A
    virtual unsigned code_blocks() const = 0;            //!< C (0 with coding NONE)
    //! LDPC iterations per code block, mean over every decoding attempt so far
    virtual double ldpc_iterations_mean() const = 0;
    //! TBs that decoded only after combining two or more transmissions
    virtual std::uint64_t harq_combined_ok() const = 0;
    //! Threads per slot: 1 or 2 (the code blocks decoded on two; same output). Set before start.
    virtual void set_threads(unsigned threads) = 0;
    virtual unsigned threads() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PUSCH_RECEIVER_H */
