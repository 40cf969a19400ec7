/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_RANGE_IFFT_H
#define INCLUDED_NRSAR_KERNEL_RANGE_IFFT_H

#include <gnuradio/fft/window.h>
#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/fft_plans.h>
#include <gnuradio/nrsar/kernel/fft_size.h>
#include <volk/volk_alloc.hh>
#include <memory>

namespace gr {
namespace nrsar {
namespace kernel {

//! Bins [first, first + count) of a range crop.
struct bin_range {
    unsigned first = 0;
    unsigned count = 0;
};

/*!
 * \brief Range compression of one OFDM symbol, eq. (29) (SPEC section 5).
 *
 * out[k'] = (1/sqrt(N)) sum_{n<N} w[n] x[n] exp(+j 2 pi n k / fft_size), k = first + k',
 * k' < count: the unitary inverse DFT of eq. (29) over the N subcarriers, zero padded to
 * fft_size, windowed by w, cropped to count bins. The scale 1/sqrt(N) does not depend on
 * fft_size, so a full-band unit-amplitude target peaks at sqrt(N) * mean(w) with or
 * without padding (padding interpolates the same range profile, it adds no energy).
 */
class NRSAR_API range_ifft
{
public:
    /*!
     * \param n subcarriers N (input length)
     * \param fft_size transform length (0 means N), >= N
     * \param window window across the N subcarriers (WIN_NONE / WIN_RECTANGULAR: none)
     * \param window_param Kaiser beta, Tukey alpha, ... (gr::fft::window::build)
     * \param first_bin, num_bins output crop; num_bins 0 means up to the last bin
     */
    range_ifft(unsigned n,
               unsigned fft_size,
               gr::fft::window::win_type window = gr::fft::window::WIN_RECTANGULAR,
               double window_param = gr::fft::window::INVALID_WIN_PARAM,
               unsigned first_bin = 0,
               unsigned num_bins = 0);
    range_ifft(const range_ifft&) = delete;
    range_ifft& operator=(const range_ifft&) = delete;
    range_ifft(range_ifft&&) = default;
    range_ifft& operator=(range_ifft&&) = default;

    /*!
     * Compresses one symbol: in has n() samples, out num_bins(). A non-finite input sample
     * (NaN, Inf) is taken as 0; returns how many were.
     */
    std::size_t execute(const gr_complex* in, gr_complex* out);

    /*!
     * The two halves of execute() for a caller that writes the windowed symbol itself
     * (kernel::range_compress: the filter's pass writes it, so the symbol is touched once):
     * input() is the transform's zero-padded input, of which the first n() samples are the
     * caller's to write (w[n] x[n] / sqrt(N), finite); the padding stays zero. transform()
     * runs the IFFT on it and writes the num_bins() cropped bins to out.
     */
    gr_complex* input() { return d_fft->get_inbuf(); }
    void transform(gr_complex* out);
    //! w[n] / sqrt(N) for each float of the n() complex inputs (each tap twice).
    const float* window_taps2() const { return d_taps.data(); }

    void set_window(gr::fft::window::win_type window, double window_param);

    unsigned n() const { return d_n; }
    unsigned fft_size() const { return d_fft_size; }
    unsigned first_bin() const { return d_first; }
    unsigned num_bins() const { return d_count; }
    gr::fft::window::win_type window() const { return d_window_type; }
    double window_param() const { return d_window_param; }
    //! mean(w): the peak of a full-band target relative to the unwindowed peak.
    double coherent_gain() const { return d_coherent_gain; }
    //! The window (without the 1/sqrt(N) scale), length n().
    std::vector<float> window_taps() const;

    /*!
     * \brief Bins whose ranges k * bin_m lie in [r_min_m, r_max_m] (r_max_m <= 0: up to
     * the last bin): first = ceil(r_min/bin), last = floor(r_max/bin), both with a
     * 1e-9-bin tolerance so that a limit on a bin's own range includes that bin.
     * count 0 when the interval holds no bin. No validation (the block does that).
     */
    static bin_range crop_bins(double bin_m, unsigned fft_size, double r_min_m, double r_max_m);

private:
    unsigned d_n;
    unsigned d_fft_size;
    unsigned d_first;
    unsigned d_count;
    gr::fft::window::win_type d_window_type;
    double d_window_param;
    double d_coherent_gain = 1.0;
    volk::vector<float> d_taps; // w[n] / sqrt(N), twice (real and imaginary part)
    fft_rev d_fft;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_RANGE_IFFT_H */
