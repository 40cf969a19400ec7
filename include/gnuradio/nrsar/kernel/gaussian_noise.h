/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_GAUSSIAN_NOISE_H
#define INCLUDED_NRSAR_KERNEL_GAUSSIAN_NOISE_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <cstddef>
#include <cstdint>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Fast, seeded circular complex Gaussian noise, Z ~ CN(0, sigma^2) (eq. 7).
 *
 * Counter-based streams: the samples of block b (the echo uses the OFDM symbol index)
 * depend only on (seed, b, element index), so the output does not depend on how a
 * stream is cut into work() calls or split across threads.
 *
 * Per block, eight xoshiro128++ lanes are seeded by splitmix64 from (seed, b); element
 * i of the block uses lane i % 8 at step i / 8. Two 32-bit words give one complex
 * sample by Box-Muller in polar form: |z|^2 = -ln(u1) is exponential with mean 1
 * (u1 = k / 2^24, so |z| <= 4.08), the angle takes 26 bits of u2 (2 quadrant bits,
 * 24 bits of a polynomial sincos on [-pi/4, pi/4)). ln, sin and cos are polynomials
 * with relative error below 1e-6, evaluated 8 lanes at a time with AVX2/FMA when the
 * CPU has them (runtime dispatch, no -march flag), or by the same algorithm in scalar
 * code. Integer streams are identical on both paths; the float samples agree to about
 * 1e-6 (FMA contraction).
 */
class NRSAR_API gaussian_noise
{
public:
    //! allow_simd = false forces the portable scalar path (tests compare the two).
    explicit gaussian_noise(std::uint64_t seed = 0, bool allow_simd = true);

    void set_seed(std::uint64_t seed) { d_seed = seed; }
    std::uint64_t seed() const { return d_seed; }

    //! out[i] = sigma z_i, z_i ~ CN(0, 1): element i of block `block` of the stream.
    void generate(std::uint64_t block, float sigma, gr_complex* out, std::size_t n) const;
    //! inout[i] += sigma z_i with the same z_i as generate().
    void add(std::uint64_t block, float sigma, gr_complex* inout, std::size_t n) const;

    //! "avx2" or "generic": the path this object uses.
    const char* implementation() const;

private:
    std::uint64_t d_seed;
    bool d_simd;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_GAUSSIAN_NOISE_H */
