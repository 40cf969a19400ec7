/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "image_sink_impl.h"
#include <gnuradio/io_signature.h>

namespace gr {
namespace nrsar {

#pragma message("set the following appropriately and remove this warning")
using input_type = float;
image_sink::sptr image_sink::make()
{
    return gnuradio::make_block_sptr<image_sink_impl>();
}


/*
 * The private constructor
 */
image_sink_impl::image_sink_impl()
    : gr::sync_block("image_sink",
                     gr::io_signature::make(
                         1 /* min inputs */, 1 /* max inputs */, sizeof(input_type)),
                     gr::io_signature::make(0, 0, 0))
{
}

/*
 * Our virtual destructor.
 */
image_sink_impl::~image_sink_impl() {}

int image_sink_impl::work(int noutput_items,
                          gr_vector_const_void_star& input_items,
                          gr_vector_void_star& output_items)
{
    auto in = static_cast<const input_type*>(input_items[0]);

#pragma message("Implement the signal processing in your block and remove this warning")
    // Do <+signal processing+>

    // Tell runtime system how many output items we produced.
    return noutput_items;
}

} /* namespace nrsar */
} /* namespace gr */
