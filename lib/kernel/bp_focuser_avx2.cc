/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// The back-projection inner loops built with -mavx2 -mfma (lib/CMakeLists.txt); called only
// after avx2_available().

#include "bp_focuser_impl.h"
#include <immintrin.h>

namespace gr {
namespace nrsar {
namespace kernel {
namespace bp_detail {

namespace {
// Pass 3, linear, four pixels at a time: each complex sample is gathered as one 64-bit
// lane (samples i and i + 1 of four pixels in two gathers), interpolated, rotated by the
// phase and added. The same operations as the generic pass (FMA contraction aside).
void interpolate_linear_gather(const line_job& j)
{
    const unsigned K = j.K;
    const double* prof = reinterpret_cast<const double*>(j.profile);
    float* acc = reinterpret_cast<float*>(j.acc);
    const __m128i zero = _mm_setzero_si128(), last = _mm_set1_epi32(j.last);
    const __m256i dup = _mm256_setr_epi32(0, 0, 1, 1, 2, 2, 3, 3);
    unsigned k = 0;
    for (; k + 4 <= K; k += 4) {
        const __m128i i = _mm_loadu_si128(reinterpret_cast<const __m128i*>(j.idx + k));
        // in: 0 <= i <= last; outside, read sample 0 with weight 0
        const __m128i out = _mm_or_si128(_mm_cmpgt_epi32(zero, i), _mm_cmpgt_epi32(i, last));
        const __m128i ic = _mm_andnot_si128(out, i);
        const __m128 w4 =
            _mm_andnot_ps(_mm_castsi128_ps(out), _mm_loadu_ps(j.valid + k));
        const __m256 s0 = _mm256_castpd_ps(_mm256_i32gather_pd(prof, ic, 8));
        const __m256 s1 = _mm256_castpd_ps(_mm256_i32gather_pd(prof + 1, ic, 8));
        const __m256 mu = _mm256_permutevar8x32_ps(_mm256_castps128_ps256(_mm_loadu_ps(j.mu + k)), dup);
        const __m256 w = _mm256_permutevar8x32_ps(_mm256_castps128_ps256(w4), dup);
        const __m256 v = _mm256_mul_ps(w, _mm256_fmadd_ps(mu, _mm256_sub_ps(s1, s0), s0));
        const __m256 cs =
            _mm256_permutevar8x32_ps(_mm256_castps128_ps256(_mm_loadu_ps(j.frac + k)), dup);
        const __m256 sn =
            _mm256_permutevar8x32_ps(_mm256_castps128_ps256(_mm_loadu_ps(j.sine + k)), dup);
        // (re, im) (cs + j sn) = (re cs - im sn, im cs + re sn)
        const __m256 swapped = _mm256_permute_ps(v, 0xB1);
        const __m256 rot = _mm256_addsub_ps(_mm256_mul_ps(v, cs), _mm256_mul_ps(swapped, sn));
        _mm256_storeu_ps(acc + 2 * k, _mm256_add_ps(_mm256_loadu_ps(acc + 2 * k), rot));
    }
    if (k < K) { // the last pixels by the generic pass
        line_job t = j;
        t.K = K - k;
        t.idx += k;
        t.mu += k;
        t.frac += k;
        t.sine += k;
        t.valid += k;
        t.acc += k;
        interpolate_pass(t);
    }
}
} // namespace

void project_line_avx2(const line_job& j)
{
    position_phase_passes(j);
    if (j.sinc_table)
        interpolate_pass(j);
    else
        interpolate_linear_gather(j);
}
void merge_line_avx2(const merge_job& m) { merge_line_body(m); }

} // namespace bp_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
