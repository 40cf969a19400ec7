/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_NMSE_PROBE_H
#define INCLUDED_NRSAR_NMSE_PROBE_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace gr {
namespace nrsar {

/*!
 * \brief Image quality metrics of a reference point target, one set per focused aperture
 * (SPEC section 8, paper section IV, eqs. (48)-(59)).
 * \ingroup nrsar
 *
 * A sink for focused image lines (vlen range bins per item, one azimuth line per item).
 * The focuser tags the first line of every aperture with tags::aperture_key() (uint64),
 * tags::azimuth_axis_key() (first line's along-track position [m], line spacing [m],
 * lines) and tags::range_axis_key() (first bin's slant range [m], bin spacing [m], bins).
 * The probe buffers one aperture (input 0, and input 1 when reference_input is true) and,
 * when it is complete (lines_per_aperture lines, or the next aperture tag, or the end of
 * the stream: reported as partial), computes
 *
 *  - c_hat = <ref, img> / <ref, ref>, pel_db = -20 log10 |c_hat|;
 *  - nmse_db: N M mean|img / c_hat - ref|^2 / max|ref|^2, mean over the image pixels (for a
 *    zero-padded aperture with a known band: over the pixels holding at least half the pulses
 *    of their bin's best-covered line, each normalised to a full correlation window, SPEC
 *    section 8, docs/accuracy.md);
 *  - nmse_theory_db: (Var(chi) + E|g|^2 / SNR_in) / E{chi}^2 over the constellation;
 *  - nmse_theory_band_db: that plus |10 log10(B_processed / B_target)|, B_target the
 *    reference target's own Doppler band over the aperture (compute_extent);
 *  - snr_out_db: peak power over the mean power of img - c_hat ref in the noise region;
 *  - islr_db, pslr_db, irw_range_m, irw_azimuth_m from 1-D cuts through the peak,
 *    interpolated to >= 16 samples per resolution cell;
 *  - peak_error_m: distance between the interpolated peak and the target's true (x, y).
 *
 * The reference ref is input 1 (the same chain fed with the noise-free echo of S = 1),
 * or, without it, the analytic PSF of eq. (47) with chi = 1: separable Dirichlet kernels
 * of the N subcarriers (range) and of the aperture's Doppler band (azimuth), centred at the
 * target's true closest-approach slant range and along-track position, with the linear
 * phase ramps of off-centre bands estimated from the image's main lobe.
 *
 * Results go out as a PMT dict on message port "metrics" and are readable by getters.
 * Non-finite input samples are zeroed, counted, and logged once per aperture.
 */
/*!
 * \brief Options of nmse_probe (everything besides the scenario, the theory's constellation,
 * filter and SNR_in, and the vector length).
 */
struct NRSAR_API probe_config {
    //! true: input 1 carries the reference image; false: the PSF model of eq. (47).
    bool reference_input = false;
    unsigned lines_per_aperture = 0;         //!< lines per aperture; 0: from the azimuth axis tag
    std::uint64_t symbols_per_aperture = 0;  //!< M_tx of the N M factor; 0: geo.symbols_per_aperture(num)
    //! N of the N M factor and of the range Dirichlet kernel; 0: num.num_subcarriers.
    unsigned num_subcarriers = 0;
    double range_resolution_m = 0.0;   //!< range cell [m]; 0: c / (2 N Delta f)
    double azimuth_resolution_m = 0.0; //!< azimuth cell [m]; 0: lambda R0 / (2 v Ta)
    //! Noise region (when noise_box is empty): range bins farther than this many range cells
    //! from every target's closest-approach slant range (>= 0).
    double noise_guard_cells = 10.0;
    //! Noise region as {r_min, r_max, y_min, y_max} [m] (slant range, along-track), or empty.
    std::vector<double> noise_box;
    double sidelobe_window_cells = 20.0; //!< ISLR/PSLR window half-width in cells; 0: whole cut
    /*!
     * Doppler band the focuser processed [Hz] (rd_focuser band_lo_hz() / band_hi_hz()); both
     * 0: unknown (nmse_theory_band_db is then NaN and every line counts in the NMSE).
     */
    double band_lo_hz = 0.0;
    double band_hi_hz = 0.0;
    /*!
     * true: each aperture was focused from its own pulses with zeros before and after (linear
     * correlation, nrsar-sim's single aperture), so pixels near its ends hold fewer pulses;
     * with a known band the NMSE then normalises every pixel to a full correlation window
     * (kernel::strip_pixel_weights). false: every pixel's window is full (circular focusing,
     * overlap_lines = 0, or the inner apertures of a stream).
     */
    bool zero_padded = false;
    /*!
     * Lines of the focuser's circular block (rd_focuser fft_size()) when a zero-padded
     * aperture's correlation window can be longer than it and wrap (full-band compression):
     * the weights count the data in every copy of the block. 0: no wrap. At least
     * lines_per_aperture when both are set.
     */
    unsigned block_lines = 0;

    //! Throws std::invalid_argument naming the field, its value and the limit.
    void validate() const;
};

class NRSAR_API nmse_probe : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<nmse_probe> sptr;

    /*!
     * \param num Numerology: subcarrier spacing (range resolution of the PSF model) and the
     *        default N.
     * \param geo Geometry: height (closest-approach slant range sqrt(x^2 + H^2)), carrier,
     *        speed and aperture time (azimuth resolution lambda R0 / (2 v Ta) of the PSF model,
     *        the reference target's own Doppler band), and the default M_tx.
     * \param scn Scene; targets[0] is the reference target, every target is kept out of the
     *        noise region.
     * \param constellation Constellation points (E|s|^2 = 1), each equally likely, for the theory.
     * \param filter Per-RE filter (RF, MF, WF) for the theory value.
     * \param snr_in_db SNR_in [dB] for the theory value (and WF's g).
     * \param vlen Range bins per image line K (>= 4).
     * \param cfg options (probe_config: reference input, N M, resolutions, noise region,
     *        sidelobe window, processed band, zero padding)
     */
    static sptr make(const numerology& num,
                     const geometry& geo,
                     const scene& scn,
                     const std::vector<gr_complex>& constellation,
                     filter_type filter,
                     double snr_in_db,
                     unsigned vlen,
                     const probe_config& cfg = probe_config());

    virtual probe_config config() const = 0;

    //! Changes SNR_in of the theory value (takes effect at the next aperture).
    virtual void set_snr_in_db(double snr_in_db) = 0;
    virtual double snr_in_db() const = 0;
    //! Changes the filter of the theory value (takes effect at the next aperture).
    virtual void set_filter(filter_type filter) = 0;
    virtual filter_type filter() const = 0;

    //! Latest values (NaN before the first aperture).
    virtual double nmse_db() const = 0;
    virtual double nmse_theory_db() const = 0;
    //! nmse_theory_db + |10 log10(B_processed / B_target)| (NaN without a processed band).
    virtual double nmse_theory_band_db() const = 0;
    virtual double pel_db() const = 0;
    virtual double snr_out_db() const = 0;
    virtual double islr_db() const = 0;
    virtual double pslr_db() const = 0;
    virtual double irw_range_m() const = 0;
    virtual double irw_azimuth_m() const = 0;
    virtual double peak_error_m() const = 0;
    //! All values of the latest aperture, under the keys of the message dict.
    virtual std::map<std::string, double> metrics() const = 0;
    //! Apertures evaluated so far (partial ones included).
    virtual std::uint64_t apertures() const = 0;
    //! Non-finite input samples zeroed so far (both inputs).
    virtual std::uint64_t nonfinite_count() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_NMSE_PROBE_H */
