/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// AVX-512F inner loop of kernel::multipath_fir (compiled with -mavx2 -mfma -mavx512f,
// called only after avx512_available()): fir_wide (td_echo_wide.h) on 16-float registers,
// 32 outputs at a time; the last n % 32 go through fir_avx2. The same per-lane arithmetic
// as fir_avx2 (one FMA per tap into x Re g and x Im g, taps in the same order, the same
// final add/subtract), so every output equals fir_avx2's bit for bit. No standard-library
// templates here: a copy of one compiled with -mavx512f could be the one the linker keeps.

#include "td_echo_impl.h"

#if defined(__x86_64__) || defined(__i386__)
#include "td_echo_wide.h"
#include <immintrin.h>
#define NRSAR_TD_AVX512 1
#endif

namespace gr {
namespace nrsar {
namespace kernel {
namespace td_detail {

#ifdef NRSAR_TD_AVX512

namespace {
struct avx512_registers {
    static constexpr std::size_t floats = 16;
    static __m512 zero() { return _mm512_setzero_ps(); }
    static __m512 load(const float* p) { return _mm512_loadu_ps(p); }
    static __m512 broadcast(const float* p) { return _mm512_set1_ps(*p); }
    static __m512 fmadd(__m512 a, __m512 b, __m512 c) { return _mm512_fmadd_ps(a, b, c); }
    static void store(float* p, __m512 a) { _mm512_storeu_ps(p, a); }
    // _mm256_addsub_ps for 16 floats: subtract in the real (even) lanes, add in the
    // imaginary ones
    static __m512 finish(__m512 a1, __m512 a2)
    {
        const __m512 p = _mm512_permute_ps(a2, 0xB1);
        return _mm512_mask_sub_ps(_mm512_add_ps(a1, p), 0x5555, a1, p);
    }
};
} // namespace

#endif

void fir_avx512(const gr_complex* x,
                const gr_complex* g,
                unsigned span,
                gr_complex* y,
                std::size_t n,
                gr_complex* tail)
{
#ifdef NRSAR_TD_AVX512
    const std::size_t i = fir_wide<avx512_registers>(x, g, span, y, n);
#else
    const std::size_t i = 0;
#endif
    if (i < n)
        fir_avx2(x + i, g, span, y + i, n - i, tail);
}

bool avx512_available()
{
#ifdef NRSAR_TD_AVX512
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f");
#else
    return false;
#endif
}

} // namespace td_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
