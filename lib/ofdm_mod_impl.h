/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_OFDM_MOD_IMPL_H
#define INCLUDED_NRSAR_OFDM_MOD_IMPL_H

#include <gnuradio/nrsar/ofdm_mod.h>

namespace gr {
namespace nrsar {

class ofdm_mod_impl : public ofdm_mod
{
private:
    // Nothing to declare in this block.

public:
    ofdm_mod_impl();
    ~ofdm_mod_impl();

    // Where all the action really happens
    void forecast(int noutput_items, gr_vector_int& ninput_items_required);

    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items);
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_MOD_IMPL_H */
