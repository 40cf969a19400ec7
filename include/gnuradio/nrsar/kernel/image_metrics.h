/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_IMAGE_METRICS_H
#define INCLUDED_NRSAR_KERNEL_IMAGE_METRICS_H

#include <gnuradio/fft/fft.h>
#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <volk/volk_alloc.hh>
#include <complex>
#include <cstddef>
#include <limits>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*
 * Image quality metrics of a reference point target (SPEC section 8, paper section IV).
 *
 * Images are `lines x bins` complex arrays stored line after line (row-major): one
 * azimuth line of `bins` range bins, then the next line, as the focuser streams them.
 */

//! What the metrics need to know besides the pixels.
struct NRSAR_API metrics_config {
    double nm_factor = 1.0;           //!< N M of the NMSE (subcarriers x symbols sent)
    double range_res_bins = 1.0;      //!< range resolution cell in range bins (> 0)
    double azimuth_res_lines = 1.0;   //!< azimuth resolution cell in lines (> 0)
    double sidelobe_window_cells = 20.0; //!< ISLR/PSLR window half-width in cells; 0: whole cut
    //! Upper bounds on that half-width per cut, e.g. half the distance to another target
    //! on the cut, so its main lobe is not taken for a sidelobe (infinity: no bound).
    double range_window_limit_cells = std::numeric_limits<double>::infinity();
    double azimuth_window_limit_cells = std::numeric_limits<double>::infinity();
    double search_cells = 4.0;        //!< peak search half-width around the expected position
    //! NESZ: RCS of the reference target [m^2] and the pixel area, range bin spacing x line
    //! spacing in the slant-range plane [m^2]; NaN: NESZ not computed.
    double reference_rcs_m2 = std::numeric_limits<double>::quiet_NaN();
    double pixel_area_m2 = std::numeric_limits<double>::quiet_NaN();
};

//! Impulse response figures of one 1-D cut through the peak (band-limited interpolation).
struct NRSAR_API cut_metrics {
    bool valid = false;
    unsigned upsample = 1;    //!< interpolation factor used
    double peak_pos = 0.0;    //!< sub-sample peak position [samples of the cut]
    double peak_power = 0.0;  //!< interpolated |.|^2 at the peak
    double irw = 0.0;         //!< -3 dB (half-power) width [samples]; NaN if not found
    double mainlobe_energy = 0.0; //!< sum of |.|^2 between the first nulls (interpolated grid)
    double sidelobe_energy = 0.0; //!< window energy outside the main lobe
    double islr_db = 0.0;     //!< eq. (50) on the cut: sidelobe / mainlobe energy
    double pslr_db = 0.0;     //!< highest sidelobe over the peak
};

//! Everything compute() measures on one aperture.
struct NRSAR_API metrics_result {
    std::complex<double> c_hat{ 0.0, 0.0 }; //!< <ref, img> / <ref, ref>
    double pel_db = 0.0;       //!< -20 log10 |c_hat|
    double nmse = 0.0;         //!< N M mean|img / c_hat - ref|^2 / max|ref|^2 (linear)
    double nmse_db = 0.0;
    std::size_t nmse_pixels = 0; //!< pixels the NMSE's mean ran over (pixel_weight > 0)
    double peak_power = 0.0;   //!< |img|^2 at the interpolated 2-D peak
    double noise_power = 0.0;  //!< mean |img - c_hat ref|^2 over the noise region
    std::size_t noise_pixels = 0;
    double snr_out_db = 0.0;   //!< peak_power / noise_power
    double peak_line = 0.0;    //!< sub-pixel peak position (line index)
    double peak_bin = 0.0;     //!< sub-pixel peak position (range bin index)
    cut_metrics range;         //!< cut along range through the peak
    cut_metrics azimuth;       //!< cut along azimuth through the peak
    double islr_db = 0.0;      //!< both cuts pooled: (side_r + side_a) / (main_r + main_a)
    double pslr_db = 0.0;      //!< the higher of the two cuts' PSLR
    double image_entropy = 0.0; //!< image_entropy of img (second paper, section 3.2.1)
    double epi = 0.0;          //!< edge_preservation_index of img against ref
    double nesz_db = 0.0;      //!< nesz_db of the noise region against the reference target
};

/*!
 * \brief Image entropy, the second paper's section 3.2.1 (its [33]):
 * E = -sum D ln D, D = |I|^2 / sum |I|^2 over the n pixels (natural log; 0 for a single
 * bright pixel, ln n for a uniform image; 0 for an all-zero image). Accumulated in double.
 */
NRSAR_API double image_entropy(const gr_complex* img, std::size_t n);

/*!
 * \brief Edge preservation index, the second paper's section 3.2.1 (its [34]): the
 * correlation coefficient sum (dx - mean dx)(dy - mean dy) / sqrt(sum (dx - mean dx)^2
 * sum (dy - mean dy)^2) of the edge-filtered amplitudes dx = L|x|, dy = L|y|, L the
 * 4-neighbour Laplacian [0 1 0; 1 -4 1; 0 1 0] over the interior pixels (lines x bins
 * images, both at least 3 x 3). 1 when y's edges are x's up to a scale; NaN when either
 * filtered image is constant.
 */
NRSAR_API double edge_preservation_index(const gr_complex* x,
                                         const gr_complex* y,
                                         std::size_t lines,
                                         std::size_t bins);
//! The same in scratch (grown to 2 lines bins doubles, reused: no allocation per image).
NRSAR_API double edge_preservation_index(const gr_complex* x,
                                         const gr_complex* y,
                                         std::size_t lines,
                                         std::size_t bins,
                                         std::vector<double>& scratch);

/*!
 * \brief Noise-equivalent sigma zero [dB] by the integral method: a point target of RCS
 * sigma_ref puts the energy E_t into the image, so a pixel of area A of a distributed
 * scene of sigma0 holds E_t sigma0 A / sigma_ref, and the noise power P_n per pixel equals
 * it at NESZ = P_n sigma_ref / (E_t A). NaN unless every argument is finite and > 0.
 */
NRSAR_API double nesz_db(double noise_power, double target_energy, double rcs_m2, double pixel_area_m2);

/*!
 * \brief <ref, img> / <ref, ref> (SPEC section 8), accumulated in double per line.
 * Returns 0 when ref is all zero.
 */
NRSAR_API std::complex<double>
calibration_factor(const gr_complex* img, const gr_complex* ref, std::size_t lines, std::size_t bins);

/*!
 * \brief Dirichlet kernel of a band of `band` frequency bins, normalised to 1 at u = 0:
 * sin(pi u / res) / (band sin(pi u / (band res))), u and res in samples (eq. (47), chi = 1).
 * Its period is band * res samples; band -> infinity gives sinc(u / res).
 */
NRSAR_API double dirichlet(double u, double res, double band);

/*!
 * \brief Separable analytic PSF R(k, m) of eq. (47) with chi = 1, centred at (line0, bin0)
 * (sub-pixel), with linear phase ramps (rad per line, rad per bin) from off-centre bands.
 *
 * Range: Dirichlet of range_band bins (the N subcarriers) with a resolution of range_res
 * bins; azimuth: Dirichlet of azimuth_band Doppler bins with a resolution of
 * azimuth_res lines. Writes lines x bins values into out.
 */
NRSAR_API void psf_model(gr_complex* out,
                         std::size_t lines,
                         std::size_t bins,
                         double line0,
                         double bin0,
                         double azimuth_res,
                         double azimuth_band,
                         double range_res,
                         double range_band,
                         double phase_per_line = 0.0,
                         double phase_per_bin = 0.0);

/*!
 * \brief Linear phase slopes (rad per line, rad per bin) of the image's main lobe around
 * (peak_line, peak_bin): arg of sum img[x + 1] conj(img[x]) over neighbour pairs that both
 * lie within 0.45 resolution cells of the peak. An off-centre band (a Doppler centroid, a
 * subcarrier grid not centred on DC) shows up exactly as such a ramp.
 */
NRSAR_API std::pair<double, double> estimate_phase_ramps(const gr_complex* img,
                                                         std::size_t lines,
                                                         std::size_t bins,
                                                         double peak_line,
                                                         double peak_bin,
                                                         double azimuth_res,
                                                         double range_res);

/*!
 * \brief Pixel of largest |img|^2 within +-half_lines x +-half_bins (at least +-2) of
 * (line, bin); the whole image when that box misses it. Returns (line, bin).
 */
NRSAR_API std::pair<std::size_t, std::size_t> find_peak(const gr_complex* img,
                                                        std::size_t lines,
                                                        std::size_t bins,
                                                        double line,
                                                        double bin,
                                                        double half_lines,
                                                        double half_bins);

/*!
 * \brief Per-pixel weights that put the pixels of one linearly focused, zero-padded aperture
 * on the footing of the paper's circular processing, or of a continuous strip (SPEC section
 * 8: every pixel carries the noise of its whole correlation window).
 *
 * Azimuth compression over the Doppler band [band_lo_hz, band_hi_hz] correlates the pixel of
 * line m (along-track position y = y0 + m dy) and range bin k (closest-approach slant range
 * r = r0 + k dr) with the pulses taken at platform positions y_p whose Doppler
 * 2 v (y - y_p) / (lambda sqrt(r^2 + (y - y_p)^2)) lies in the band (stationary phase):
 * y - y_p in [r c(f_lo), r c(f_hi)], c(f) = f lambda / (2 v sqrt(1 - (f lambda / (2 v))^2))
 * (f lambda / (2 v) for every f when a band edge has (f lambda / (2 v))^2 >= 0.99, the
 * focuser's parabolic fallback, eq. (40)).
 * Of that window, W = r (c(f_hi) - c(f_lo)) long, only the part s within [data_lo_m,
 * data_hi_m] holds pulses, and the pixel's noise and data-randomness power scale with s
 * (circular processing: with W). The lines x bins weights (row-major) are W / s where
 * s >= min(W, data_hi_m - data_lo_m) / 2, 0 elsewhere (pixels holding less than half the
 * pulses of the bin's best-covered line; no weight exceeds 2 W / min(W, span)).
 * period_m > 0: the focuser correlated circularly over a block of that length (its azimuth
 * FFT size times dy) holding the data and zeros, so a window longer than the block wraps
 * (full-band compression after presumming: W is tens of seconds of track): s counts the
 * data under the window in every copy of the block, at most n span + min(r, span) for
 * W = n period_m + r, and the weights tend to period_m / span. 0: no wrap (the overlap
 * holds the whole window).
 * Bins at a slant range <= 0 (no correlation window, no echo) get weight 0.
 * Throws std::invalid_argument for an empty or non-finite band, an empty data span, a
 * negative or non-finite period or a non-finite axis.
 * Writes them into w (resized; its capacity is reused from one aperture to the next).
 */
NRSAR_API void strip_pixel_weights_into(std::vector<float>& w,
                                        std::size_t lines,
                                        std::size_t bins,
                                        double y0_m,
                                        double dy_m,
                                        double r0_m,
                                        double dr_m,
                                        double data_lo_m,
                                        double data_hi_m,
                                        double band_lo_hz,
                                        double band_hi_hz,
                                        double wavelength_m,
                                        double velocity_mps,
                                        double period_m = 0.0);

//! Replaces non-finite samples by 0; returns how many there were.
NRSAR_API std::size_t zero_nonfinite(gr_complex* data, std::size_t n);

/*!
 * \brief Point-target metrics of an image against its reference.
 *
 * Owns the FFTs of the cut interpolation (one per cut direction, re-planned only when a
 * cut length changes) and its work buffers. Movable, not copyable.
 */
class NRSAR_API image_metrics
{
public:
    image_metrics();
    ~image_metrics();
    image_metrics(image_metrics&&) noexcept;
    image_metrics& operator=(image_metrics&&) noexcept;
    image_metrics(const image_metrics&) = delete;
    image_metrics& operator=(const image_metrics&) = delete;

    /*!
     * \brief All metrics of img (lines x bins) against ref (same shape).
     *
     * expected_line/expected_bin: where the target should be (peak search centre).
     * bin_mask/line_mask (bins / lines entries, non-zero = in the region) select the
     * target-free noise region as their outer product; nullptr = all bins / all lines.
     * pixel_weight (lines x bins, >= 0; nullptr = all 1): the NMSE's mean runs over the
     * pixels of non-zero weight, each pixel's error power times its weight
     * (strip_pixel_weights_into).
     * Non-finite metrics (no noise pixel, reference all zero, ...) come back as NaN.
     */
    metrics_result compute(const gr_complex* img,
                           const gr_complex* ref,
                           std::size_t lines,
                           std::size_t bins,
                           double expected_line,
                           double expected_bin,
                           const metrics_config& cfg,
                           const std::uint8_t* bin_mask = nullptr,
                           const std::uint8_t* line_mask = nullptr,
                           const float* pixel_weight = nullptr);

    /*!
     * \brief IRW, PSLR, ISLR and sub-sample peak of one cut of n samples (stride apart).
     *
     * The cut is interpolated by zero-padding its spectrum (exact for a periodic,
     * band-limited cut) to at least 16 samples per resolution cell (res_samples samples
     * per cell); the peak is searched within +-1 sample of `around`, refined by a parabola;
     * the main lobe runs between the first minima either side; the -3 dB crossings are
     * interpolated linearly in power. window_cells = 0 integrates the whole cut.
     */
    cut_metrics analyse_cut(const gr_complex* cut,
                            std::size_t n,
                            std::size_t stride,
                            std::size_t around,
                            double res_samples,
                            double window_cells,
                            int slot = 0);

private:
    struct upsampler;
    std::unique_ptr<upsampler> d_up[2];
    volk::vector<gr_complex> d_line;
    volk::vector<float> d_power;
    std::vector<double> d_amp; // edge_preservation_index's amplitudes
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_IMAGE_METRICS_H */
