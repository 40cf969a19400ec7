/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// AVX2/FMA Box-Muller group of kernel::gaussian_noise, shared by the noise generator and
// the echo's fused loop. Include only from translation units compiled with -mavx2 -mfma.

#ifndef INCLUDED_NRSAR_KERNEL_NOISE_AVX2_H
#define INCLUDED_NRSAR_KERNEL_NOISE_AVX2_H

#include "gaussian_noise_impl.h"

#if defined(__x86_64__) || defined(__i386__)
#define NRSAR_HAVE_AVX2_PATH 1
#include <immintrin.h>

namespace gr {
namespace nrsar {
namespace kernel {
namespace noise_detail {

inline __m256i rotl(__m256i v, int k)
{
    return _mm256_or_si256(_mm256_slli_epi32(v, k), _mm256_srli_epi32(v, 32 - k));
}

//! 8 xoshiro128++ lanes in registers.
struct xoshiro8 {
    __m256i s0, s1, s2, s3;

    explicit xoshiro8(const lane_state& st)
    : s0(_mm256_load_si256(reinterpret_cast<const __m256i*>(st.s[0]))),
      s1(_mm256_load_si256(reinterpret_cast<const __m256i*>(st.s[1]))),
      s2(_mm256_load_si256(reinterpret_cast<const __m256i*>(st.s[2]))),
      s3(_mm256_load_si256(reinterpret_cast<const __m256i*>(st.s[3])))
    {
    }
    void store(lane_state& st) const
    {
    _mm256_store_si256(reinterpret_cast<__m256i*>(st.s[0]), s0);
    _mm256_store_si256(reinterpret_cast<__m256i*>(st.s[1]), s1);
    _mm256_store_si256(reinterpret_cast<__m256i*>(st.s[2]), s2);
    _mm256_store_si256(reinterpret_cast<__m256i*>(st.s[3]), s3);
    }
    __m256i next()
    {
    const __m256i result = _mm256_add_epi32(rotl(_mm256_add_epi32(s0, s3), 7), s0);
    const __m256i t = _mm256_slli_epi32(s1, 9);
    s2 = _mm256_xor_si256(s2, s0);
    s3 = _mm256_xor_si256(s3, s1);
    s1 = _mm256_xor_si256(s1, s2);
    s0 = _mm256_xor_si256(s0, s3);
    s2 = _mm256_xor_si256(s2, t);
    s3 = rotl(s3, 11);
    return result;
    }
};

inline __m256 poly(__m256 x, __m256 c0, __m256 c1) { return _mm256_fmadd_ps(x, c1, c0); }

/*!
 * Next 8 samples sigma z_l of the lanes, interleaved: out0 = samples 0..3, out1 = 4..7.
 * Same expressions as box_muller() in gaussian_noise_impl.h.
 */
inline void box_muller8(xoshiro8& g, __m256 v_sigma, __m256& out0, __m256& out1)
{
    const __m256 one = _mm256_set1_ps(1.0f);
    const __m256 half = _mm256_set1_ps(0.5f);
    const __m256 zero = _mm256_setzero_ps();
    const __m256i mant_mask = _mm256_set1_epi32(0x7fffff);
    const __m256i one_bits = _mm256_set1_epi32(0x3f800000);
    const __m256i bias = _mm256_set1_epi32(127);
    const __m256i sign = _mm256_set1_epi32(static_cast<int>(0x80000000u));
    const __m256i angle_mask = _mm256_set1_epi32(0xffffff);
    const __m256i w1 = g.next();
    const __m256i w2 = g.next();

    // Radius: sqrt(-ln u1), u1 = (w1 >> 8 + 1) 2^-24.
    const __m256 u1 = _mm256_mul_ps(
        _mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_srli_epi32(w1, 8), _mm256_set1_epi32(1))),
        _mm256_set1_ps(u1_scale));
    const __m256i b = _mm256_castps_si256(u1);
    __m256 e = _mm256_cvtepi32_ps(_mm256_sub_epi32(_mm256_srli_epi32(b, 23), bias));
    __m256 m = _mm256_castsi256_ps(_mm256_or_si256(_mm256_and_si256(b, mant_mask), one_bits));
    const __m256 big = _mm256_cmp_ps(m, _mm256_set1_ps(sqrt2), _CMP_GT_OQ);
    m = _mm256_blendv_ps(m, _mm256_mul_ps(m, half), big);
    e = _mm256_add_ps(e, _mm256_and_ps(big, one));
    const __m256 s = _mm256_div_ps(_mm256_sub_ps(m, one), _mm256_add_ps(m, one));
    const __m256 z = _mm256_mul_ps(s, s);
    __m256 p = poly(z, _mm256_set1_ps(ln_c7), _mm256_set1_ps(ln_c9));
    p = poly(z, _mm256_set1_ps(ln_c5), p);
    p = poly(z, _mm256_set1_ps(ln_c3), p);
    p = poly(z, one, p);
    const __m256 ln_u =
        _mm256_add_ps(_mm256_mul_ps(e, _mm256_set1_ps(ln2)), _mm256_mul_ps(_mm256_add_ps(s, s), p));
    const __m256 r = _mm256_mul_ps(
        _mm256_sqrt_ps(_mm256_max_ps(zero, _mm256_sub_ps(zero, ln_u))), v_sigma);

    // Angle: quadrant bits 31, 30; offset from bits 6..29.
    const __m256 a = _mm256_sub_ps(
        _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(w2, 6), angle_mask)),
                      _mm256_set1_ps(angle_scale)),
        _mm256_set1_ps(quarter_pi));
    const __m256 a2 = _mm256_mul_ps(a, a);
    __m256 sp = poly(a2, _mm256_set1_ps(s5), _mm256_set1_ps(s7));
    sp = poly(a2, _mm256_set1_ps(s3), sp);
    sp = poly(a2, one, sp);
    const __m256 sn = _mm256_mul_ps(a, sp);
    __m256 cs = poly(a2, _mm256_set1_ps(c6), _mm256_set1_ps(c8));
    cs = poly(a2, _mm256_set1_ps(c4), cs);
    cs = poly(a2, _mm256_set1_ps(c2), cs);
    cs = poly(a2, one, cs);
    const __m256i w2s = _mm256_slli_epi32(w2, 1); // b0 in the sign bit
    const __m256 swap = _mm256_castsi256_ps(w2s);
    __m256 re = _mm256_blendv_ps(cs, sn, swap);
    __m256 im = _mm256_blendv_ps(sn, cs, swap);
    re = _mm256_xor_ps(re, _mm256_castsi256_ps(_mm256_and_si256(_mm256_xor_si256(w2, w2s), sign)));
    im = _mm256_xor_ps(im, _mm256_castsi256_ps(_mm256_and_si256(w2, sign)));
    re = _mm256_mul_ps(re, r);
    im = _mm256_mul_ps(im, r);

    // Interleave to 8 complex samples.
    const __m256 lo = _mm256_unpacklo_ps(re, im);
    const __m256 hi = _mm256_unpackhi_ps(re, im);
    out0 = _mm256_permute2f128_ps(lo, hi, 0x20);
    out1 = _mm256_permute2f128_ps(lo, hi, 0x31);
}

} // namespace noise_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif // x86
#endif
