/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_TRANSPORT_BLOCK_H
#define INCLUDED_NRSAR_KERNEL_TRANSPORT_BLOCK_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/nr_crc.h>
#include <gnuradio/nrsar/kernel/nr_ulsch.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/pusch_config.h>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief G, the data bits of one PUSCH slot: (symbols_per_slot - DMRS symbols) N bits_per_symbol
 * (tx_mode DATA, no SRS).
 */
NRSAR_API std::size_t
pusch_slot_bits(const numerology& num, modulation mod, const dmrs_config& dmrs);

/*!
 * \brief The framing of a TB's bytes: one MAC PDU of TS 38.321 6.1.2 carrying at most one
 * RLC UMD PDU of TS 38.322 6.2.2.3 (6-bit SN), then padding.
 *
 *   MAC subheader   R(1) F(1)=1 LCID(6) | L(16)       3 bytes, L = RLC header + data bytes
 *   RLC UMD header  SI(2) R(6)                        complete SDU (SI 00), 1 byte
 *                   SI(2) SN(6)                       first segment (SI 01), 1 byte
 *                   SI(2) SN(6) | SO(16)              last (10) / middle (11) segment, 3 bytes
 *   data
 *   padding         R(1) F(1)=0 LCID(6)=63, then zero bytes to the end of the TB
 *
 * A TB with no SDU (filler) is the padding subheader and zeros. The SDUs are the PDUs given
 * to pusch_encoder (at most 65535 bytes: SO has 16 bits); PDCP, MAC CEs and the BSR are left
 * out (docs/nr_coding.md, "PDU framing").
 */
struct NRSAR_API mac_sdu {
    //! RLC segmentation information SI of 38.322 6.2.3.4.
    enum segment_info : std::uint8_t { complete = 0, first = 1, last = 2, middle = 3 };
    static constexpr std::uint8_t lcid = 4;          //!< logical channel of the data (a DRB)
    static constexpr std::uint8_t lcid_padding = 63; //!< 38.321 Table 6.2.1-2
    static constexpr std::size_t mac_header_bytes = 3;

    bool filler = true;  //!< no SDU, padding only
    segment_info si = complete;
    std::uint8_t sn = 0; //!< RLC sequence number of the SDU, mod 64 (not sent when complete)
    std::uint16_t so = 0; //!< byte offset of the segment in its SDU (sent for last / middle)
    std::vector<std::uint8_t> data;

    //! RLC header bytes of a segment of kind si.
    static std::size_t rlc_header_bytes(segment_info si) { return si >= last ? 3 : 1; }
    //! Largest data bytes of segment kind si in a TB of tb_bytes bytes (0 if none fit).
    static std::size_t capacity(std::size_t tb_bytes, segment_info si);

    /*!
     * Writes the MAC PDU of this SDU (data, si, sn, so; or padding only when filler) into
     * tb[0 .. tb_bytes). data must fit (capacity()).
     */
    void write(std::uint8_t* tb, std::size_t tb_bytes) const;
    /*!
     * Parses a MAC PDU; false when it is not one this framing writes (unknown LCID, L beyond
     * the TB, non-zero reserved bits, SO on a first / complete segment).
     */
    bool read(const std::uint8_t* tb, std::size_t tb_bytes);
};

//! What decode() found.
struct NRSAR_API tb_result {
    bool crc_ok = false;    //!< TB CRC (CRC24A, or CRC16 when A <= 3824) matched
    bool parity_ok = false; //!< every code block's LDPC parity checks held (= crc_ok uncoded)
    bool header_ok = false; //!< CRC ok, LDPC converged and the MAC PDU parsed
    mac_sdu sdu;            //!< when header_ok
    unsigned code_blocks = 0;    //!< C (0 uncoded)
    unsigned cb_crc_ok = 0;      //!< code blocks whose CRC checked
    double mean_iterations = 0;  //!< LDPC iterations per code block
};

/*!
 * \brief One transport block per PUSCH transmission, filling its G data bits.
 *
 * NR_LDPC: the UL-SCH of TS 38.212 6.2 (kernel::nr_ulsch: CRC, segmentation, LDPC,
 * rate matching of rv, concatenation) for the TBS of 38.214 5.1.3.2 (pusch_config), then
 * 38.211 6.3.1.1 scrambling. NONE: A = 8 floor((G - 24) / 8) bits, CRC24A, zeros up to G,
 * scrambled; hard decisions at the receiver.
 * Scrambling: c_init() of pusch_config::scrambling (standard n_RNTI 2^15 + n_ID, or the
 * module's per-slot sequence).
 */
class NRSAR_API transport_block_codec
{
public:
    //! Validates cfg (std::invalid_argument naming the field).
    explicit transport_block_codec(const pusch_config& cfg);
    ~transport_block_codec();
    transport_block_codec(transport_block_codec&&) noexcept;
    transport_block_codec& operator=(transport_block_codec&&) noexcept;
    transport_block_codec(const transport_block_codec&) = delete;
    transport_block_codec& operator=(const transport_block_codec&) = delete;

    std::size_t slot_bits() const { return d_G; }
    //! A, the transport block size in bits (a multiple of 8).
    std::size_t tbs_bits() const { return d_A; }
    std::size_t tb_bytes() const { return d_A / 8; }
    //! Largest PDU bytes one TB carries whole (complete SDU).
    std::size_t payload_bytes() const { return mac_sdu::capacity(tb_bytes(), mac_sdu::complete); }
    bool coded() const { return d_ulsch != nullptr; }
    unsigned code_blocks() const { return coded() ? d_ulsch->segmentation().C : 0; }
    int base_graph() const { return coded() ? d_ulsch->base_graph() : 0; }
    //! (A + TB CRC) / G: what the LDPC code and rate matching carry per coded bit.
    double code_rate() const;
    //! Payload bits over slot bits: 8 payload_bytes() / G.
    double efficiency() const;

    //! c_init of the scrambling of a transmission in slot (38.211 6.3.1.1 or per slot).
    std::uint32_t c_init(std::uint64_t slot) const;
    //! The module's non-standard per-slot c_init (pusch_scrambling::PER_SLOT).
    static std::uint32_t per_slot_c_init(unsigned n_id, std::uint64_t slot);

    //! tb: tb_bytes() bytes (a_0 = MSB of tb[0]) -> out: G scrambled bits (0/1), rv.
    void encode(const std::uint8_t* tb, unsigned rv, std::uint64_t slot, std::uint8_t* out);

    /*!
     * G LLRs (positive = bit 0, before descrambling; non-finite count as 0) of a transmission
     * with rv in slot. combine adds them to the previous transmissions of the same TB (HARQ
     * soft combining; NR_LDPC only), otherwise the TB starts afresh.
     */
    tb_result decode(const float* llr, unsigned rv, std::uint64_t slot, bool combine);

    //! Threads of decode() (1 or 2: nr_ulsch::set_threads; NONE decodes on one).
    void set_threads(unsigned threads);

private:
    pusch_config d_cfg;
    std::size_t d_G, d_A;
    std::unique_ptr<nr_ulsch> d_ulsch;
    nr_crc d_crc;
    std::vector<std::uint8_t> d_bits;  // A (+ CRC) unpacked bits
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_TRANSPORT_BLOCK_H */
