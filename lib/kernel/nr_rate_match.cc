/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/nr_ldpc.h>
#include <gnuradio/nrsar/kernel/nr_rate_match.h>
#include <algorithm>
#include <limits>

namespace gr {
namespace nrsar {
namespace kernel {

void nr_rate_match_params::validate() const
{
    nr_base_graph::get(base_graph);
    nr_check_lifting_size(zc);
    const std::size_t K = nr_ldpc_k(base_graph, zc);
    if (k_prime <= 2 * std::size_t{ zc } || k_prime > K)
        throw_param("k_prime", k_prime, "must be in (2 Zc, K] = (" + std::to_string(2 * zc) + ", " + std::to_string(K) + "]");
    check_range("rv", rv, 0u, 3u);
    if (!(qm == 1 || qm == 2 || qm == 4 || qm == 6 || qm == 8))
        throw_param("qm", qm, "must be 1, 2, 4, 6 or 8");
    // N_cb must hold at least the systematic bits that are sent (K' - 2 Zc) for k0 to be meaningful.
    if (n_ref != 0 && n_ref < K - 2 * std::size_t{ zc })
        throw_param("n_ref", n_ref, "must be 0 (no limit) or at least K - 2 Zc = " + std::to_string(K - 2 * zc));
}

std::size_t nr_rate_match_params::n() const { return nr_ldpc_n(base_graph, zc); }

std::size_t nr_rate_match_params::n_cb() const { return n_ref == 0 ? n() : std::min(n(), n_ref); }

std::size_t nr_rate_match_params::k0() const
{
    // Table 5.4.2.1-2: k0 = floor(a N_cb / (b Zc)) Zc, b = 66 (BG1) or 50 (BG2).
    static const unsigned a1[4] = { 0, 17, 33, 56 };
    static const unsigned a2[4] = { 0, 13, 25, 43 };
    const std::size_t b = base_graph == 1 ? 66 : 50;
    const std::size_t a = base_graph == 1 ? a1[rv] : a2[rv];
    return (a * n_cb()) / (b * zc) * zc;
}

std::size_t nr_rate_match_params::filler_begin() const { return k_prime - 2 * std::size_t{ zc }; }

std::size_t nr_rate_match_params::filler_end() const { return nr_ldpc_k(base_graph, zc) - 2 * std::size_t{ zc }; }

std::vector<std::size_t> nr_code_block_e(std::size_t G, unsigned C, unsigned qm, unsigned n_layers)
{
    check_at_least("C", C, 1u);
    check_at_least("qm", qm, 1u);
    check_at_least("n_layers", n_layers, 1u);
    const std::size_t unit = std::size_t{ n_layers } * qm;
    if (G % unit != 0)
        throw_param("G", G, "must be a multiple of N_L Qm = " + std::to_string(unit));
    const std::size_t symbols = G / unit;
    std::vector<std::size_t> e(C);
    for (unsigned r = 0; r < C; r++)
        e[r] = unit * (r < C - symbols % C ? symbols / C : (symbols + C - 1) / C);
    return e;
}

namespace {

// Bit selection (38.212 5.4.2.1) and interleaving (5.4.2.2) in one walk: the selected bits
// e_k, k = i rows + j, are read from the circular buffer from k0 on, skipping the fillers,
// and e_k is f[i + j Qm]. Calls run(circular position, f index, n) for runs of n selected
// bits at consecutive positions (f indices Qm apart), in the order of k.
template <class Run>
void for_each_run(const nr_rate_match_params& p, std::size_t e, Run run)
{
    p.validate();
    if (e % p.qm != 0)
        throw_param("e", e, "must be a multiple of qm = " + std::to_string(p.qm));
    const std::size_t ncb = p.n_cb(), fb = p.filler_begin(), fe = p.filler_end();
    if (e > 0 && ncb <= fe - fb)
        throw_param("n_ref", p.n_ref, "leaves no bit outside the fillers");
    const std::size_t rows = e / p.qm; // E / Qm
    std::size_t j = p.k0();
    for (unsigned i = 0; i < p.qm; i++)
        for (std::size_t row = 0; row < rows;) {
            if (j >= ncb)
                j = 0;
            if (j >= fb && j < fe) {
                j = fe;
                if (j >= ncb)
                    j = 0;
            }
            // up to the fillers or the end of the buffer
            const std::size_t end = j < fb ? std::min(fb, ncb) : ncb;
            const std::size_t n = std::min(rows - row, end - j);
            run(j, i + row * p.qm, n);
            j += n;
            row += n;
        }
}

} // namespace

void nr_rate_match(const std::uint8_t* d, const nr_rate_match_params& p, std::size_t e, std::uint8_t* f)
{
    const std::size_t qm = p.qm;
    for_each_run(p, e, [&](std::size_t j, std::size_t out, std::size_t n) {
        for (std::size_t t = 0; t < n; t++)
            f[out + t * qm] = d[j + t];
    });
}

void nr_rate_recover(const float* f_llr,
                     const nr_rate_match_params& p,
                     std::size_t e,
                     float* d_llr,
                     bool combine,
                     std::uint8_t* nonzero_columns)
{
    p.validate(); // before the sizes below are read
    const std::size_t qm = p.qm, ncb = p.n_cb(), fb = p.filler_begin(), fe = p.filler_end();
    const std::size_t zc = p.zc, cols = p.n() / zc;
    // The columns this call writes (fillers included), for nonzero_columns.
    std::uint8_t written[nr_max_columns] = {};
    const auto mark = [&](std::size_t begin, std::size_t end) {
        for (std::size_t c = begin / zc; begin < end && c < (end + zc - 1) / zc; c++)
            written[c] = 1;
    };
    // The walk visits the circular buffer in order: its first `distinct` reads are the
    // positions outside the fillers once each, the later ones wrap onto them again.
    const std::size_t distinct = ncb - (std::min(fe, ncb) - std::min(fb, ncb));
    std::size_t visited = 0, next = p.k0();
    for_each_run(p, e, [&](std::size_t j, std::size_t in, std::size_t n) {
        std::size_t t = 0;
        if (!combine)
            for (; t < n && visited + t < distinct; t++)
                d_llr[j + t] = f_llr[in + t * qm];
        for (; t < n; t++)
            d_llr[j + t] += f_llr[in + t * qm];
        visited += n;
        next = j + n;
        mark(j, j + n);
    });
    if (!combine) {
        // Zeros where nothing was read; with nonzero_columns only in the columns that may
        // hold something else (a receiver's soft buffer written by the same rv at the same
        // E each time has nothing to clear).
        const auto clear = [&](std::size_t begin, std::size_t end) {
            if (!nonzero_columns) {
                std::fill(d_llr + begin, d_llr + end, 0.0f);
                return;
            }
            for (std::size_t c = begin / zc; c < (end + zc - 1) / zc; c++)
                if (nonzero_columns[c])
                    std::fill(d_llr + std::max(begin, c * zc),
                              d_llr + std::min(end, (c + 1) * zc),
                              0.0f);
        };
        // not read: from where the walk stopped round to k0 (fillers included, set below),
        // and the bits beyond a limited buffer
        const std::size_t k0 = p.k0();
        if (visited == 0)
            clear(0, ncb);
        else if (visited < distinct) {
            next = next >= ncb ? 0 : next;
            if (next <= k0)
                clear(next, k0);
            else {
                clear(next, ncb);
                clear(0, k0);
            }
        }
        clear(ncb, p.n());
    }
    std::fill(d_llr + fb, d_llr + fe, std::numeric_limits<float>::infinity());
    if (nonzero_columns) {
        mark(fb, fe);
        for (std::size_t c = 0; c < cols; c++)
            nonzero_columns[c] = written[c] || (combine && nonzero_columns[c]);
    }
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
