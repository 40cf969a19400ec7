/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// AVX2/FMA inner loop of kernel::scene_echo. This file alone is compiled with
// -mavx2 -mfma (lib/CMakeLists.txt) and called only after a runtime CPU check.

// No std:: templates here: an out-of-line instantiation compiled for AVX2 could be
// picked by the linker for the generic code too (checked: `nm` shows no weak symbols).

#include "scene_echo_impl.h"

#include "noise_avx2.h" // defines NRSAR_HAVE_AVX2_PATH on x86

namespace gr {
namespace nrsar {
namespace kernel {
namespace echo_detail {

#ifdef NRSAR_HAVE_AVX2_PATH

bool avx2_available() { return noise_detail::avx2_available(); }

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

// Bit 31 set iff the float's exponent is all ones (inf or NaN): (e + 1) overflows.
inline __m256i nonfinite_bits(__m256 v)
{
    return _mm256_add_epi32(_mm256_and_si256(_mm256_castps_si256(v), _mm256_set1_epi32(0x7f800000)),
                            _mm256_set1_epi32(0x00800000));
}

} // namespace

void avx2_block(const target_lanes* t, unsigned nq, block_io& io, std::size_t len)
{
    using noise_detail::xoshiro8;
    __m256 p[max_targets][2], sr[max_targets], si[max_targets];
    for (unsigned q = 0; q < nq; q++) {
        p[q][0] = _mm256_load_ps(t[q].v);
        p[q][1] = _mm256_load_ps(t[q].v + 8);
        sr[q] = _mm256_set1_ps(t[q].step[0]);
        si[q] = _mm256_set1_ps(t[q].step[1]);
    }
    const bool noise = io.s && io.noise;
    noise_detail::lane_state dummy{};
    xoshiro8 rng(noise ? *io.noise : dummy);
    const __m256 v_sigma = _mm256_set1_ps(io.sigma);
    __m256i bad = _mm256_setzero_si256();

    // One group of 8 subcarriers; the last partial group goes through local copies.
    auto group = [&](const float* sp, float* yp, float* hp) {
        __m256 h0 = io.accumulate ? _mm256_loadu_ps(hp) : _mm256_setzero_ps();
        __m256 h1 = io.accumulate ? _mm256_loadu_ps(hp + 8) : _mm256_setzero_ps();
        for (unsigned q = 0; q < nq; q++) {
            h0 = _mm256_add_ps(h0, p[q][0]);
            h1 = _mm256_add_ps(h1, p[q][1]);
            p[q][0] = cmul_bcast(p[q][0], sr[q], si[q]);
            p[q][1] = cmul_bcast(p[q][1], sr[q], si[q]);
        }
        if (hp) {
            _mm256_storeu_ps(hp, h0);
            _mm256_storeu_ps(hp + 8, h1);
        }
        if (sp) {
            const __m256 s0 = _mm256_loadu_ps(sp);
            const __m256 s1 = _mm256_loadu_ps(sp + 8);
            bad = _mm256_or_si256(bad, _mm256_or_si256(nonfinite_bits(s0), nonfinite_bits(s1)));
            __m256 y0 = cmul(h0, s0); // eq. (7): Y = S H (+ Z)
            __m256 y1 = cmul(h1, s1);
            if (noise) {
                __m256 z0, z1;
                noise_detail::box_muller8(rng, v_sigma, z0, z1);
                y0 = _mm256_add_ps(y0, z0);
                y1 = _mm256_add_ps(y1, z1);
            }
            _mm256_storeu_ps(yp, y0);
            _mm256_storeu_ps(yp + 8, y1);
        }
    };
    const std::size_t full = len / lanes;
    const float* sf = reinterpret_cast<const float*>(io.s);
    float* yf = reinterpret_cast<float*>(io.y);
    float* hf = reinterpret_cast<float*>(io.h);
    for (std::size_t g = 0; g < full; g++)
        group(sf ? sf + 16 * g : nullptr, yf + 16 * g, hf ? hf + 16 * g : nullptr);
    const std::size_t rest = len - full * lanes;
    if (rest) {
        alignas(32) float st[2 * lanes] = {}, yt[2 * lanes], ht[2 * lanes] = {};
        const std::size_t off = 2 * full * lanes;
        const std::size_t nf = 2 * rest;
        if (io.accumulate)
            for (std::size_t i = 0; i < nf; i++)
                ht[i] = hf[off + i];
        if (io.s)
            for (std::size_t i = 0; i < nf; i++)
                st[i] = sf[off + i];
        group(io.s ? st : nullptr, yt, io.h ? ht : nullptr);
        if (io.h)
            for (std::size_t i = 0; i < nf; i++)
                hf[off + i] = ht[i];
        if (io.s)
            for (std::size_t i = 0; i < nf; i++)
                yf[off + i] = yt[i];
    }
    if (noise)
        rng.store(*io.noise);
    if (_mm256_movemask_ps(_mm256_castsi256_ps(bad)))
        io.nonfinite = true;
}

#else

bool avx2_available() { return false; }
void avx2_block(const target_lanes*, unsigned, block_io&, std::size_t) {}

#endif

} // namespace echo_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
