/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_AUTOFOCUS_CONFIG_H
#define INCLUDED_NRSAR_AUTOFOCUS_CONFIG_H

#include <gnuradio/nrsar/api.h>

namespace gr {
namespace nrsar {

//! How the azimuth phase error is estimated (docs/blocks/autofocus.md).
enum class autofocus_method {
    NONE,    //!< pass the image through, estimate nothing
    PGA,     //!< phase gradient autofocus (Wahl, Eichel, Ghiglia, Jakowatz 1994)
    ENTROPY, //!< minimum image entropy (the second paper's [33])
};

/*!
 * \brief Options of the autofocus block and kernel::autofocus. Plain values; validate()
 * throws std::invalid_argument naming the field, its value and the limit.
 */
struct NRSAR_API autofocus_config {
    autofocus_method method = autofocus_method::PGA;
    //! Lines per image M when no azimuth_axis tag says it (0: the tag must say it).
    unsigned lines_per_aperture = 0;
    //! Most iterations (1..1000).
    unsigned max_iterations = 30;
    //! Stop when the energy-weighted rms of one iteration's phase update is below this [rad].
    double tolerance_rad = 1e-3;
    //! PGA: range bins whose peak power lies within this many dB of the strongest bin's.
    double pga_bins_db = 20.0;
    //! PGA: the window spans twice the width over which the centred, averaged intensity
    //! profile stays within this many dB of its peak.
    double pga_window_db = 10.0;
    //! PGA: narrowest window [lines] (>= 2).
    unsigned pga_min_window = 8;
    //! Minimum entropy: 0 = one phase per azimuth frequency bin, 2..16 = a polynomial of
    //! this order in the normalised frequency (the constant and linear terms excluded).
    unsigned entropy_order = 0;
    //! The targets' band: Doppler bins whose energy (a moving sum over a sixteenth of the
    //! band's equivalent width) lies within this many dB of the strongest stretch. Outside it the phase is held (noise
    //! alone would otherwise be phased into the targets, or its random gradient integrated),
    //! and the fits and the rms count only the band.
    double support_db = 10.0;
    //! PGA: carrier wavelength [m] with which the image was focused on a slant-range grid;
    //! > 0 deramps each range bin's windowed target by the focuser's azimuth chirp
    //! exp(j 4 pi sqrt(r^2 + y^2) / lambda) before its spectrum, so that a Doppler bin is
    //! a set of pulses and a focused image a fixed point (needs the image axes). 0: off.
    double wavelength_m = 0.0;

    void validate() const;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_AUTOFOCUS_CONFIG_H */
