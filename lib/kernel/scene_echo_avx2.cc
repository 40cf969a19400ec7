/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// AVX2/FMA inner loop of kernel::scene_echo. This file alone is compiled with
// -mavx2 -mfma (lib/CMakeLists.txt) and called only after a runtime CPU check.

#include "scene_echo_impl.h"
#include <algorithm>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define NRSAR_HAVE_AVX2_PATH 1
#endif

namespace gr {
namespace nrsar {
namespace kernel {
namespace echo_detail {

#ifdef NRSAR_HAVE_AVX2_PATH

bool avx2_available()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

namespace {

// a * b for 4 interleaved complex a and a broadcast b = (br, bi).
inline __m256 cmul_bcast(__m256 a, __m256 br, __m256 bi)
{
    return _mm256_fmaddsub_ps(a, br, _mm256_mul_ps(_mm256_permute_ps(a, 0xB1), bi));
}

// a * b, both 4 interleaved complex.
inline __m256 cmul(__m256 a, __m256 b)
{
    const __m256 br = _mm256_moveldup_ps(b);
    const __m256 bi = _mm256_movehdup_ps(b);
    return _mm256_fmaddsub_ps(a, br, _mm256_mul_ps(_mm256_permute_ps(a, 0xB1), bi));
}

} // namespace

void avx2_block(const target_lanes* t,
                unsigned nq,
                bool accumulate,
                const gr_complex* s,
                gr_complex* y,
                gr_complex* h,
                std::size_t len)
{
    __m256 p[max_targets][2], sr[max_targets], si[max_targets];
    for (unsigned q = 0; q < nq; q++) {
        p[q][0] = _mm256_load_ps(t[q].v);
        p[q][1] = _mm256_load_ps(t[q].v + 8);
        sr[q] = _mm256_set1_ps(t[q].step[0]);
        si[q] = _mm256_set1_ps(t[q].step[1]);
    }
    // One group of 8 subcarriers; the last partial group goes through a local copy.
    auto group = [&](const float* sp, float* yp, float* hp) {
        __m256 h0 = accumulate ? _mm256_loadu_ps(hp) : _mm256_setzero_ps();
        __m256 h1 = accumulate ? _mm256_loadu_ps(hp + 8) : _mm256_setzero_ps();
        for (unsigned q = 0; q < nq; q++) {
            h0 = _mm256_add_ps(h0, p[q][0]);
            h1 = _mm256_add_ps(h1, p[q][1]);
            p[q][0] = cmul_bcast(p[q][0], sr[q], si[q]);
            p[q][1] = cmul_bcast(p[q][1], sr[q], si[q]);
        }
        _mm256_storeu_ps(hp, h0);
        _mm256_storeu_ps(hp + 8, h1);
        if (sp) { // eq. (7): Y = S H
            _mm256_storeu_ps(yp, cmul(h0, _mm256_loadu_ps(sp)));
            _mm256_storeu_ps(yp + 8, cmul(h1, _mm256_loadu_ps(sp + 8)));
        }
    };
    const std::size_t full = len / lanes;
    const float* sf = reinterpret_cast<const float*>(s);
    float* yf = reinterpret_cast<float*>(y);
    float* hf = reinterpret_cast<float*>(h);
    for (std::size_t g = 0; g < full; g++)
        group(sf ? sf + 16 * g : nullptr, yf + 16 * g, hf + 16 * g);
    const std::size_t rest = len - full * lanes;
    if (rest) {
        alignas(32) gr_complex st[lanes] = {}, yt[lanes], ht[lanes] = {};
        const std::size_t off = full * lanes;
        std::copy(h + off, h + len, ht);
        if (s)
            std::copy(s + off, s + len, st);
        group(s ? reinterpret_cast<const float*>(st) : nullptr,
              reinterpret_cast<float*>(yt),
              reinterpret_cast<float*>(ht));
        std::copy(ht, ht + rest, h + off);
        if (s)
            std::copy(yt, yt + rest, y + off);
    }
}

#else

bool avx2_available() { return false; }
void avx2_block(const target_lanes*,
                unsigned,
                bool,
                const gr_complex*,
                gr_complex*,
                gr_complex*,
                std::size_t)
{
}

#endif

} // namespace echo_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
