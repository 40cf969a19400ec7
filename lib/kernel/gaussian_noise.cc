/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "gaussian_noise_impl.h"
#include <gnuradio/nrsar/kernel/gaussian_noise.h>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace gr {
namespace nrsar {
namespace kernel {

using namespace noise_detail;

namespace {

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

void generic_run(lane_state& st, float sigma, gr_complex* out, std::size_t n, bool add)
{
    std::uint32_t w1[lanes], w2[lanes];
    for (std::size_t i0 = 0; i0 < n; i0 += lanes) {
        for (unsigned l = 0; l < lanes; l++)
            w1[l] = next(st, l);
        for (unsigned l = 0; l < lanes; l++)
            w2[l] = next(st, l);
        const std::size_t len = std::min<std::size_t>(lanes, n - i0);
        for (std::size_t l = 0; l < len; l++) {
            const gr_complex z = sigma * box_muller(w1[l], w2[l]);
            if (add)
                out[i0 + l] += z;
            else
                out[i0 + l] = z;
        }
    }
}

void run(std::uint64_t seed,
         std::uint64_t block,
         float sigma,
         gr_complex* out,
         std::size_t n,
         bool add,
         bool simd)
{
    lane_state st;
    seed_lanes(seed, block, st);
    if (!simd) {
        generic_run(st, sigma, out, n, add);
        return;
    }
    const std::size_t groups = n / lanes;
    avx2_run(st, sigma, out, groups, add);
    const std::size_t done = groups * lanes;
    if (done < n) {
        // The tail through the same path, so a sample does not depend on n.
        gr_complex last[lanes];
        avx2_run(st, sigma, last, 1, false);
        for (std::size_t i = done; i < n; i++) {
            if (add)
                out[i] += last[i - done];
            else
                out[i] = last[i - done];
        }
    }
}

} // namespace

gaussian_noise::gaussian_noise(std::uint64_t seed, bool allow_simd)
    : d_seed(seed), d_simd(allow_simd && avx2_available())
{
}

void gaussian_noise::generate(std::uint64_t block,
                              float sigma,
                              gr_complex* out,
                              std::size_t n) const
{
    run(d_seed, block, sigma, out, n, false, d_simd);
}

void gaussian_noise::add(std::uint64_t block,
                         float sigma,
                         gr_complex* inout,
                         std::size_t n) const
{
    run(d_seed, block, sigma, inout, n, true, d_simd);
}

const char* gaussian_noise::implementation() const { return d_simd ? "avx2" : "generic"; }

} // namespace kernel
} // namespace nrsar
} // namespace gr
