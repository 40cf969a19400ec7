/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_TD_ECHO_IMPL_H
#define INCLUDED_NRSAR_TD_ECHO_IMPL_H

#include <gnuradio/nrsar/td_echo.h>

namespace gr {
namespace nrsar {

class td_echo_impl : public td_echo
{
private:
    // Nothing to declare in this block.

public:
    td_echo_impl();
    ~td_echo_impl();

    // Where all the action really happens
    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items);
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TD_ECHO_IMPL_H */
