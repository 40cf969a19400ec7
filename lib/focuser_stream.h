/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// What rd_focuser and bp_focuser share of the stream: the end of the input (they hold
// their last item back until the upstream is done, so that the scheduler calls them once
// more to flush), the range axis they start from, the axis tags they follow and the input
// loop of their general_work.

#ifndef INCLUDED_NRSAR_FOCUSER_STREAM_H
#define INCLUDED_NRSAR_FOCUSER_STREAM_H

#include "param_check.h"
#include <gnuradio/block_detail.h>
#include <gnuradio/buffer_reader.h>
#include <gnuradio/logger.h>
#include <gnuradio/nrsar/kernel/aperture_focuser.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/tags.h>
#include <gnuradio/gr_complex.h>
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

/*!
 * forecast()'s input items of a block that holds its last input item back until the upstream
 * is done, so that the scheduler calls it once more at the end of the stream to flush (the
 * focusers, autofocus): 2, or 1 once the upstream is done.
 */
inline int items_until_flush(const gr::block_detail_sptr& detail)
{
    return detail && detail->input(0)->done() ? 1 : 2;
}

//! The range bin before the first range_axis tag: range_bin_m, or the numerology's bin for 0.
inline double default_range_bin(const numerology& num, double range_bin_m)
{
    num.validate();
    if (range_bin_m == 0.0)
        return num.range_bin_m(num.fft_size);
    check_finite_positive("range_bin_m", range_bin_m);
    return range_bin_m;
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

//! The line count of an azimuth_axis tag (first [m], spacing [m], lines): false when the
//! value is not such a tuple (the count's range is the caller's rule).
inline bool parse_azimuth_lines(const pmt::pmt_t& v, uint64_t& lines)
{
    if (!(pmt::is_tuple(v) && pmt::length(v) >= 3))
        return false;
    const pmt::pmt_t m = pmt::tuple_ref(v, 2);
    if (!(pmt::is_integer(m) || pmt::is_uint64(m)))
        return false;
    lines = pmt::to_uint64(m);
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

/*!
 * \brief The input loop of both focusers' general_work: deliver what is queued; while the
 * output has room and nothing is queued, apply the axis tags at the next line, ingest up to
 * the next tag, the end of the input or a full aperture, and focus a full one; at the end
 * of the stream (upstream_done) focus what flush_due() says is left, then set flush_done.
 * tags: the input tags from lines_in() on, in offset order. S, the block's side:
 *   uint64_t lines_in() const: absolute index of the next input line to ingest;
 *   void handle_tag(const gr::tag_t&); unsigned room(): lines before the aperture is full;
 *   void ingest(const gr_complex* lines, unsigned n); bool block_full() const;
 *   bool flush_due() const; void focus(); bool queues_empty() const;
 *   bool wants_input() const: output room and queues empty; void drain(): queues to output.
 * Returns the items to consume: what was ingested, the last one held back until the stream
 * has ended and everything is delivered (so that the scheduler calls once more to flush).
 */
template <typename S>
int focuser_stream_loop(S& s,
                        const std::vector<gr::tag_t>& tags,
                        const gr_complex* in,
                        unsigned K,
                        uint64_t nread,
                        int navail,
                        bool upstream_done,
                        bool& flush_done)
{
    s.drain();
    size_t next_tag = 0;
    while (s.wants_input()) {
        const uint64_t next = s.lines_in(); // absolute index of the next line to ingest
        const int i = static_cast<int>(next - nread);
        if (i < navail) {
            while (next_tag < tags.size() && tags[next_tag].offset <= next)
                s.handle_tag(tags[next_tag++]);
            uint64_t end = nread + navail;
            if (next_tag < tags.size())
                end = std::min<uint64_t>(end, tags[next_tag].offset);
            const unsigned n = static_cast<unsigned>(std::min<uint64_t>(end - next, s.room()));
            s.ingest(in + static_cast<size_t>(i) * K, n);
            if (s.block_full())
                s.focus();
        } else if (upstream_done && !flush_done) {
            if (s.flush_due())
                s.focus();
            else
                flush_done = true;
        } else {
            break;
        }
        s.drain();
    }
    int consume = static_cast<int>(s.lines_in() - nread);
    if (!(upstream_done && flush_done && s.queues_empty()))
        consume = std::min(consume, navail - 1);
    return std::max(consume, 0);
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
