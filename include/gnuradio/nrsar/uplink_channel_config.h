/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_UPLINK_CHANNEL_CONFIG_H
#define INCLUDED_NRSAR_UPLINK_CHANNEL_CONFIG_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {

/*!
 * \brief The UAV -> base station channel of the ISAC backhaul (uplink_channel,
 * kernel::uplink_channel): timing offset, multipath taps, carrier frequency offset and
 * AWGN. Plain values; validate() throws std::invalid_argument naming the field, its value
 * and the limit.
 */
struct NRSAR_API uplink_channel_config {
    //! Zero samples before the burst (the timing offset the base station must find).
    std::uint64_t delay_samples = 0;
    //! Multipath taps h[l] at the sample rate, lag l = index (1 .. 256 taps, finite).
    std::vector<gr_complex> taps{ gr_complex(1.0f, 0.0f) };
    //! Carrier frequency offset [cycles per sample], |cfo| < 0.5.
    double cfo = 0.0;
    //! Noise standard deviation per complex sample (E|n|^2 = noise_voltage^2), >= 0.
    double noise_voltage = 0.0;
    //! Seed of the noise.
    std::uint64_t seed = 0;

    void validate() const;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_UPLINK_CHANNEL_CONFIG_H */
