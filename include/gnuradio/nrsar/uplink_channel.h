/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_UPLINK_CHANNEL_H
#define INCLUDED_NRSAR_UPLINK_CHANNEL_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/uplink_channel_config.h>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * \brief The UAV -> base station channel of nrsar-isac in one block: timing offset,
 * multipath, carrier frequency offset, AWGN (in that order, as gr-channels'
 * channel_model), one pass over the samples.
 * \ingroup nrsar
 *
 *     y[n] = e^{j 2 pi cfo n} sum_l taps[l] x[n - delay_samples - l] + noise_voltage z[n]
 *
 * z ~ CN(0, 1) (kernel::gaussian_noise, counter-based: z[n] depends on (seed, n) only),
 * x[i] = 0 before the stream. The output is a function of the input stream, however the
 * scheduler cuts it (kernel::uplink_channel). The first delay_samples outputs are noise
 * only, then every input sample follows (delay_samples + N outputs for N inputs). Tags
 * propagate with the delay added.
 */
class NRSAR_API uplink_channel : virtual public gr::block
{
public:
    typedef std::shared_ptr<uplink_channel> sptr;

    //! cfg: uplink_channel_config (validated).
    static sptr make(const uplink_channel_config& cfg);

    //! Output samples so far.
    virtual std::uint64_t samples() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_UPLINK_CHANNEL_H */
