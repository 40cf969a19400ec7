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
 * Word-parallel: each register is a 64-bit window x(n..n+63) (bit i = x(n+i)). Both
 * recursions reach back at most 31 - 3 = 28 positions, so 16 new bits follow from the
 * window in one shift/xor step; two steps give the next 32 bits of c(n). The sequence is
 * continuous across calls (period 2^31 - 1 bits).
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

    //! Index n of the next value c(n) that a call returns.
    std::uint64_t position() const { return d_position; }
    std::uint32_t c_init() const { return d_c_init; }

private:
    // 32 new values of c straight from the registers (bypasses d_buf).
    std::uint32_t raw_word()
    {
        const auto out = static_cast<std::uint32_t>(d_x1 ^ d_x2);
        advance16();
        advance16();
        return out;
    }

    void advance16()
    {
        // New bit k (k = 0..15) of the window is x(n+64+k); with m = n+33+k the recursions
        // read x(m), .., x(m+3), all inside the current window (33 + 15 + 3 = 51 < 64).
        const std::uint64_t n1 = ((d_x1 >> 36) ^ (d_x1 >> 33)) & 0xffffu;
        const std::uint64_t n2 =
            ((d_x2 >> 36) ^ (d_x2 >> 35) ^ (d_x2 >> 34) ^ (d_x2 >> 33)) & 0xffffu;
        d_x1 = (d_x1 >> 16) | (n1 << 48);
        d_x2 = (d_x2 >> 16) | (n2 << 48);
    }

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
