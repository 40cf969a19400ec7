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
// Pass 3, linear, eight pixels at a time: each pixel's samples i and i + 1 as one 128-bit
// load, interpolated, rotated by the phase and added. Loads instead of two vgatherdpd per
// four pixels: the pass takes 0.78 of the time (docs/blocks/bp_focuser.md, Speed). The
// generic pass's operations (FMA contraction aside; the weight, 0 or 1, on the phasor).
void interpolate_linear_loads(const line_job& j)
{
    const unsigned K = j.K;
    const float* prof = reinterpret_cast<const float*>(j.profile);
    float* acc = reinterpret_cast<float*>(j.acc);
    const __m256i last = _mm256_set1_epi32(j.last), zero = _mm256_setzero_si256();
    const __m256i dup_lo = _mm256_setr_epi32(0, 0, 1, 1, 2, 2, 3, 3);
    const __m256i dup_hi = _mm256_setr_epi32(4, 4, 5, 5, 6, 6, 7, 7);
    alignas(32) int ib[8];
    unsigned k = 0;
    for (; k + 8 <= K; k += 8) {
        const __m256i i = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(j.idx + k));
        // in: 0 <= i <= last; outside, read sample 0 with weight 0 (folded into the phasor)
        const __m256i out =
            _mm256_or_si256(_mm256_cmpgt_epi32(zero, i), _mm256_cmpgt_epi32(i, last));
        _mm256_store_si256(reinterpret_cast<__m256i*>(ib), _mm256_andnot_si256(out, i));
        const __m256 w = _mm256_andnot_ps(_mm256_castsi256_ps(out), _mm256_loadu_ps(j.valid + k));
        const __m256 cn = _mm256_mul_ps(w, _mm256_loadu_ps(j.frac + k));
        const __m256 sn = _mm256_mul_ps(w, _mm256_loadu_ps(j.sine + k));
        const __m256 mu = _mm256_loadu_ps(j.mu + k);
        // samples i, i + 1 of pixels (0|2), (1|3), (4|6), (5|7): 128 bits each
        auto pair = [&](int x, int y) {
            return _mm256_insertf128_ps(
                _mm256_castps128_ps256(_mm_loadu_ps(prof + 2 * ib[x])),
                _mm_loadu_ps(prof + 2 * ib[y]), 1);
        };
        const __m256 p02 = pair(0, 2), p13 = pair(1, 3), p46 = pair(4, 6), p57 = pair(5, 7);
        auto rotate_add = [&](__m256 l0, __m256 l1, __m256i dup, float* dst) {
            const __m256 s0 = _mm256_shuffle_ps(l0, l1, 0x44); // sample i of 4 pixels
            const __m256 s1 = _mm256_shuffle_ps(l0, l1, 0xEE); // sample i + 1
            const __m256 v = _mm256_fmadd_ps(
                _mm256_permutevar8x32_ps(mu, dup), _mm256_sub_ps(s1, s0), s0);
            // (re, im) (cn + j sn) = (re cn - im sn, im cn + re sn)
            const __m256 x = _mm256_mul_ps(_mm256_permute_ps(v, 0xB1),
                                           _mm256_permutevar8x32_ps(sn, dup));
            const __m256 rot = _mm256_fmaddsub_ps(v, _mm256_permutevar8x32_ps(cn, dup), x);
            _mm256_storeu_ps(dst, _mm256_add_ps(_mm256_loadu_ps(dst), rot));
        };
        rotate_add(p02, p13, dup_lo, acc + 2 * k);
        rotate_add(p46, p57, dup_hi, acc + 2 * k + 8);
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
    position_phase_passes(j, true);
    if (j.sinc_table)
        interpolate_pass(j);
    else
        interpolate_linear_loads(j);
}
void merge_line_avx2(const merge_job& m) { merge_line_body(m); }

} // namespace bp_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
