/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_OFDM_MOD_H
#define INCLUDED_NRSAR_OFDM_MOD_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/sync_interpolator.h>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * \brief CP-OFDM modulator: transmit grid (one symbol per item) -> time-domain samples.
 * \ingroup nrsar
 *
 * Input (`in`): one grid column per item, N = num.num_subcarriers REs.
 * Output (`out`): num.cp_samples + num.fft_size complex samples per input item, at
 * num.sample_rate_hz(): x[t] = (1/sqrt(fft_size)) sum_n S[n] exp(+j 2 pi (n - k0) t /
 * fft_size), t = -cp .. fft_size - 1, with k0 = num.dc_subcarrier(): subcarrier n at baseband
 * frequency (n - k0) Delta f, FFT bin (n - k0) mod fft_size. Unitary: ofdm_demod undoes it
 * exactly, and per-sample white noise of variance s2 becomes per-RE noise of variance s2.
 *
 * Tags: every input tag moves to the first sample (CP start) of its symbol; a NaN/Inf RE is
 * zeroed, counted (nonfinite_count()) and tagged with tags::nonfinite_key() on that sample.
 */
class NRSAR_API ofdm_mod : virtual public gr::sync_interpolator
{
public:
    typedef std::shared_ptr<ofdm_mod> sptr;

    /*!
     * \param num numerology: N, fft_size, cp_samples (validated)
     */
    static sptr make(const numerology& num);

    //! Output samples per symbol, cp_samples + fft_size.
    virtual unsigned symbol_length() const = 0;
    //! Non-finite input REs replaced by 0 so far.
    virtual std::uint64_t nonfinite_count() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_MOD_H */
