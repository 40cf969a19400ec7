/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_BP_FOCUSER_H
#define INCLUDED_NRSAR_KERNEL_BP_FOCUSER_H

#include <gnuradio/fft/fft.h>
#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/sinc_interpolator.h>
#include <array>
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

//! The input pulses' range axis and the image grid of one back-projected aperture.
struct NRSAR_API bp_grid {
    unsigned num_range_bins = 0; //!< K: bins of every input pulse and of every image line
    double first_range_m = 0.0;  //!< slant range of bin 0 [m] (input and image)
    double range_bin_m = 0.0;    //!< rho [m]
    double wavelength_m = 0.0;   //!< lambda of the carrier (subcarrier 0)
    //! Centre of the range spectrum [cycles/bin] (focuser_config::range_centre_cycles).
    double range_centre_cycles = 0.0;
    unsigned upsample = 8;       //!< U
    unsigned num_lines = 0;      //!< image lines
    double first_y_m = 0.0;      //!< along-track position of line 0 [m]
    double line_spacing_m = 0.0; //!< [m] (with line_step: the pulses' spacing)
    //! Line j at first_y_m + (j line_step) line_spacing_m, every line_step-th line of the
    //! num_lines line_step grid, and the image scaled by 1 / sqrt(num_lines line_step): the
    //! same pixels, bit for bit (1..4096; trajectory_autofocus: 1).
    unsigned line_step = 1;
    //! H: pixel (r0, y) is the scatterer (sqrt(r0^2 - H^2), y, 0)
    double reference_height_m = 0.0;
    //! Ground grid instead: pixel (j, k) is the point (first_x + k dx, y_j, ground_height).
    bool ground = false;
    double first_x_m = 0.0;       //!< cross-track position of column 0 [m]
    double x_spacing_m = 0.0;     //!< dx [m]
    double ground_height_m = 0.0; //!< z of the grid's plane [m]
    //! Range interpolation: 0 = the profile upsampled U times, linearly interpolated; an
    //! even 2..32 = a Kaiser-windowed sinc of that many taps on the input bins (U unused;
    //! exact BP only).
    unsigned sinc_taps = 0;
    //! Fast factorized back-projection: pulses per subaperture (0 or 1: exact BP).
    unsigned subaperture = 0;
    //! FFBP's beams per Nyquist beam of the subaperture's angular bandwidth (>= 1).
    double beam_oversample = 2.0;
    //! FFBP's polar levels (1..8): 1 = two-level (subapertures, then the image); n > 1:
    //! the subimages merged merge_factor at a time into the polar subimages of larger
    //! subapertures, n - 1 times, before the image (recursive FFBP).
    unsigned levels = 1;
    //! Subimages per merged subimage of recursive FFBP (2..16; levels > 1).
    unsigned merge_factor = 4;

    void validate() const;
};

/*!
 * \brief Time-domain back-projection of range-compressed pulses onto a slant-range x
 * along-track grid or a ground (x, y) grid (the second paper's imager, section 3), exact
 * or factorized (FFBP).
 *
 * Pixel (j, k): closest-approach slant range r0 = first_range + k rho, along-track
 * y = first_y + j dy, the scatterer at (g, y, 0), g = sqrt(r0^2 - H^2) (pixels with r0 <= H
 * stay 0). Per pulse n with antenna phase centre a_n:
 *  1. demodulate the profile by exp(-j 2 pi fc_r k) (its spectrum to 0), upsample it by U
 *     (K-point FFT, zero padding, U K-point inverse FFT: exact at the input bins);
 *  2. per pixel the exact distance R = |a_n - (g, y, 0)| in double precision, the profile
 *     at q = (R - first_range) / rho by linear interpolation of the upsampled samples
 *     (0 for q outside [0, K - 1]);
 *  3. phase correction exp(+j (4 pi R / lambda + 2 pi fc_r q)): the carrier and the
 *     remodulation of the range spectrum's centre, formed in cycles in double precision and
 *     reduced before a float sin/cos;
 *  4. coherent sum over the pulses, scaled by 1 / sqrt(M) at image() (M = num_lines
 *     line_step: the pulses of a whole aperture).
 * For the echo exp(-j 4 pi R / lambda) D(q - q_R) of range_ifft (D the Dirichlet kernel of
 * the N subcarriers), a unit target seen by all M pulses of the aperture focuses to
 * sqrt(N) M / sqrt(M) = sqrt(N M) at its pixel; white input noise of variance sigma^2 gives
 * pixel noise of about sigma^2 (unitary, as rd_focuser).
 * Short sinc (sinc_taps L > 0) instead of steps 1-2's upsampling and linear interpolation:
 * the demodulated profile at q by the L-tap Kaiser-windowed sinc of kernel::sinc_interpolator
 * (its table of 1024 phases, samples outside [0, K) zero).
 * Ground grid: the same per pixel with the point (x_k, y_j, h).
 *
 * FFBP (subaperture L > 1): the pulses of each add() call are taken L at a time. Each
 * subaperture, centred at c (its middle pulse's antenna), is back-projected as above onto a
 * polar grid around c: range r_i = first_range + i rho (the input's bins) times beams of
 * direction cosine u = (y - c_y) / r along track, each sample the point of the image surface
 * (z = 0, or the ground grid's height) at (r_i, u_b), and baseband-shifted by
 * exp(-j 2 pi (2 r / lambda + fc_r q_r)). Its beam spacing is the Nyquist spacing of the
 * subaperture's angular bandwidth, 1 / (2 cs D) with cs = 2 / lambda + fc_r / rho and D the
 * largest pulse distance from c (over sqrt(1 - u^2)), divided by beam_oversample. Every
 * beam is upsampled U times in range like a pulse; each pixel then takes the subimage at
 * its own (r, u) by linear interpolation in range and between beams, remodulated by
 * exp(+j 2 pi (2 r / lambda + fc_r q_r)). Work: L B K + M K per subaperture of L pulses
 * against L M K for BP (B beams, M lines): the speed-up approaches L when B << M; the
 * error falls with beam_oversample (linear interpolation between beams) and grows with L
 * (the subimage's curvature over a beam).
 * Recursive FFBP (levels n > 1): the subapertures of L pulses are merged F = merge_factor
 * at a time, n - 1 times, into the polar subimages of subapertures of L F, L F^2, ...
 * pulses (each centred at its middle pulse's antenna, its beams at the Nyquist spacing of
 * its own D, so their count grows with F): every point of the larger subimage takes each
 * smaller one at its own (r, u), bilinearly, remodulated; the largest are merged onto the
 * image as above. Work: L B K + (n - 1) F B' K per L pulses (B' the merged subimages'
 * beams per L pulses, about B) + M K per L F^(n-1) pulses; each level adds one bilinear
 * interpolation's error.
 * Speed: the distance and phase pass (double) and the interpolation pass (float) vectorise;
 * an AVX2/FMA build of both is chosen at run time; two threads split the lines (and FFBP's
 * beams).
 */
class NRSAR_API bp_focuser
{
public:
    explicit bp_focuser(const bp_grid& grid, unsigned num_threads = 1, bool allow_simd = true);
    ~bp_focuser();
    bp_focuser(const bp_focuser&) = delete;
    bp_focuser& operator=(const bp_focuser&) = delete;

    //! Zeroes the image and moves it to first_y_m (a new aperture).
    void reset(double first_y_m);
    /*!
     * Back-projects n pulses (line-major, n x K) from antenna positions (x, y, z) [m], one
     * per pulse, into the image.
     */
    void add(const gr_complex* pulses, unsigned n, const std::array<double, 3>* antenna);
    //! The image so far, num_lines x K line-major, scaled by 1 / sqrt(num_lines line_step)
    //! (written to out).
    void image(gr_complex* out) const;

    const bp_grid& grid() const { return d_grid; }
    unsigned num_threads() const { return d_threads; }
    bool simd() const { return d_simd; }
    //! Pulses added since the last reset.
    unsigned pulses() const { return d_pulses; }
    //! FFBP: beams of the last subaperture merged onto the image (0 for BP).
    unsigned beams() const { return d_beams; }

private:
    struct worker;
    bp_grid d_grid;
    unsigned d_threads;
    bool d_simd;
    unsigned d_pulses = 0;
    unsigned d_beams = 0;
    double d_surface_z = 0.0;     // z of the imaged surface (0, or the ground grid's height)
    std::vector<double> d_ground; // K: x of every column (slant: g, 0 where r0 <= H)
    std::vector<float> d_valid;   // K: 1 where the pixel has a ground point
    std::vector<gr_complex> d_image;
    std::vector<std::unique_ptr<worker>> d_workers;
    std::unique_ptr<sinc_interpolator> d_sinc; // sinc_taps > 0
    size_t d_stride = 0; // samples per prepared profile: U K, or K + taps (sinc, zero padded)

    //! Along-track y of image line j.
    double line_y(unsigned j) const
    {
        return d_grid.first_y_m +
               static_cast<double>(j * d_grid.line_step) * d_grid.line_spacing_m;
    }
    void upsample(worker& w, const gr_complex* pulse, gr_complex* out);
    void upsample_pulses(const gr_complex* pulses, unsigned n, gr_complex* prof);
    void project_lines(worker& w,
                       unsigned line0,
                       unsigned line1,
                       const gr_complex* profiles,
                       unsigned n,
                       const std::array<double, 3>* antenna);
    void add_bp(const gr_complex* pulses, unsigned n, const std::array<double, 3>* antenna);
    void add_ffbp(const gr_complex* pulses, unsigned n, const std::array<double, 3>* antenna);
    struct polar_node;
    unsigned node_pulses(unsigned depth, unsigned n) const;
    bool plan_node(polar_node& node, const std::array<double, 3>* antenna,
                   const polar_node* parent);
    void prepare_workers(unsigned Kp);
    void build_node(unsigned depth, const gr_complex* pulses,
                    const std::array<double, 3>* antenna);
    void back_project_leaf(polar_node& node, const gr_complex* pulses,
                           const std::array<double, 3>* antenna);
    void merge_child(polar_node& parent, const polar_node& child);
    void upsample_node(polar_node& node);
    void merge_onto_image(const polar_node& node);
    // FFBP scratch: the subaperture's profiles and one polar subimage per level of the tree
    // (depth 0 merges onto the image), built depth first.
    std::vector<gr_complex> d_prof;
    std::vector<std::unique_ptr<polar_node>> d_nodes;
    std::vector<gr_complex> d_base; // Kp: a polar row's baseband shift
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_BP_FOCUSER_H */
