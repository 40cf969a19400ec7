/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_RANGE_COMPRESS_H
#define INCLUDED_NRSAR_RANGE_COMPRESS_H

#include <gnuradio/fft/window.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {

/*!
 * \brief Options of range_compress: tf_filter's (filter, snr_db, estimate_snr) and
 * range_ifft's (fft_size, window, window_param, r_min_m, r_max_m), with the same
 * meanings, defaults and limits as those blocks' make() parameters.
 */
struct NRSAR_API range_compress_config {
    filter_type filter = filter_type::WF;
    double snr_db = 20.0;      //!< SNR_in [dB] for WF, in [-100, 200]
    bool estimate_snr = false; //!< WF: estimate SNR_in from the data
    unsigned fft_size = 0;     //!< 0: N (no padding), otherwise >= N
    gr::fft::window::win_type window = gr::fft::window::WIN_RECTANGULAR;
    double window_param = gr::fft::window::INVALID_WIN_PARAM;
    double r_min_m = 0.0; //!< first slant range of the crop [m]
    double r_max_m = 0.0; //!< last slant range of the crop [m]; <= 0: the last bin
    //! S = 1 on every RE: no `reference` input (a reference branch's all-ones grid, not
    //! streamed); the same output as that input fed with ones
    bool unit_grid = false;
};

/*!
 * \brief tf_filter and range_ifft in one block: per-RE filter (eq. 25), window,
 * zero-padded unitary inverse FFT (eq. 29) and range crop of each symbol in one pass.
 * \ingroup nrsar
 *
 * Inputs: 0 (`echo`) the received grid Y, 1 (`reference`) the transmitted symbols S, both
 * N = num.num_subcarriers REs per item; with cfg.unit_grid input 0 only, S = 1.
 * Output (`out`): K = num_bins() range bins per item, exactly tf_filter followed by
 * range_ifft with the same parameters (the same roundings in the same order), without the
 * N-wide stream between them: the filter writes each windowed product straight into the
 * transform's padded input, so every symbol is read once and stays in the cache
 * (docs/blocks/range_compress.md). The separate blocks stay for graphs that need the
 * filtered grid itself (TF-domain presumming, pilot-only imaging).
 *
 * Tags: those of input 0 propagate (as tf_filter); tags::range_axis_key() (first bin
 * range [m], bin spacing [m], K) on the first output item and after set_window();
 * tags::nonfinite_key() (uint64 count) on an item whose input held NaN / Inf (zeroed).
 */
class NRSAR_API range_compress : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<range_compress> sptr;

    //! Every field of cfg checked as by tf_filter::make and range_ifft::make.
    static sptr make(const numerology& num,
                     const range_compress_config& cfg = range_compress_config());

    virtual void set_filter_type(gr::nrsar::filter_type type) = 0;
    virtual void set_snr_db(double snr_db) = 0;
    virtual void set_estimate_snr(bool estimate) = 0;
    //! tf_filter::set_snr_history: a strip task's start (docs/scale.md).
    virtual void set_snr_history(const std::vector<double>& history) = 0;
    //! tf_filter::snr_history.
    virtual std::vector<double> snr_history() const = 0;
    //! tf_filter::set_constant_modulus_path (default on).
    virtual void set_constant_modulus_path(bool on) = 0;
    //! Changes the window at run time (re-tags the range axis on the next item).
    virtual void set_window(gr::fft::window::win_type window, double window_param) = 0;

    virtual gr::nrsar::filter_type filter_type() const = 0;
    virtual double snr_db() const = 0;
    virtual bool estimate_snr() const = 0;
    //! Latest SNR_in estimate [dB]; NaN before the first valid estimate.
    virtual double estimated_snr_db() const = 0;
    virtual bool constant_modulus_path() const = 0;
    //! Items filtered by the constant-modulus shortcut so far.
    virtual std::uint64_t constant_modulus_items() const = 0;
    //! REs with an empty reference (|s|^2 = 0) seen so far.
    virtual std::uint64_t empty_re_count() const = 0;
    //! Non-finite input samples replaced by 0 so far.
    virtual std::uint64_t nonfinite_count() const = 0;

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
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_RANGE_COMPRESS_H */
