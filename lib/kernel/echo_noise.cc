/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/echo_noise.h>
#include <cmath>

namespace gr {
namespace nrsar {
namespace kernel {

echo_noise::echo_noise(std::uint64_t seed) : d_gen(seed), d_snr_db(INFINITY) {}

void echo_noise::set_snr_db(double snr_db)
{
    check_snr_db(snr_db);
    d_snr_db = snr_db;
    update();
}

void echo_noise::set_signal_power(double signal_power)
{
    if (!(signal_power >= 0.0 && std::isfinite(signal_power)))
        throw_param("signal power (sum of RCS)", signal_power, "must be finite and >= 0");
    d_power = signal_power;
    update();
}

void echo_noise::update()
{
    // SNR per RE = signal power / sigma^2 (SPEC section 2).
    d_variance = std::isinf(d_snr_db) ? 0.0 : d_power / std::pow(10.0, d_snr_db / 10.0);
    d_sigma = static_cast<float>(std::sqrt(d_variance));
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
