/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_TRANSPORT_BLOCK_H
#define INCLUDED_NRSAR_KERNEL_TRANSPORT_BLOCK_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace gr {
namespace fec {
class generic_encoder;
class generic_decoder;
} // namespace fec
namespace digital {
class crc;
} // namespace digital
namespace nrsar {
namespace kernel {

/*!
 * \brief G, the data bits of one PUSCH slot: (symbols_per_slot - DMRS symbols) N bits_per_symbol
 * (tx_mode DATA, no SRS).
 */
NRSAR_API std::size_t
pusch_slot_bits(const numerology& num, modulation mod, const dmrs_config& dmrs);

//! Header of a transport block (5 bytes, big endian on the air).
struct NRSAR_API tb_header {
    static constexpr unsigned bytes = 5;
    static constexpr std::uint8_t filler = 1;    //!< no payload: keeps the radar grid full
    static constexpr std::uint8_t pdu_start = 2; //!< payload starts a PDU
    static constexpr std::uint8_t pdu_end = 4;   //!< payload ends a PDU
    static constexpr std::uint8_t known_flags = 7;

    std::uint16_t payload_len = 0; //!< payload bytes in this TB
    std::uint16_t seq = 0;         //!< TB sequence number (mod 2^16)
    std::uint8_t flags = 0;

    void write(std::uint8_t* out) const;
    /*!
     * Parses 5 bytes; returns false (and leaves *this unspecified) when the header is
     * inconsistent: payload_len > capacity, unknown flag bits, filler with payload.
     */
    bool read(const std::uint8_t* in, std::size_t capacity);
};

//! What decode() found.
struct NRSAR_API tb_result {
    bool crc_ok = false;    //!< CRC24A matched
    bool header_ok = false; //!< CRC matched and the header is consistent
    tb_header header;
    std::vector<std::uint8_t> payload; //!< header.payload_len bytes when header_ok, else empty
};

/*!
 * \brief One transport block per slot, filling the slot's G data bits.
 *
 * TB = header (5 bytes) | payload (payload_bytes(), zero padded) | CRC24A (TS 38.212 5.1,
 * g(D) = D^24 + D^23 + D^18 + D^17 + D^14 + D^11 + D^10 + D^7 + D^6 + D^5 + D^4 + D^3 + D + 1,
 * over header and payload). Uncoded: the TB bits, then zeros up to G. LDPC (an alist code of
 * gr-fec, n code bits per k info bits): the TB, zero padded to C k, split into C = floor(G / n)
 * codewords, then zeros up to G. All G bits are scrambled (TS 38.211 6.3.1.1):
 *   b~(i) = b(i) xor c(i),
 *   c_init = ((2^15 scrambling_id + (slot mod 2^15)) 0x9E3779B1 + 0x2545F491) mod 2^31
 * Deviation from 38.211 (c_init = n_RNTI 2^15 + n_ID): the slot counter takes n_ID's place, so
 * an all-zero payload still gives a fresh grid every slot, and the affine bijection spreads
 * low-weight values, whose c(n) stays biased long after Nc = 1600 (c_init = 0: 39 % ones over
 * the first 3072 bits).
 * payload_bytes() = floor((info bits - 24) / 8) - 5 with info bits = G (uncoded) or C k.
 *
 * decode(): LLRs (positive = bit 0) in -> descramble -> LDPC belief propagation (gr-fec
 * ldpc_decoder) or hard decision -> CRC -> header parse. Never reads beyond G LLRs; any
 * input is safe.
 */
class NRSAR_API transport_block_codec
{
public:
    /*!
     * \param slot_bits      G, data bits of one slot (> 0)
     * \param ldpc_alist     path of an alist parity-check matrix; empty = uncoded
     * \param scrambling_id  0 .. 65535
     * \param max_iterations LDPC belief-propagation iterations (>= 1)
     * Throws std::invalid_argument when the file does not exist or the slot is too small for
     * one codeword / a one-byte payload.
     */
    transport_block_codec(std::size_t slot_bits,
                          const std::string& ldpc_alist = "",
                          unsigned scrambling_id = 0,
                          unsigned max_iterations = 25);
    ~transport_block_codec();
    transport_block_codec(transport_block_codec&&) noexcept;
    transport_block_codec& operator=(transport_block_codec&&) noexcept;
    transport_block_codec(const transport_block_codec&) = delete;
    transport_block_codec& operator=(const transport_block_codec&) = delete;

    std::size_t slot_bits() const { return d_G; }
    std::size_t payload_bytes() const { return d_payload; }
    //! TB bits incl. header and CRC: 8 (5 + payload_bytes() + 3).
    std::size_t tb_bits() const { return 8 * (tb_header::bytes + d_payload + 3); }
    bool coded() const { return d_k > 0; }
    unsigned codewords() const { return d_C; }
    unsigned code_n() const { return d_n; }
    unsigned code_k() const { return d_k; }
    //! LDPC rate k / n (1 uncoded).
    double code_rate() const;
    //! Payload bits over slot bits: 8 payload_bytes() / G.
    double efficiency() const;

    static std::uint32_t scrambling_c_init(unsigned scrambling_id, std::uint64_t slot);

    /*!
     * Encodes one TB: header (payload_len = len is set here) and len <= payload_bytes()
     * payload bytes. out gets G bits, one per byte (0/1), scrambled for slot.
     */
    void encode(tb_header header,
                const std::uint8_t* payload,
                std::size_t len,
                std::uint64_t slot,
                std::uint8_t* out) const;

    //! Decodes G LLRs (positive = bit 0) of slot. Non-finite LLRs count as 0.
    tb_result decode(const float* llr, std::uint64_t slot);

    /*!
     * CRC check and header parse of TB bytes (tb_bits() / 8 of them): what decode() does after
     * the bits are known.
     */
    tb_result parse(const std::uint8_t* tb) const;

private:
    std::size_t d_G;
    unsigned d_scrambling_id;
    unsigned d_n = 0, d_k = 0, d_C = 0;
    std::size_t d_payload = 0;
    std::unique_ptr<gr::digital::crc> d_crc;
    std::shared_ptr<gr::fec::generic_encoder> d_enc;
    std::shared_ptr<gr::fec::generic_decoder> d_dec;
    // work buffers
    std::vector<float> d_soft;
    std::vector<std::uint8_t> d_bits;
    std::vector<std::uint8_t> d_bytes;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_TRANSPORT_BLOCK_H */
