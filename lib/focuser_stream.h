/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// What rd_focuser and bp_focuser share of the stream: the end of the input (they hold
// their last item back until the upstream is done, so that the scheduler calls them once
// more to flush) and the values of the axis tags they follow.

#ifndef INCLUDED_NRSAR_FOCUSER_STREAM_H
#define INCLUDED_NRSAR_FOCUSER_STREAM_H

#include <gnuradio/block_detail.h>
#include <gnuradio/buffer_reader.h>
#include <gnuradio/nrsar/tags.h>
#include <gnuradio/tags.h>
#include <pmt/pmt.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

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

//! Tags of image lines by offset; on one line the aperture tag first (it closes the
//! previous image before the axis tags of the new one apply).
inline void sort_aperture_first(std::vector<gr::tag_t>& tags)
{
    std::stable_sort(tags.begin(), tags.end(), [](const gr::tag_t& a, const gr::tag_t& b) {
        if (a.offset != b.offset)
            return a.offset < b.offset;
        return pmt::eq(a.key, tags::aperture_key()) && !pmt::eq(b.key, tags::aperture_key());
    });
}

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_FOCUSER_STREAM_H */
