/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_RD_FOCUSER_H
#define INCLUDED_NRSAR_RD_FOCUSER_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/focuser_config.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/trajectory.h>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * \brief Range-Doppler SAR focusing of range-compressed pulses, eqs. (31)-(47) (SPEC 7).
 * \ingroup nrsar
 *
 * Input: one vector of K range bins per pulse (range_ifft output), pulse interval
 * T = num.symbol_s() * cfg.symbols_per_pulse, overridden from a tagged item on by a
 * tags::pulse_interval_key() tag (double, s). The range axis (first bin [m], spacing [m], K)
 * comes from a tags::range_axis_key() tag when present (it wins over the constructor values;
 * a warning names the difference).
 *
 * Output: the focused image, one vector of K range bins per azimuth line, line spacing v T,
 * one aperture of M lines after another. Output line j is the image at along-track position
 * y0 + j v T, y0 = geo.track_start_m + s v T, where s = line_shift() is where the pulses of
 * an aperture focus on average (the band centre over Ka: the paper scene lies ahead of the
 * track, s = 1.43 s of pulses). A point target at (x, y) peaks on line (y - y0) / (v T) at its
 * closest-approach slant-range bin. The first line of every aperture carries
 * tags::aperture_key() (uint64 index), tags::azimuth_axis_key() (tuple: along-track position
 * of the line [m], v T [m], M) and tags::range_axis_key() (first bin [m], spacing [m], K).
 *
 * Streaming: aperture i (image lines [i M + s, i M + s + M)) is focused from a processing
 * block of before + M + after input pulses (overlap-save): before/after cover the azimuth
 * extent of a target's energy in the scene band around the shift s, so consecutive apertures
 * join into one continuous image. With overlap 0 every aperture's M pulses are focused alone
 * and circularly, the output rotated by s (the paper's whole-block case; a target focusing
 * outside the window wraps around). Memory: about
 * (before + 2 M + after + B) K complex samples, B the processed Doppler bins (ESTIMATE adds
 * K x FFT size). When the input ends, the apertures that the
 * received pulses belong to are flushed with zero padding (no hang).
 * Non-finite input samples are zeroed, counted, logged once and reported with a
 * tags::nonfinite_key() tag on the next aperture's first line.
 *
 * Optional second output "rd_map" (for live displays): per aperture, the range-Doppler map
 * of its processing block after RCMC (eq. 41) and before azimuth compression (eq. 47),
 * band_bins() vectors of K range bins in ascending Doppler; a target is a straight line
 * at its closest-approach range. Use its magnitude (the phase carries the interpolator's
 * range demodulation; without RCMC it is the azimuth spectrum itself). The first line of
 * every map carries tags::aperture_key(), tags::doppler_axis_key() (Doppler of the line
 * [Hz], 1 / (fft_size() T) [Hz], band_bins()) and tags::range_axis_key(). The map is
 * computed only while the port is connected: unconnected, the block does exactly the work
 * it did without it. Connected, its consumer must keep up (the image waits for it).
 */
class NRSAR_API rd_focuser : virtual public gr::block
{
public:
    typedef std::shared_ptr<rd_focuser> sptr;

    /*!
     * \param num OFDM numerology (pulse interval num.symbol_s() * cfg.symbols_per_pulse)
     * \param geo platform geometry (carrier, v, track start, aperture Ta)
     * \param scn the scene: its Doppler band (compute_extent) sets the processed band
     *            (doppler_band::SCENE) and the automatic overlap
     * \param num_range_bins K, the vector length of the input; both outputs carry the
     *        K - 2 cfg.guard_bins inner bins (num_output_bins())
     * \param first_range_m slant range of bin 0 [m] when no range_axis tag arrives
     * \param range_bin_m slant-range spacing of the bins [m]; 0: c / (2 num.fft_size Delta f)
     * \param cfg processing options (focuser_config: band, RCMC, overlap, M, FFT size,
     *        motion compensation)
     * \param nav navigation path for the motion compensation (cfg.moco) before the azimuth
     *        FFT; empty (the default): the ideal line, nothing to compensate
     */
    static sptr make(const numerology& num,
                     const geometry& geo,
                     const scene& scn,
                     unsigned num_range_bins,
                     double first_range_m,
                     double range_bin_m = 0.0,
                     const focuser_config& cfg = focuser_config(),
                     const trajectory& nav = trajectory());

    virtual focuser_config config() const = 0;
    //! Output lines per aperture M (current pulse interval).
    virtual unsigned lines_per_aperture() const = 0;
    //! History lines before / look-ahead lines after each aperture in its processing block.
    virtual unsigned overlap_before() const = 0;
    virtual unsigned overlap_after() const = 0;
    /*!
     * Offset s of the output window from the aperture's pulses [lines]: aperture i holds image
     * lines [i M + s, i M + s + M), s = f_c / (Ka T) at the band centre f_c and mid range,
     * where the energy of its own pulses focuses.
     */
    virtual long long line_shift() const = 0;
    //! Azimuth FFT size of the processing block.
    virtual unsigned fft_size() const = 0;
    virtual double pulse_interval_s() const = 0;
    virtual double first_range_m() const = 0;
    virtual double range_bin_m() const = 0;
    //! Bins per output line: num_range_bins - 2 cfg.guard_bins (guard).
    virtual unsigned num_output_bins() const = 0;
    //! Doppler band processed for the last aperture [Hz] and its number of FFT bins (the
    //! lines of one rd_map aperture; before the first aperture: those of the configured band).
    virtual double band_lo_hz() const = 0;
    virtual double band_hi_hz() const = 0;
    virtual unsigned band_bins() const = 0;
    //! Largest range migration over the processed band [bins] and whether RCMC ran.
    virtual double max_migration_bins() const = 0;
    virtual bool rcmc_applied() const = 0;
    //! Apertures emitted so far.
    virtual std::uint64_t apertures() const = 0;
    //! Non-finite input samples zeroed so far.
    virtual std::uint64_t nonfinite_count() const = 0;
    //! The flight's line of the first input line this block expects: 0, or with
    //! cfg.first_aperture the first line of that aperture's processing block (a strip's
    //! task reads its data from there, docs/scale.md).
    virtual std::uint64_t stream_first_line() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_RD_FOCUSER_H */
