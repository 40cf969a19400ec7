/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// AVX2/FMA inner loop of kernel::multipath_fir (compiled with -mavx2 -mfma, called only
// after the runtime check noise_detail::avx2_available()).
//
// y[i] = sum_j g[j] x[i + j]: 16 outputs (4 registers of 4 complex) at a time, every
// tap broadcast once and applied to the 4 registers: per tap 4 unaligned loads and 8 FMA,
// accumulating x * Re g and x * Im g separately; one addsub/permute per register at the
// end forms the complex product. Measured against one volk_32fc_x2_dot_prod_32fc call per
// output in docs/blocks/td_echo.md. Where the CPU has AVX-512F, fir_avx512 (a function
// target attribute, so the file needs no -mavx512f) does the same with 8 complex per
// register.

#include "td_echo_impl.h"
#include <algorithm>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define NRSAR_TD_AVX2 1
#endif

namespace gr {
namespace nrsar {
namespace kernel {
namespace td_detail {

#ifdef NRSAR_TD_AVX2

namespace {
inline __m256 finish(__m256 a1, __m256 a2)
{
    // a1 = sum (xr gr, xi gr), a2 = sum (xr gi, xi gi): x g = (xr gr - xi gi, xi gr + xr gi)
    return _mm256_addsub_ps(a1, _mm256_permute_ps(a2, 0xB1));
}
} // namespace

void fir_avx2(const gr_complex* x,
              const gr_complex* g,
              unsigned span,
              gr_complex* y,
              std::size_t n,
              gr_complex* tail)
{
    const float* xf = reinterpret_cast<const float*>(x);
    const float* gf = reinterpret_cast<const float*>(g);
    float* yf = reinterpret_cast<float*>(y);
    std::size_t i = 0;
    for (; i + 16 <= n; i += 16) {
        __m256 a0 = _mm256_setzero_ps(), a1 = a0, a2 = a0, a3 = a0;
        __m256 b0 = a0, b1 = a0, b2 = a0, b3 = a0;
        const float* p = xf + 2 * i;
        for (unsigned j = 0; j < span; j++, p += 2) {
            const __m256 gr = _mm256_broadcast_ss(gf + 2 * j);
            const __m256 gi = _mm256_broadcast_ss(gf + 2 * j + 1);
            const __m256 x0 = _mm256_loadu_ps(p), x1 = _mm256_loadu_ps(p + 8);
            const __m256 x2 = _mm256_loadu_ps(p + 16), x3 = _mm256_loadu_ps(p + 24);
            a0 = _mm256_fmadd_ps(x0, gr, a0);
            b0 = _mm256_fmadd_ps(x0, gi, b0);
            a1 = _mm256_fmadd_ps(x1, gr, a1);
            b1 = _mm256_fmadd_ps(x1, gi, b1);
            a2 = _mm256_fmadd_ps(x2, gr, a2);
            b2 = _mm256_fmadd_ps(x2, gi, b2);
            a3 = _mm256_fmadd_ps(x3, gr, a3);
            b3 = _mm256_fmadd_ps(x3, gi, b3);
        }
        _mm256_storeu_ps(yf + 2 * i, finish(a0, b0));
        _mm256_storeu_ps(yf + 2 * i + 8, finish(a1, b1));
        _mm256_storeu_ps(yf + 2 * i + 16, finish(a2, b2));
        _mm256_storeu_ps(yf + 2 * i + 24, finish(a3, b3));
    }
    for (; i + 4 <= n; i += 4) {
        __m256 a = _mm256_setzero_ps(), b = a;
        const float* p = xf + 2 * i;
        for (unsigned j = 0; j < span; j++, p += 2) {
            const __m256 xv = _mm256_loadu_ps(p);
            a = _mm256_fmadd_ps(xv, _mm256_broadcast_ss(gf + 2 * j), a);
            b = _mm256_fmadd_ps(xv, _mm256_broadcast_ss(gf + 2 * j + 1), b);
        }
        _mm256_storeu_ps(yf + 2 * i, finish(a, b));
    }
    if (i == n)
        return;
    // The last 1..3 outputs through the same 4-wide arithmetic on a zero-padded copy, so
    // an output sample does not depend on where the stream is cut.
    const std::size_t rest = n - i;
    std::fill(tail, tail + span + 3, gr_complex(0.0f, 0.0f));
    std::copy(x + i, x + i + span + rest - 1, tail);
    gr_complex out[4];
    fir_avx2(tail, g, span, out, 4, nullptr);
    std::copy(out, out + rest, y + i);
}

namespace {
// finish() for 8 complex: subtract in the real (even) lanes, add in the imaginary ones,
// as _mm256_addsub_ps
__attribute__((target("avx512f"))) inline __m512 finish512(__m512 a1, __m512 a2)
{
    const __m512 p = _mm512_permute_ps(a2, 0xB1);
    return _mm512_mask_sub_ps(_mm512_add_ps(a1, p), 0x5555, a1, p);
}
} // namespace

// AVX-512F: the same per-lane arithmetic (one FMA per tap into x Re g and x Im g, taps
// in the same order, the same final add/subtract), 32 outputs at a time, so every output
// equals fir_avx2's bit for bit; the last n % 32 outputs go through fir_avx2.
__attribute__((target("avx512f"))) void fir_avx512(const gr_complex* x,
                                                   const gr_complex* g,
                                                   unsigned span,
                                                   gr_complex* y,
                                                   std::size_t n,
                                                   gr_complex* tail)
{
    const float* xf = reinterpret_cast<const float*>(x);
    const float* gf = reinterpret_cast<const float*>(g);
    float* yf = reinterpret_cast<float*>(y);
    std::size_t i = 0;
    for (; i + 32 <= n; i += 32) {
        __m512 a0 = _mm512_setzero_ps(), a1 = a0, a2 = a0, a3 = a0;
        __m512 b0 = a0, b1 = a0, b2 = a0, b3 = a0;
        const float* p = xf + 2 * i;
        for (unsigned j = 0; j < span; j++, p += 2) {
            const __m512 gr = _mm512_set1_ps(gf[2 * j]);
            const __m512 gi = _mm512_set1_ps(gf[2 * j + 1]);
            const __m512 x0 = _mm512_loadu_ps(p), x1 = _mm512_loadu_ps(p + 16);
            const __m512 x2 = _mm512_loadu_ps(p + 32), x3 = _mm512_loadu_ps(p + 48);
            a0 = _mm512_fmadd_ps(x0, gr, a0);
            b0 = _mm512_fmadd_ps(x0, gi, b0);
            a1 = _mm512_fmadd_ps(x1, gr, a1);
            b1 = _mm512_fmadd_ps(x1, gi, b1);
            a2 = _mm512_fmadd_ps(x2, gr, a2);
            b2 = _mm512_fmadd_ps(x2, gi, b2);
            a3 = _mm512_fmadd_ps(x3, gr, a3);
            b3 = _mm512_fmadd_ps(x3, gi, b3);
        }
        _mm512_storeu_ps(yf + 2 * i, finish512(a0, b0));
        _mm512_storeu_ps(yf + 2 * i + 16, finish512(a1, b1));
        _mm512_storeu_ps(yf + 2 * i + 32, finish512(a2, b2));
        _mm512_storeu_ps(yf + 2 * i + 48, finish512(a3, b3));
    }
    if (i < n)
        fir_avx2(x + i, g, span, y + i, n - i, tail);
}

bool avx512_available()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f");
}

#else

void fir_avx2(const gr_complex* x,
              const gr_complex* g,
              unsigned span,
              gr_complex* y,
              std::size_t n,
              gr_complex*)
{
    for (std::size_t i = 0; i < n; i++)
        y[i] = fir_generic_one(x + i, g, span);
}

void fir_avx512(const gr_complex* x,
                const gr_complex* g,
                unsigned span,
                gr_complex* y,
                std::size_t n,
                gr_complex* tail)
{
    fir_avx2(x, g, span, y, n, tail);
}

bool avx512_available() { return false; }

#endif

} // namespace td_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
