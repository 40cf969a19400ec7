/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/kernel/rx_time_aligner.h>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gr {
namespace nrsar {
namespace kernel {

rx_time_aligner::rx_time_aligner(double sample_rate_hz,
                                 std::uint64_t symbol_length,
                                 std::uint64_t tx_start_full_s,
                                 double tx_start_frac_s)
    : d_fs(sample_rate_hz), d_len(symbol_length), d_full(tx_start_full_s), d_frac(tx_start_frac_s)
{
    if (!(std::isfinite(sample_rate_hz) && sample_rate_hz > 0.0))
        throw std::invalid_argument("sample_rate_hz = " + std::to_string(sample_rate_hz) +
                                    " must be finite and > 0");
    if (symbol_length < 1)
        throw std::invalid_argument("symbol_length = 0 must be at least 1");
    if (!std::isfinite(tx_start_frac_s))
        throw std::invalid_argument("tx_start_frac_s must be finite");
    const double whole = std::floor(d_frac);
    d_frac -= whole;
    d_full = std::uint64_t(std::int64_t(d_full) + std::int64_t(whole));
}

void rx_time_aligner::split_seconds(double t, std::uint64_t& full, double& frac)
{
    if (!(std::isfinite(t) && t >= 0.0))
        throw std::invalid_argument("time = " + std::to_string(t) + " must be finite and >= 0");
    const double whole = std::floor(t);
    full = std::uint64_t(whole);
    frac = t - whole; // exact (Sterbenz): t and floor(t) share the exponent range
}

std::int64_t rx_time_aligner::samples_until_start(std::uint64_t rx_full_s, double rx_frac_s) const
{
    // Whole seconds as integers, fractions in double: (T0 - T) fs keeps the fraction's
    // precision whatever the epoch.
    const std::int64_t dfull = std::int64_t(d_full) - std::int64_t(rx_full_s);
    const double dfrac = d_frac - rx_frac_s;
    return std::int64_t(std::llround(double(dfull) * d_fs + dfrac * d_fs));
}

rx_time_aligner::result
rx_time_aligner::align(std::uint64_t rx_full_s, double rx_frac_s, std::uint64_t expected_symbol) const
{
    return align_offset(samples_until_start(rx_full_s, rx_frac_s), d_len, expected_symbol);
}

rx_time_aligner::result rx_time_aligner::align_offset(std::int64_t tx_start_offset,
                                                      std::uint64_t symbol_length,
                                                      std::uint64_t expected_symbol)
{
    result r{};
    r.tx_start_offset = tx_start_offset;
    const auto len = std::int64_t(symbol_length);
    if (r.tx_start_offset >= 0) {
        // The stamped sample precedes the TX start: drop up to it, then symbol 0.
        r.skip = std::uint64_t(r.tx_start_offset);
        r.next_symbol = 0;
    } else {
        // The stamped sample lies d samples after the TX start, inside symbol floor(d / L);
        // that symbol is incomplete, so the next whole one is ceil(d / L).
        const std::int64_t d = -r.tx_start_offset;
        const std::int64_t k = (d + len - 1) / len;
        r.skip = std::uint64_t(k * len - d);
        r.next_symbol = std::uint64_t(k);
    }
    r.lost_symbols = std::int64_t(r.next_symbol) - std::int64_t(expected_symbol);
    return r;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
