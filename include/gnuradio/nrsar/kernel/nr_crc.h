/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_NR_CRC_H
#define INCLUDED_NRSAR_KERNEL_NR_CRC_H

#include <gnuradio/nrsar/api.h>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief The cyclic generator polynomials of TS 38.212 5.1 that the data channel uses:
 *   gCRC24A(D) = D^24+D^23+D^18+D^17+D^14+D^11+D^10+D^7+D^6+D^5+D^4+D^3+D+1  (transport block, A > 3824)
 *   gCRC24B(D) = D^24+D^23+D^6+D^5+D+1                                  (code block)
 *   gCRC16(D)  = D^16+D^12+D^5+1                                        (transport block, A <= 3824)
 */
enum class nr_crc_type { crc24a, crc24b, crc16 };

/*!
 * \brief CRC of 38.212 5.1 on unpacked bits (one bit per byte, 0/1, a_0 first).
 *
 * The parity bits p_0 .. p_{L-1} are the remainder of a(D) D^L divided by g(D), with
 * a(D) = a_0 D^{A+L-1} + ... (a_0 is the highest power): zero initial state, no
 * reflection, no final xor. Table driven, 8 input bits per step.
 */
class NRSAR_API nr_crc
{
public:
    explicit nr_crc(nr_crc_type type);

    //! "24A", "24B" or "16" (the names of 38.212 5.1); std::invalid_argument otherwise.
    static nr_crc_type parse(const std::string& name);

    unsigned length() const { return d_L; }

    //! Remainder of bits[0..n) D^L mod g(D); p_0 is bit L-1 of the value.
    std::uint32_t remainder(const std::uint8_t* bits, std::size_t n) const;

    //! out[0..n) = bits, out[n..n+L) = p_0 .. p_{L-1} (out may alias bits).
    void attach(const std::uint8_t* bits, std::size_t n, std::uint8_t* out) const;

    //! True when bits[0..n) (data followed by its L parity bits) divides by g(D).
    bool check(const std::uint8_t* bits, std::size_t n) const { return remainder(bits, n) == 0; }

private:
    unsigned d_L;
    std::uint32_t d_poly; // g(D) without the D^L term, bit k = coefficient of D^k
    //! d_table[k][b] = b D^(8k + L) mod g(D): byte b followed by k zero bytes (slicing by
    //! L / 8 bytes per step)
    std::array<std::array<std::uint32_t, 256>, 3> d_table;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_NR_CRC_H */
