/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_NR_ULSCH_H
#define INCLUDED_NRSAR_KERNEL_NR_ULSCH_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/nr_crc.h>
#include <gnuradio/nrsar/kernel/nr_ldpc.h>
#include <gnuradio/nrsar/kernel/nr_ldpc_decoder.h>
#include <gnuradio/nrsar/kernel/nr_segmentation.h>
#include <gnuradio/nrsar/kernel/split_worker.h>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

//! What nr_ulsch::decode() found.
struct nr_ulsch_result {
    bool tb_crc_ok = false;     //!< the TB CRC (CRC24A or CRC16) checks
    //! Every code block's LDPC parity checks held. The CRCs of 38.212 start from a zero state,
    //! so an all-zero TB passes them: a decoder that learnt nothing (e.g. rv 1 or 2 alone at
    //! a high rate, which carry no systematic bits) outputs zeros with tb_crc_ok set, and this
    //! flag is then false.
    bool parity_ok = false;
    unsigned cb_crc_ok = 0;     //!< code blocks whose CRC24B checks (all C when C = 1 and the TB checks)
    unsigned code_blocks = 0;   //!< C
    double mean_iterations = 0; //!< LDPC iterations per code block
};

/*!
 * \brief The UL-SCH of TS 38.212 6.2 for one transport block and its PUSCH scrambling
 * (TS 38.211 6.3.1.1), on unpacked bits: TB CRC attachment (6.2.1), base-graph selection
 * (6.2.2), code-block segmentation with CRC24B (6.2.3 = 5.2.2), LDPC encoding (6.2.4 =
 * 5.3.2), rate matching (6.2.5 = 5.4.2, E_r per block), code-block concatenation (6.2.6 =
 * 5.5), then b~(i) = b(i) xor c(i) with c from c_init = n_RNTI 2^15 + n_ID.
 *
 * The receiver keeps one soft buffer per code block (N values): decode(..., combine = true)
 * adds a retransmission (any rv) to the previous ones (HARQ).
 */
class NRSAR_API nr_ulsch
{
public:
    /*!
     * \param tbs            A, transport block bits (>= 24, a TBS of 38.214)
     * \param code_rate      R of the MCS (selects the base graph), in (0, 1)
     * \param qm             bits per symbol: 1, 2, 4, 6, 8
     * \param g              G, coded bits of the slot (a multiple of n_layers qm)
     * \param n_layers       N_L
     * \param n_ref          N_ref of limited-buffer rate matching, 0 = none
     * \param max_iterations LDPC iterations per decode
     */
    nr_ulsch(std::size_t tbs,
             double code_rate,
             unsigned qm,
             std::size_t g,
             unsigned n_layers = 1,
             std::size_t n_ref = 0,
             unsigned max_iterations = 8);

    std::size_t tbs() const { return d_A; }
    std::size_t g() const { return d_G; }
    int base_graph() const { return d_seg.base_graph; }
    const nr_segmentation& segmentation() const { return d_seg; }
    const std::vector<std::size_t>& e() const { return d_E; }
    //! Effective code rate (A + TB CRC) / G.
    double effective_rate() const { return double(d_A + d_tb_crc.length()) / double(d_G); }

    //! a: A bits (0/1) -> out: G scrambled bits of redundancy version rv.
    void encode(const std::uint8_t* a, unsigned rv, std::uint32_t c_init, std::uint8_t* out);

    /*!
     * G LLRs (positive = bit 0, before descrambling; NaN counts as 0, +-inf as a known bit)
     * of redundancy version rv -> a (A bits).
     * combine = false starts a new transport block (the soft buffers are cleared first).
     */
    nr_ulsch_result
    decode(const float* llr, unsigned rv, std::uint32_t c_init, bool combine, std::uint8_t* a);

    /*!
     * Threads of decode(): 1, or 2 (code blocks [0, C/2) on the caller, [C/2, C) on a
     * kernel::split_worker thread, each half with its own decoder). Same results.
     */
    void set_threads(unsigned threads);
    unsigned threads() const { return d_threads; }

private:
    std::size_t d_A, d_G;
    unsigned d_qm;
    std::size_t d_n_ref;
    nr_crc d_tb_crc;
    nr_segmentation d_seg;
    std::vector<std::size_t> d_E;
    nr_ldpc_encoder d_enc;
    unsigned d_max_iterations;
    std::vector<nr_ldpc_decoder> d_dec; // one per thread
    std::vector<std::uint8_t> d_tb, d_cb, d_d, d_c, d_scr;
    std::vector<float> d_soft;            // C x N soft buffers
    // per block, N / Zc flags: the columns of its soft buffer that may hold non-zero LLRs
    // (nr_rate_recover's record: the unread columns are neither cleared nor decoded again)
    std::vector<std::uint8_t> d_soft_columns;
    std::vector<std::vector<float>> d_llr; // per thread: one descrambled block's E LLRs
    std::vector<std::size_t> d_e_begin;    // first LLR of each block in the slot
    std::vector<unsigned> d_cb_iterations;  // per block, of the last decode
    std::vector<std::uint8_t> d_cb_parity;  // per block, of the last decode
    unsigned d_threads = 1;
    split_worker d_worker;
    std::uint32_t d_scr_c_init = 0;   // c_init of d_scr, the G scrambling bits
    bool d_scr_valid = false;

    void scrambling(std::uint32_t c_init); // d_scr for c_init
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_NR_ULSCH_H */
