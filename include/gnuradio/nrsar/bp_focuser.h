/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_BP_FOCUSER_H
#define INCLUDED_NRSAR_BP_FOCUSER_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/bp_config.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/trajectory.h>
#include <array>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * \brief Time-domain back-projection of range-compressed pulses along the navigation path
 * (the second paper's imager, section 3) onto rd_focuser's image grid.
 * \ingroup nrsar
 *
 * Input: one vector of K range bins per pulse (range_ifft or cheby_presum output), pulse
 * interval T = num.symbol_s() * cfg.symbols_per_pulse, overridden by a
 * tags::pulse_interval_key() tag; the range axis from a tags::range_axis_key() tag when
 * present (as rd_focuser; a change applies from the next aperture). Pulse n flies at
 * t_n = n T (the sum of the intervals), the antenna phase centre at nav.position(t_n).
 *
 * Output: the image, one vector of K range bins per azimuth line, M = cfg.lines_per_aperture
 * (0: round(aperture_s / T)) lines per aperture, built from the aperture's own M pulses
 * (kernel::bp_focuser: exact distance per pixel and pulse, linear interpolation of the
 * profile upsampled cfg.upsample times, carrier and range-centre phase, coherent sum,
 * 1 / sqrt(M)). Grid: rd_focuser's (same range bins; line j of aperture i at along-track
 * y0 + (i M + j) v T, y0 = geo.track_start_m + s v T with rd_focuser's shift s), so images
 * compare pixel for pixel; pixel (r0, y) is the scatterer (sqrt(r0^2 - H^2), y, 0). With
 * cfg.line_step L > 1: lines j = 0, L, 2 L, ... of that grid only (M / L lines per aperture,
 * L v T apart, each bit for bit the L = 1 image's line; exact BP's work falls by L). With
 * cfg.grid GROUND: column k is the point (x0 + k dx, y, cfg.ground_height_m) instead. With
 * cfg.ffbp_subaperture > 1: fast factorized back-projection (kernel::bp_focuser; recursive
 * with cfg.ffbp_levels > 1). The first
 * line of every aperture carries tags::aperture_key(), tags::azimuth_axis_key() and
 * tags::range_axis_key() (ground grid: tags::ground_range_axis_key(), (x0, dx, K)). When the input ends, the partial aperture is imaged from the
 * pulses received. Non-finite input samples are zeroed, counted, logged once per aperture
 * and reported with a tags::nonfinite_key() tag.
 */
class NRSAR_API bp_focuser : virtual public gr::block
{
public:
    typedef std::shared_ptr<bp_focuser> sptr;

    /*!
     * \param num OFDM numerology (pulse interval, range spectrum centre)
     * \param geo platform geometry (carrier, v, H, track start, aperture)
     * \param scn the scene: its Doppler band places the image window as in rd_focuser
     * \param num_range_bins K, the vector length of input and output
     * \param first_range_m slant range of bin 0 [m] when no range_axis tag arrives
     * \param range_bin_m slant-range spacing [m]; 0: c / (2 num.fft_size Delta f)
     * \param cfg processing options (bp_config)
     * \param nav the navigation path the pulses are projected from; empty (the default):
     *        the ideal line of geo
     */
    static sptr make(const numerology& num,
                     const geometry& geo,
                     const scene& scn,
                     unsigned num_range_bins,
                     double first_range_m,
                     double range_bin_m = 0.0,
                     const bp_config& cfg = bp_config(),
                     const trajectory& nav = trajectory());

    virtual bp_config config() const = 0;
    //! M: pulses per aperture (the image lines with cfg.line_step 1).
    virtual unsigned lines_per_aperture() const = 0;
    //! Output lines per aperture: M / cfg.line_step.
    virtual unsigned image_lines_per_aperture() const = 0;
    //! The ground grid's column axis: x of column 0 and the spacing [m] (0, 0 on the slant
    //! grid).
    virtual double ground_first_x_m() const = 0;
    virtual double ground_spacing_m() const = 0;
    //! Offset s of the image window from the aperture's pulses [lines] (rd_focuser's).
    virtual long long line_shift() const = 0;
    virtual double pulse_interval_s() const = 0;
    virtual double first_range_m() const = 0;
    virtual double range_bin_m() const = 0;
    //! Bins per output line: num_range_bins (no guard bins; rd_focuser's interface).
    virtual unsigned num_output_bins() const = 0;
    //! The scene's Doppler band with margin that places the image window [Hz] (rd_focuser's
    //! SCENE band; back-projection itself sums every pulse of the aperture).
    virtual double band_lo_hz() const = 0;
    virtual double band_hi_hz() const = 0;
    //! Whether the AVX2/FMA inner loop runs.
    virtual bool simd() const = 0;
    //! Apertures emitted so far.
    virtual std::uint64_t apertures() const = 0;
    virtual std::uint64_t nonfinite_count() const = 0;
    //! The flight's line of the first input line this block expects (cfg.first_aperture M).
    virtual std::uint64_t stream_first_line() const = 0;
    //! cfg.trajectory_autofocus: rms over the pulses of the latest aperture's estimated
    //! navigation error along the points' mean line of sight [m] (NaN before, or without);
    //! 0 where the correction was not kept (not above significance standard errors).
    virtual double trajectory_los_rms_m() const = 0;
    //! cfg.trajectory_autofocus: the standard error of the latest aperture's correction,
    //! rms over the pulses, from its phase histories' noise [m] (NaN before, or without).
    virtual double trajectory_se_m() const = 0;
    //! cfg.autofocus_gcp: the ground control points the latest aperture used (0: none in
    //! its image with a usable history; then the three below are NaN).
    virtual unsigned trajectory_gcp_used() const = 0;
    //! Its navigation error's constant (x, y, z) at the aperture's middle pulse [m], and
    //! drift (x, y, z) [m/s], from the GCPs (the offset's y, e_y, and the drift's, the
    //! along-track speed error d_y: 0 unless GCPs spread along track solved them).
    virtual std::array<double, 3> trajectory_gcp_offset_m() const = 0;
    virtual std::array<double, 3> trajectory_gcp_drift_mps() const = 0;
    //! Their standard errors from the GCPs' phase noise, rms of x and z: offset [m], drift
    //! [m/s]; then the offset's y [m] and the drift's y [m/s] (NaN where not solved).
    virtual std::array<double, 4> trajectory_gcp_se() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_BP_FOCUSER_H */
