/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_RX_TIME_TAG_H
#define INCLUDED_NRSAR_RX_TIME_TAG_H

#include <pmt/pmt.h>
#include <cmath>
#include <cstdint>

namespace gr {
namespace nrsar {

//! rx_time = (whole seconds, fractional seconds): uint64 (UHD) or integer, and a real.
inline bool parse_rx_time(const pmt::pmt_t& v, std::uint64_t& full, double& frac)
{
    if (!pmt::is_tuple(v) || pmt::length(v) < 2)
        return false;
    const auto a = pmt::tuple_ref(v, 0);
    const auto b = pmt::tuple_ref(v, 1);
    if (!pmt::is_real(b))
        return false;
    if (pmt::is_uint64(a))
        full = pmt::to_uint64(a);
    else if (pmt::is_integer(a) && pmt::to_long(a) >= 0)
        full = std::uint64_t(pmt::to_long(a));
    else
        return false;
    frac = pmt::to_double(b);
    return std::isfinite(frac);
}

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_RX_TIME_TAG_H */
