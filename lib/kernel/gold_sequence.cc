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

// Characteristic polynomials of 38.211 5.2.1 (bit i = coefficient of D^i).
constexpr std::uint64_t p1 = (std::uint64_t{ 1 } << 31) | (1u << 3) | 1u;
constexpr std::uint64_t p2 = (std::uint64_t{ 1 } << 31) | (1u << 3) | (1u << 2) | (1u << 1) | 1u;

// a * b mod p over GF(2), a and b of degree < 31.
std::uint64_t mulmod(std::uint64_t a, std::uint64_t b, std::uint64_t p)
{
    std::uint64_t r = 0;
    for (; b; b >>= 1, a <<= 1)
        if (b & 1u)
            r ^= a;
    for (int i = 61; i >= 31; i--)
        if ((r >> i) & 1u)
            r ^= p << (i - 31);
    return r;
}

// x(31..63) of the window from x(0..30) by the recursion of p (its taps below D^31).
std::uint64_t extend_window(std::uint64_t x, std::uint64_t p)
{
    for (unsigned n = 0; n + 31 < 64; n++) {
        const std::uint64_t b = static_cast<std::uint64_t>(
            __builtin_parityll((x >> n) & p & 0x7fffffffu));
        x |= b << (n + 31);
    }
    return x;
}

// The window x(m + n .. m + n + 63) from the window x(m .. m + 63): with r(D) = D^n mod
// p(D), x(m + n + j) = sum_i r_i x(m + i + j) for j < 31 (reads x up to m + 60).
std::uint64_t jump_window(std::uint64_t x, std::uint64_t n, std::uint64_t p)
{
    std::uint64_t r = 1, d = 2; // D^0, D^1
    for (; n; n >>= 1, d = mulmod(d, d, p))
        if (n & 1u)
            r = mulmod(r, d, p);
    std::uint64_t low = 0;
    for (unsigned j = 0; j < 31; j++)
        low |= static_cast<std::uint64_t>(__builtin_parityll((x >> j) & r)) << j;
    return extend_window(low, p);
}
} // namespace

gold_sequence::gold_sequence(std::uint32_t c_init) { reset(c_init); }

void gold_sequence::reset(std::uint32_t c_init)
{
    if (c_init > max_c_init)
        throw_param("c_init", c_init, "must be in [0, 2147483647] (31 bits, TS 38.211 5.2.1)");
    d_c_init = c_init;
    // x(0..30) from the initial conditions, x(31..63) by the plain recursions.
    d_x1 = extend_window(1, p1);
    d_x2 = extend_window(c_init, p2);
    // Skip Nc = 1600 = 50 * 32 values: the windows then start at x(Nc).
    static_assert(Nc % 32 == 0, "Nc must be a multiple of the 32-bit step");
    for (unsigned i = 0; i < Nc / 32; i++)
        advance32(d_x1, d_x2);
    d_buf = 0;
    d_buf_bits = 0;
    d_position = 0;
}

void gold_sequence::discard(std::uint64_t n)
{
    d_position += n;
    if (n < d_buf_bits) {
        d_buf >>= n;
        d_buf_bits -= static_cast<unsigned>(n);
        return;
    }
    // The registers are d_buf_bits values ahead of the buffer's first one.
    n -= d_buf_bits;
    d_buf = 0;
    d_buf_bits = 0;
    d_x1 = jump_window(d_x1, n, p1);
    d_x2 = jump_window(d_x2, n, p2);
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
