/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Where an aperture's image lies along track: the scene's Doppler band with its margin and
// the output window's offset from the aperture's pulses. One computation for rd_focuser and
// bp_focuser, so that their images share the same lines.

#ifndef INCLUDED_NRSAR_AZIMUTH_WINDOW_H
#define INCLUDED_NRSAR_AZIMUTH_WINDOW_H

#include <gnuradio/nrsar/params.h>

namespace gr {
namespace nrsar {

struct azimuth_window {
    double band_lo_hz = 0.0; //!< scene Doppler band with margin
    double band_hi_hz = 0.0;
    //! Azimuth extent of the band's energy [lines]: a target at zero-Doppler line t0 has
    //! energy on the pulses [t0 - e_hi, t0 - e_lo].
    double e_lo = 0.0;
    double e_hi = 0.0;
    //! Offset s of the output window from the aperture's pulses [lines].
    long long line_shift = 0;
};

/*!
 * The window of pulse interval T, range axis (first_range, range_bin, K) and the scene's
 * band with margin band_margin_hz (< 0: 10 % of the band plus two resolution cells
 * 2 / aperture_s). Throws when the extent exceeds 1e9 lines.
 */
azimuth_window scene_azimuth_window(const geometry& geo,
                                    const scene& scn,
                                    double band_margin_hz,
                                    double T,
                                    double first_range,
                                    double range_bin,
                                    unsigned K);

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_AZIMUTH_WINDOW_H */
