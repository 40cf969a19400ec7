/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// AVX2 path of kernel::soft_demapper: the closed form of soft_demapper_impl.h on 8 symbols
// at a time, in the order of the generic path (no FMA: the same floats). This file alone is
// compiled with -mavx2 (lib/CMakeLists.txt) and called only after a runtime CPU check. No
// std:: templates here (an AVX2 instantiation could be picked by the linker for the
// generic code too).

#include "soft_demapper_impl.h"
#include "cpu_features.h"

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace gr {
namespace nrsar {
namespace kernel {
namespace demap_detail {

#if defined(__AVX2__)

bool avx2_available() { return cpu_supports_avx2(); }

namespace {
inline __m256 clamp8(__m256 v, __m256 lo, __m256 hi)
{
    return _mm256_min_ps(_mm256_max_ps(v, lo), hi);
}
inline __m256 odd_round8(__m256 u)
{
    const __m256 half = _mm256_set1_ps(0.5f), two = _mm256_set1_ps(2.0f),
                 one = _mm256_set1_ps(1.0f);
    return _mm256_add_ps(_mm256_mul_ps(two, _mm256_floor_ps(_mm256_mul_ps(half, u))), one);
}
} // namespace

std::size_t demap_avx2(const axis_shape& s,
                       const gr_complex* y,
                       const float* nv,
                       bool per_symbol,
                       std::size_t nsym,
                       float* llr,
                       double* sq_err)
{
    const unsigned bits = 2 * s.na;
    const std::size_t groups = nsym / 8;
    const __m256 sign = _mm256_set1_ps(-0.0f), one = _mm256_set1_ps(1.0f);
    const __m256 to_unit = _mm256_set1_ps(s.to_unit), unit2 = _mm256_set1_ps(s.unit2);
    const __m256 top = _mm256_set1_ps(s.top);
    alignas(32) float buf[8][8];
    alignas(32) float err[8];
    for (std::size_t g = 0; g < groups; g++) {
        const float* p = reinterpret_cast<const float*>(y + 8 * g);
        const __m256 v0 = _mm256_loadu_ps(p), v1 = _mm256_loadu_ps(p + 8);
        // de-interleave: lanes 0 1 4 5 2 3 6 7, then restore the symbol order
        const __m256 re = _mm256_castpd_ps(_mm256_permute4x64_pd(
            _mm256_castps_pd(_mm256_shuffle_ps(v0, v1, _MM_SHUFFLE(2, 0, 2, 0))),
            _MM_SHUFFLE(3, 1, 2, 0)));
        const __m256 im = _mm256_castpd_ps(_mm256_permute4x64_pd(
            _mm256_castps_pd(_mm256_shuffle_ps(v0, v1, _MM_SHUFFLE(3, 1, 3, 1))),
            _MM_SHUFFLE(3, 1, 2, 0)));
        const __m256 var = per_symbol ? _mm256_loadu_ps(nv + 8 * g) : _mm256_set1_ps(nv[0]);
        const __m256 scale = _mm256_div_ps(unit2, var);
        __m256 e = _mm256_setzero_ps();
        for (unsigned axis = 0; axis < 2; axis++) {
            const __m256 x = _mm256_mul_ps(axis == 0 ? re : im, to_unit);
            const __m256 a = _mm256_andnot_ps(sign, x);
            const __m256 dn = _mm256_sub_ps(a, clamp8(odd_round8(a), one, top));
            const __m256 a1 = _mm256_add_ps(a, one);
            const __m256 l0 =
                _mm256_sub_ps(_mm256_mul_ps(a1, a1), _mm256_mul_ps(dn, dn));
            _mm256_store_ps(buf[axis],
                            _mm256_mul_ps(_mm256_or_ps(l0, _mm256_and_ps(sign, x)), scale));
            e = _mm256_add_ps(e, _mm256_mul_ps(dn, dn));
            __m256 u = a;
            float t = s.half;
            for (unsigned j = 1; j < s.na; j++) {
                const __m256 r = odd_round8(u);
                const __m256 din =
                    _mm256_sub_ps(u, clamp8(r, one, _mm256_set1_ps(t - 1.0f)));
                const __m256 dout = _mm256_sub_ps(
                    u, clamp8(r, _mm256_set1_ps(t + 1.0f), _mm256_set1_ps(2.0f * t - 1.0f)));
                const __m256 l = _mm256_sub_ps(_mm256_mul_ps(dout, dout),
                                               _mm256_mul_ps(din, din));
                _mm256_store_ps(buf[2 * j + axis], _mm256_mul_ps(l, scale));
                u = _mm256_andnot_ps(sign, _mm256_sub_ps(u, _mm256_set1_ps(t)));
                t *= 0.5f;
            }
        }
        float* out = llr + 8 * g * bits;
        for (unsigned i = 0; i < 8; i++)
            for (unsigned b = 0; b < bits; b++)
                out[i * bits + b] = buf[b][i];
        if (sq_err) {
            _mm256_store_ps(err, _mm256_mul_ps(e, unit2));
            for (unsigned i = 0; i < 8; i++)
                *sq_err += static_cast<double>(err[i]);
        }
    }
    return groups * 8;
}

#else

bool avx2_available() { return false; }
std::size_t demap_avx2(const axis_shape&,
                       const gr_complex*,
                       const float*,
                       bool,
                       std::size_t,
                       float*,
                       double*)
{
    return 0;
}

#endif

} // namespace demap_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
