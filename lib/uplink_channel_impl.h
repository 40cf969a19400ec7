/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_UPLINK_CHANNEL_IMPL_H
#define INCLUDED_NRSAR_UPLINK_CHANNEL_IMPL_H

#include <gnuradio/nrsar/kernel/uplink_channel.h>
#include <gnuradio/nrsar/uplink_channel.h>

namespace gr {
namespace nrsar {

class uplink_channel_impl : public uplink_channel
{
private:
    kernel::uplink_channel d_kernel;
    std::uint64_t d_delay;

public:
    explicit uplink_channel_impl(const uplink_channel_config& cfg);

    std::uint64_t samples() const override { return d_kernel.samples(); }

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_UPLINK_CHANNEL_IMPL_H */
