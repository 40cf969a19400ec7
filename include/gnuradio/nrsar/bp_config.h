/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_BP_CONFIG_H
#define INCLUDED_NRSAR_BP_CONFIG_H

#include <gnuradio/nrsar/api.h>
#include <limits>

namespace gr {
namespace nrsar {

/*!
 * \brief Processing options of the back-projection focuser (bp_focuser block and
 * kernel::bp_focuser). Plain values; validate() throws std::invalid_argument naming the
 * field, its value and the limit.
 */
struct NRSAR_API bp_config {
    //! Slow-time spacing of the input pulses in OFDM symbols (as focuser_config's); a
    //! pulse_interval tag overrides it.
    unsigned symbols_per_pulse = 1;
    //! Output lines (and input pulses) per aperture M; 0: round(geo.aperture_s / T).
    unsigned lines_per_aperture = 0;
    //! Range profile upsampling factor U (1..64) before linear interpolation: the
    //! interpolation error power falls as U^-4 (docs/blocks/bp_focuser.md).
    unsigned upsample = 8;
    //! Margin of the scene Doppler band that places the image window [Hz], as
    //! focuser_config::band_margin_hz (< 0: automatic), so that bp_focuser's image lines are
    //! rd_focuser's.
    double band_margin_hz = -1.0;
    //! Centre of the range spectrum [cycles per range bin], as
    //! focuser_config::range_centre_cycles (NaN: (N - 1) Delta f rho / c).
    double range_centre_cycles = std::numeric_limits<double>::quiet_NaN();
    //! Worker threads of the back-projection (1 or 2: the image lines are split).
    unsigned num_threads = 1;

    void validate() const;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_BP_CONFIG_H */
