/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// AVX2 layer update of kernel::nr_ldpc_decoder. This file alone is compiled with -mavx2
// (lib/CMakeLists.txt) and called only after a runtime CPU check. No std:: templates here
// (an AVX2 instantiation could be picked by the linker for the generic code too); its own
// templates have internal linkage.

#include "nr_ldpc_decoder_impl.h"
#include "cpu_features.h"
#include <cmath>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

namespace gr {
namespace nrsar {
namespace kernel {
namespace ldpc_detail {

bool avx2_available() { return cpu_supports_avx2(); }

namespace {

// The instructions of one lane width, so that the layer update and the sign test are written
// once for int8 (32 lanes) and int16 (16 lanes). sign_bits: the movemask bits that hold the
// lanes' signs (int16: the high byte of each lane).
struct lanes8 {
    using T = std::int8_t;
    static constexpr unsigned n = 32;
    static constexpr unsigned sign_bits = 0xFFFFFFFFu;
    static __m256i set1(int x) { return _mm256_set1_epi8(static_cast<char>(x)); }
    static __m256i ramp()
    {
        return _mm256_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19,
                                20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31);
    }
    static __m256i subs(__m256i a, __m256i b) { return _mm256_subs_epi8(a, b); }
    static __m256i adds(__m256i a, __m256i b) { return _mm256_adds_epi8(a, b); }
    static __m256i subs_unsigned(__m256i a, __m256i b) { return _mm256_subs_epu8(a, b); }
    static __m256i max(__m256i a, __m256i b) { return _mm256_max_epi8(a, b); }
    static __m256i min(__m256i a, __m256i b) { return _mm256_min_epi8(a, b); }
    static __m256i abs(__m256i a) { return _mm256_abs_epi8(a); }
    static __m256i sign(__m256i a, __m256i b) { return _mm256_sign_epi8(a, b); }
    static __m256i eq(__m256i a, __m256i b) { return _mm256_cmpeq_epi8(a, b); }
    static __m256i gt(__m256i a, __m256i b) { return _mm256_cmpgt_epi8(a, b); }
};

struct lanes16 {
    using T = std::int16_t;
    static constexpr unsigned n = 16;
    static constexpr unsigned sign_bits = 0xAAAAAAAAu;
    static __m256i set1(int x) { return _mm256_set1_epi16(static_cast<short>(x)); }
    static __m256i ramp() { return _mm256_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15); }
    static __m256i subs(__m256i a, __m256i b) { return _mm256_subs_epi16(a, b); }
    static __m256i adds(__m256i a, __m256i b) { return _mm256_adds_epi16(a, b); }
    static __m256i subs_unsigned(__m256i a, __m256i b) { return _mm256_subs_epu16(a, b); }
    static __m256i max(__m256i a, __m256i b) { return _mm256_max_epi16(a, b); }
    static __m256i min(__m256i a, __m256i b) { return _mm256_min_epi16(a, b); }
    static __m256i abs(__m256i a) { return _mm256_abs_epi16(a); }
    static __m256i sign(__m256i a, __m256i b) { return _mm256_sign_epi16(a, b); }
    static __m256i eq(__m256i a, __m256i b) { return _mm256_cmpeq_epi16(a, b); }
    static __m256i gt(__m256i a, __m256i b) { return _mm256_cmpgt_epi16(a, b); }
};

template <typename V>
bool layer(typename V::T* t, typename V::T* r, unsigned deg, unsigned zp, unsigned zc, typename V::T offset)
{
    const __m256i lo = V::set1(-fixed<typename V::T>::max);
    const __m256i one = V::set1(1);
    const __m256i off = V::set1(offset);
    __m256i bad = _mm256_setzero_si256();
    for (unsigned v = 0; v < zp; v += V::n) {
        __m256i min1 = V::set1(fixed<typename V::T>::max), min2 = min1;
        __m256i sgn = _mm256_setzero_si256(), sgnl = sgn;
        for (unsigned e = 0; e < deg; e++) {
            __m256i* pt = reinterpret_cast<__m256i*>(t + e * zp + v);
            const __m256i l = _mm256_loadu_si256(pt);
            const __m256i x =
                V::max(V::subs(l, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(r + e * zp + v))), lo);
            _mm256_storeu_si256(pt, x);
            const __m256i a = V::abs(x);
            min2 = V::min(min2, V::max(min1, a));
            min1 = V::min(min1, a);
            sgn = _mm256_xor_si256(sgn, x);
        }
        // max(m - offset, 0): unsigned saturating subtraction (0 <= m <= max)
        const __m256i m1 = V::subs_unsigned(min1, off);
        const __m256i m2 = V::subs_unsigned(min2, off);
        for (unsigned e = 0; e < deg; e++) {
            __m256i* pt = reinterpret_cast<__m256i*>(t + e * zp + v);
            __m256i* pr = reinterpret_cast<__m256i*>(r + e * zp + v);
            const __m256i x = _mm256_loadu_si256(pt);
            const __m256i m = _mm256_blendv_epi8(m1, m2, V::eq(V::abs(x), min1));
            // sign of the others' product: sgn xor x; "| 1" keeps sign from zeroing
            const __m256i s = V::sign(m, _mm256_or_si256(_mm256_xor_si256(sgn, x), one));
            _mm256_storeu_si256(pr, s);
            const __m256i l = V::max(V::adds(x, s), lo);
            _mm256_storeu_si256(pt, l);
            sgnl = _mm256_xor_si256(sgnl, l);
        }
        if (v + V::n > zc) // lanes at and beyond zc are padding: ramp < zc - v keeps the others
            sgnl = _mm256_and_si256(sgnl, V::gt(V::set1(static_cast<int>(zc - v)), V::ramp()));
        bad = _mm256_or_si256(bad, sgnl);
    }
    return (static_cast<unsigned>(_mm256_movemask_epi8(bad)) & V::sign_bits) == 0;
}

template <typename V>
unsigned unsatisfied(const typename V::T* t, unsigned deg, unsigned zp, unsigned zc)
{
    unsigned bad = 0;
    for (unsigned v = 0; v < zp; v += V::n) {
        __m256i x = _mm256_setzero_si256();
        for (unsigned e = 0; e < deg; e++)
            x = _mm256_xor_si256(x, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(t + e * zp + v)));
        if (v + V::n > zc)
            x = _mm256_and_si256(x, V::gt(V::set1(static_cast<int>(zc - v)), V::ramp()));
        bad += __builtin_popcount(static_cast<unsigned>(_mm256_movemask_epi8(x)) & V::sign_bits);
    }
    return bad;
}

} // namespace

bool layer_avx2(std::int8_t* t, std::int8_t* r, unsigned deg, unsigned zp, unsigned zc, std::int8_t offset)
{
    return layer<lanes8>(t, r, deg, zp, zc, offset);
}

bool layer_avx2(std::int16_t* t, std::int16_t* r, unsigned deg, unsigned zp, unsigned zc, std::int16_t offset)
{
    return layer<lanes16>(t, r, deg, zp, zc, offset);
}

unsigned unsatisfied_avx2(const std::int8_t* t, unsigned deg, unsigned zp, unsigned zc)
{
    return unsatisfied<lanes8>(t, deg, zp, zc);
}

unsigned unsatisfied_avx2(const std::int16_t* t, unsigned deg, unsigned zp, unsigned zc)
{
    return unsatisfied<lanes16>(t, deg, zp, zc);
}

namespace {

// 8 LLRs -> 8 int32 of fixed<T>: round(clamp(v scale, -in_max, in_max)) (nearest, ties to
// even), NaN -> 0, +-inf -> +-max.
template <typename T>
__m256i quantize8(const float* in, __m256 s)
{
    const __m256 v = _mm256_loadu_ps(in);
    __m256 x = _mm256_and_ps(_mm256_mul_ps(v, s), _mm256_cmp_ps(v, v, _CMP_ORD_Q)); // NaN -> 0
    x = _mm256_min_ps(_mm256_max_ps(x, _mm256_set1_ps(-fixed<T>::in_max)), _mm256_set1_ps(fixed<T>::in_max));
    const __m256 big = _mm256_set1_ps(static_cast<float>(fixed<T>::max));
    x = _mm256_blendv_ps(x, big, _mm256_cmp_ps(v, _mm256_set1_ps(INFINITY), _CMP_EQ_OQ));
    x = _mm256_blendv_ps(x, _mm256_sub_ps(_mm256_setzero_ps(), big), _mm256_cmp_ps(v, _mm256_set1_ps(-INFINITY), _CMP_EQ_OQ));
    return _mm256_cvtps_epi32(x);
}

// The same for the last n % 8 values.
template <typename T>
void quantize_tail(const float* in, unsigned k, unsigned n, float scale, T* out)
{
    for (; k < n; k++) {
        const float v = in[k];
        float x = v == v ? v * scale : 0.0f;
        x = x < -fixed<T>::in_max ? -fixed<T>::in_max : (x > fixed<T>::in_max ? fixed<T>::in_max : x);
        const int r = _mm_cvtss_si32(_mm_set_ss(x));
        out[k] = static_cast<T>(v == INFINITY ? fixed<T>::max : (v == -INFINITY ? -fixed<T>::max : r));
    }
}

} // namespace

void quantize_avx2(const float* in, unsigned n, float scale, std::int8_t* out)
{
    const __m256 s = _mm256_set1_ps(scale);
    const __m256i order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
    unsigned k = 0;
    for (; k + 32 <= n; k += 32) {
        const __m256i q0 = quantize8<std::int8_t>(in + k, s), q1 = quantize8<std::int8_t>(in + k + 8, s);
        const __m256i q2 = quantize8<std::int8_t>(in + k + 16, s), q3 = quantize8<std::int8_t>(in + k + 24, s);
        // packs works per 128-bit lane: the permutation restores the element order.
        const __m256i w = _mm256_packs_epi16(_mm256_packs_epi32(q0, q1), _mm256_packs_epi32(q2, q3));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + k), _mm256_permutevar8x32_epi32(w, order));
    }
    quantize_tail(in, k, n, scale, out);
}

void quantize_avx2(const float* in, unsigned n, float scale, std::int16_t* out)
{
    const __m256 s = _mm256_set1_ps(scale);
    unsigned k = 0;
    for (; k + 16 <= n; k += 16) {
        const __m256i q0 = quantize8<std::int16_t>(in + k, s), q1 = quantize8<std::int16_t>(in + k + 8, s);
        // packs works per 128-bit lane: 64-bit quarters 0 2 1 3 restore the order.
        const __m256i w = _mm256_permute4x64_epi64(_mm256_packs_epi32(q0, q1), 0xD8);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + k), w);
    }
    quantize_tail(in, k, n, scale, out);
}

bool any_received_avx2(const float* in, unsigned n)
{
    const __m256 zero = _mm256_setzero_ps();
    __m256 any = zero;
    unsigned k = 0;
    for (; k + 8 <= n; k += 8) // not equal and ordered: NaN gives false
        any = _mm256_or_ps(any, _mm256_cmp_ps(_mm256_loadu_ps(in + k), zero, _CMP_NEQ_OQ));
    bool got = _mm256_movemask_ps(any) != 0;
    for (; k < n; k++)
        got = got || (in[k] != 0.0f && in[k] == in[k]);
    return got;
}

void root_sums_avx2(const float* in, std::size_t n8, float* part, float* cnt)
{
    __m256 p = _mm256_loadu_ps(part), c = _mm256_loadu_ps(cnt);
    const __m256 sign = _mm256_set1_ps(-0.0f), zero = _mm256_setzero_ps();
    const __m256 inf = _mm256_set1_ps(INFINITY), one = _mm256_set1_ps(1.0f);
    for (std::size_t k = 0; k < n8; k += 8) {
        const __m256 a = _mm256_andnot_ps(sign, _mm256_loadu_ps(in + k));
        const __m256 use = _mm256_and_ps(_mm256_cmp_ps(a, zero, _CMP_GT_OQ), _mm256_cmp_ps(a, inf, _CMP_LT_OQ));
        p = _mm256_add_ps(p, _mm256_and_ps(_mm256_sqrt_ps(a), use));
        c = _mm256_add_ps(c, _mm256_and_ps(one, use));
    }
    _mm256_storeu_ps(part, p);
    _mm256_storeu_ps(cnt, c);
}

void info_sums_avx2(const float* in, std::size_t n8, float* part, float* cnt)
{
    const float* table = info_table();
    __m256 p = _mm256_loadu_ps(part), c = _mm256_loadu_ps(cnt);
    const __m256 sign = _mm256_set1_ps(-0.0f), zero = _mm256_setzero_ps();
    const __m256 step = _mm256_set1_ps(info_step), one = _mm256_set1_ps(1.0f);
    const __m256 last = _mm256_set1_ps(static_cast<float>(info_bins - 1));
    for (std::size_t k = 0; k < n8; k += 8) {
        const __m256 v = _mm256_loadu_ps(in + k);
        // NaN -> 0 before the index (min_ps would pass it on)
        const __m256 a = _mm256_and_ps(_mm256_andnot_ps(sign, v), _mm256_cmp_ps(v, v, _CMP_ORD_Q));
        const __m256i i = _mm256_cvttps_epi32(_mm256_min_ps(_mm256_mul_ps(a, step), last));
        p = _mm256_add_ps(p, _mm256_i32gather_ps(table, i, 4));
        c = _mm256_add_ps(c, _mm256_and_ps(one, _mm256_cmp_ps(a, zero, _CMP_GT_OQ)));
    }
    _mm256_storeu_ps(part, p);
    _mm256_storeu_ps(cnt, c);
}

} // namespace ldpc_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#else

namespace gr {
namespace nrsar {
namespace kernel {
namespace ldpc_detail {
bool avx2_available() { return false; }
bool layer_avx2(std::int8_t* t, std::int8_t* r, unsigned deg, unsigned zp, unsigned zc, std::int8_t offset)
{
    return layer_generic(t, r, deg, zp, zc, offset);
}
bool layer_avx2(std::int16_t* t, std::int16_t* r, unsigned deg, unsigned zp, unsigned zc, std::int16_t offset)
{
    return layer_generic(t, r, deg, zp, zc, offset);
}
void quantize_avx2(const float* in, unsigned n, float scale, std::int8_t* out)
{
    quantize_generic(in, n, scale, out);
}
void quantize_avx2(const float* in, unsigned n, float scale, std::int16_t* out)
{
    quantize_generic(in, n, scale, out);
}
bool any_received_avx2(const float* in, unsigned n) { return any_received_generic(in, n); }
void root_sums_avx2(const float* in, std::size_t n8, float* part, float* cnt)
{
    root_sums_generic(in, n8, part, cnt);
}
void info_sums_avx2(const float* in, std::size_t n8, float* part, float* cnt)
{
    info_sums_generic(in, n8, part, cnt);
}
unsigned unsatisfied_avx2(const std::int8_t* t, unsigned deg, unsigned zp, unsigned zc)
{
    return unsatisfied_generic(t, deg, zp, zc);
}
unsigned unsatisfied_avx2(const std::int16_t* t, unsigned deg, unsigned zp, unsigned zc)
{
    return unsatisfied_generic(t, deg, zp, zc);
}
} // namespace ldpc_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif
