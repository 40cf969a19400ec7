/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_SCENE_ECHO_H
#define INCLUDED_NRSAR_KERNEL_SCENE_ECHO_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/gaussian_noise.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/trajectory.h>
#include <volk/volk_alloc.hh>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {
namespace echo_detail {

constexpr unsigned lanes = 8;       //!< subcarriers advanced together
constexpr unsigned max_targets = 4; //!< targets summed per pass over a block

//! One target at the start of a block: phasors of the first 8 subcarriers (exact,
//! from double) and the step exp(-j 4 pi 8 Delta f R / c) that advances all 8 lanes.
struct alignas(32) target_lanes {
    float v[2 * lanes];
    float step[2];
};

} // namespace echo_detail

/*!
 * \brief TF echo of a point-target scene, one OFDM symbol at a time: eq. (7) with the
 * exact range (8),
 *
 *     H[n, m] = sum_q alpha_q exp(-j 4 pi (fc + n Delta f) R_q(m) / c),  n = 0 .. N-1
 *     R_q(m) = sqrt(x_q^2 + H^2 + (y_p(m) - y_q)^2),  y_p(m) = track_start + v m Tsym
 *     alpha_q = sqrt(rcs_q) exp(j phase_q),   Y[n, m] = S[n, m] H[n, m] + sigma Z[n, m]
 *
 * m is the absolute symbol index (an endless stream keeps the platform moving). On a true
 * flight path p(t) (trajectory, SPEC 9) the range is |(x_q, y_q, 0) - p(m Tsym)|, from the
 * interpolated phase centre in double; the rest is the same (stop-and-go per symbol, as
 * on the ideal line: no generator models motion within a symbol).
 * Ranges and phases are formed in double: per symbol and target, the phasors of 8
 * neighbouring subcarriers at every anchor_interval-th subcarrier come from a
 * double-precision recurrence started at an exact sincos; in between, the 8 lanes are
 * advanced in float by exp(-j 4 pi 8 Delta f R / c) (AVX2/FMA with runtime dispatch, or
 * the same recurrence in scalar code), summed over the targets and multiplied by S in
 * one pass, together with the noise (kernel::gaussian_noise) and the non-finite test
 * of S. Error against a float64 evaluation: about -125 dB (tests/test_scene_echo.cc).
 * VOLK 2.5's rotator gave -43 to -58 dB here (its SIMD versions compound the float
 * increment), hence the own loop.
 */
class NRSAR_API scene_echo
{
public:
    //! Subcarriers between exact anchors: 32 float steps of step^8, drift ~2e-6 rad.
    static constexpr unsigned anchor_interval = 256;

    /*!
     * Validates num, geo and scn (std::invalid_argument); no scenario check here.
     * path: the true flight path; empty (default) or trajectory::ideal(geo): the ideal
     * line, bit-identical to a scene_echo without a path (flies_ideal_line).
     */
    scene_echo(const numerology& num,
               const geometry& geo,
               const scene& scn,
               const trajectory& path = trajectory());

    scene_echo(scene_echo&&) = default;
    scene_echo& operator=(scene_echo&&) = default;
    scene_echo(const scene_echo&) = delete;
    scene_echo& operator=(const scene_echo&) = delete;

    void set_scene(const scene& scn);
    const scene& get_scene() const { return d_scene; }
    unsigned num_subcarriers() const { return d_num.num_subcarriers; }

    //! Platform along-track position y_p(m) [m] on the ideal line (double).
    double platform_y(std::uint64_t m) const;
    //! The true flight path (empty: the ideal line of the geometry).
    const trajectory& path() const { return d_path; }

    //! h[n] = H[n, m]: the echo of S = 1 without noise (the reference of SPEC 8).
    void reference(std::uint64_t m, gr_complex* h);

    /*!
     * y[n] = s[n] H[n, m] + sigma Z[n, m], eq. (7), in one pass over the symbol.
     *
     * \param m absolute symbol index (slow time).
     * \param s transmit symbol S[:, m] (N values); non-finite values count as 0.
     * \param y output Y[:, m] (not aliasing s).
     * \param h when not null, receives H[n, m] as well.
     * \param noise when not null and sigma > 0, Z = the samples noise->generate(m, ...)
     *        gives (same seed and block index; drawn here in the same pass).
     * \param sigma noise standard deviation, E|sigma Z|^2 = sigma^2.
     * \return the number of non-finite samples of s (then treated as 0).
     */
    std::size_t echo(std::uint64_t m,
                     const gr_complex* s,
                     gr_complex* y,
                     gr_complex* h = nullptr,
                     const gaussian_noise* noise = nullptr,
                     float sigma = 0.0f);

    //! false: the portable scalar inner loop even when the CPU has AVX2 (tests).
    void set_simd(bool allow);
    //! "avx2" or "generic".
    const char* implementation() const { return d_simd ? "avx2" : "generic"; }

private:
    numerology d_num;
    geometry d_geo;
    scene d_scene;
    trajectory d_path;
    bool d_line; //!< flies geo's ideal line
    bool d_simd;
    std::vector<point_target> d_active; //!< targets with rcs > 0
    std::vector<echo_detail::target_lanes> d_lanes;
    std::vector<std::complex<double>> d_anchor, d_block_step, d_sc_pow;
    volk::vector<gr_complex> d_h;     //!< H across target passes when the caller has no buffer
    volk::vector<gr_complex> d_clean; //!< S with non-finite samples zeroed
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_SCENE_ECHO_H */
