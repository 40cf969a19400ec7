/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/nr_crc.h>
#include <gnuradio/nrsar/kernel/nr_ldpc.h>
#include <gnuradio/nrsar/kernel/nr_segmentation.h>
#include <algorithm>
#include <cmath>

namespace gr {
namespace nrsar {
namespace kernel {

int nr_select_base_graph(std::size_t tbs, double code_rate)
{
    check_at_least<std::size_t>("tbs", tbs, 1);
    if (!(code_rate > 0.0 && code_rate < 1.0))
        throw_param("code_rate", code_rate, "must be in (0, 1)");
    if (tbs <= 292 || (tbs <= 3824 && code_rate <= 0.67) || code_rate <= 0.25)
        return 2;
    return 1;
}

unsigned nr_tb_crc_length(std::size_t tbs) { return tbs > 3824 ? 24 : 16; }

nr_segmentation nr_segmentation::compute(std::size_t B, int base_graph)
{
    check_at_least<std::size_t>("B", B, 1);
    nr_base_graph::get(base_graph); // validates base_graph
    nr_segmentation s;
    s.base_graph = base_graph;
    s.B = B;
    const std::size_t Kcb = base_graph == 1 ? 8448 : 3840;
    std::size_t Bp;
    if (B <= Kcb) {
        s.L = 0;
        s.C = 1;
        Bp = B;
    } else {
        s.L = 24;
        s.C = static_cast<unsigned>((B + (Kcb - s.L) - 1) / (Kcb - s.L));
        Bp = B + std::size_t{ s.C } * s.L;
    }
    if (Bp % s.C != 0) // never for a TBS of 38.214 with its CRC
        throw_param("B", B, "gives B' = B + 24 C not divisible by C (TS 38.212 5.2.2 needs K' = B' / C)");
    s.K_prime = static_cast<unsigned>(Bp / s.C);
    if (base_graph == 1)
        s.Kb = 22;
    else if (B > 640)
        s.Kb = 10;
    else if (B > 560)
        s.Kb = 9;
    else if (B > 192)
        s.Kb = 8;
    else
        s.Kb = 6;
    for (unsigned z : nr_lifting_sizes())
        if (std::size_t{ s.Kb } * z >= s.K_prime) {
            s.Zc = z;
            break;
        }
    s.K = (base_graph == 1 ? 22u : 10u) * s.Zc;
    s.F = s.K - s.K_prime;
    return s;
}

void nr_segment(const std::uint8_t* b, const nr_segmentation& s, std::uint8_t* cb, std::uint8_t filler_value)
{
    static const nr_crc crc(nr_crc_type::crc24b); // tables made once
    const std::size_t data = s.K_prime - s.L;
    for (unsigned r = 0; r < s.C; r++) {
        std::uint8_t* c = cb + std::size_t{ r } * s.K;
        const std::uint8_t* src = b + r * data;
        if (s.C > 1)
            crc.attach(src, data, c);
        else
            for (std::size_t k = 0; k < data; k++)
                c[k] = src[k] & 1u;
        std::fill(c + s.K_prime, c + s.K, filler_value);
    }
}

bool nr_desegment(const std::uint8_t* cb, const nr_segmentation& s, std::uint8_t* b, bool* cb_crc_ok)
{
    static const nr_crc crc(nr_crc_type::crc24b); // tables made once
    const std::size_t data = s.K_prime - s.L;
    bool all = true;
    for (unsigned r = 0; r < s.C; r++) {
        const std::uint8_t* c = cb + std::size_t{ r } * s.K;
        const bool ok = s.C == 1 || crc.check(c, s.K_prime);
        if (cb_crc_ok)
            cb_crc_ok[r] = ok;
        all = all && ok;
        std::copy(c, c + data, b + r * data);
    }
    return all;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
