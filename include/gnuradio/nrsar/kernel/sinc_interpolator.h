/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_SINC_INTERPOLATOR_H
#define INCLUDED_NRSAR_KERNEL_SINC_INTERPOLATOR_H

#include <gnuradio/fft/window.h>
#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <volk/volk_alloc.hh>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Truncated windowed-sinc interpolator of a sampled band-limited sequence, eq. (41).
 *
 * The value at fractional position pos = i + mu (i = floor(pos), 0 <= mu < 1) is
 * sum_{j = -L/2+1}^{L/2} in[i + j] h(j - mu), h(x) = sinc(x) w(x / (L/2)), with samples
 * outside [0, n) taken as zero. The taps are tabulated at `phases` fractional shifts (nearest
 * phase is used, so the shift error is at most 1 / (2 phases) samples) and each phase is
 * normalised to unit DC gain, so a constant is reproduced exactly.
 * Windows: WIN_RECTANGULAR / WIN_NONE, WIN_HANN, WIN_HAMMING, WIN_BLACKMAN, WIN_KAISER (beta).
 */
class NRSAR_API sinc_interpolator
{
public:
    sinc_interpolator(unsigned taps = 16,
                      gr::fft::window::win_type window = gr::fft::window::WIN_KAISER,
                      double window_param = 6.0,
                      unsigned phases = 1024);
    sinc_interpolator(const sinc_interpolator&) = delete;
    sinc_interpolator& operator=(const sinc_interpolator&) = delete;
    sinc_interpolator(sinc_interpolator&&) = default;
    sinc_interpolator& operator=(sinc_interpolator&&) = default;

    unsigned taps() const { return d_taps; }
    unsigned phases() const { return d_phases; }

    //! The continuous kernel h(x) = sinc(x) w(x / (L/2)) in double (0 for |x| >= L/2).
    double kernel(double x) const;

    //! Value of in[0..n) at fractional position pos (table taps; zeros outside [0, n)).
    gr_complex at(const gr_complex* in, int n, double pos) const;

    /*!
     * \brief out[k] = value of in at position k + shift[k], k < n (the RCMC resampling of
     * one Doppler column: shift[k] is the migration Delta k of range bin k, eq. (41)).
     */
    void resample(const gr_complex* in, int n, const float* shift, gr_complex* out) const;

    //! The taps of the phase nearest mu in [0, 1]: h(j - mu + 1 - L/2), j < L.
    const float* phase_taps(double mu) const;

private:
    unsigned d_taps;
    unsigned d_phases;
    gr::fft::window::win_type d_window;
    double d_window_param;
    double d_i0_beta; // I0(beta) for the Kaiser window
    volk::vector<float> d_table; // (phases + 1) x taps

    double window(double u) const; // u in [-1, 1]
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_SINC_INTERPOLATOR_H */
