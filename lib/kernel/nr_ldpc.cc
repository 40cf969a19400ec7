/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/nr_ldpc.h>
#include <algorithm>
#include <map>
#include <stdexcept>

namespace gr {
namespace nrsar {
namespace kernel {
namespace nr_tables {
extern const nr_bg_entry bg1_entries[316];
extern const nr_bg_entry bg2_entries[197];
} // namespace nr_tables

namespace {

nr_base_graph make_graph(int id, unsigned rows, unsigned cols, unsigned info, const nr_bg_entry* e, std::size_t n)
{
    nr_base_graph g{ id, rows, cols, info, e, n, std::vector<std::size_t>(rows + 1, n) };
    for (std::size_t k = n; k-- > 0;)
        g.row_begin[e[k].i] = k;
    for (unsigned i = rows; i-- > 0;) // rows without entries (none in 38.212) stay empty
        g.row_begin[i] = std::min(g.row_begin[i], g.row_begin[i + 1]);
    return g;
}

// x[r] ^= y[(r + s) mod zc]: adds P^s y (a block of H times a column block of bits).
void add_shifted(std::uint8_t* x, const std::uint8_t* y, unsigned s, unsigned zc)
{
    const unsigned head = zc - s;
    for (unsigned r = 0; r < head; r++)
        x[r] ^= y[r + s];
    for (unsigned r = head; r < zc; r++)
        x[r] ^= y[r - head];
}

} // namespace

const nr_base_graph& nr_base_graph::get(int base_graph)
{
    static const nr_base_graph bg1 = make_graph(1, 46, 68, 22, nr_tables::bg1_entries, 316);
    static const nr_base_graph bg2 = make_graph(2, 42, 52, 10, nr_tables::bg2_entries, 197);
    if (base_graph == 1)
        return bg1;
    if (base_graph == 2)
        return bg2;
    throw_param("base_graph", base_graph, "must be 1 or 2 (TS 38.212 5.3.2)");
}

const std::array<unsigned, 51>& nr_lifting_sizes()
{
    // Table 5.3.2-1: Zc = a 2^j with a in {2, 3, 5, 7, 9, 11, 13, 15}, Zc <= 384.
    static const std::array<unsigned, 51> sizes = [] {
        std::array<unsigned, 51> z{};
        std::size_t n = 0;
        for (unsigned a : { 2u, 3u, 5u, 7u, 9u, 11u, 13u, 15u })
            for (unsigned v = a; v <= 384; v *= 2)
                z[n++] = v;
        std::sort(z.begin(), z.end());
        return z;
    }();
    return sizes;
}

int nr_lifting_set_index(unsigned zc)
{
    // Table 5.3.2-1 holds every a 2^j in [2, 384] with odd part a <= 15 (a = 1 belongs to
    // the set of a = 2): iLS = 0 for powers of two, (a - 1) / 2 otherwise.
    if (zc < 2 || zc > 384)
        return -1;
    unsigned a = zc;
    while (a % 2 == 0)
        a /= 2;
    if (a > 15)
        return -1;
    return a == 1 ? 0 : static_cast<int>((a - 1) / 2);
}

void nr_check_lifting_size(unsigned zc)
{
    if (nr_lifting_set_index(zc) < 0)
        throw_param("zc", zc, "is not a lifting size of TS 38.212 Table 5.3.2-1");
}

std::size_t nr_ldpc_n(int base_graph, unsigned zc)
{
    return std::size_t{ nr_base_graph::get(base_graph).cols - 2 } * zc;
}

std::size_t nr_ldpc_k(int base_graph, unsigned zc)
{
    return std::size_t{ nr_base_graph::get(base_graph).info_cols } * zc;
}

std::vector<std::vector<nr_lifted_edge>> nr_lifted_rows(int base_graph, unsigned zc)
{
    const nr_base_graph& g = nr_base_graph::get(base_graph);
    nr_check_lifting_size(zc);
    const int ils = nr_lifting_set_index(zc);
    std::vector<std::vector<nr_lifted_edge>> rows(g.rows);
    for (std::size_t k = 0; k < g.n_entries; k++) {
        const nr_bg_entry& e = g.entries[k];
        rows[e.i].push_back({ e.j, static_cast<unsigned>(e.v[ils] % zc) }); // P_ij = V_ij mod Zc
    }
    return rows;
}

nr_ldpc_encoder::nr_ldpc_encoder(int base_graph, unsigned zc)
    : d_bg(base_graph), d_zc(zc), d_cols(nr_base_graph::get(base_graph).cols),
      d_rows(nr_lifted_rows(base_graph, zc)),
      d_x(std::size_t{ d_cols } * zc),
      d_lambda(zc)
{
    const unsigned info = nr_base_graph::get(base_graph).info_cols;
    // Sum of the 4 core rows: shifts of each parity column that occur an odd number of times.
    std::map<unsigned, std::map<unsigned, unsigned>> count; // col -> shift -> count
    for (unsigned i = 0; i < 4; i++)
        for (const auto& e : d_rows[i])
            if (e.col >= info)
                count[e.col][e.shift]++;
    unsigned odd_terms = 0;
    for (const auto& [col, shifts] : count)
        for (const auto& [s, n] : shifts)
            if (n % 2 == 1) {
                if (col != info)
                    throw std::logic_error("nr_ldpc_encoder: core rows do not sum to one column");
                d_core_shift = s;
                odd_terms++;
            }
    if (odd_terms != 1)
        throw std::logic_error("nr_ldpc_encoder: core rows do not sum to one shifted block");
    // Then every row with one unknown column left solves it, the core rows first.
    std::vector<bool> known(d_cols, false);
    for (unsigned j = 0; j <= info; j++)
        known[j] = true;
    std::vector<bool> used(d_rows.size(), false);
    for (bool progress = true; progress;) {
        progress = false;
        for (unsigned i = 0; i < d_rows.size(); i++) {
            if (used[i])
                continue;
            unsigned unknown = 0;
            step st{ i, 0, 0 };
            for (const auto& e : d_rows[i])
                if (!known[e.col]) {
                    unknown++;
                    st.col = e.col;
                    st.shift = e.shift;
                }
            if (unknown == 1) {
                d_steps.push_back(st);
                known[st.col] = true;
                used[i] = true;
                progress = true;
                break; // restart from the first row: the core rows come first
            }
            if (unknown == 0)
                used[i] = true; // a redundant row (the fourth core row)
        }
    }
    if (std::find(known.begin(), known.end(), false) != known.end())
        throw std::logic_error("nr_ldpc_encoder: parity columns left unsolved");
}

void nr_ldpc_encoder::encode(const std::uint8_t* c, std::uint8_t* d)
{
    const unsigned zc = d_zc;
    const unsigned info = nr_base_graph::get(d_bg).info_cols;
    std::uint8_t* x = d_x.data();
    for (std::size_t k = 0; k < std::size_t{ info } * zc; k++)
        x[k] = c[k] & 1u;
    std::fill(d_x.begin() + std::size_t{ info } * zc, d_x.end(), 0);

    // w_0 = P^-x (sum over the core rows of their information part).
    std::uint8_t* lam = d_lambda.data();
    std::fill(d_lambda.begin(), d_lambda.end(), 0);
    for (unsigned i = 0; i < 4; i++)
        for (const auto& e : d_rows[i])
            if (e.col < info)
                add_shifted(lam, x + std::size_t{ e.col } * zc, e.shift, zc);
    std::uint8_t* w0 = x + std::size_t{ info } * zc;
    for (unsigned m = 0; m < zc; m++)
        w0[(m + d_core_shift) % zc] = lam[m];

    for (const step& st : d_steps) {
        std::fill(d_lambda.begin(), d_lambda.end(), 0);
        for (const auto& e : d_rows[st.row])
            if (e.col != st.col)
                add_shifted(lam, x + std::size_t{ e.col } * zc, e.shift, zc);
        // P^s w = lam: w[(m + s) mod zc] = lam[m]
        std::uint8_t* w = x + std::size_t{ st.col } * zc;
        for (unsigned m = 0; m < zc; m++)
            w[(m + st.shift) % zc] = lam[m];
    }
    std::copy(d_x.begin() + 2 * std::size_t{ zc }, d_x.end(), d);
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
