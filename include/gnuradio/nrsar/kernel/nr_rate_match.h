/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_NR_RATE_MATCH_H
#define INCLUDED_NRSAR_KERNEL_NR_RATE_MATCH_H

#include <gnuradio/nrsar/api.h>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Rate matching of one LDPC code block (TS 38.212 5.4.2).
 *
 * Bit selection (5.4.2.1): the circular buffer is d_0 .. d_{N_cb-1}, N_cb = N, or
 * min(N, N_ref) with limited-buffer rate matching (N_ref = floor(TBS_LBRM / (C R_LBRM)),
 * R_LBRM = 2/3, given by the caller); reading starts at k0 of Table 5.4.2.1-2 and skips
 * the filler bits d_{K'-2Zc} .. d_{K-2Zc-1}.
 * Bit interleaving (5.4.2.2): f_{i + j Qm} = e_{i E/Qm + j}.
 */
struct NRSAR_API nr_rate_match_params {
    int base_graph = 1;
    unsigned zc = 384;
    unsigned k_prime = 0; //!< K': code-block bits without fillers (<= K)
    std::size_t n_ref = 0; //!< N_ref of limited-buffer rate matching; 0: none (N_cb = N)
    unsigned rv = 0;       //!< redundancy version 0 .. 3
    unsigned qm = 2;       //!< bits per modulation symbol: 1, 2, 4, 6, 8

    //! Throws std::invalid_argument naming the first invalid field.
    void validate() const;
    std::size_t n() const;    //!< N = 66 Zc / 50 Zc
    std::size_t n_cb() const; //!< circular buffer length
    std::size_t k0() const;   //!< starting position of rv (Table 5.4.2.1-2)
    std::size_t filler_begin() const; //!< K' - 2 Zc
    std::size_t filler_end() const;   //!< K - 2 Zc
};

/*!
 * \brief E_r of each of the C code blocks of a transport block mapped to G coded bits
 * (5.4.2.1, every block scheduled): N_L Qm floor(G / (N_L Qm C)) for the first
 * C - mod(G / (N_L Qm), C) blocks, N_L Qm ceil(G / (N_L Qm C)) for the others.
 */
NRSAR_API std::vector<std::size_t>
nr_code_block_e(std::size_t G, unsigned C, unsigned qm, unsigned n_layers = 1);

//! d (N bits, one per byte) -> f (E bits). E must be a multiple of Qm.
NRSAR_API void nr_rate_match(const std::uint8_t* d, const nr_rate_match_params& p, std::size_t e, std::uint8_t* f);

//! Columns of Zc bits of a circular buffer at most (N / Zc: 66 in BG1, 50 in BG2).
constexpr std::size_t nr_max_columns = 66;

/*!
 * \brief Rate recovery with soft combining: the E LLRs of f are de-interleaved and added to
 * the circular-buffer positions they were read from, into d_llr (N values, accumulated:
 * a retransmission with another rv adds to the first, HARQ chase / incremental redundancy
 * combining). Filler positions are set to +infinity (known 0 bits). combine = false starts
 * a new buffer (the first transmission): d_llr need not be initialised, the positions not
 * read are set to 0 (the same values as zeroing it first, in one pass).
 *
 * nonzero_columns (optional, N / Zc flags, one per column d_{c Zc} .. d_{(c+1) Zc - 1}):
 * the caller's record of which columns of d_llr may hold anything but 0, kept across calls
 * on the same buffer (all 0 for a zeroed buffer). combine = false then clears only the
 * flagged columns' unread positions (the others hold zeros already) and leaves exactly the
 * columns it wrote (fillers included) flagged; combine = true adds them to the flags. The
 * same values as without; nr_ldpc_decoder::decode() need not read an unflagged column.
 */
NRSAR_API void nr_rate_recover(const float* f_llr,
                               const nr_rate_match_params& p,
                               std::size_t e,
                               float* d_llr,
                               bool combine = true,
                               std::uint8_t* nonzero_columns = nullptr);

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_NR_RATE_MATCH_H */
