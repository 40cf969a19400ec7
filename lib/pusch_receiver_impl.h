/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_PUSCH_RECEIVER_IMPL_H
#define INCLUDED_NRSAR_PUSCH_RECEIVER_IMPL_H

#include <gnuradio/nrsar/pusch_receiver.h>

namespace gr {
namespace nrsar {

class pusch_receiver_impl : public pusch_receiver
{
private:
    // Nothing to declare in this block.

public:
    pusch_receiver_impl();
    ~pusch_receiver_impl();

    // Where all the action really happens
    void forecast(int noutput_items, gr_vector_int& ninput_items_required);

    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items);
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PUSCH_RECEIVER_IMPL_H */
