/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_RANGE_IFFT_H
#define INCLUDED_NRSAR_RANGE_IFFT_H

#include <gnuradio/fft/window.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/sync_block.h>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * \brief Range compression, eq. (29) (SPEC section 5): windowed, zero-padded, unitary
 * inverse FFT over the subcarriers of each symbol, cropped to a range window.
 * \ingroup nrsar
 *
 * Input (`in`): one TF-filtered symbol per item, N = num.num_subcarriers REs.
 * Output (`out`): K = num_bins() range bins per item, bin k (k = first_bin() .. first_bin()
 * + K - 1 of the fft_size-point transform) at slant range k c / (2 fft_size Delta f).
 *
 * out[k] = (1/sqrt(N)) sum_n w[n] x[n] exp(+j 2 pi n k / fft_size): the 1/sqrt(N) of
 * eq. (29) is kept whatever the padding, so a full-band unit-amplitude target peaks at
 * sqrt(N) * mean(w) (mean(w) = coherent_gain(), 1 without a window).
 *
 * Tags: tags::range_axis_key() with the tuple (first bin range [m] (double), bin spacing
 * [m] (double), K (uint64)) on the first output item and after every parameter change;
 * tags::nonfinite_key() (uint64 count) on an item whose input held NaN/Inf (zeroed).
 * Input tags propagate.
 */
class NRSAR_API range_ifft : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<range_ifft> sptr;

    /*!
     * \param num numerology: N = num.num_subcarriers inputs per item, Delta f for the axis
     * \param fft_size IFFT length: 0 means N (no padding), otherwise >= N; see
     *        fast_fft_size() for a fast choice
     * \param window window across the N subcarriers before the IFFT (gr::fft::window),
     *        default WIN_RECTANGULAR (none)
     * \param window_param Kaiser beta, Tukey alpha, Gaussian sigma, exponential d (these
     *        windows need it); ignored by the others, for which -1 (INVALID_WIN_PARAM) is fine
     * \param r_min_m first slant range of the crop [m], >= 0 and below c/(2 Delta f)
     * \param r_max_m last slant range of the crop [m]; <= 0 means up to the last bin,
     *        otherwise in [r_min_m, c/(2 Delta f)]; bins ceil(r_min/bin) .. floor(r_max/bin)
     */
    static sptr make(const numerology& num,
                     unsigned fft_size = 0,
                     gr::fft::window::win_type window = gr::fft::window::WIN_RECTANGULAR,
                     double window_param = gr::fft::window::INVALID_WIN_PARAM,
                     double r_min_m = 0.0,
                     double r_max_m = 0.0);

    //! Smallest 2^a 3^b 5^c 7^d >= n (see kernel::fast_fft_size for why).
    static unsigned fast_fft_size(unsigned n);

    //! Changes the window at run time (re-tags the range axis on the next item).
    virtual void set_window(gr::fft::window::win_type window, double window_param) = 0;

    virtual gr::fft::window::win_type window() const = 0;
    virtual double window_param() const = 0;
    //! K: bins per output item.
    virtual unsigned num_bins() const = 0;
    //! Index of the first output bin in the fft_size-point transform.
    virtual unsigned first_bin() const = 0;
    //! Slant range of the first output bin [m].
    virtual double range_axis_first_m() const = 0;
    //! Slant-range bin spacing c / (2 fft_size Delta f) [m].
    virtual double range_bin_m() const = 0;
    virtual unsigned fft_size() const = 0;
    //! mean(w) of the window in use.
    virtual double coherent_gain() const = 0;
    //! Non-finite input samples replaced by 0 so far.
    virtual std::uint64_t nonfinite_count() const = 0;
    /*!
     * Threads per work() call, 1 (default) or 2: with 2, the second half of the call's
     * symbols is transformed on a persistent second thread (kernel::split_worker) with its
     * own FFT plan. See docs/performance.md ("Two cores") for when it pays.
     */
    virtual void set_threads(unsigned threads) = 0;
    virtual unsigned threads() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_RANGE_IFFT_H */
