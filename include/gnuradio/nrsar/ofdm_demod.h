/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_OFDM_DEMOD_H
#define INCLUDED_NRSAR_OFDM_DEMOD_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/sync_decimator.h>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * \brief CP-OFDM demodulator: time-domain samples -> one grid column per symbol.
 * \ingroup nrsar
 *
 * Input (`in`): complex samples, symbol-aligned (sample 0 = CP start of a symbol), each
 * symbol cp_samples + fft_size long. Output (`out`): N = num.num_subcarriers REs per item:
 * Y[n] = (1/sqrt(fft_size)) sum_{t=0}^{fft_size-1} x[fft_start + t] exp(-j 2 pi (n - k0) t /
 * fft_size), k0 = num.dc_subcarrier() (the inverse of ofdm_mod).
 *
 * With fft_start = cp_samples (default) an echo delayed by 0 .. CP gives exactly the TF
 * model of SPEC section 3. An earlier window (fft_start < cp) multiplies subcarrier n by
 * exp(-j 2 pi (n - k0) (cp - fft_start) / fft_size) (the symbol appears cp - fft_start
 * samples late in the window), in exchange for tolerance of late timing.
 *
 * Tags: a tag on input sample s goes to output item floor(s / (cp + fft_size)) (the symbol
 * the sample falls in). NaN/Inf samples are zeroed, counted and tagged
 * (tags::nonfinite_key()) on the output item.
 */
class NRSAR_API ofdm_demod : virtual public gr::sync_decimator
{
public:
    typedef std::shared_ptr<ofdm_demod> sptr;

    /*!
     * \param num numerology: N, fft_size, cp_samples (validated)
     * \param fft_start FFT window start within the symbol, 0 .. cp_samples; a negative value
     *        means cp_samples (right after the CP, the default)
     */
    static sptr make(const numerology& num, int fft_start = -1);

    virtual unsigned fft_start() const = 0;
    //! Input samples per symbol, cp_samples + fft_size.
    virtual unsigned symbol_length() const = 0;
    //! Non-finite input samples replaced by 0 so far.
    virtual std::uint64_t nonfinite_count() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_DEMOD_H */
