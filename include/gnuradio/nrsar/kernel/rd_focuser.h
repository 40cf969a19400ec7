/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_RD_FOCUSER_H
#define INCLUDED_NRSAR_KERNEL_RD_FOCUSER_H

#include <gnuradio/nrsar/kernel/fft_plans.h>
#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/focuser_config.h>
#include <gnuradio/nrsar/kernel/motion_compensation.h>
#include <gnuradio/nrsar/kernel/sinc_interpolator.h>
#include <volk/volk_alloc.hh>
#include <memory>
#include <utility>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

//! What one processing block of the focuser looks like physically.
struct NRSAR_API rd_block {
    unsigned num_range_bins = 0;   //!< K
    unsigned num_lines = 0;        //!< lines per processing block (before FFT padding)
    double pulse_interval_s = 0.0; //!< T
    double velocity_mps = 0.0;     //!< v
    double wavelength_m = 0.0;     //!< lambda
    double first_range_m = 0.0;    //!< slant range of bin 0
    double range_bin_m = 0.0;      //!< rho, slant-range spacing of the bins
    double band_lo_hz = 0.0;       //!< processed Doppler band (SCENE); ignored for FULL
    double band_hi_hz = 0.0;       //!< and ESTIMATE (which uses it as a fallback only)
    //! Centre of the range spectrum [cycles/bin] (see focuser_config::range_centre_cycles).
    double range_centre_cycles = 0.0;
    //! Circular shift of the output [lines]: out line j is image line j + line_shift.
    long long line_shift = 0;

    void validate() const;
};

/*!
 * \brief Range-Doppler focusing of one block of range-compressed pulses, eqs. (31)-(47).
 *
 * in: num_lines x K (line-major: line m holds K range bins); out: num_lines x K focused
 * image, azimuth x range. Per range bin k (slant range R0 = first_range + k rho):
 *  1. azimuth FFT over the block zero-padded to fft_size() lines, eq. (31);
 *  2. on the processed Doppler bins only: RCMC, y(k, f) <- y(k + Delta k(k, f), f), eq. (41),
 *     by windowed-sinc interpolation of the range profile demodulated by its spectrum centre,
 *     with Delta k = R0 (1 / D(f) - 1) / rho, D(f) = sqrt(1 - (lambda f / 2 v)^2) (hyperbolic)
 *     or Delta k = lambda^2 R0 f^2 / (8 v^2 rho) (eq. 40, parabolic);
 *  3. azimuth compression by exp(+j 4 pi R0 (D(f) - 1) / lambda) (hyperbolic) or
 *     exp(-j pi f^2 / Ka(R0)), Ka = 2 v^2 / (lambda R0) (eq. 47), the conjugate of the
 *     target's range-Doppler phase, eq. (39);
 *  4. inverse azimuth FFT, eq. (47); bins outside the band are zero.
 * The Doppler of FFT bin p is the alias of p / (fft_size T) nearest to the band centre,
 * so a band that is not centred at 0 (or wraps across PRF / 2) is handled.
 * Scaling: unitary forward and inverse azimuth DFTs (1 / sqrt(fft_size) each, eqs. 31 and
 * 47), so a unit target with range peak A illuminated over M_t pulses focuses to
 * A sqrt(M_t B_t T), B_t = Ka M_t T its Doppler bandwidth, independent of fft_size.
 */
/*!
 * \brief dst[c * dst_stride + r] = src[r * src_stride + c] for r < rows, c < cols (tiled).
 */
NRSAR_API void transpose(const gr_complex* src,
                         size_t src_stride,
                         gr_complex* dst,
                         size_t dst_stride,
                         unsigned rows,
                         unsigned cols);

class NRSAR_API rd_focuser
{
public:
    rd_focuser(const focuser_config& cfg, const rd_block& blk);
    rd_focuser(const rd_focuser&) = delete;
    rd_focuser& operator=(const rd_focuser&) = delete;
    rd_focuser(rd_focuser&&) = default;
    rd_focuser& operator=(rd_focuser&&) = default;

    //! Focuses one block; in and out hold num_lines() x num_range_bins() samples (may alias).
    void focus(const gr_complex* in, gr_complex* out);
    /*!
     * \brief Focuses one block and writes only output lines [first_line, first_line + count)
     * to out (count x num_range_bins() samples): the valid part of an overlap-save block.
     */
    void focus(const gr_complex* in, gr_complex* out, unsigned first_line, unsigned count);
    /*!
     * \brief The same from range-major input: range bin k holds lines 0..num_lines()-1 at
     * in + k * row_stride (row_stride >= num_lines()). This is the kernel's own layout; a
     * streaming caller that stores its pulses this way saves a full transpose.
     */
    void focus_range_major(const gr_complex* in,
                           size_t row_stride,
                           gr_complex* out,
                           unsigned first_line,
                           unsigned count);
    /*!
     * \brief The same, and also writes the range-Doppler map after RCMC (eq. 41) and before
     * azimuth compression to rd_map: band_bins() lines of num_range_bins() samples, in
     * ascending Doppler (line b at rd_doppler_first_hz() + b fft_size()^-1 / T). Its magnitude
     * is the RCMC'd map; its phase carries the range demodulation of the interpolator
     * (without RCMC: the map after the azimuth FFT as it is). rd_map == nullptr: nothing
     * extra is done.
     */
    void focus_range_major(const gr_complex* in,
                           size_t row_stride,
                           gr_complex* out,
                           unsigned first_line,
                           unsigned count,
                           gr_complex* rd_map);
    //! Doppler of the first line of the rd_map of the last focus call [Hz].
    double rd_doppler_first_hz() const;

    unsigned num_range_bins() const { return d_blk.num_range_bins; }
    unsigned num_lines() const { return d_blk.num_lines; }
    unsigned fft_size() const { return d_nfft; }
    const focuser_config& config() const { return d_cfg; }
    const rd_block& block() const { return d_blk; }

    //! Doppler [Hz] of FFT bin p (the alias nearest to the band centre).
    double doppler_hz(unsigned p) const;
    //! Band processed by the last focus() call (for SCENE / FULL: the configured band).
    double band_lo_hz() const { return d_band_lo; }
    double band_hi_hz() const { return d_band_hi; }
    /*!
     * Band [lo, hi] a kernel of cfg processes for the configured band [lo, hi] at pulse
     * rate prf: FULL (or a band of prf or more) is the pulse rate centred on the band.
     */
    static std::pair<double, double>
    configured_band(const focuser_config& cfg, double lo, double hi, double prf);
    //! Number of Doppler bins processed by the last focus() call.
    unsigned band_bins() const { return static_cast<unsigned>(d_band_bins.size()); }
    /*!
     * The band_bins() of a kernel built from cfg and blk, before its first focus() (ESTIMATE:
     * the configured band it falls back to), without its FFT plans and tables: the one
     * selection the kernel itself makes, for sizing memory and displays.
     */
    static unsigned configured_band_bins(const focuser_config& cfg, const rd_block& blk);
    //! Largest migration over the processed band [range bins].
    double max_migration_bins() const { return d_max_migration; }
    //! Whether the last focus() applied RCMC (enabled and migration above the threshold).
    bool rcmc_applied() const { return d_rcmc_applied; }
    //! Migration Delta k of range bin k at Doppler f [bins] (eq. 40 or hyperbolic).
    double migration_bins(unsigned k, double f_hz) const;
    //! Azimuth compression phase at range bin k and Doppler f [rad] (double precision).
    double compression_phase(unsigned k, double f_hz) const;

    /*!
     * \brief Motion compensation (cfg.moco) before the azimuth FFT, eq. (31), from the line
     * of sight los: line m of a block at slow time block_start_s() + m T. Per line, with the
     * displacement dR(R0, t) = |p(t) - P(R0)| - ideal range (los_reference): FIRST shifts the
     * range profile by dR(ref_range_m, t) / rho (windowed-sinc, the RCMC interpolator, on the
     * profile demodulated by its spectrum centre) and multiplies it by
     * exp(+j 4 pi f dR(ref_range_m, t) / c); SECOND multiplies bin k by
     * exp(+j 4 pi f dR(R0(k), t) / c) instead (the residual per bin). f: the frequency of the
     * range-compressed phase, fc + (N - 1) Delta f / 2. Lines outside the path's span (the
     * zeros before the stream, a flush's padding) are left as they are. An ideal los or
     * moco OFF: nothing is done. cfg.moco_resample: first, every range bin's slow-time
     * signal is resampled at the times tau_m where the navigation's along-track position is
     * the ideal line's at t_m (y_nav(tau_m) = track_start + v t_m), by the RCMC windowed sinc
     * on the signal demodulated by the band centre's spatial frequency f_c y_nav(t) / v and
     * re-modulated at y(t_m); the line-of-sight compensation then uses p(tau_m).
     */
    void set_motion(std::shared_ptr<const los_reference> los,
                    double phase_frequency_hz,
                    double ref_range_m);
    void set_block_start_s(double t0_s) { d_t0 = t0_s; }
    double block_start_s() const { return d_t0; }
    //! Whether focus() compensates motion (moco on and a non-ideal path).
    bool moco_active() const
    {
        return d_los && !d_los->ideal() && d_cfg.moco != moco_order::OFF;
    }
    //! Largest |dR(ref_range, t)| of the last compensated block [m].
    double moco_max_shift_m() const { return d_moco_max_m; }

private:
    focuser_config d_cfg;
    rd_block d_blk;
    unsigned d_nfft;
    double d_band_lo;
    double d_band_hi;
    double d_centre;
    double d_max_migration;
    bool d_rcmc_applied;
    fft_fwd d_fwd;
    fft_rev d_rev;
    sinc_interpolator d_interp;
    volk::vector<gr_complex> d_stage;      // K x num_lines, for line-major input (lazy)
    volk::vector<gr_complex> d_spec;       // K x nfft spectra, ESTIMATE only
    volk::vector<gr_complex> d_tile;       // tile_rows x nfft inverse-FFT outputs
    volk::vector<gr_complex> d_band;       // band bins x K, band-major
    volk::vector<gr_complex> d_filter;     // band bins x K, compression x scale
    volk::vector<float> d_shift;           // band bins x K, migration
    volk::vector<gr_complex> d_col;        // K
    volk::vector<gr_complex> d_col2;       // K
    volk::vector<gr_complex> d_demod;      // K, exp(-j 2 pi fc k), range spectrum to 0
    volk::vector<float> d_power;           // nfft, azimuth power spectrum
    std::vector<unsigned> d_band_bins;     // processed FFT bins
    std::vector<unsigned> d_filter_bins;   // bins d_filter was built for
    std::vector<unsigned> d_rd_row;        // band bin b -> rd_map line (ascending Doppler)

    std::shared_ptr<const los_reference> d_los; // motion compensation (set_motion)
    double d_moco_f = 0.0, d_moco_ref = 0.0, d_t0 = 0.0, d_moco_max_m = 0.0;
    volk::vector<gr_complex> d_moco;       // K x num_lines compensated, range-major
    volk::vector<float> d_moco_shift;      // K, one line's envelope shift
    std::vector<vec3> d_moco_pts;          // K, the bins' reference points (los_reference)
    std::vector<double> d_moco_r2;         // K, the bins' R0^2
    std::vector<double> d_moco_range;      // K, the path's ranges to them at a line
    std::vector<double> d_moco_tau;        // num_lines, each line's path time
    volk::vector<float> d_az_shift;        // num_lines, resampling shift [lines]
    volk::vector<gr_complex> d_az_demod;   // num_lines, exp(-j 2 pi f_c y_nav(t_m) / v)
    volk::vector<gr_complex> d_az_remod;   // num_lines, exp(+j 2 pi f_c y(t_m) / v)
    volk::vector<gr_complex> d_az_row;     // num_lines

    void compensate_motion(const gr_complex* in, size_t row_stride);
    // Slow-time resampling onto the uniform along-track grid into d_moco (moco_resample).
    void resample_along_track(const gr_complex* in, size_t row_stride);
    static unsigned fft_size_of(const focuser_config& cfg, const rd_block& blk);
    // The FFT bins whose Doppler alias nearest to centre lies in [lo, hi] (every bin for a
    // band of the pulse rate or more; the bin nearest to centre for one narrower than a bin).
    static std::vector<unsigned> bins_in_band(const focuser_config& cfg,
                                              unsigned nfft,
                                              double pulse_interval_s,
                                              double centre,
                                              double lo,
                                              double hi);
    void select_band(); // from the configuration (SCENE / FULL)
    void estimate_band();
    void build_filter();
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_RD_FOCUSER_H */
