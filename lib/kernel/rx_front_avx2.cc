/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Built with -mavx2 (not -mfma: a fused multiply-add would round the products differently
// from the generic loop and from VOLK); called only after avx2_available().

#include "rx_front_impl.h"
#include "cpu_features.h"
#if defined(__AVX2__)
#include <immintrin.h>
#endif
#include <limits>

namespace gr {
namespace nrsar {
namespace kernel {
namespace rx_front {

#if defined(__AVX2__)

bool avx2_available() { return cpu_supports_avx2(); }

namespace {
float hsum(__m256 v)
{
    alignas(32) float lanes[8];
    _mm256_store_ps(lanes, v);
    float total = 0.0f;
    for (float x : lanes)
        total += x;
    return total;
}

// The inputs of these loops arrive from beyond L2: a 3333-wide edge is a 13.6 MB buffer
// (lcm(26664, 4096) bytes), which the faster block upstream keeps full, and the hardware
// prefetcher stops at each 4 kB page. Asking for the line a page ahead cut range_compress
// from 10.5 to 7-9 us per symbol on such input (bench_range_compress, ring), range_ifft's
// work() by 3-7 % in a flowgraph; prefetching past the end of an input cannot fault.
template <typename T>
void prefetch_ahead(const T* p)
{
    _mm_prefetch(reinterpret_cast<const char*>(p) + 4096, _MM_HINT_T0);
}
} // namespace

std::size_t filter_pass_avx2(weight_rule rule,
                             const gr_complex* y,
                             const gr_complex* s,
                             float inv_snr,
                             gr_complex* out,
                             std::size_t n,
                             const float* taps2,
                             float m0,
                             float tol,
                             pass_sums& sums)
{
    const __m256 m0v = _mm256_set1_ps(m0), tolv = _mm256_set1_ps(tol);
    const __m256 magnitude = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    __m256 off = _mm256_setzero_ps();
    const __m256 one = _mm256_set1_ps(1.0f);
    const __m256 reg = _mm256_set1_ps(inv_snr);
    const __m256 tiny = _mm256_set1_ps(std::numeric_limits<float>::min());
    __m256 acc0 = _mm256_setzero_ps(), acc1 = _mm256_setzero_ps();
    std::size_t empty = 0;
    const std::size_t done = n / 8 * 8;
    // Eight REs (one cache line of each input) per step, split into real and imaginary
    // parts (lanes in the order 0 1 4 5 | 2 3 6 7): one divide per eight weights, where
    // interleaved vectors took one per four (WF's divide bounded the loop), and fewer
    // shuffles. The same multiplies and adds per RE as the generic loop.
    for (std::size_t i = 0; i < done; i += 8) {
        prefetch_ahead(y + i);
        prefetch_ahead(s + i);
        const float* yf = reinterpret_cast<const float*>(y + i);
        const float* sf = reinterpret_cast<const float*>(s + i);
        const __m256 y0 = _mm256_loadu_ps(yf), y1 = _mm256_loadu_ps(yf + 8);
        const __m256 s0 = _mm256_loadu_ps(sf), s1 = _mm256_loadu_ps(sf + 8);
        acc0 = _mm256_add_ps(acc0, _mm256_add_ps(y0, s0));
        acc1 = _mm256_add_ps(acc1, _mm256_add_ps(y1, s1));
        const __m256 yr = _mm256_shuffle_ps(y0, y1, 0x88), yi = _mm256_shuffle_ps(y0, y1, 0xDD);
        const __m256 sr = _mm256_shuffle_ps(s0, s1, 0x88), si = _mm256_shuffle_ps(s0, s1, 0xDD);
        const __m256 m = _mm256_add_ps(_mm256_mul_ps(sr, sr), _mm256_mul_ps(si, si));
        const __m256 is_empty = _mm256_cmp_ps(m, tiny, _CMP_LT_OQ);
        empty += unsigned(__builtin_popcount(_mm256_movemask_ps(is_empty)));
        // y conj(s) = (yr sr + yi si, yi sr - yr si)
        __m256 pr = _mm256_add_ps(_mm256_mul_ps(yr, sr), _mm256_mul_ps(yi, si));
        __m256 pi = _mm256_sub_ps(_mm256_mul_ps(yi, sr), _mm256_mul_ps(yr, si));
        __m256 w = one;
        if (rule == weight_rule::scale) {
            // |m - m0| > tol on a non-empty RE (the ordered compares leave a NaN to the sum)
            const __m256 dev = _mm256_and_ps(_mm256_sub_ps(m, m0v), magnitude);
            off = _mm256_or_ps(off,
                               _mm256_and_ps(_mm256_cmp_ps(dev, tolv, _CMP_GT_OQ),
                                             _mm256_cmp_ps(m, _mm256_setzero_ps(), _CMP_NEQ_OQ)));
            w = reg;
        } else if (rule == weight_rule::wf) {
            w = _mm256_div_ps(one, _mm256_add_ps(m, reg));
        } else if (rule == weight_rule::rf) {
            const __m256 e = _mm256_and_ps(is_empty, one);
            w = _mm256_div_ps(_mm256_sub_ps(one, e), _mm256_add_ps(m, e));
        }
        if (rule != weight_rule::mf) {
            pr = _mm256_mul_ps(pr, w);
            pi = _mm256_mul_ps(pi, w);
        }
        __m256 p0 = _mm256_unpacklo_ps(pr, pi), p1 = _mm256_unpackhi_ps(pr, pi);
        if (taps2) {
            p0 = _mm256_mul_ps(p0, _mm256_loadu_ps(taps2 + 2 * i));
            p1 = _mm256_mul_ps(p1, _mm256_loadu_ps(taps2 + 2 * i + 8));
        }
        float* of = reinterpret_cast<float*>(out + i);
        _mm256_storeu_ps(of, p0);
        _mm256_storeu_ps(of + 8, p1);
    }
    sums.empty += empty;
    sums.off_modulus = sums.off_modulus || _mm256_movemask_ps(off) != 0;
    sums.sum += hsum(_mm256_add_ps(acc0, acc1));
    return done;
}

std::size_t window_pass_avx2(
    const gr_complex* in, const float* taps2, gr_complex* dst, std::size_t n, float& sum)
{
    const float* x = reinterpret_cast<const float*>(in);
    float* d = reinterpret_cast<float*>(dst);
    // One cache line per step, two accumulators (one add chain bounded the hot loop).
    __m256 acc0 = _mm256_setzero_ps(), acc1 = _mm256_setzero_ps();
    const std::size_t done = n / 8 * 8;
    for (std::size_t j = 0; j < 2 * done; j += 16) {
        prefetch_ahead(x + j);
        const __m256 a = _mm256_loadu_ps(x + j), b = _mm256_loadu_ps(x + j + 8);
        acc0 = _mm256_add_ps(acc0, a);
        acc1 = _mm256_add_ps(acc1, b);
        _mm256_storeu_ps(d + j, _mm256_mul_ps(a, _mm256_loadu_ps(taps2 + j)));
        _mm256_storeu_ps(d + j + 8, _mm256_mul_ps(b, _mm256_loadu_ps(taps2 + j + 8)));
    }
    sum += hsum(_mm256_add_ps(acc0, acc1));
    return done;
}

std::size_t copy_pass_avx2(const gr_complex* in, gr_complex* dst, std::size_t n, float& sum)
{
    const float* x = reinterpret_cast<const float*>(in);
    float* d = reinterpret_cast<float*>(dst);
    __m256 acc0 = _mm256_setzero_ps(), acc1 = _mm256_setzero_ps();
    const std::size_t done = n / 8 * 8;
    for (std::size_t j = 0; j < 2 * done; j += 16) { // two accumulators: no add chain stall
        const __m256 a = _mm256_loadu_ps(x + j), b = _mm256_loadu_ps(x + j + 8);
        acc0 = _mm256_add_ps(acc0, a);
        acc1 = _mm256_add_ps(acc1, b);
        _mm256_storeu_ps(d + j, a);
        _mm256_storeu_ps(d + j + 8, b);
    }
    sum += hsum(_mm256_add_ps(acc0, acc1));
    return done;
}

#else

bool avx2_available() { return false; }
std::size_t filter_pass_avx2(weight_rule,
                             const gr_complex*,
                             const gr_complex*,
                             float,
                             gr_complex*,
                             std::size_t,
                             const float*,
                             float,
                             float,
                             pass_sums&)
{
    return 0;
}
std::size_t
window_pass_avx2(const gr_complex*, const float*, gr_complex*, std::size_t, float&)
{
    return 0;
}
std::size_t copy_pass_avx2(const gr_complex*, gr_complex*, std::size_t, float&) { return 0; }

#endif

} // namespace rx_front
} // namespace kernel
} // namespace nrsar
} // namespace gr
