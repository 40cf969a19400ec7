/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// What rd_focuser and bp_focuser share of the stream: the end of the input (they hold
// their last item back until the upstream is done, so that the scheduler calls them once
// more to flush) and the axis tags they follow.

#ifndef INCLUDED_NRSAR_FOCUSER_STREAM_H
#define INCLUDED_NRSAR_FOCUSER_STREAM_H

#include <gnuradio/block_detail.h>
#include <gnuradio/buffer_reader.h>
#include <gnuradio/logger.h>
#include <gnuradio/nrsar/kernel/aperture_focuser.h>
#include <gnuradio/nrsar/tags.h>
#include <gnuradio/tags.h>
#include <pmt/pmt.h>
#include <cmath>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * The upstream of input 0 is done and navail (the scheduler's count) is all it wrote.
 * done() alone is not enough: the upstream may have written its last lines and set done
 * after the scheduler counted navail, and flushing then would zero-pad lines that are
 * already in the buffer (seen as a rare, load-dependent image difference). Both are read
 * under the buffer's lock, as the scheduler does, and nothing may have arrived since.
 */
inline bool input_ended(const gr::block_detail_sptr& detail, int navail)
{
    const auto& reader = detail->input(0);
    gr::thread::scoped_lock lock(*reader->mutex());
    return reader->done() && reader->items_available() == navail;
}

//! The value of a pulse_interval tag: false unless a finite number > 0.
inline bool parse_pulse_interval(const pmt::pmt_t& v, double& T)
{
    const double t = pmt::is_number(v) ? pmt::to_double(v) : NAN;
    if (!(std::isfinite(t) && t > 0.0))
        return false;
    T = t;
    return true;
}

//! The tuple (first [m], spacing [m], bins) of a range_axis tag: false when malformed.
inline bool parse_range_axis(const pmt::pmt_t& v, double& first, double& step, uint64_t& k)
{
    if (!pmt::is_tuple(v) || pmt::length(v) < 3 || !pmt::is_number(pmt::tuple_ref(v, 0)) ||
        !pmt::is_number(pmt::tuple_ref(v, 1)) ||
        !(pmt::is_integer(pmt::tuple_ref(v, 2)) || pmt::is_uint64(pmt::tuple_ref(v, 2))))
        return false;
    first = pmt::to_double(pmt::tuple_ref(v, 0));
    step = pmt::to_double(pmt::tuple_ref(v, 1));
    k = pmt::to_uint64(pmt::tuple_ref(v, 2));
    return true;
}

/*!
 * The axes (T, first, step) after a pulse_interval or range_axis tag, starting from the
 * ones the next aperture would use. False when the tag is neither or is refused (logged:
 * malformed, another bin count); a range_axis unlike the constructor's axis is used and
 * logged.
 */
inline bool axes_from_tag(const gr::tag_t& tag,
                          unsigned K,
                          double ctor_first,
                          double ctor_step,
                          const gr::logger_ptr& logger,
                          double& T,
                          double& first_range,
                          double& range_bin)
{
    if (pmt::eq(tag.key, tags::pulse_interval_key())) {
        if (parse_pulse_interval(tag.value, T))
            return true;
        logger->warn("ignoring pulse_interval tag with value {}", pmt::write_string(tag.value));
        return false;
    }
    if (!pmt::eq(tag.key, tags::range_axis_key()))
        return false;
    double first = 0.0, step = 0.0;
    uint64_t k = 0;
    if (!parse_range_axis(tag.value, first, step, k)) {
        logger->warn("ignoring malformed range_axis tag {}", pmt::write_string(tag.value));
        return false;
    }
    if (k != K || !(first >= 0.0) || !(step > 0.0) || !std::isfinite(first + step)) {
        logger->warn("ignoring range_axis tag ({}, {}, {}): the block has {} bins", first, step, k, K);
        return false;
    }
    if (kernel::aperture_focuser::differs(first, ctor_first) ||
        kernel::aperture_focuser::differs(step, ctor_step))
        logger->warn("range_axis tag ({} m, {} m) differs from the constructor's ({} m, {} m): "
                     "using the tag",
                     first,
                     step,
                     ctor_first,
                     ctor_step);
    first_range = first;
    range_bin = step;
    return true;
}

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_FOCUSER_STREAM_H */
