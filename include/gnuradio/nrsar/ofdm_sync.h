/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_OFDM_SYNC_H
#define INCLUDED_NRSAR_OFDM_SYNC_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <cstdint>

namespace gr {
namespace nrsar {

/*!
 * \brief Base-station acquisition of the uplink burst: timing and fractional CFO from the
 * first PUSCH DMRS symbol (Schmidl & Cox), then a slot-aligned, CFO-corrected stream.
 * \ingroup nrsar
 *
 * A DMRS symbol (dmrs_config) carries data only on even subcarriers, so its body repeats with
 * period H = fft_size / 2. Metric (kernel::sc_acquirer):
 *   P(d) = sum_{m<H} conj(r[d+m]) r[d+m+H],  E(d) = sum_{m<2H} |r[d+m]|^2,
 *   M(d) = |P(d)|^2 / (E(d)/2)^2 in [0, 1].
 * M has a plateau over d in [d0 + D, d0 + cp] for a DMRS symbol starting at d0 (channel delay
 * spread D). Detection at the first M > threshold; the plateau is the window of cp + 1
 * positions around it with the largest sum of M; its start is the symbol start estimate
 * d0_hat (= d0 + D/2: the estimate sits D/2 after the first path), and the phase of P summed
 * over the middle half of the plateau (and over the same part of the slot's other DMRS
 * symbols, so lock waits for the last of them) gives the CFO: cfo = angle(sum P) Delta f / pi,
 * unambiguous for |CFO| < Delta f (30 kHz = 8.6 ppm at 3.5 GHz). Integer multiples of
 * 2 Delta f are not detected. The 38.211 DMRS sequence (dmrs.scrambling_id, slot within the
 * frame, symbol; kernel::dmrs_matcher) then refines d0_hat: the phase step between
 * neighbouring DMRS REs gives the symbol's start (1.7 samples rms at 3 dB per RE against the
 * plateau's 15-19). The stream must carry that sequence: a crossing that fits no sequence
 * (noise or data above the threshold, likely where H is short: 4% per position at `tiny`) is
 * rejected and the search goes on after its plateau window.
 *
 * Output (`out`): complex samples; output sample 0 is the first sample (CP start) of the slot
 * that holds the first detected DMRS symbol, moved earlier by the backoff:
 *   start = d0_hat - dmrs.symbols[0] (cp + fft_size) - round(backoff cp),
 * derotated by exp(-j 2 pi cfo t / fs) (t = output sample index; double-precision phase).
 * Nothing is output before lock. Samples before the input's first sample are zeros. The
 * backoff moves the FFT window of a downstream ofdm_demod (fft_start = cp) that many samples
 * into the CP, away from the next symbol: safe against late timing, at the price of a linear
 * phase exp(-j 2 pi (n - k0) b / fft_size) across the subcarriers (b = samples early, the
 * backoff plus the estimation error), which a per-subcarrier channel estimate absorbs.
 *
 * Tags on the output: tags::sync_key() on sample 0 of each acquisition (a dict: "cfo_hz"
 * double, "timing" int64 = input sample index of d0_hat, "start" int64 = input sample index
 * of output sample 0, "metric" double = Mmax); tags::symbol_key() (uint64 symbol index) and
 * tags::slot_key() (uint64 slot index) on the first sample of every slot, tags::frame_key()
 * (uint64) on every slots_per_frame-th slot. An acquisition numbers its slot by the DMRS
 * sequence the found symbol carries (modulo slots_per_frame; a burst starting at slot 0 is
 * numbered from 0; NR's base station would know the frame timing from its own downlink).
 * Input tags are not propagated: they belong to the transmitter's
 * timeline, which the base station does not know. Non-finite input samples are zeroed and
 * counted (after lock also tagged with tags::nonfinite_key()).
 *
 * Gaps (kernel::sync_tracker): an `rx_time` tag (uint64 s, double s) whose time does not
 * continue the previous stamp's gives the samples lost exactly; the slots that lost samples
 * are not output whole (the cut symbol is completed with zeros, the rest of the last cut slot
 * dropped) and output resumes at the next whole slot with its slot number. Without tags, a
 * per-slot test of the first DMRS symbol against the slot's own DMRS sequence (correlation
 * rho below a threshold of false-alarm probability 1e-9, or the symbol's start more than
 * max(backoff cp, cp / 8) samples early or cp / 2 late, in two consecutive slots) loses the
 * lock; a new search puts the DMRS found back on the slot grid, the gap modulo a slot from
 * its timing and the whole slots from its sequence's slot number (a gap known modulo a frame).
 * The CFO is kept. Counted: lost_samples(), rx_time_gaps(), lock_losses(), reacquisitions(),
 * skipped_slots(), skipped_symbols(). reset() or any message on the `reset` port starts a
 * fresh acquisition at the next input sample (output continues; the new first slot starts where
 * the new acquisition's output begins). Memory is bounded: before lock the block keeps
 * dmrs.symbols[0] (cp + fft_size) + cp + fft_size / 2 + backoff samples of history plus
 * the search span (up to the slot's last DMRS symbol while the CFO is refined).
 */
class NRSAR_API ofdm_sync : virtual public gr::block
{
public:
    typedef std::shared_ptr<ofdm_sync> sptr;

    /*!
     * \param num numerology (fft_size must be even)
     * \param dmrs DMRS layout of the slot; must have at least one DMRS symbol
     * \param threshold detection threshold on M, in (0, 1); the plateau value is about
     *        (snr / (1 + snr))^2 (snr: time-domain SNR of the DMRS symbol), pure noise or data
     *        gives M ~ Exp(mean 1/H), above t with probability exp(-t H) per independent position
     *        (H = fft_size / 2; e^-51 for sdr20 at 0.1). Default 0.1: detects a DMRS symbol
     *        whose time-domain SNR exceeds about -3.4 dB
     * \param backoff how far before the estimated slot start output sample 0 is placed, as a
     *        fraction of cp_samples, in [0, 1); default 0.125
     */
    static sptr make(const numerology& num,
                     const dmrs_config& dmrs,
                     double threshold = 0.1,
                     double backoff = 0.125);

    //! True once the current acquisition has locked.
    virtual bool locked() const = 0;
    //! CFO estimate [Hz] (0 before lock).
    virtual double cfo_hz() const = 0;
    //! Input sample index of the estimated start of the first detected DMRS symbol (-1 before lock).
    virtual std::int64_t timing_samples() const = 0;
    //! Input sample index that became output sample 0 of this acquisition (may be negative).
    virtual std::int64_t start_samples() const = 0;
    //! Peak metric Mmax of the lock (0 before lock).
    virtual double metric() const = 0;
    virtual double threshold() const = 0;
    //! Threshold for the next acquisition, in (0, 1).
    virtual void set_threshold(double threshold) = 0;
    virtual double backoff() const = 0;
    //! Starts a new acquisition at the next input sample.
    virtual void reset() = 0;
    //! Non-finite input samples replaced by 0 so far.
    virtual std::uint64_t nonfinite_count() const = 0;
    //! Samples lost in gaps: exact from rx_time jumps, plus the shift (modulo a slot) that a
    //! re-acquisition after a lost lock found.
    virtual std::uint64_t lost_samples() const = 0;
    //! Times the slot grid was re-established after a gap (from an rx_time jump, or a new
    //! search after a lost lock); reset() is not counted.
    virtual std::uint64_t reacquisitions() const = 0;
    //! Times the per-slot DMRS check lost the lock (or an rx_time stamp went back in time).
    virtual std::uint64_t lock_losses() const = 0;
    //! Slots with lost samples, or cut by a lost lock, that were not output whole.
    virtual std::uint64_t skipped_slots() const = 0;
    //! Symbols from the one a gap (or lost lock) cuts to the resumed slot's first.
    virtual std::uint64_t skipped_symbols() const = 0;
    //! rx_time stamps that did not continue the previous one (overflows).
    virtual std::uint64_t rx_time_gaps() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_SYNC_H */
