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
    // Skip Nc = 1600 = 50 * 32 values: the windows then start at x(Nc).
    static_assert(Nc % 32 == 0, "Nc must be a multiple of the 32-bit step");
    for (unsigned i = 0; i < Nc / 32; i++)
        advance32(d_x1, d_x2);
    d_buf = 0;
    d_buf_bits = 0;
    d_position = 0;
}

void gold_sequence::generate_packed(std::uint8_t* bytes, std::size_t nbytes)
{
    const auto& rev = reverse_table();
    std::size_t i = 0;
    if (d_buf_bits == 0) {
        // Fast path on word boundaries: registers kept in locals, bits reversed inside
        // each byte with three mask-and-swap steps instead of four table look-ups.
        std::uint64_t x1 = d_x1, x2 = d_x2;
        for (; i + 4 <= nbytes; i += 4) {
            std::uint32_t w = static_cast<std::uint32_t>(x1 ^ x2);
            advance32(x1, x2);
            w = ((w >> 1) & 0x55555555u) | ((w & 0x55555555u) << 1);
            w = ((w >> 2) & 0x33333333u) | ((w & 0x33333333u) << 2);
            w = ((w >> 4) & 0x0f0f0f0fu) | ((w & 0x0f0f0f0fu) << 4);
            bytes[i] = static_cast<std::uint8_t>(w);
            bytes[i + 1] = static_cast<std::uint8_t>(w >> 8);
            bytes[i + 2] = static_cast<std::uint8_t>(w >> 16);
            bytes[i + 3] = static_cast<std::uint8_t>(w >> 24);
        }
        d_x1 = x1;
        d_x2 = x2;
        d_position += 8 * i;
    }
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
