/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// AVX2/FMA path of kernel::gaussian_noise. This file alone is compiled with
// -mavx2 -mfma (lib/CMakeLists.txt) and is only called after a runtime CPU check,
// so the library itself keeps the baseline x86-64 ISA.

#include "gaussian_noise_impl.h"
#include "cpu_features.h"

#include "noise_avx2.h" // defines NRSAR_HAVE_AVX2_PATH on x86

namespace gr {
namespace nrsar {
namespace kernel {
namespace noise_detail {

#ifdef NRSAR_HAVE_AVX2_PATH

bool avx2_available() { return cpu_supports_avx2(true); }

void avx2_run(lane_state& st, float sigma, gr_complex* out, std::size_t groups, bool add)
{
    xoshiro8 g(st);
    const __m256 v_sigma = _mm256_set1_ps(sigma);
    float* o = reinterpret_cast<float*>(out);
    for (std::size_t gi = 0; gi < groups; gi++, o += 16) {
        __m256 out0, out1;
        box_muller8(g, v_sigma, out0, out1);
        if (add) {
            out0 = _mm256_add_ps(out0, _mm256_loadu_ps(o));
            out1 = _mm256_add_ps(out1, _mm256_loadu_ps(o + 8));
        }
        _mm256_storeu_ps(o, out0);
        _mm256_storeu_ps(o + 8, out1);
    }
    g.store(st);
}

#else

bool avx2_available() { return false; }
void avx2_run(lane_state&, float, gr_complex*, std::size_t, bool) {}

#endif

} // namespace noise_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
