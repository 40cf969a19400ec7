/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/kernel/dmrs.h>
#include <gnuradio/nrsar/kernel/gold_sequence.h>
#include <cmath>

namespace gr {
namespace nrsar {
namespace kernel {

std::uint32_t dmrs_c_init(unsigned scrambling_id, unsigned slot_in_frame, unsigned symbol)
{
    // 38.211 6.4.1.1.1.1; formed in 64 bits, reduced mod 2^31.
    const std::uint64_t nid = scrambling_id;
    const std::uint64_t v =
        (std::uint64_t{ 1 } << 17) * (14u * std::uint64_t{ slot_in_frame } + symbol + 1) *
            (2 * nid + 1) +
        2 * nid;
    return static_cast<std::uint32_t>(v & 0x7fffffffu);
}

std::vector<gr_complex>
dmrs_values(unsigned scrambling_id, unsigned slot_in_frame, unsigned symbol, unsigned count)
{
    gold_sequence c(dmrs_c_init(scrambling_id, slot_in_frame, symbol));
    const float a = static_cast<float>(1.0 / std::sqrt(2.0));
    std::vector<gr_complex> r(count);
    for (unsigned i = 0; i < count; i++) {
        const std::uint32_t b = c.next_bits(2); // c(2i) in bit 0, c(2i+1) in bit 1
        r[i] = gr_complex((b & 1u) ? -a : a, (b & 2u) ? -a : a);
    }
    return r;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
