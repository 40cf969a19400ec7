/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_AUTOFOCUS_H
#define INCLUDED_NRSAR_KERNEL_AUTOFOCUS_H

#include <gnuradio/nrsar/kernel/fft_plans.h>
#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/autofocus_config.h>
#include <volk/volk_alloc.hh>
#include <cstddef>
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*
 * Autofocus of one focused image (lines x bins, row-major: one azimuth line of `bins`
 * range bins after the other, as the focusers stream them).
 *
 * Model: the azimuth phase error the navigation did not know multiplies the image's
 * azimuth spectrum, G_err(p, k) = G(p, k) exp(j phi(p)), with G the unitary DFT over the M
 * lines of range bin k and p = 0..M-1 the DFT bin (Doppler p / (M T), aliased). For a
 * target that sees the whole aperture, bin p is one slow time of its phase history, so
 * phi is the per-pulse error mapped through the target's Doppler history. The constant
 * and linear parts of phi do not defocus (a phase and a shift) and are not estimated:
 * every estimate comes back with its energy-weighted constant and linear fit removed
 * (weights w(p) = sum_k |G(p, k)|^2 over the targets' band, config support_db; frequency unwrapped from the weakest stretch of w, so
 * a band across DFT bin 0 is one piece), so the corrected image stays where it was.
 */
struct NRSAR_API autofocus_result {
    std::vector<double> phase_rad; //!< phi(p), p = 0..M-1 (DFT order) [rad]
    std::vector<double> weight;    //!< w(p) of the input image inside the band, 0 outside
    double phase_rms_rad = 0.0;    //!< sqrt(sum w phi^2 / sum w)
    double entropy_before = 0.0;   //!< image_entropy of the input
    double entropy_after = 0.0;    //!< and of the corrected image
    unsigned iterations = 0;
};

//! The image's grid: slant range of bin k = range_first_m + k range_step_m, lines
//! line_spacing_m apart along track (the focusers' range_axis / azimuth_axis tags).
//! All three > 0 (and config wavelength_m > 0) turn PGA's deramp on.
struct NRSAR_API image_axes {
    double range_first_m = 0.0;
    double range_step_m = 0.0;
    double line_spacing_m = 0.0;
};

/*!
 * \brief Removes the weighted least-squares fit a + b u from phi in place, u = (p - start)
 * mod n the frequency unwrapped from bin `start` (p = 0..n-1; weights w >= 0). The fit
 * is a phase and a circular shift wherever the band does not straddle `start`.
 */
NRSAR_API void
remove_linear_phase(double* phi, const double* w, std::size_t n, std::size_t start = 0);

/*!
 * \brief Estimates and removes the azimuth phase error of images. Owns its FFTs
 * (re-planned only when M changes) and work buffers. Movable, not copyable.
 */
class NRSAR_API autofocus
{
public:
    explicit autofocus(const autofocus_config& cfg);
    ~autofocus();
    autofocus(autofocus&&) noexcept;
    autofocus& operator=(autofocus&&) noexcept;
    autofocus(const autofocus&) = delete;
    autofocus& operator=(const autofocus&) = delete;

    const autofocus_config& config() const { return d_cfg; }

    /*!
     * \brief Estimates phi of img (lines x bins) and corrects img in place (its spectrum
     * times exp(-j phi)). Method NONE leaves img as it is and returns phi = 0.
     * Throws std::invalid_argument for lines < 4 or bins < 1.
     */
    autofocus_result
    focus(gr_complex* img, std::size_t lines, std::size_t bins, const image_axes& axes = {});

private:
    autofocus_config d_cfg;
    std::size_t d_M = 0, d_K = 0;
    fft_fwd d_fwd;
    fft_rev d_rev;
    volk::vector<gr_complex> d_spec;  // K x M: azimuth spectrum of the input, range-major
    volk::vector<gr_complex> d_work;  // K x M: corrected image / PGA's windowed lines
    std::vector<double> d_phi;        // M: the estimate so far
    std::vector<double> d_weight;     // M
    image_axes d_axes;

    void plan(std::size_t lines, std::size_t bins);
    void image_of(const double* phi);       // d_work = IDFT(d_spec exp(-j phi)), range-major
    double entropy_of_work() const;
    unsigned run_pga();
    void undo_range_coupling(gr_complex* G,
                             std::size_t k,
                             double r,
                             const std::vector<double>& peak,
                             const std::vector<std::size_t>& at,
                             double kw) const;
    unsigned run_entropy();
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_AUTOFOCUS_H */
