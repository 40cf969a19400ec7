/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_BIT_PACK_H
#define INCLUDED_NRSAR_KERNEL_BIT_PACK_H

#include <cstdint>
#include <cstring>

namespace gr {
namespace nrsar {
namespace kernel {

//! Eight 0/1 bytes into one byte, bits[0] the MSB: each bit k lands on bit 63 - k of the
//! product (little-endian load; no carry reaches the top byte).
inline std::uint8_t pack8(const std::uint8_t* bits)
{
    std::uint64_t w = 0;
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    std::memcpy(&w, bits, 8);
#else
    for (unsigned k = 0; k < 8; k++)
        w |= std::uint64_t{ bits[k] } << (8 * k);
#endif
    return static_cast<std::uint8_t>(((w & 0x0101010101010101ull) * 0x8040201008040201ull) >> 56);
}

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif
