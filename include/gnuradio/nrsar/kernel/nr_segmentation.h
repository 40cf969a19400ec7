/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_NR_SEGMENTATION_H
#define INCLUDED_NRSAR_KERNEL_NR_SEGMENTATION_H

#include <gnuradio/nrsar/api.h>
#include <cstddef>
#include <cstdint>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief LDPC base graph of a UL-SCH / DL-SCH transport block (TS 38.212 6.2.2 / 7.2.2):
 * 2 when A <= 292, or A <= 3824 and R <= 0.67, or R <= 0.25; 1 otherwise.
 * \param tbs       A, transport block size in bits (> 0)
 * \param code_rate R, target code rate of the MCS, in (0, 1)
 */
NRSAR_API int nr_select_base_graph(std::size_t tbs, double code_rate);

//! Transport-block CRC length (38.212 6.2.1 / 7.2.1): 24 (CRC24A) for A > 3824, else 16.
NRSAR_API unsigned nr_tb_crc_length(std::size_t tbs);

//! Sizes of a code-block segmentation (TS 38.212 5.2.2).
struct NRSAR_API nr_segmentation {
    int base_graph = 1;
    std::size_t B = 0;  //!< input bits (TB with its CRC)
    unsigned C = 0;     //!< code blocks
    unsigned L = 0;     //!< CB CRC bits: 24 (CRC24B) when C > 1, else 0
    unsigned K_prime = 0; //!< bits per code block incl. CB CRC: B' / C
    unsigned Kb = 0;    //!< information columns used: 22 (BG1), 10, 9, 8 or 6 (BG2)
    unsigned Zc = 0;    //!< lifting size: the smallest with Kb Zc >= K'
    unsigned K = 0;     //!< bits per code block incl. fillers: 22 Zc (BG1), 10 Zc (BG2)
    unsigned F = 0;     //!< filler bits per code block: K - K'

    //! Sizes for B bits (1 <= B) and base_graph 1 or 2 (Kcb = 8448 / 3840).
    static nr_segmentation compute(std::size_t B, int base_graph);
};

/*!
 * \brief Code-block segmentation (5.2.2): b_0 .. b_{B-1} (one bit per byte) into C code blocks
 * of K bits each, cb[r K + k]: K' - L bits of b, CRC24B when C > 1, then F fillers, written
 * as filler_value (0 for the encoder, which 5.3.2 prescribes).
 */
NRSAR_API void nr_segment(const std::uint8_t* b,
                          const nr_segmentation& s,
                          std::uint8_t* cb,
                          std::uint8_t filler_value = 0);

/*!
 * \brief Code-block desegmentation: the first K' - L bits of each of the C decoded blocks
 * back into b (B bits). cb_crc_ok[r] (when given) = CRC24B of block r checks (true for C = 1).
 * Returns true when every block's CRC24B checks.
 */
NRSAR_API bool nr_desegment(const std::uint8_t* cb,
                            const nr_segmentation& s,
                            std::uint8_t* b,
                            bool* cb_crc_ok = nullptr);

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_NR_SEGMENTATION_H */
