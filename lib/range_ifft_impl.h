/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_RANGE_IFFT_IMPL_H
#define INCLUDED_NRSAR_RANGE_IFFT_IMPL_H

#include <gnuradio/nrsar/range_ifft.h>

namespace gr {
namespace nrsar {

class range_ifft_impl : public range_ifft
{
private:
    // Nothing to declare in this block.

public:
    range_ifft_impl();
    ~range_ifft_impl();

    // Where all the action really happens
    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items);
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_RANGE_IFFT_IMPL_H */
