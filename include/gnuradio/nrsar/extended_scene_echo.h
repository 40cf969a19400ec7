/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_EXTENDED_SCENE_ECHO_H
#define INCLUDED_NRSAR_EXTENDED_SCENE_ECHO_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/extended_scene.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <limits>
#include <vector>

namespace gr {
namespace nrsar {

/*!
 * \brief TF-domain echo of an extended scene: reflectivity maps (optionally speckled)
 * plus point targets, with an optional antenna footprint, eqs. (1)-(3), (7), (8).
 * \ingroup nrsar
 *
 *     Y[n,m] = S[n,m] sum_k a_k g_k(m) exp(-j 4 pi (fc + n Delta f) R_k(m) / c) + Z[n,m]
 *
 * R_k(m) is the exact range (8); g_k(m) the two-way beam amplitude (1 with
 * beam_mode::WHOLE_BLOCK, the paper's assumption); Z ~ CN(0, sigma^2),
 * sigma^2 = total_power() / 10^(snr_db/10). The sum is evaluated by kernel::extended_scene
 * (spreading on an oversampled slant-range grid + FFT), not K x N rotations.
 *
 * Ports (vectors of N = num.num_subcarriers gr_complex, one per OFDM symbol):
 * - in0 `tx`: the transmit grid S.
 * - out0 `echo`: Y.
 * - out1 `reference` (optional): H[n,m], the echo of S = 1 without noise.
 *
 * Tags: input tags propagate to both outputs; non-finite input samples are zeroed,
 * counted, logged once and tagged with tags::nonfinite_key() on out0.
 */
class NRSAR_API extended_scene_echo : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<extended_scene_echo> sptr;

    /*!
     * \param num numerology; N = num.num_subcarriers is the vector length of every port.
     * \param geo geometry: fc, v, H, track start.
     * \param points point targets added on top of the maps (may be empty).
     * \param maps reflectivity maps (kernel::reflectivity_map: nx x ny complex amplitudes,
     *        spacing dx, dy [m], origin x0, y0 [m], optional seeded speckle).
     * \param beam illumination: WHOLE_BLOCK (default), AZIMUTH (eq. 1, two-way sinc^2)
     *        or AZIMUTH_ELEVATION (eqs. 1-3); apertures D_a, D_e [m], boresight theta_c.
     * \param snr_db SNR per RE [dB] = total_power() / sigma^2; +inf (default): no noise.
     * \param seed noise seed (the noise of symbol m depends on (seed, m) only).
     * \param taps interpolation kernel length L (even, 2..32, default 8).
     * \param oversampling slant-range grid oversampling O (1.25..8, default 2).
     * \param path the true flight path (exact range per symbol and scatterer from
     *        path.position(m Tsym) in double, the beam's gain from the pose per symbol,
     *        attitude steering it); empty (default) or trajectory::ideal(geo): the ideal
     *        line, bit-identical to a block without a path.
     * The bounding box of the scatterers must pass check_scenario (CP, eta, range).
     */
    static sptr make(const numerology& num,
                     const geometry& geo,
                     const scene& points,
                     const std::vector<kernel::reflectivity_map>& maps,
                     const kernel::antenna_beam& beam = kernel::antenna_beam(),
                     double snr_db = std::numeric_limits<double>::infinity(),
                     std::uint64_t seed = 0,
                     unsigned taps = 8,
                     double oversampling = 2.0,
                     const trajectory& path = trajectory());

    virtual void set_snr_db(double snr_db) = 0;
    virtual double snr_db() const = 0;
    //! sigma^2 = total_power() / 10^(snr_db/10), 0 without noise.
    virtual double noise_variance() const = 0;
    //! Sum of |a_k|^2 of all scatterers (after speckle; beam not applied).
    virtual double total_power() const = 0;
    //! Scatterers kept (non-zero, inside the elevation cutoff).
    virtual std::uint64_t num_scatterers() const = 0;
    //! Size P of the slant-range grid and of its FFT.
    virtual unsigned grid_size() const = 0;
    virtual std::uint64_t nonfinite_count() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_EXTENDED_SCENE_ECHO_H */
