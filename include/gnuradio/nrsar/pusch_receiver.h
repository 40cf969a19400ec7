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
#include <gnuradio/nrsar/params.h>
#include <cstdint>
#include <string>

namespace gr {
namespace nrsar {

/*!
 * \brief The base station's PUSCH receiver on the frequency-domain grid: DMRS channel
 * estimation, equalisation, soft demapping, transport block decoding (kernel::pusch_rx).
 * \ingroup nrsar
 *
 * Input 0: one vector of N = num.num_subcarriers gr_complex per OFDM symbol, the first item
 * is symbol 0 of slot 0. A tags::slot_key() tag re-aligns the slot counter (the tagged item
 * starts slot = tag value; a partial slot before it is discarded and counted).
 *
 * Message output "pdus": one PDU per slot, (meta . u8vector) with meta a dict
 * {slot (uint64), seq (int), crc_ok (bool), filler (bool), payload_len (int), pdu_start (bool),
 * pdu_end (bool), snr_db (double), evm_db (double)}; the u8vector holds the payload only when
 * crc_ok (CRC24A matched and the header is consistent), otherwise it is empty (a failed TB is
 * reported, never delivered as data).
 *
 * Output 0 (optional): the equalised data REs of every slot (gr_complex stream, data symbols
 * in time order, subcarriers in order; (symbols_per_slot - DMRS symbols) N per slot), e.g.
 * for a QT constellation sink.
 */
class NRSAR_API pusch_receiver : virtual public gr::block
{
public:
    typedef std::shared_ptr<pusch_receiver> sptr;

    /*!
     * \param num            numerology of the grid (input vlen = num.num_subcarriers)
     * \param mod            QPSK, QAM16, QAM64 or QAM256 (as pusch_encoder)
     * \param dmrs           DMRS layout of the transmitter (at least one symbol)
     * \param ldpc_alist     as pusch_encoder ("" = uncoded)
     * \param scrambling_id  as pusch_encoder, 0 .. 65535
     * \param freq_window    DMRS REs averaged per channel estimate (odd >= 1; 1 = plain LS)
     * \param max_iterations LDPC belief-propagation iterations (>= 1)
     */
    static sptr make(const numerology& num = numerology(),
                     modulation mod = modulation::QAM256,
                     const dmrs_config& dmrs = dmrs_config::preset("pusch2"),
                     const std::string& ldpc_alist = "",
                     unsigned scrambling_id = 0,
                     unsigned freq_window = 3,
                     unsigned max_iterations = 25);

    virtual std::uint64_t blocks_ok() const = 0;       //!< TBs with CRC ok (filler included)
    virtual std::uint64_t blocks_failed() const = 0;   //!< TBs with CRC / header failure
    virtual std::uint64_t filler_blocks() const = 0;   //!< CRC-ok filler TBs
    virtual std::uint64_t payload_bytes_ok() const = 0; //!< payload bytes delivered
    virtual double last_snr_db() const = 0;            //!< SNR estimate of the last slot
    virtual double last_evm_db() const = 0;            //!< EVM of the last slot
    virtual std::uint64_t partial_slots() const = 0;   //!< slots cut short by a slot tag
    virtual std::uint64_t nonfinite_samples() const = 0; //!< non-finite inputs zeroed
    virtual double code_rate() const = 0;
    virtual std::uint64_t payload_bits_per_slot() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PUSCH_RECEIVER_H */
