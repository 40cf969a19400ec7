/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_TF_FILTER_IMPL_H
#define INCLUDED_NRSAR_TF_FILTER_IMPL_H

#include <gnuradio/nrsar/tf_filter.h>

namespace gr {
namespace nrsar {

class tf_filter_impl : public tf_filter
{
private:
    // Nothing to declare in this block.

public:
    tf_filter_impl();
    ~tf_filter_impl();

    // Where all the action really happens
    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items);
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TF_FILTER_IMPL_H */
