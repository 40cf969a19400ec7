/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_NR_LDPC_H
#define INCLUDED_NRSAR_KERNEL_NR_LDPC_H

#include <gnuradio/nrsar/api.h>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

//! One non-zero entry of an LDPC base graph: row i, column j, V_ij for iLS = 0 .. 7.
struct nr_bg_entry {
    std::uint8_t i;
    std::uint8_t j;
    std::uint16_t v[8];
};

/*!
 * \brief An LDPC base graph of TS 38.212 5.3.2 (base_graph 1: Table 5.3.2-2, 46 x 68,
 * 22 information columns; base_graph 2: Table 5.3.2-3, 42 x 52, 10 information columns).
 * Entries are in row order; row i holds entries [row_begin[i], row_begin[i + 1]).
 */
struct NRSAR_API nr_base_graph {
    int id;
    unsigned rows;
    unsigned cols;
    unsigned info_cols; //!< 22 or 10: K = info_cols Zc
    const nr_bg_entry* entries;
    std::size_t n_entries;
    std::vector<std::size_t> row_begin;

    //! base_graph 1 or 2; std::invalid_argument otherwise.
    static const nr_base_graph& get(int base_graph);
};

//! The 51 lifting sizes Zc of TS 38.212 Table 5.3.2-1, ascending.
NRSAR_API const std::array<unsigned, 51>& nr_lifting_sizes();

//! Set index iLS of Zc (Table 5.3.2-1), or -1 when zc is not a lifting size.
NRSAR_API int nr_lifting_set_index(unsigned zc);

//! Throws std::invalid_argument naming zc when it is not a lifting size.
NRSAR_API void nr_check_lifting_size(unsigned zc);

//! N, the LDPC codeword length after the 2 Zc punctured bits: 66 Zc (BG1) or 50 Zc (BG2).
NRSAR_API std::size_t nr_ldpc_n(int base_graph, unsigned zc);

//! K, information bits of a code block incl. fillers: 22 Zc (BG1) or 10 Zc (BG2).
NRSAR_API std::size_t nr_ldpc_k(int base_graph, unsigned zc);

//! The lifted edges of one base-graph row: column and shift P_ij = V_ij mod Zc (5.3.2).
struct nr_lifted_edge {
    unsigned col;
    unsigned shift;
};

/*!
 * \brief Edges of every row of H for one (base_graph, Zc): row i of H's block row i,
 * column block j, is the identity cyclically shifted right by P_ij, i.e. row r of the block
 * checks bit (r + P_ij) mod Zc of column block j.
 */
NRSAR_API std::vector<std::vector<nr_lifted_edge>> nr_lifted_rows(int base_graph, unsigned zc);

/*!
 * \brief LDPC encoder of TS 38.212 5.3.2 for one (base graph, Zc).
 *
 * Input c_0 .. c_{K-1} (one bit per byte, fillers as 0, which 5.3.2 prescribes for
 * encoding); output d_0 .. d_{N-1}: d_{k-2Zc} = c_k for k >= 2 Zc, then the parity bits w,
 * so that H [c w]^T = 0. Fillers stay 0 in d (rate matching skips them).
 *
 * Parity: the 4 x 4 core of H (columns info_cols .. info_cols + 3) is solved by summing its
 * four rows, which cancels every core column but the first one up to one shift P^x; the
 * other parity blocks then follow one row at a time, each row having one unknown left.
 */
class NRSAR_API nr_ldpc_encoder
{
public:
    nr_ldpc_encoder(int base_graph, unsigned zc);

    int base_graph() const { return d_bg; }
    unsigned zc() const { return d_zc; }
    std::size_t k() const { return nr_ldpc_k(d_bg, d_zc); }
    std::size_t n() const { return nr_ldpc_n(d_bg, d_zc); }

    void encode(const std::uint8_t* c, std::uint8_t* d);

private:
    struct step {
        unsigned row;
        unsigned col;   // column solved by this row
        unsigned shift; // its shift in that row
    };
    int d_bg;
    unsigned d_zc;
    unsigned d_cols;
    std::vector<std::vector<nr_lifted_edge>> d_rows;
    unsigned d_core_shift = 0; // x: the sum of the core rows is P^x w_0
    std::vector<step> d_steps;
    std::vector<std::uint8_t> d_x;      // the full [c w] (cols Zc), w filled here
    std::vector<std::uint8_t> d_lambda; // per row: sum over the known columns
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_NR_LDPC_H */
