/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_TD_ECHO_H
#define INCLUDED_NRSAR_TD_ECHO_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/extended_scene.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/trajectory.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <limits>

namespace gr {
namespace nrsar {

/*!
 * \brief Time-domain monostatic echo of a point-target scene (the sample stream an SDR
 * would receive; the time-domain twin of scene_echo).
 * \ingroup nrsar
 *
 *     y(t) = sum_q sqrt(rcs_q) e^{j phase_q} x(t - tau_q(m)) e^{-j 2 pi (fc + k0 Delta f) tau_q(m)}
 *            + sigma z(t)
 *     tau_q(m) = 2 R_q(m) / c,  R_q(m) = sqrt(x_q^2 + H^2 + (y_p(m) - y_q)^2)  (eq. 8)
 *     y_p(m) = track_start + v m Tsym,   sigma^2 = scene.total_rcs() / 10^(snr_db / 10)
 *
 * x is the transmitted baseband stream of ofdm_mod (symbol 0 starts at the first input
 * sample, cp_samples + fft_size samples per symbol, subcarrier n at (n - k0) Delta f,
 * k0 = num.dc_subcarrier(), unitary IFFT). m is the symbol an output sample belongs to
 * (one delay per target and symbol, stop-and-go). The fractional delay is a Kaiser-windowed
 * sinc FIR of `taps` taps computed in double from the exact delay; samples before the
 * stream start are 0. With the delay inside the CP and eta small, ofdm_demod of y gives
 * eq. (7) (scene_echo's output); white noise of variance sigma^2 per sample is sigma^2
 * per RE after the unitary FFT, so snr_db has scene_echo's meaning (SNR per RE).
 *
 * Ports: in0 `tx` and out0 `echo`, gr_complex samples. Tags propagate. Non-finite input
 * samples are zeroed, counted (nonfinite_count()), logged once and reported by a
 * `nonfinite` tag (tags::nonfinite_key(), uint64 count of that work() call) on the
 * output at the first bad sample. The noise depends only on (seed, sample index).
 * Targets whose delay exceeds one OFDM symbol (possible after the aperture, as the
 * platform flies on) are left out and counted (dropped_paths()); delays below taps/2
 * samples lose the filter's look-ahead taps. Optional antenna beam (kernel::antenna_beam,
 * eqs. 1-3, as extended_scene_echo): target q's amplitude is multiplied by its two-way
 * beam gain at symbol m; the SNR still refers to the total RCS without beam.
 */
class NRSAR_API td_echo : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<td_echo> sptr;

    /*!
     * \param num numerology: sample rate fft_size Delta f, symbol length cp + fft_size,
     *        k0 = dc_subcarrier().
     * \param geo geometry: carrier fc, speed v, height H, track start (y at symbol 0).
     * \param scn point targets (x, y [m], rcs linear power, phase [rad]).
     *        check_scenario(num, geo, scn) must accept it (round trip within the CP over
     *        the aperture, eta < 0.1, ...); its warnings are logged.
     * \param snr_db SNR per resource element [dB] (total RCS over sigma^2); +inf
     *        (default): no noise; NaN and -inf are refused.
     * \param seed seed of the noise.
     * \param taps fractional-delay FIR length, even, 2 .. 256 (default 32: tone error
     *        below -80 dB at the paper numerology, docs/blocks/td_echo.md).
     * \param kaiser_beta Kaiser window parameter in [0, 50]; negative (default): from
     *        Kaiser's formula for `taps` and the numerology's band edge.
     * \param beam antenna illumination (default WHOLE_BLOCK, the paper's assumption;
     *        AZIMUTH / AZIMUTH_ELEVATION: sinc^2 two-way patterns of eqs. 1-3; Python
     *        nrsar.make_beam).
     * \param path the true flight path (exact range per symbol from path.position(m Tsym)
     *        in double; with attitude the beam turns with the body, antenna_beam::gain);
     *        empty (default) or trajectory::ideal(geo): the ideal line, bit-identical to a
     *        block without a path. A sampled path must cover [0, geo.aperture_s] and pass
     *        check_scenario(num, geo, scn, path).
     */
    static sptr make(const numerology& num,
                     const geometry& geo,
                     const scene& scn,
                     double snr_db = std::numeric_limits<double>::infinity(),
                     std::uint64_t seed = 0,
                     unsigned taps = 32,
                     double kaiser_beta = -1.0,
                     const kernel::antenna_beam& beam = kernel::antenna_beam(),
                     const trajectory& path = trajectory());

    //! New SNR per RE [dB] (+inf: no noise); takes effect at the next work() call.
    virtual void set_snr_db(double snr_db) = 0;
    virtual double snr_db() const = 0;
    //! sigma^2 per sample (= per RE), 0 without noise.
    virtual double noise_variance() const = 0;

    //! New scene (validated with check_scenario against the block's num and geo).
    virtual void set_scene(const scene& scn) = 0;
    virtual scene get_scene() const = 0;

    virtual unsigned taps() const = 0;
    virtual kernel::antenna_beam beam() const = 0;
    //! The true flight path (empty: the ideal line).
    virtual trajectory path() const = 0;
    //! The Kaiser beta in use (the default one when make() got a negative value).
    virtual double kaiser_beta() const = 0;

    //! Non-finite input samples zeroed so far.
    virtual std::uint64_t nonfinite_count() const = 0;
    //! (target, symbol) pairs left out because the delay exceeded one OFDM symbol.
    virtual std::uint64_t dropped_paths() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TD_ECHO_H */
