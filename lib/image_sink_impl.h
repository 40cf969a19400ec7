/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_IMAGE_SINK_IMPL_H
#define INCLUDED_NRSAR_IMAGE_SINK_IMPL_H

#include <gnuradio/nrsar/image_sink.h>

namespace gr {
namespace nrsar {

class image_sink_impl : public image_sink
{
private:
    // Nothing to declare in this block.

public:
    image_sink_impl();
    ~image_sink_impl();

    // Where all the action really happens
    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items);
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_IMAGE_SINK_IMPL_H */
