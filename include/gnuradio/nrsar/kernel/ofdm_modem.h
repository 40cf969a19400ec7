/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_OFDM_MODEM_H
#define INCLUDED_NRSAR_KERNEL_OFDM_MODEM_H

#include <gnuradio/nrsar/kernel/fft_plans.h>
#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <volk/volk_alloc.hh>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief CP-OFDM modulator: one grid column (N subcarriers) -> cp + fft_size samples.
 *
 * Subcarrier n (0 .. N-1) sits at baseband frequency (n - k0) Delta f, FFT bin
 * (n - k0) mod fft_size (k0 = numerology::dc_subcarrier()); the other bins are empty.
 * Unitary scaling: x[t] = (1/sqrt(fft_size)) sum_n S[n] exp(+j 2 pi (n - k0) t / fft_size),
 * t = -cp .. fft_size - 1 (the cyclic prefix is the last cp samples of the body).
 */
class NRSAR_API ofdm_modulator
{
public:
    ofdm_modulator(unsigned n, unsigned fft_size, unsigned cp, unsigned k0);
    ofdm_modulator(const ofdm_modulator&) = delete;
    ofdm_modulator& operator=(const ofdm_modulator&) = delete;
    ofdm_modulator(ofdm_modulator&&) = default;
    ofdm_modulator& operator=(ofdm_modulator&&) = default;

    //! in: n() REs, out: symbol_length() samples.
    void execute(const gr_complex* in, gr_complex* out);

    unsigned n() const { return d_n; }
    unsigned fft_size() const { return d_fft_size; }
    unsigned cp() const { return d_cp; }
    unsigned symbol_length() const { return d_cp + d_fft_size; }

private:
    unsigned d_n, d_fft_size, d_cp, d_k0;
    float d_scale;
    fft_rev d_fft;
};

/*!
 * \brief CP-OFDM demodulator: cp + fft_size samples -> N subcarriers.
 *
 * The FFT window starts fft_start samples into the symbol (fft_start <= cp; cp means right
 * after the CP): Y[n] = (1/sqrt(fft_size)) sum_t x[fft_start + t] exp(-j 2 pi (n - k0) t /
 * fft_size). For the modulator's output Y = S exp(-j 2 pi (n - k0) (cp - fft_start) / fft_size):
 * a window starting cp - fft_start samples early sees the symbol delayed by that much, a
 * linear phase across the subcarriers.
 */
class NRSAR_API ofdm_demodulator
{
public:
    ofdm_demodulator(unsigned n, unsigned fft_size, unsigned cp, unsigned k0, unsigned fft_start);
    ofdm_demodulator(const ofdm_demodulator&) = delete;
    ofdm_demodulator& operator=(const ofdm_demodulator&) = delete;
    ofdm_demodulator(ofdm_demodulator&&) = default;
    ofdm_demodulator& operator=(ofdm_demodulator&&) = default;

    //! in: symbol_length() samples, out: n() REs.
    void execute(const gr_complex* in, gr_complex* out);
    /*!
     * execute() when every sample of in is finite (the copy into the transform's input
     * carries the check: one pass over the symbol); false, and out untouched, when one is
     * not (the caller then guards the input and calls execute()).
     */
    bool execute_if_finite(const gr_complex* in, gr_complex* out);

    unsigned n() const { return d_n; }
    unsigned fft_size() const { return d_fft_size; }
    unsigned cp() const { return d_cp; }
    unsigned fft_start() const { return d_fft_start; }
    unsigned symbol_length() const { return d_cp + d_fft_size; }

private:
    //! The transform of the window in the FFT's input, scaled into the n() REs of out.
    void transform(gr_complex* out);

    unsigned d_n, d_fft_size, d_cp, d_k0, d_fft_start;
    float d_scale;
    fft_fwd d_fft;
};

/*!
 * \brief Frequency shifter with a double-precision phase: out[i] = in[i] exp(j phase_i),
 * phase_{i+1} = phase_i + 2 pi freq (freq in cycles per sample).
 *
 * VOLK's rotator (volk_32fc_s32fc_x2_rotator_32fc: float phasor, renormalised every few
 * hundred samples) makes the phasors of one block of 512 samples, seeded from the double
 * accumulator (wrapped to [-pi, pi)) at the block's start, so the phase error stays below 512
 * times the float rounding of the increment's angle (about 3e-5 rad) instead of growing with
 * the stream length. The blocks are counted from the last set_phase / set_frequency, not
 * from the start of a rotate() call, and the samples are multiplied by the block's stored
 * phasors: the output is the same however the stream is cut into calls (chunk invariance,
 * qa_chunking).
 */
class NRSAR_API phase_rotator
{
public:
    static constexpr std::size_t block = 512;
    explicit phase_rotator(double freq = 0.0) : d_freq(freq) {}
    //! New frequency from the current sample on (the phase there is kept).
    void set_frequency(double freq);
    double frequency() const { return d_freq; }
    //! Phase of the next sample; restarts the block grid there.
    void set_phase(double phase);
    double phase() const;
    void rotate(const gr_complex* in, gr_complex* out, std::size_t n);

private:
    double d_freq = 0.0;
    double d_block_phase = 0.0; // phase of the first sample of the current block
    std::uint64_t d_count = 0;  // samples rotated since the grid (re)started
    std::int64_t d_table_block = -1; // block whose phasors d_table holds
    volk::vector<gr_complex> d_table;
};

/*!
 * \brief Schmidl & Cox acquisition on a symbol whose body repeats with period fft_size / 2
 * (a PUSCH DMRS symbol: data only on even subcarriers).
 *
 * Metric at sample d, with H = fft_size / 2:
 *   P(d) = sum_{m=0}^{H-1} conj(r[d+m]) r[d+m+H]
 *   E(d) = sum_{m=0}^{2H-1} |r[d+m]|^2
 *   M(d) = |P(d)|^2 / (E(d)/2)^2   in [0, 1] (Cauchy-Schwarz)
 * P and E are running sums in double, recomputed exactly every 2^16 positions.
 * On the repeated symbol starting at d0 (cyclic prefix cp), M has a plateau for d in
 * [d0 + D, d0 + cp] (D: channel delay spread) with edges falling as (1 - e/H)^2.
 * Detection: the first d with M(d) > threshold (searching: VOLK products, running sums,
 * no division); M and P are then recomputed from cp + H/2 positions before it to
 * H + cp + H/2 after it. The plateau is the window of cp + 1 positions with the
 * largest sum of M (a matched filter to the plateau; with symmetric edges it starts at
 * d0 + D/2). Estimates:
 *   symbol start d0_hat = start of that window          (= d0 + D/2 with a delay spread D)
 *   CFO = angle(sum of P over the middle half of the window) / (2 pi H) cycles per sample,
 *   |CFO| < 1/(2H) (= Delta f: fractional CFO only).
 * The acquirer keeps the samples from (d - lookback) on so that the caller can output from
 * before the detected symbol; memory is bounded by lookback + 2 fft_size + a chunk.
 */
class NRSAR_API sc_acquirer
{
public:
    struct result {
        bool locked = false;
        std::int64_t symbol_start = 0; //!< d0_hat, absolute sample index
        double cfo = 0.0;              //!< cycles per sample
        double metric = 0.0;           //!< Mmax within the plateau window
        double plateau_first = 0.0;    //!< first position of the plateau window
        double plateau_last = 0.0;     //!< last position (plateau_first + cp)
        unsigned repeats_used = 1;     //!< repeated symbols whose P entered the CFO
    };

    sc_acquirer(unsigned fft_size, unsigned cp, double threshold, std::size_t lookback);
    sc_acquirer(const sc_acquirer&) = delete;
    sc_acquirer& operator=(const sc_acquirer&) = delete;
    sc_acquirer(sc_acquirer&&) = default;
    sc_acquirer& operator=(sc_acquirer&&) = default;

    /*!
     * Appends n samples (absolute indices continue from the previous call) and runs the
     * metric over every position it can. Returns true once locked; after that push() only
     * appends (the buffered samples are the caller's to drain).
     */
    bool push(const gr_complex* in, std::size_t n);
    const result& get() const { return d_res; }
    /*!
     * Further symbols with the same half-period structure at these offsets (samples, > 0)
     * after the detected one (e.g. the other DMRS symbols of the slot): their P over the same
     * plateau part is added before the CFO is taken (sqrt(K) less noise for K symbols). Lock
     * then waits until those samples have arrived.
     */
    void set_repeats(const std::vector<std::int64_t>& offsets);
    bool locked() const { return d_res.locked; }
    /*!
     * The lock failed the caller's test (a false alarm): unlocks and searches on after its
     * threshold crossing for plateau windows that start after the rejected one, over the
     * samples buffered already at the next push() (n = 0 allowed).
     */
    void reject();
    //! Forgets everything: next push() starts at absolute index 0 again.
    void reset();

    //! Buffered samples: absolute indices buffer_start() .. buffer_start() + buffered() - 1.
    std::int64_t buffer_start() const { return d_base; }
    std::size_t buffered() const { return d_buf.size(); }
    const gr_complex* buffer() const { return d_buf.data(); }
    //! Drops buffered samples with absolute index below abs (after the caller used them).
    void discard_before(std::int64_t abs);

    double threshold() const { return d_threshold; }
    void set_threshold(double t) { d_threshold = t; }

private:
    void recompute(std::int64_t d);
    bool search(std::int64_t end);
    bool try_refine(std::int64_t end);
    void finish();

    unsigned d_half, d_cp;
    double d_threshold;
    std::size_t d_lookback;
    std::vector<gr_complex> d_buf;
    std::int64_t d_base = 0;  // absolute index of d_buf[0]
    std::int64_t d_pos = 0;   // next metric position
    std::int64_t d_since_recompute = -1;
    std::complex<double> d_p = 0.0;
    double d_e = 0.0;
    bool d_collecting = false;
    std::int64_t d_first = 0; // first position above threshold
    std::int64_t d_floor = 0; // plateau windows start here or later (after a rejected one)
    std::int64_t d_m_start = 0; // position of d_m[0]
    std::vector<double> d_m;
    std::vector<std::complex<double>> d_pv;
    volk::vector<gr_complex> d_q; // conj(r[i]) r[i+H] of a search chunk
    volk::vector<float> d_g;      // |r[i]|^2 of a search chunk
    result d_res;
    std::vector<std::int64_t> d_repeats;
    bool d_refining = false;
    std::complex<double> d_psum = 0.0;
    std::int64_t d_cfo_window = 1;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_OFDM_MODEM_H */
