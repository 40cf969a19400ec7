/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_BP_CONFIG_H
#define INCLUDED_NRSAR_BP_CONFIG_H

#include <gnuradio/nrsar/api.h>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace gr {
namespace nrsar {

//! The image grid of bp_focuser.
enum class image_grid {
    SLANT, //!< closest-approach slant range x along track: rd_focuser's grid
    GROUND //!< ground (x, y) at ground_height_m
};

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
    //! Along-track pixel spacing: an image line every line_step-th pulse position (1..4096,
    //! dividing M; 1: one per pulse, rd_focuser's grid). M / line_step lines per aperture,
    //! line_step v T apart, each the line_step = 1 image's line bit for bit; the work of
    //! exact BP falls by line_step. Not with trajectory_autofocus.
    unsigned line_step = 1;
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
    //! Range interpolation: 0 = upsampled by U, linear; an even 2..32 = a Kaiser-windowed
    //! sinc of that many taps on the input bins (exact BP only; docs: the trade-off).
    unsigned sinc_taps = 0;
    //! Worker threads of the back-projection (1 or 2: the image lines are split).
    unsigned num_threads = 1;
    //! The image grid; GROUND: column k at x = ground_first_x_m + k ground_spacing_m.
    image_grid grid = image_grid::SLANT;
    //! Height of the ground grid's plane [m] (finite, below the platform).
    double ground_height_m = 0.0;
    //! Cross-track x of the ground grid's column 0 [m]; NaN: the ground range of the first
    //! range bin at that height.
    double ground_first_x_m = std::numeric_limits<double>::quiet_NaN();
    //! Column spacing of the ground grid [m]; 0: the range bin projected to the ground at
    //! mid range, rho r / x.
    double ground_spacing_m = 0.0;
    //! Fast factorized back-projection: pulses per subaperture (0 or 1: exact BP). The
    //! speed-up approaches it while the beams stay fewer than the lines.
    unsigned ffbp_subaperture = 0;
    //! FFBP's beams per Nyquist beam of a subaperture (1..64): its error power falls as
    //! beam_oversample^-4 (pi^4 / (600 os^4), docs/blocks/bp_focuser.md).
    double ffbp_beam_oversample = 8.0;
    //! Recursive FFBP: polar levels (1..8; 1: two-level, the subimages onto the image; n > 1:
    //! merged ffbp_merge_factor at a time into larger subapertures' subimages n - 1 times,
    //! each level one more interpolation's error; needs ffbp_subaperture > 1).
    unsigned ffbp_levels = 1;
    //! Subimages per merged subimage of recursive FFBP (2..16; with ffbp_levels > 1).
    unsigned ffbp_merge_factor = 4;
    //! A strip cut into tasks (as focuser_config::first_aperture): the first aperture to
    //! emit; its input stream starts at the flight's line first_aperture M.
    std::uint64_t first_aperture = 0;
    //! Apertures to emit, then the block is done (0: until the stream ends).
    std::uint64_t apertures = 0;
    //! Autofocus by trajectory estimation per aperture (kernel::trajectory_autofocus with
    //! the four options below): the navigation corrected along the prominent points' lines
    //! of sight, the aperture back-projected again (docs/blocks/bp_focuser.md).
    bool trajectory_autofocus = false;
    //! Its back-projections that estimate (1..50; kernel max_iterations).
    unsigned autofocus_iterations = 4;
    //! Its prominent points (1..64; kernel points).
    unsigned autofocus_points = 8;
    //! It stops when an iteration's correction is below this rms [m] (0..1, exclusive).
    double autofocus_tolerance_m = 1e-4;
    //! It keeps a correction only above this many standard errors ([0, 100]; 0: always).
    double autofocus_significance = 2.0;
    //! Its ground control points: surveyed (x, y, z) [m] in the scene frame (at most 16, each
    //! used by the aperture whose image holds it): they fix the navigation error's constant
    //! and drift (kernel gcp); empty: none.
    std::vector<std::array<double, 3>> autofocus_gcp;
    //! The GCPs solve the along-track offset e_y where its predicted standard error is below
    //! this [m] ([0, 1]; 0: never; kernel gcp_along_track_se_m).
    double autofocus_gcp_along_track_se_m = 0.05;
    //! With e_y they solve the along-track speed error d_y where its predicted standard
    //! error is below this [m/s] ([0, 1]; 0: never; kernel gcp_speed_se_m, this times the
    //! aperture's duration).
    double autofocus_gcp_speed_se_mps = 0.02;

    void validate() const;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_BP_CONFIG_H */
