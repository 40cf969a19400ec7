/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/gold_sequence.h>
#include <array>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
// Bit-reversal of a byte: c(n) arrives LSB first, packed payload bytes are MSB first.
const std::array<std::uint8_t, 256>& reverse_table()
{
    static const std::array<std::uint8_t, 256> table = [] {
        std::array<std::uint8_t, 256> t{};
        for (unsigned i = 0; i < 256; i++) {
            unsigned r = 0;
            for (unsigned b = 0; b < 8; b++)
                r |= ((i >> b) & 1u) << (7 - b);
            t[i] = static_cast<std::uint8_t>(r);
        }
        return t;
    }();
    return table;
}
} // namespace

gold_sequence::gold_sequence(std::uint32_t c_init) { reset(c_init); }

void gold_sequence::reset(std::uint32_t c_init)
{
    if (c_init > max_c_init)
        throw_param("c_init", c_init, "must be in [0, 2147483647] (31 bits, TS 38.211 5.2.1)");
    d_c_init = c_init;
    // x(0..30) from the initial conditions, x(31..63) by the plain recursions.
    d_x1 = 1;
    d_x2 = c_init;
    for (unsigned n = 0; n + 31 < 64; n++) {
        const std::uint64_t b1 = ((d_x1 >> (n + 3)) ^ (d_x1 >> n)) & 1u;
        const std::uint64_t b2 =
            ((d_x2 >> (n + 3)) ^ (d_x2 >> (n + 2)) ^ (d_x2 >> (n + 1)) ^ (d_x2 >> n)) & 1u;
        d_x1 |= b1 << (n + 31);
        d_x2 |= b2 << (n + 31);
    }
    // Skip Nc = 1600 = 100 * 16 values: the windows then start at x(Nc).
    static_assert(Nc % 16 == 0, "Nc must be a multiple of the 16-bit step");
    for (unsigned i = 0; i < Nc / 16; i++)
        advance16();
    d_buf = 0;
    d_buf_bits = 0;
    d_position = 0;
}

void gold_sequence::generate_packed(std::uint8_t* bytes, std::size_t nbytes)
{
    const auto& rev = reverse_table();
    std::size_t i = 0;
    for (; i + 4 <= nbytes; i += 4) {
        const std::uint32_t w = next_word();
        bytes[i] = rev[w & 0xffu];
        bytes[i + 1] = rev[(w >> 8) & 0xffu];
        bytes[i + 2] = rev[(w >> 16) & 0xffu];
        bytes[i + 3] = rev[w >> 24];
    }
    for (; i < nbytes; i++)
        bytes[i] = rev[next_bits(8)];
}

void gold_sequence::generate_unpacked(std::uint8_t* bits, std::size_t nbits)
{
    std::size_t i = 0;
    for (; i + 32 <= nbits; i += 32) {
        const std::uint32_t w = next_word();
        for (unsigned b = 0; b < 32; b++)
            bits[i + b] = static_cast<std::uint8_t>((w >> b) & 1u);
    }
    for (; i < nbits; i++)
        bits[i] = static_cast<std::uint8_t>(next_bits(1));
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
