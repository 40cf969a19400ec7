/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// AVX2 path of pusch_rx's equaliser: 8 REs at a time, the operations of the generic pass
// in its order (no FMA: the same floats). This file alone is compiled with -mavx2
// (lib/CMakeLists.txt) and called only after a runtime CPU check. No std:: templates
// here.

#include "cpu_features.h"
#include "pusch_rx_impl.h"

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace gr {
namespace nrsar {
namespace kernel {
namespace pusch_detail {

#if defined(__AVX2__)

bool avx2_available() { return cpu_supports_avx2(); }

std::uint32_t equalise_avx2(const gr_complex* y,
                            const gr_complex* h,
                            float s2,
                            unsigned n,
                            gr_complex* x,
                            float* nv,
                            float* g)
{
    const float* yf = reinterpret_cast<const float*>(y);
    const float* hf = reinterpret_cast<const float*>(h);
    float* xf = reinterpret_cast<float*>(x);
    const __m256 floor = _mm256_set1_ps(1e-20f), one = _mm256_set1_ps(1.0f);
    const __m256 vs2 = _mm256_set1_ps(s2);
    const __m256i expo = _mm256_set1_epi32(0x7f800000);
    // de-interleaving by shuffle_ps leaves the REs in the order 0 1 4 5 2 3 6 7
    const __m256i natural = _mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7);
    __m256i bad = _mm256_setzero_si256();
    unsigned k = 0;
    for (; k + 8 <= n; k += 8) {
        const __m256 h0 = _mm256_loadu_ps(hf + 2 * k),
                     h1 = _mm256_loadu_ps(hf + 2 * k + 8);
        const __m256 y0 = _mm256_loadu_ps(yf + 2 * k),
                     y1 = _mm256_loadu_ps(yf + 2 * k + 8);
        const __m256 hr = _mm256_shuffle_ps(h0, h1, _MM_SHUFFLE(2, 0, 2, 0));
        const __m256 hi = _mm256_shuffle_ps(h0, h1, _MM_SHUFFLE(3, 1, 3, 1));
        const __m256 yr = _mm256_shuffle_ps(y0, y1, _MM_SHUFFLE(2, 0, 2, 0));
        const __m256 yi = _mm256_shuffle_ps(y0, y1, _MM_SHUFFLE(3, 1, 3, 1));
        // max(floor, a) returns a when a is NaN, as std::max(a, floor) does
        const __m256 gk = _mm256_max_ps(
            floor, _mm256_add_ps(_mm256_mul_ps(hr, hr), _mm256_mul_ps(hi, hi)));
        const __m256 inv = _mm256_div_ps(one, gk);
        const __m256 xr = _mm256_mul_ps(
            _mm256_add_ps(_mm256_mul_ps(yr, hr), _mm256_mul_ps(yi, hi)), inv);
        const __m256 xi = _mm256_mul_ps(
            _mm256_sub_ps(_mm256_mul_ps(yi, hr), _mm256_mul_ps(yr, hi)), inv);
        const __m256 v = _mm256_mul_ps(vs2, inv);
        // unpack restores the interleaved layout of the loads
        _mm256_storeu_ps(xf + 2 * k, _mm256_unpacklo_ps(xr, xi));
        _mm256_storeu_ps(xf + 2 * k + 8, _mm256_unpackhi_ps(xr, xi));
        _mm256_storeu_ps(nv + k, _mm256_permutevar8x32_ps(v, natural));
        _mm256_storeu_ps(g + k, _mm256_permutevar8x32_ps(gk, natural));
        // exponent all ones: inf or NaN
        bad = _mm256_or_si256(
            bad,
            _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_castps_si256(xr), expo), expo));
        bad = _mm256_or_si256(
            bad,
            _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_castps_si256(xi), expo), expo));
        bad = _mm256_or_si256(
            bad,
            _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_castps_si256(v), expo), expo));
    }
    std::uint32_t any = _mm256_movemask_epi8(bad) != 0;
    if (k < n)
        any |= equalise_generic(y + k, h + k, s2, n - k, x + k, nv + k, g + k);
    return any;
}

#else

bool avx2_available() { return false; }

std::uint32_t equalise_avx2(const gr_complex* y,
                            const gr_complex* h,
                            float s2,
                            unsigned n,
                            gr_complex* x,
                            float* nv,
                            float* g)
{
    return equalise_generic(y, h, s2, n, x, nv, g);
}

#endif

} // namespace pusch_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
