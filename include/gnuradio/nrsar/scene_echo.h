/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_SCENE_ECHO_H
#define INCLUDED_NRSAR_SCENE_ECHO_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/trajectory.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <limits>

namespace gr {
namespace nrsar {

/*!
 * \brief TF-domain echo of a point-target scene: eq. (7) with the exact range (8).
 * \ingroup nrsar
 *
 *     Y[n,m] = sum_q alpha_q S[n,m] exp(-j 4 pi (fc + n Delta f) R_q(m) / c) + Z[n,m]
 *     R_q(m) = sqrt(x_q^2 + H^2 + (y_p(m) - y_q)^2),  y_p(m) = track_start + v m Tsym
 *     alpha_q = sqrt(rcs_q) exp(j phase_q),  Z ~ CN(0, sigma^2),
 *     sigma^2 = scene.total_rcs() / 10^(snr_db / 10)   (SNR per RE, SPEC section 2)
 *
 * n = 0 .. N-1 is the subcarrier index; m is the absolute index of the input item
 * (nitems_read), so an endless stream keeps the platform moving along the track.
 *
 * Ports (vectors of N = num.num_subcarriers gr_complex, one per OFDM symbol):
 * - in0 `tx`: the transmit grid S.
 * - out0 `echo`: Y.
 * - out1 `reference` (optional): H[n,m], the same echo with S = 1 and Z = 0 (the
 *   reference branch of SPEC section 8; deterministic).
 *
 * Tags: input tags propagate to both outputs. Non-finite input samples are zeroed,
 * counted (nonfinite_count()), logged once and reported by a `nonfinite` tag
 * (tags::nonfinite_key(), uint64 count in that symbol) on out0 at that symbol.
 *
 * The noise of symbol m depends only on (seed, m): the output does not depend on how
 * the scheduler cuts the stream (kernel::gaussian_noise).
 */
class NRSAR_API scene_echo : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<scene_echo> sptr;

    /*!
     * \param num numerology; N = num.num_subcarriers is the vector length of every port,
     *        Delta f and Tsym set the subcarrier frequencies and the slow time.
     * \param geo geometry: carrier fc, speed v, height H, track start (y at m = 0).
     * \param scn point targets (x, y on the ground [m], rcs linear power, phase [rad]).
     *        check_scenario(num, geo, scn) must accept it (round trip within the CP,
     *        eta < 0.1, inside the unambiguous range); its warnings are logged.
     * \param snr_db input SNR per resource element [dB], total RCS over sigma^2;
     *        +inf (default) turns the noise off; NaN and -inf are refused.
     * \param seed seed of the noise (a given seed gives the same noise on every run).
     * \param path the true flight path the echo is computed from (exact range per symbol
     *        from path.position(m Tsym), double); empty (default) or trajectory::ideal(geo):
     *        the ideal line, every output bit-identical to a block without a path. A
     *        sampled path must cover [0, geo.aperture_s] and pass check_scenario(num, geo,
     *        scn, path) (targets in front of the antenna, round trips within the CP).
     */
    static sptr make(const numerology& num,
                     const geometry& geo,
                     const scene& scn,
                     double snr_db = std::numeric_limits<double>::infinity(),
                     std::uint64_t seed = 0,
                     const trajectory& path = trajectory());

    //! New SNR per RE [dB] (+inf: no noise); takes effect at the next work() call.
    virtual void set_snr_db(double snr_db) = 0;
    virtual double snr_db() const = 0;
    //! sigma^2 = total RCS / 10^(snr_db/10), 0 without noise.
    virtual double noise_variance() const = 0;

    //! New scene (validated with check_scenario against the block's num and geo).
    virtual void set_scene(const scene& scn) = 0;
    virtual scene get_scene() const = 0;
    //! The true flight path (empty: the ideal line).
    virtual trajectory path() const = 0;

    //! Non-finite input samples zeroed so far.
    virtual std::uint64_t nonfinite_count() const = 0;

    /*!
     * Threads computing the echo: 1 (default, the scheduler's thread) or 2 (a
     * persistent second thread, kernel::split_worker, takes the second half of each work()
     * call of at least 4 symbols). The output does not depend on it. See docs/blocks/scene_echo.md for when it pays.
     */
    virtual void set_threads(unsigned threads) = 0;
    virtual unsigned threads() const = 0;

    /*!
     * Reference only (set before the graph starts): out0 carries H[n,m], the `reference`
     * port's values, and out1 must stay unconnected. Y is not computed: the input paces the
     * block (m = nitems_read) and brings its tags, its samples are not read (no non-finite
     * count). For a graph that needs only the noise-free reference (nrsar-isac's reference
     * branch, whose echo comes from td_echo): no Y to compute, store and throw away.
     */
    virtual void set_reference_only(bool on) = 0;
    virtual bool reference_only() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_SCENE_ECHO_H */
