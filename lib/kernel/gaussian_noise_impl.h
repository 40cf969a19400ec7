/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Shared by the generic and the AVX2 path of kernel::gaussian_noise: stream seeding,
// the xoshiro128++ step and the Box-Muller constants, so both paths draw the same integers.

#ifndef INCLUDED_NRSAR_KERNEL_GAUSSIAN_NOISE_IMPL_H
#define INCLUDED_NRSAR_KERNEL_GAUSSIAN_NOISE_IMPL_H

#include <gnuradio/gr_complex.h>
#include <cstddef>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace gr {
namespace nrsar {
namespace kernel {
namespace noise_detail {

constexpr unsigned lanes = 8;

//! xoshiro128++ state of 8 lanes, word-major (s[w][lane]) so the AVX2 path loads rows.
struct alignas(32) lane_state {
    std::uint32_t s[4][lanes];
};

inline std::uint64_t splitmix64(std::uint64_t& x)
{
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

//! Independent stream per (seed, block): bijective mixes, so distinct blocks get distinct states.
inline void seed_lanes(std::uint64_t seed, std::uint64_t block, lane_state& st)
{
    std::uint64_t k = seed;
    const std::uint64_t key = splitmix64(k);
    std::uint64_t b = block;
    std::uint64_t x = key ^ splitmix64(b);
    for (unsigned w = 0; w < 4; w += 2)
        for (unsigned l = 0; l < lanes; l++) {
            const std::uint64_t r = splitmix64(x);
            st.s[w][l] = static_cast<std::uint32_t>(r);
            st.s[w + 1][l] = static_cast<std::uint32_t>(r >> 32);
        }
    for (unsigned l = 0; l < lanes; l++) // xoshiro must not start from all zeros
        if ((st.s[0][l] | st.s[1][l] | st.s[2][l] | st.s[3][l]) == 0)
            st.s[0][l] = 1;
}

inline std::uint32_t rotl32(std::uint32_t v, int k) { return (v << k) | (v >> (32 - k)); }

//! One xoshiro128++ step of lane l.
inline std::uint32_t next(lane_state& st, unsigned l)
{
    std::uint32_t* s0 = &st.s[0][l];
    std::uint32_t* s1 = &st.s[1][l];
    std::uint32_t* s2 = &st.s[2][l];
    std::uint32_t* s3 = &st.s[3][l];
    const std::uint32_t result = rotl32(*s0 + *s3, 7) + *s0;
    const std::uint32_t t = *s1 << 9;
    *s2 ^= *s0;
    *s3 ^= *s1;
    *s1 ^= *s2;
    *s0 ^= *s3;
    *s2 ^= t;
    *s3 = rotl32(*s3, 11);
    return result;
}

// Box-Muller constants (float).
constexpr float u1_scale = 0x1p-24f;                      // 24-bit uniform in (0, 1]
constexpr float angle_scale = 1.57079632679489662f * 0x1p-24f; // 24 bits -> [0, pi/2)
constexpr float quarter_pi = 0.785398163397448310f;
constexpr float ln2 = 0.693147180559945309f;
constexpr float sqrt2 = 1.41421356237309505f;
// ln m = 2 atanh(s), s = (m - 1)/(m + 1), |s| <= 0.1716: series to s^9 (error < 1e-9).
constexpr float ln_c3 = 1.0f / 3.0f, ln_c5 = 1.0f / 5.0f, ln_c7 = 1.0f / 7.0f,
                ln_c9 = 1.0f / 9.0f;
// Taylor sin to a^7 and cos to a^8 on |a| <= pi/4 (errors 3e-7 and 3e-8).
constexpr float s3 = -1.0f / 6.0f, s5 = 1.0f / 120.0f, s7 = -1.0f / 5040.0f;
constexpr float c2 = -0.5f, c4 = 1.0f / 24.0f, c6 = -1.0f / 720.0f, c8 = 1.0f / 40320.0f;

inline float as_float(std::uint32_t b)
{
    float f;
    std::memcpy(&f, &b, sizeof f);
    return f;
}

inline std::uint32_t as_bits(float f)
{
    std::uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    return b;
}

//! Unit-power complex Gaussian from two words (polar Box-Muller); the AVX2 path
//! evaluates the same expressions 8 lanes at a time.
inline gr_complex box_muller(std::uint32_t w1, std::uint32_t w2)
{
    // |z|^2 = -ln(u1), u1 = k / 2^24, k = 1 .. 2^24 (exact in float).
    const float u1 = static_cast<float>((w1 >> 8) + 1u) * u1_scale;
    const std::uint32_t b = as_bits(u1);
    float e = static_cast<float>(static_cast<int>(b >> 23) - 127);
    float m = as_float((b & 0x7fffffu) | 0x3f800000u);
    if (m > sqrt2) {
        m *= 0.5f;
        e += 1.0f;
    }
    const float s = (m - 1.0f) / (m + 1.0f);
    const float z = s * s;
    const float p = 1.0f + z * (ln_c3 + z * (ln_c5 + z * (ln_c7 + z * ln_c9)));
    const float ln_u = e * ln2 + 2.0f * s * p;
    const float r = std::sqrt(std::max(0.0f, -ln_u));

    // Angle: 2 quadrant bits + a 24-bit offset in [-pi/4, pi/4).
    const float a = static_cast<float>((w2 >> 6) & 0xffffffu) * angle_scale - quarter_pi;
    const float a2 = a * a;
    const float sn = a * (1.0f + a2 * (s3 + a2 * (s5 + a2 * s7)));
    const float cs = 1.0f + a2 * (c2 + a2 * (c4 + a2 * (c6 + a2 * c8)));
    const bool b0 = (w2 >> 30) & 1u;
    const bool b1 = (w2 >> 31) & 1u;
    // Rotation by quadrant q = 2 b1 + b0: (c, s), (-s, c), (-c, -s), (s, -c).
    float re = b0 ? sn : cs;
    float im = b0 ? cs : sn;
    if (b0 != b1)
        re = -re;
    if (b1)
        im = -im;
    return gr_complex(r * re, r * im);
}

//! One group of 8 samples of lane state st (generic path): out[l] = sigma z_l.
inline void generic_group(lane_state& st, float sigma, gr_complex out[lanes])
{
    std::uint32_t w1[lanes], w2[lanes];
    for (unsigned l = 0; l < lanes; l++)
        w1[l] = next(st, l);
    for (unsigned l = 0; l < lanes; l++)
        w2[l] = next(st, l);
    for (unsigned l = 0; l < lanes; l++)
        out[l] = sigma * box_muller(w1[l], w2[l]);
}

// AVX2 path: groups of 8 complex samples of one block starting at group 0. Returns
// false when the CPU lacks AVX2/FMA (then nothing was written).
bool avx2_available();
void avx2_run(lane_state& st, float sigma, gr_complex* out, std::size_t groups, bool add);

} // namespace noise_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif
