/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// The blocks' common reaction to non-finite input samples (already zeroed by
// kernel::finite_guard): log the first occurrence, return the value of the nonfinite tag.

#ifndef INCLUDED_NRSAR_NONFINITE_LOG_H
#define INCLUDED_NRSAR_NONFINITE_LOG_H

#include <gnuradio/logger.h>
#include <pmt/pmt.h>
#include <cstdint>

namespace gr {
namespace nrsar {

inline pmt::pmt_t
note_nonfinite(const gr::logger_ptr& logger, bool& warned, std::size_t bad, std::uint64_t item)
{
    if (!warned) {
        logger->warn("{} non-finite input samples in item {} replaced by 0 "
                     "(further occurrences are only tagged and counted)",
                     bad,
                     item);
        warned = true;
    }
    return pmt::from_uint64(bad);
}

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_NONFINITE_LOG_H */
