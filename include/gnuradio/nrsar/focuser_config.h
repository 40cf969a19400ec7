/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_FOCUSER_CONFIG_H
#define INCLUDED_NRSAR_FOCUSER_CONFIG_H

#include <gnuradio/fft/window.h>
#include <gnuradio/nrsar/api.h>
#include <cstdint>
#include <limits>

namespace gr {
namespace nrsar {

//! Which Doppler bins the range-Doppler focuser processes (SPEC section 7).
enum class doppler_band {
    SCENE,    //!< the scene's band from compute_extent(geo, scn), plus a margin
    ESTIMATE, //!< estimated per processing block from the azimuth power spectrum
    FULL      //!< every Doppler bin of the PRF (the explicit full-band option)
};

//! Motion compensation from the navigation before the azimuth FFT (docs/flight.md).
enum class moco_order {
    OFF,   //!< none: the pulses are focused as flown
    FIRST, //!< per pulse, the line-of-sight displacement at the scene's reference range:
           //!< its phase and its range (envelope) shift
    SECOND //!< FIRST, and the range-dependent residual phase per range bin
};

/*!
 * \brief Processing options of the range-Doppler focuser (rd_focuser block and
 * kernel::rd_focuser). Plain values; validate() throws std::invalid_argument naming the
 * field, its value and the limit.
 */
struct NRSAR_API focuser_config {
    //! Slow-time spacing of the input pulses in OFDM symbols (1: full-rate data). The
    //! pulse interval is T = num.symbol_s() * symbols_per_pulse unless a pulse_interval tag
    //! overrides it.
    unsigned symbols_per_pulse = 1;
    //! Output lines per aperture M; 0: round(geo.aperture_s / T).
    unsigned lines_per_aperture = 0;
    //! Overlap of consecutive processing blocks in lines, on each side where needed:
    //! -1 auto (the azimuth extent of a target's energy in the scene band), 0 none (each
    //! aperture focused alone, circularly: the paper's whole-block case), n > 0: n lines of
    //! history before and n lines of look-ahead after every aperture.
    int overlap_lines = -1;
    //! Azimuth FFT size: true the next 7-smooth size >= the block length, false exactly it.
    bool fast_fft_size = true;
    doppler_band band = doppler_band::SCENE; //!< processed Doppler band
    //! Margin added on both sides of the scene or estimated band [Hz]; < 0: automatic
    //! (10 % of the band plus two Doppler resolution cells 1/Ta).
    double band_margin_hz = -1.0;
    //! ESTIMATE: band edges where the smoothed azimuth power spectrum falls this many dB
    //! below its peak (measured above the noise floor).
    double estimate_threshold_db = 20.0;
    //! Exact hyperbolic range history in the range-Doppler domain (true) or the paper's
    //! parabolic approximation, eqs. (40) and (47) (false).
    bool hyperbolic = true;
    bool rcmc = true;        //!< range cell migration correction, eq. (41)
    unsigned rcmc_taps = 16; //!< windowed-sinc interpolator length (even, 2..64)
    gr::fft::window::win_type rcmc_window = gr::fft::window::WIN_KAISER; //!< kernel window
    double rcmc_window_param = 6.0; //!< Kaiser beta (ignored by the other windows)
    //! RCMC is skipped when the largest migration over the processed band is below this
    //! many range bins.
    double rcmc_skip_below_bins = 0.05;
    /*!
     * Centre of the range spectrum [cycles per range bin]: RCMC interpolates the range
     * profile after shifting this frequency to 0 (a range IFFT over subcarriers 0..N-1,
     * eq. (29), puts it at (N - 1) / (2 fft_size), close to the Nyquist edge, where a short
     * sinc kernel would fail). NaN: automatic, (N - 1) Delta f rho / c from the numerology
     * and the range bin spacing rho.
     */
    double range_centre_cycles = std::numeric_limits<double>::quiet_NaN();
    /*!
     * Guard bins dropped from each side of the output (guard): the RCMC kernel of the edge
     * bins reads (max migration + rcmc_taps / 2) bins beyond them, zeros past the crop, so
     * those bins carry less noise. The input is cropped g bins wider on each side and the
     * block outputs only the K - 2 g inner bins (range_axis tag moved by g bins). 0: none.
     */
    unsigned guard_bins = 0;
    /*!
     * Motion compensation from the navigation path given to the block (docs/flight.md).
     * On the ideal line (no navigation) every order is a no-op and the output is unchanged,
     * so SECOND is the default: a navigation, when given, is used.
     */
    moco_order moco = moco_order::SECOND;
    /*!
     * With moco FIRST or SECOND: before the line-of-sight compensation, the pulses are
     * resampled in slow time onto the ideal line's uniform along-track grid (line m at
     * track_start + v t_m, found on the navigation's along-track position), so that the
     * azimuth FFT sees uniform spacing in y under a varying along-track speed
     * (docs/flight.md, "Azimuth resampling"). Off by default (an unchanged output).
     */
    bool moco_resample = false;
    /*!
     * A strip cut into tasks (nrsar-process --dask, docs/scale.md): the first aperture to
     * emit. Its input stream then starts at the flight's line stream_first_line() (the first
     * line of that aperture's processing block, or the flight's line 0 if the block starts
     * before it) instead of line 0; the image lines are those of the whole flight's run.
     */
    std::uint64_t first_aperture = 0;
    //! Apertures to emit, then the block is done (0: until the stream ends).
    std::uint64_t apertures = 0;

    void validate() const;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_FOCUSER_CONFIG_H */
