/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_TD_ECHO_H
#define INCLUDED_NRSAR_KERNEL_TD_ECHO_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/extended_scene.h>
#include <gnuradio/nrsar/kernel/gaussian_noise.h>
#include <gnuradio/nrsar/params.h>
#include <volk/volk_alloc.hh>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

//! One propagation path: delay in samples (>= 0) and complex gain (double).
struct echo_path {
    double delay_samples = 0.0;
    std::complex<double> gain = 1.0;
};

/*!
 * \brief Sum of fractionally delayed copies of a sampled band-limited signal,
 *
 *     y[k] = sum_p gain_p x(k - d_p),   x(t) = sum_i x[i] h(t - i),
 *     h(t) = sinc(t) w_Kaiser(t / (L/2)), |t| < L/2,
 *
 * as one FIR y[k] = sum_l g[l] x[k - l] over lags l = lag_lo .. lag_hi (taps computed in
 * double from the exact delays, no phase table; each path's taps are normalised to unit
 * DC gain; an integer delay gives the single tap 1, so it is exact). Taps at negative lags
 * (delays below L/2 samples) are dropped: the filter is causal. A path whose lags exceed
 * max_lag is dropped and counted.
 * Inner loop over the span lag_hi - lag_lo + 1: an AVX2/FMA loop (16 outputs per pass,
 * runtime dispatch) or, without AVX2, one volk_32fc_x2_dot_prod_32fc per output.
 */
class NRSAR_API multipath_fir
{
public:
    //! taps L even in [2, 256]; kaiser_beta in [0, 50]; max_lag >= L.
    multipath_fir(unsigned taps, double kaiser_beta, unsigned max_lag);
    multipath_fir(multipath_fir&&) = default;
    multipath_fir& operator=(multipath_fir&&) = default;
    multipath_fir(const multipath_fir&) = delete;
    multipath_fir& operator=(const multipath_fir&) = delete;

    /*!
     * Kaiser beta for L taps and a signal occupying |f| <= band_edge (cycles/sample):
     * Kaiser's design formula with the transition band 2 (0.5 - band_edge),
     * A = 14.36 * 2 (0.5 - band_edge) (L - 1) + 7.95 dB, capped at 150 dB.
     */
    static double default_beta(unsigned taps, double band_edge);

    unsigned taps() const { return d_taps; }
    double beta() const { return d_beta; }
    unsigned max_lag() const { return d_max_lag; }
    //! Lags of the current filter (lag_lo > lag_hi: no path).
    int lag_lo() const { return d_lag_lo; }
    int lag_hi() const { return d_lag_hi; }

    //! The continuous kernel h(t) in double (0 for |t| >= L/2).
    double kernel(double t) const;

    //! New paths; returns how many were dropped (delay beyond max_lag, or non-finite).
    std::size_t set_paths(const echo_path* paths, std::size_t n);

    /*!
     * y[i] = sum_l g[l] x[i - l], i < n. x[-max_lag() .. n) must be readable (the
     * caller's delay line). y must not alias x.
     */
    void filter(const gr_complex* x, gr_complex* y, std::size_t n) const;

    //! false: the VOLK dot-product loop even when the CPU has AVX2/FMA (tests, bench).
    void set_simd(bool allow);
    //! false: the AVX2 loop even when the CPU has AVX-512F (tests, bench; the same outputs).
    void set_avx512(bool allow);
    //! "avx512", "avx2" or "volk".
    const char* implementation() const
    {
        return d_simd ? (d_avx512 ? "avx512" : "avx2") : "volk";
    }

private:
    bool d_simd;
    bool d_avx512; //!< with d_simd: the AVX-512F loop
    unsigned d_taps;
    double d_beta;
    double d_i0_beta;
    unsigned d_max_lag;
    int d_lag_lo = 1, d_lag_hi = 0;
    std::vector<std::complex<double>> d_acc; //!< g over lags 0 .. max_lag (double)
    volk::vector<gr_complex> d_grev;         //!< g[lag_hi - i], i < span (float)
    mutable volk::vector<gr_complex> d_tail; //!< scratch of the AVX2 loop's last outputs
};

/*!
 * \brief Time-domain monostatic echo of a point-target scene (the time-domain twin of
 * kernel::scene_echo):
 *
 *     y(t) = sum_q sqrt(rcs_q) e^{j phase_q} x(t - tau_q(m)) e^{-j 2 pi (fc + k0 Delta f) tau_q(m)}
 *            + sigma z(t)
 *     tau_q(m) = 2 R_q(m) / c,  R_q(m) of eq. (8) at t_m = m Tsym,
 *
 * m = floor(k / (cp_samples + fft_size)) the OFDM symbol that output sample k belongs
 * to (stop-and-go: one delay per target and symbol), k0 = num.dc_subcarrier(). Delays,
 * phases and taps are computed in double per symbol (multipath_fir). With the unitary
 * OFDM modulator of the module (subcarrier n at (n - k0) Delta f), a delay inside the CP
 * and eta small, demodulating y gives eq. (7) exactly:
 * x(t - tau) puts S[n] e^{-j 2 pi (n - k0) Delta f tau} on subcarrier n, and the carrier
 * term completes it to e^{-j 2 pi (fc + n Delta f) tau} = e^{-j 4 pi (fc + n Delta f) R / c}.
 *
 * With an antenna beam (antenna_beam, eqs. 1-3) each target's amplitude is multiplied by
 * the two-way gain azimuth_gain(y_q - y_p(m), R_q(m)) elevation_gain(x_q) at symbol m;
 * targets with gain 0 (beyond the beam's cutoff) are left out. On a true flight path
 * (trajectory) R_q(m) = |(x_q, y_q, 0) - p(m Tsym)| in double and the gain is
 * antenna_beam::gain of the pose (attitude steers the footprint).
 *
 * Noise: sample i of symbol m is sigma z with z element i of block m of
 * kernel::gaussian_noise, independent of how the stream is cut.
 */
class NRSAR_API td_echo
{
public:
    /*!
     * \param taps fractional-delay FIR length (even, 2 .. 256).
     * \param kaiser_beta Kaiser window parameter; negative: default_beta for the band
     *        edge of num (max(k0, N - k0) / fft_size).
     * \param beam illumination (default WHOLE_BLOCK: every target lit all the time).
     * \param path the true flight path (empty or trajectory::ideal(geo): the ideal line,
     *        bit-identical to a td_echo without one; flies_ideal_line).
     * Validates num, geo, scn, beam, path; no scenario check here.
     */
    td_echo(const numerology& num,
            const geometry& geo,
            const scene& scn,
            unsigned taps = 32,
            double kaiser_beta = -1.0,
            const antenna_beam& beam = antenna_beam(),
            const trajectory& path = trajectory());
    td_echo(td_echo&&) = default;
    td_echo& operator=(td_echo&&) = default;
    td_echo(const td_echo&) = delete;
    td_echo& operator=(const td_echo&) = delete;

    void set_scene(const scene& scn);
    const scene& get_scene() const { return d_scene; }
    const antenna_beam& beam() const { return d_beam; }
    const trajectory& path() const { return d_path; }

    //! Samples per OFDM symbol, cp_samples + fft_size.
    unsigned symbol_samples() const { return d_sym; }
    //! Longest supported delay [samples]: one OFDM symbol. Longer paths are dropped.
    unsigned max_delay_samples() const { return d_sym; }
    //! Past input samples process() reads before x[0]: max_delay_samples() + taps / 2.
    unsigned history() const { return d_fir.max_lag(); }
    //! Highest |f| of the OFDM signal [cycles/sample], max(k0, N - k0) / fft_size.
    double band_edge() const;
    const multipath_fir& fir() const { return d_fir; }
    multipath_fir& fir() { return d_fir; }

    //! Delays [samples] and gains (carrier term included) of the targets at symbol m.
    std::vector<echo_path> paths(std::uint64_t m) const;

    /*!
     * y[i] = echo at absolute output sample s0 + i, i < n. x[i] is the input sample
     * s0 + i; x[-history() .. 0) the samples before it (zeros before the stream start).
     * noise/sigma: see the class comment (none when null or sigma = 0).
     * \return the number of (target, symbol) paths dropped so far.
     */
    std::uint64_t process(std::uint64_t s0,
                          const gr_complex* x,
                          gr_complex* y,
                          std::size_t n,
                          const gaussian_noise* noise = nullptr,
                          float sigma = 0.0f);

    std::uint64_t dropped_paths() const { return d_dropped; }

private:
    numerology d_num;
    geometry d_geo;
    scene d_scene;
    antenna_beam d_beam;
    trajectory d_path;
    bool d_line; //!< flies geo's ideal line
    unsigned d_sym;
    multipath_fir d_fir;
    std::uint64_t d_cur_m = ~std::uint64_t(0); //!< symbol whose paths d_fir holds
    std::uint64_t d_dropped = 0;
    std::vector<echo_path> d_paths;
    volk::vector<gr_complex> d_z; //!< one symbol of noise for partial symbols
    std::uint64_t d_z_m = ~std::uint64_t(0); //!< symbol, sigma and seed d_z was drawn for
    float d_z_sigma = 0.0f;
    std::uint64_t d_z_seed = 0;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_TD_ECHO_H */
