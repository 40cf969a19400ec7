/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "rx_front_impl.h"
#include <volk/volk.h>
#include <cmath>
#include <cstring>
#include <limits>

namespace gr {
namespace nrsar {
namespace kernel {
namespace rx_front {

namespace {
const bool use_avx2 = avx2_available();
} // namespace

pass_sums filter_pass(weight_rule rule,
                      const gr_complex* y,
                      const gr_complex* s,
                      float inv_snr,
                      gr_complex* out,
                      std::size_t n,
                      const float* taps2,
                      float m0,
                      float tol)
{
    constexpr float empty_mag2 = std::numeric_limits<float>::min();
    pass_sums sums;
    std::size_t i = use_avx2 ? filter_pass_avx2(rule, y, s, inv_snr, out, n, taps2, m0, tol, sums) : 0;
    for (; i < n; i++) {
        const float yr = y[i].real(), yi = y[i].imag(), sr = s[i].real(),
                    si = s[i].imag();
        sums.sum += (yr + yi) + (sr + si);
        const float m = sr * sr + si * si;
        const float empty = m < empty_mag2 ? 1.0f : 0.0f;
        sums.empty += std::size_t(empty);
        float w = 1.0f;
        if (rule == weight_rule::wf)
            w = 1.0f / (m + inv_snr);
        else if (rule == weight_rule::rf)
            w = (1.0f - empty) / (m + empty);
        else if (rule == weight_rule::scale) {
            w = inv_snr;
            if (m != 0.0f && std::fabs(m - m0) > tol)
                sums.off_modulus = true;
        }
        float pr = yr * sr + yi * si, pi = yi * sr - yr * si;
        if (rule != weight_rule::mf) {
            pr *= w;
            pi *= w;
        }
        if (taps2) {
            pr *= taps2[2 * i];
            pi *= taps2[2 * i + 1];
        }
        out[i] = gr_complex(pr, pi);
    }
    return sums;
}

bool one_pass() { return use_avx2; }

float window_pass(const gr_complex* in,
                  const float* taps2,
                  gr_complex* dst,
                  std::size_t n)
{
    float sum = 0.0f;
    if (!use_avx2) { // VOLK's two passes beat a loop built for the baseline ISA
        const auto x = reinterpret_cast<const float*>(in);
        volk_32f_x2_multiply_32f(reinterpret_cast<float*>(dst), x, taps2, 2 * n);
        volk_32f_accumulator_s32f(&sum, x, 2 * n);
        return sum;
    }
    std::size_t i = window_pass_avx2(in, taps2, dst, n, sum);
    for (; i < n; i++) {
        sum += in[i].real() + in[i].imag();
        dst[i] = gr_complex(in[i].real() * taps2[2 * i], in[i].imag() * taps2[2 * i + 1]);
    }
    return sum;
}

float copy_pass(const gr_complex* in, gr_complex* dst, std::size_t n)
{
    float sum = 0.0f;
    if (!use_avx2) {
        volk_32f_accumulator_s32f(&sum, reinterpret_cast<const float*>(in), 2 * n);
        std::memcpy(dst, in, sizeof(gr_complex) * n);
        return sum;
    }
    std::size_t i = copy_pass_avx2(in, dst, n, sum);
    for (; i < n; i++) {
        sum += in[i].real() + in[i].imag();
        dst[i] = in[i];
    }
    return sum;
}

} // namespace rx_front
} // namespace kernel
} // namespace nrsar
} // namespace gr
