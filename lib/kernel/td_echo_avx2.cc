/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// AVX2/FMA inner loop of kernel::multipath_fir (compiled with -mavx2 -mfma, called only
// after the runtime check noise_detail::avx2_available()).
//
// y[i] = sum_j g[j] x[i + j]: fir_wide (td_echo_wide.h) on 8-float registers, 16 outputs
// at a time, then one register at a time and a zero-padded tail. Measured against one
// volk_32fc_x2_dot_prod_32fc call per output in docs/blocks/td_echo.md. Where the CPU has
// AVX-512F, fir_avx512 (td_echo_avx512.cc) runs fir_wide on 16-float registers.

#include "td_echo_impl.h"
#include <algorithm>

#if defined(__x86_64__) || defined(__i386__)
#include "td_echo_wide.h"
#include <immintrin.h>
#define NRSAR_TD_AVX2 1
#endif

namespace gr {
namespace nrsar {
namespace kernel {
namespace td_detail {

#ifdef NRSAR_TD_AVX2

namespace {
struct avx2_registers {
    static constexpr std::size_t floats = 8;
    static __m256 zero() { return _mm256_setzero_ps(); }
    static __m256 load(const float* p) { return _mm256_loadu_ps(p); }
    static __m256 broadcast(const float* p) { return _mm256_broadcast_ss(p); }
    static __m256 fmadd(__m256 a, __m256 b, __m256 c) { return _mm256_fmadd_ps(a, b, c); }
    static void store(float* p, __m256 a) { _mm256_storeu_ps(p, a); }
    // a1 = sum (xr gr, xi gr), a2 = sum (xr gi, xi gi): x g = (xr gr - xi gi, xi gr + xr gi)
    static __m256 finish(__m256 a1, __m256 a2)
    {
        return _mm256_addsub_ps(a1, _mm256_permute_ps(a2, 0xB1));
    }
};
} // namespace

void fir_avx2(const gr_complex* x,
              const gr_complex* g,
              unsigned span,
              gr_complex* y,
              std::size_t n,
              gr_complex* tail)
{
    using V = avx2_registers;
    const float* xf = reinterpret_cast<const float*>(x);
    const float* gf = reinterpret_cast<const float*>(g);
    float* yf = reinterpret_cast<float*>(y);
    std::size_t i = fir_wide<V>(x, g, span, y, n);
    for (; i + 4 <= n; i += 4) {
        __m256 a = V::zero(), b = a;
        const float* p = xf + 2 * i;
        for (unsigned j = 0; j < span; j++, p += 2) {
            const __m256 xv = V::load(p);
            a = V::fmadd(xv, V::broadcast(gf + 2 * j), a);
            b = V::fmadd(xv, V::broadcast(gf + 2 * j + 1), b);
        }
        V::store(yf + 2 * i, V::finish(a, b));
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

#endif

} // namespace td_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
