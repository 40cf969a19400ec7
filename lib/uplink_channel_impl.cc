/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "uplink_channel_impl.h"
#include <gnuradio/io_signature.h>
#include <algorithm>

namespace gr {
namespace nrsar {

uplink_channel::sptr uplink_channel::make(const uplink_channel_config& cfg)
{
    cfg.validate();
    return gnuradio::make_block_sptr<uplink_channel_impl>(cfg);
}

uplink_channel_impl::uplink_channel_impl(const uplink_channel_config& cfg)
    : gr::block("uplink_channel",
                gr::io_signature::make(1, 1, sizeof(gr_complex)),
                gr::io_signature::make(1, 1, sizeof(gr_complex))),
      d_kernel(cfg),
      d_delay(cfg.delay_samples)
{
    // the scheduler moves tags by the relative rate (1): the delay is added by hand
    set_tag_propagation_policy(TPP_DONT);
}

void uplink_channel_impl::forecast(int noutput_items, gr_vector_int& ninput_items_required)
{
    const std::uint64_t n = d_kernel.samples();
    const std::uint64_t zeros = n < d_delay ? d_delay - n : 0;
    ninput_items_required[0] =
        static_cast<int>(std::max<std::int64_t>(0, noutput_items - std::int64_t(zeros)));
}

int uplink_channel_impl::general_work(int noutput_items,
                                      gr_vector_int& ninput_items,
                                      gr_vector_const_void_star& input_items,
                                      gr_vector_void_star& output_items)
{
    const auto in = static_cast<const gr_complex*>(input_items[0]);
    auto out = static_cast<gr_complex*>(output_items[0]);
    auto want = static_cast<std::uint64_t>(noutput_items);
    const std::uint64_t n = d_kernel.samples();
    std::uint64_t done = 0;
    if (n < d_delay) { // the zeros before the burst
        done = std::min(want, d_delay - n);
        d_kernel.process(nullptr, out, done);
    }
    const std::uint64_t m = std::min<std::uint64_t>(want - done, ninput_items[0]);
    std::vector<gr::tag_t> tags;
    get_tags_in_range(tags, 0, nitems_read(0), nitems_read(0) + m);
    for (auto t : tags) {
        t.offset += d_delay;
        add_item_tag(0, t);
    }
    d_kernel.process(in, out + done, m);
    consume_each(static_cast<int>(m));
    return static_cast<int>(done + m);
}

} // namespace nrsar
} // namespace gr
