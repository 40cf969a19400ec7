/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "bit_pack.h"
#include "param_check.h"
#include <gnuradio/nrsar/kernel/nr_crc.h>
#include <cstring>

namespace gr {
namespace nrsar {
namespace kernel {

nr_crc::nr_crc(nr_crc_type type)
{
    switch (type) {
    case nr_crc_type::crc24a:
        d_L = 24;
        d_poly = 0x864CFB; // D^23+D^18+D^17+D^14+D^11+D^10+D^7+D^6+D^5+D^4+D^3+D+1
        break;
    case nr_crc_type::crc24b:
        d_L = 24;
        d_poly = 0x800063; // D^23+D^6+D^5+D+1
        break;
    default:
        d_L = 16;
        d_poly = 0x1021; // D^12+D^5+1
        break;
    }
    const std::uint32_t top = std::uint32_t{ 1 } << (d_L - 1);
    const std::uint32_t mask = (top << 1) - 1;
    for (std::uint32_t b = 0; b < 256; b++) {
        std::uint32_t r = b << (d_L - 8);
        for (int k = 0; k < 8; k++)
            r = (r & top) ? ((r << 1) ^ d_poly) & mask : (r << 1) & mask;
        d_table[0][b] = r;
    }
    for (unsigned k = 1; k < d_L / 8; k++)
        for (std::uint32_t b = 0; b < 256; b++) {
            const std::uint32_t v = d_table[k - 1][b];
            d_table[k][b] = ((v << 8) & mask) ^ d_table[0][v >> (d_L - 8)];
        }
}

nr_crc_type nr_crc::parse(const std::string& name)
{
    if (name == "24A")
        return nr_crc_type::crc24a;
    if (name == "24B")
        return nr_crc_type::crc24b;
    if (name == "16")
        return nr_crc_type::crc16;
    throw_param("poly", "'" + name + "'", "must be \"24A\", \"24B\" or \"16\" (TS 38.212 5.1)");
}

std::uint32_t nr_crc::remainder(const std::uint8_t* bits, std::size_t n) const
{
    const std::uint32_t top = std::uint32_t{ 1 } << (d_L - 1);
    const std::uint32_t mask = (top << 1) - 1;
    std::uint32_t r = 0;
    std::size_t i = 0;
    // L / 8 bytes per step (the register's width): r' = sum_k T_k[byte k of (r ^ bytes)],
    // the table look-ups independent of each other
    const unsigned nb = d_L / 8;
    for (; i + 8 * nb <= n; i += 8 * nb) {
        std::uint32_t v = r;
        for (unsigned k = 0; k < nb; k++)
            v ^= std::uint32_t{ pack8(bits + i + 8 * k) } << (8 * (nb - 1 - k));
        std::uint32_t next = 0;
        for (unsigned k = 0; k < nb; k++)
            next ^= d_table[k][(v >> (8 * k)) & 0xffu];
        r = next;
    }
    for (; i + 8 <= n; i += 8)
        r = ((r << 8) & mask) ^ d_table[0][((r >> (d_L - 8)) ^ pack8(bits + i)) & 0xffu];
    for (; i < n; i++) {
        const bool fb = ((r & top) != 0) != ((bits[i] & 1u) != 0);
        r = (r << 1) & mask;
        if (fb)
            r ^= d_poly;
    }
    return r;
}

void nr_crc::attach(const std::uint8_t* bits, std::size_t n, std::uint8_t* out) const
{
    const std::uint32_t p = remainder(bits, n);
    if (out != bits)
        for (std::size_t i = 0; i < n; i++)
            out[i] = bits[i] & 1u;
    for (unsigned k = 0; k < d_L; k++)
        out[n + k] = static_cast<std::uint8_t>((p >> (d_L - 1 - k)) & 1u);
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
