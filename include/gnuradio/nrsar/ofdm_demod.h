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
#include <gnuradio/block.h>
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
 *
 * rx_time alignment (tx_start_time >= 0; off by default, then the block is a plain
 * 1-in-(cp + fft_size) decimator): an `rx_time` tag (pmt tuple (uint64 whole seconds,
 * double fractional seconds), as a UHD source puts on its first sample and on the first
 * sample after an overflow) on input sample s stamps its time T; the TX started symbol 0 at
 * tx_start_time T0, i.e. at input sample s + round((T0 - T) fs), fs = num.sample_rate_hz().
 * Samples before that (or before the next whole symbol when the stamp falls inside a
 * symbol) are dropped; the first output vector after a stamp is the symbol its time says,
 * tagged `symbol` (uint64 index), and every slot start is tagged `symbol` and `slot`.
 * Samples before the first stamp are dropped (their time is unknown). Symbols lost to a
 * late start or an overflow are output as zero vectors (output item k stays symbol k, so a
 * radar's reference grid and slow time go on; the image loses their share), counted and
 * logged, as are the dropped samples.
 */
class NRSAR_API ofdm_demod : virtual public gr::block
{
public:
    typedef std::shared_ptr<ofdm_demod> sptr;

    /*!
     * \param num numerology: N, fft_size, cp_samples (validated)
     * \param fft_start FFT window start within the symbol, 0 .. cp_samples; a negative value
     *        means cp_samples (right after the CP, the default)
     * \param tx_start_time device time [s] at which the transmitter sent the first sample of
     *        symbol 0 (timed start); negative (default -1) turns the rx_time alignment off.
     *        Precise to the double's ulp (use device times reset near 0, as the examples do;
     *        add a calibrated fixed TX->RX hardware delay d samples as d / fs)
     */
    static sptr make(const numerology& num, int fft_start = -1, double tx_start_time = -1.0);

    virtual unsigned fft_start() const = 0;
    //! Input samples per symbol, cp_samples + fft_size.
    virtual unsigned symbol_length() const = 0;
    //! Non-finite input samples replaced by 0 so far.
    virtual std::uint64_t nonfinite_count() const = 0;

    //! TX start time [s] of the rx_time alignment; negative = alignment off.
    virtual double tx_start_time() const = 0;
    //! Sets the TX start time (negative: off); waits for the next rx_time tag to re-align.
    virtual void set_tx_start_time(double t) = 0;
    //! True once an rx_time tag has aligned the stream (alignment on).
    virtual bool aligned() const = 0;
    //! Symbol index of the next output vector (alignment on; else the output count).
    virtual std::uint64_t next_symbol() const = 0;
    //! Symbols output as zeros: the receiver started after them or lost samples (overflow).
    virtual std::uint64_t lost_symbols() const = 0;
    //! Input samples dropped by the alignment (before TX start, partial symbols, no stamp yet).
    virtual std::uint64_t dropped_samples() const = 0;
    //! rx_time tags seen.
    virtual std::uint64_t rx_time_tags() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_DEMOD_H */
