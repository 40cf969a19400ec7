/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_BP_AUTOFOCUS_H
#define INCLUDED_NRSAR_KERNEL_BP_AUTOFOCUS_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/bp_focuser.h>
#include <array>
#include <limits>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

//! Options of trajectory_autofocus(); validate() throws std::invalid_argument naming the
//! field, its value and the limit.
struct NRSAR_API trajectory_autofocus_config {
    unsigned max_iterations = 4; //!< back-projections that estimate (1..50)
    unsigned points = 8;         //!< prominent points used (1..64)
    double points_db = 20.0;     //!< points within this many dB of the brightest (0, 60]
    //! Pulses of the complex moving sum that smooths each point's phase history (1..n):
    //! the navigation error must be slow over it.
    unsigned smooth_pulses = 16;
    //! Solve both cross-track and vertical displacement per pulse when the points' weighted
    //! rms look-angle spread reaches this [rad]; below it only the displacement along their
    //! mean line of sight (the perpendicular one would be noise amplified 1 / spread).
    double look_spread_rad = 0.05;
    //! Stop when the rms of one iteration's correction falls below this [m].
    double tolerance_m = 1e-4;
    //! Keep the path's correction only when its rms exceeds this many times its standard
    //! error (from the phase histories' noise); else return the navigation and its image
    //! (0: always keep). Under noise alone the ratio is about 1.
    double significance = 2.0;
    //! Width of the pulses' range spectrum around grid.range_centre_cycles [cycles/bin],
    //! [0, 1]: the phase histories and the GCPs' range peaks are read from the pulses tapered
    //! by a Hann window over it (the other targets' unwindowed range sidelobes would beat in
    //! them); the image stays untapered. NaN: a range IFFT of subcarriers 0..N-1 (eq. 29),
    //! 2 |range_centre_cycles| + 1 / K (N / fft_size when K is the FFT size), refused below
    //! 0.25 (a spectrum centred near 0 is not one: set the band); 0: no taper.
    double range_band_cycles = std::numeric_limits<double>::quiet_NaN();
    //! Ground control points: surveyed positions (x, y, z) in the scene frame [m], at most
    //! max_gcp. Those inside the image fix the navigation error's constant and linear trend
    //! over the pulses (which focus cannot see) from their phase histories (the constant's
    //! ambiguity of about lambda / 2 from their range peak); empty: none, the trend stays.
    std::vector<std::array<double, 3>> gcp;
    static constexpr unsigned max_gcp = 16;
    //! The GCPs also solve the along-track offset e_y (its u_y e_y in each constant) when its
    //! predicted standard error, from their spread along track and phase noise, is below this
    //! [m], [0, 1] (0: never); else e_y stays in the drift (docs/blocks/bp_focuser.md, "The
    //! along-track offset"). 5 cm: under half a GNSS class's e_y (0.2-0.35 m); two GCPs
    //! 25 m apart along track at 10 dB give 4 mm.
    double gcp_along_track_se_m = 0.05;
    //! The GCPs also solve the along-track speed error d_y (its u_y d_y in each slope), with
    //! e_y only, when n times its predicted standard error per pulse (the along-track
    //! stretch it would leave from the first pulse to the last) is below this [m], [0, 1]
    //! (0: never); else d_y stays (docs/blocks/bp_focuser.md, "The along-track speed").
    //! 2 cm: a GNSS class's 0.1 m/s stretches a 1 s aperture by 10 cm; n se is about
    //! sqrt(12) e_y's se (the GCPs that solve e_y to 3.2 mm give 11 mm).
    double gcp_speed_se_m = 0.02;

    void validate() const;
};

struct NRSAR_API trajectory_autofocus_result {
    //! The corrected antenna path, one position per pulse [m].
    std::vector<std::array<double, 3>> antenna;
    //! Estimated navigation error a_nav - a_true per pulse (x, 0, z) [m], less its
    //! least-squares constant and linear trend over the pulses (they only move the image:
    //! a phase and a Doppler shift, not observable by focus).
    std::vector<std::array<double, 3>> displacement_m;
    //! The displacement projected on the points' mean line of sight (x-z plane) [m].
    std::vector<double> los_m;
    std::vector<std::array<unsigned, 2>> points; //!< (line, bin) of the points used last
    double look_spread_rad = 0.0;                //!< of the last iteration's points
    bool two_dimensional = false;                //!< both components solved (last iteration)
    double last_update_rms_m = 0.0;
    unsigned iterations = 0;
    //! Standard error of the correction, rms over the pulses of (x, z) [m]: what the
    //! phase histories' noise alone makes it (last iteration's points).
    double standard_error_m = 0.0;
    //! The correction was kept (its rms above significance x standard_error_m); false:
    //! antenna, image and displacement are the navigation's (displacement 0).
    bool accepted = false;
    //! cfg.gcp: the GCPs in the image whose history was used (0: no calibration).
    unsigned gcp_used = 0;
    //! The navigation error's constant (x, y, z) at the middle pulse [m] and drift per
    //! pulse (x, y, z) [m] the GCPs gave, taken off antenna ((x, z) along their mean line
    //! of sight unless gcp_two_dimensional; the offset's y 0 unless gcp_along_track, the
    //! drift's unless gcp_along_track_speed); zero without.
    std::array<double, 3> gcp_offset_m{};
    std::array<double, 3> gcp_drift_m{};
    bool gcp_two_dimensional = false; //!< GCPs at spread look angles: x and z solved
    double gcp_offset_se_m = 0.0;     //!< standard error of gcp_offset_m (rms of x, z)
    double gcp_drift_se_m = 0.0;      //!< of gcp_drift_m [m / pulse]
    //! GCPs spread along track: the constant's y (e_y) solved (cfg.gcp_along_track_se_m).
    bool gcp_along_track = false;
    double gcp_offset_y_se_m = 0.0; //!< standard error of gcp_offset_m's y (0: not solved)
    //! GCPs spread along track: the drift's y (d_y) solved (cfg.gcp_speed_se_m).
    bool gcp_along_track_speed = false;
    double gcp_drift_y_se_m = 0.0; //!< of gcp_drift_m's y [m / pulse] (0: not solved)
};

/*!
 * \brief Autofocus by trajectory estimation: back-projects the pulses along `antenna`,
 * takes the image's prominent points, estimates per pulse the antenna displacement that
 * their phase histories see, corrects the path and back-projects again (docs/blocks/
 * bp_focuser.md, "Autofocus along the path").
 *
 * A point at p seen from a_n contributes to its pixel c(n) = A exp(j 2 pi cs (R_nav -
 * R_true)) (the BP summand; cs = 2 / lambda + fc_r / rho, the carrier and the range
 * spectrum's centre), R_nav - R_true = u_n . (a_nav - a_true), u_n the unit vector from p
 * to the antenna. The phase of the smoothed c (complex moving sum of smooth_pulses,
 * unwrapped over the pulses, its mean removed) gives per pulse and point one equation
 * psi_i(n) / (2 pi cs) = u_i(n) . d(n) in d = (d_x, d_z); least squares over the
 * points (weights: the inverse variance of their smoothed phase, sigma_i^2 / (2 L A_i^2)
 * with sigma_i^2 from each history's deviation from its moving mean), both components when
 * the look angles spread (config look_spread_rad), else along their mean line of sight.
 * The solution's constant and linear trend over the pulses are removed (they only move
 * the image). Each iteration smooths the histories with the correction so far added back
 * (the whole error, not the residual), so the estimate stays smoothed. Points whose
 * smoothed SNR is below 2 are not used. Correcting the path (not a phase) fixes every
 * pixel's phase and range: the error a position error makes is space-variant. A
 * correction no larger than cfg.significance times its standard error is noise: the
 * navigation is kept. Ground control points (cfg.gcp) then fix the trend: each one's
 * history along the corrected path, referenced to its surveyed position, is R_nav -
 * R_true itself; its constant (the integer of ~lambda / 2 from its range peak) and slope over
 * the pulses, solved for x and z (look angles spread) or along their line of sight, and
 * the along-track offset and speed error where the GCPs' spread along track determines
 * them, are taken off the path before the last back-projection.
 * pulses: n x K line-major; image_out: M x K, the image along the corrected path.
 */
NRSAR_API trajectory_autofocus_result
trajectory_autofocus(const gr_complex* pulses,
                     unsigned n,
                     const std::array<double, 3>* antenna,
                     const bp_grid& grid,
                     const trajectory_autofocus_config& cfg,
                     gr_complex* image_out,
                     unsigned num_threads = 1);

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_BP_AUTOFOCUS_H */
