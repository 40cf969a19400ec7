/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_GOLD_SEQUENCE_H
#define INCLUDED_NRSAR_KERNEL_GOLD_SEQUENCE_H

#include <gnuradio/nrsar/api.h>
#include <cstddef>
#include <cstdint>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Pseudo-random sequence c(n) of 3GPP TS 38.211 section 5.2.1 (SPEC section 2).
 *
 *   x1(n+31) = (x1(n+3) + x1(n)) mod 2,                 x1(0) = 1, x1(1..30) = 0
 *   x2(n+31) = (x2(n+3) + x2(n+2) + x2(n+1) + x2(n)) mod 2, sum_i x2(i) 2^i = c_init
 *   c(n)     = (x1(n + Nc) + x2(n + Nc)) mod 2,          Nc = 1600
 *
 * Word-parallel: each register is a 64-bit window x(n..n+63) (bit i = x(n+i)). Squaring
 * the characteristic polynomials over GF(2), (1 + D^3 + D^31)^2 = 1 + D^6 + D^62 and
 * (1 + D + D^2 + D^3 + D^31)^2 = 1 + D^2 + D^4 + D^6 + D^62, gives recursions that
 * every sequence of the originals also obeys,
 *   x1(m+62) = x1(m+6) + x1(m),   x2(m+62) = x2(m+6) + x2(m+4) + x2(m+2) + x2(m),
 * and they reach only 62 - 6 = 56 positions back: the next 32 values of both registers
 * follow from the current windows in one shift/xor step, with no dependence inside the
 * step. The sequence is continuous across calls (period 2^31 - 1 bits).
 */
class NRSAR_API gold_sequence
{
public:
    static constexpr unsigned Nc = 1600;              //!< initial skip of 38.211 5.2.1
    static constexpr std::uint32_t max_c_init = 0x7fffffffu; //!< c_init has 31 bits

    //! Throws std::invalid_argument when c_init > max_c_init.
    explicit gold_sequence(std::uint32_t c_init = 0);

    //! Restart at c(0) with a new c_init.
    void reset(std::uint32_t c_init);

    //! The next k <= 32 values c(n..n+k-1), c(n) in bit 0 (least significant bit first).
    std::uint32_t next_bits(unsigned k)
    {
        if (d_buf_bits < k) {
            d_buf |= static_cast<std::uint64_t>(raw_word()) << d_buf_bits;
            d_buf_bits += 32;
        }
        const std::uint64_t mask = (std::uint64_t{ 1 } << k) - 1;
        const auto out = static_cast<std::uint32_t>(d_buf & mask);
        d_buf >>= k;
        d_buf_bits -= k;
        d_position += k;
        return out;
    }

    //! The next 32 values c(n..n+31), c(n) in bit 0.
    std::uint32_t next_word() { return next_bits(32); }

    //! The next 8 * nbytes values packed MSB first (first bit in bit 7 of bytes[0]).
    void generate_packed(std::uint8_t* bytes, std::size_t nbytes);

    //! The next nbits values, one per byte (0 or 1).
    void generate_unpacked(std::uint8_t* bits, std::size_t nbits);

    /*!
     * Skips the next n values: the following call returns c(position() + n). A jump of
     * both registers by D^n mod p(D) over GF(2) (square and multiply, O(log n)), so a far
     * start costs microseconds, not n / 32 register steps.
     */
    void discard(std::uint64_t n);

    //! Index n of the next value c(n) that a call returns.
    std::uint64_t position() const { return d_position; }
    std::uint32_t c_init() const { return d_c_init; }

private:
    // 32 new values of c straight from the registers (bypasses d_buf).
    std::uint32_t raw_word()
    {
        const auto out = static_cast<std::uint32_t>(d_x1 ^ d_x2);
        advance32(d_x1, d_x2);
        return out;
    }

public:
    //! Moves the windows x(n..n+63) on by 32: new bit k is x(n+64+k), from the squared
    //! recursions with m = n + 2 + k (reads bits 2 + k .. 8 + k <= 39 of the window).
    static void advance32(std::uint64_t& x1, std::uint64_t& x2)
    {
        const std::uint64_t n1 = ((x1 >> 8) ^ (x1 >> 2)) & 0xffffffffu;
        const std::uint64_t n2 = ((x2 >> 8) ^ (x2 >> 6) ^ (x2 >> 4) ^ (x2 >> 2)) & 0xffffffffu;
        x1 = (x1 >> 32) | (n1 << 32);
        x2 = (x2 >> 32) | (n2 << 32);
    }

private:
    std::uint64_t d_x1 = 0;
    std::uint64_t d_x2 = 0;
    std::uint64_t d_position = 0;
    std::uint32_t d_c_init = 0;
    std::uint64_t d_buf = 0; // values generated but not handed out yet, next in bit 0
    unsigned d_buf_bits = 0;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_GOLD_SEQUENCE_H */
