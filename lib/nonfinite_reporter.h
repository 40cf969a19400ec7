/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// The blocks' common reaction to non-finite input samples, after their kernel zeroed them:
// count them, log the first occurrence (again after every rearm(), which blocks that work
// aperture by aperture call per aperture), and give the nonfinite tag that marks them.

#ifndef INCLUDED_NRSAR_NONFINITE_REPORTER_H
#define INCLUDED_NRSAR_NONFINITE_REPORTER_H

#include <gnuradio/logger.h>
#include <gnuradio/nrsar/tags.h>
#include <gnuradio/tags.h>
#include <pmt/pmt.h>
#include <cstdint>

namespace gr {
namespace nrsar {

class nonfinite_reporter
{
public:
    //! Records bad zeroed samples found at index where (an item, line or symbol);
    //! returns the nonfinite tag's value (the count of this occurrence).
    pmt::pmt_t note(const gr::logger_ptr& logger, std::uint64_t bad, std::uint64_t where)
    {
        d_count += bad;
        if (!d_logged) {
            logger->warn("{} non-finite input samples at index {} replaced by 0 (logged once "
                         "per aperture; see nonfinite_count() and the nonfinite tags)",
                         bad,
                         where);
            d_logged = true;
        }
        return pmt::from_uint64(bad);
    }

    //! note() and the nonfinite tag on output item `item` (value: the count), from srcid.
    gr::tag_t tag(const gr::logger_ptr& logger,
                  std::uint64_t bad,
                  std::uint64_t item,
                  std::uint64_t where,
                  const pmt::pmt_t& srcid)
    {
        gr::tag_t t;
        t.offset = item;
        t.key = nrsar::tags::nonfinite_key();
        t.value = note(logger, bad, where);
        t.srcid = srcid;
        return t;
    }

    std::uint64_t count() const { return d_count; }
    void rearm() { d_logged = false; }

private:
    std::uint64_t d_count = 0;
    bool d_logged = false;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_NONFINITE_REPORTER_H */
