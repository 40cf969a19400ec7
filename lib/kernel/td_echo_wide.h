/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// The main loop of kernel::multipath_fir's SIMD paths over the register width: one
// template, instantiated by td_echo_avx2.cc (-mavx2 -mfma) and td_echo_avx512.cc (also
// -mavx512f). Internal linkage, so each file's copy keeps its own instruction set (a shared
// inline copy could run AVX-512 code on an AVX2-only CPU).

#ifndef INCLUDED_NRSAR_KERNEL_TD_ECHO_WIDE_H
#define INCLUDED_NRSAR_KERNEL_TD_ECHO_WIDE_H

#include <gnuradio/gr_complex.h>
#include <cstddef>

namespace gr {
namespace nrsar {
namespace kernel {
namespace td_detail {
namespace {

/*!
 * y[i] = sum_j g[j] x[i + j] for the first n - n % (4 V::width) outputs; returns their
 * count. V: the registers (V::floats floats each) with zero, load, broadcast, fmadd,
 * store and finish. 4 registers of outputs at a time, every tap broadcast once and applied
 * to the 4: per tap 4 unaligned loads and 8 FMA, accumulating x Re g and x Im g separately;
 * V::finish forms the complex product at the end. Every lane does the same operations in
 * the same order whatever the width, so the widths' outputs are equal bit for bit.
 */
template <class V>
inline std::size_t
fir_wide(const gr_complex* x, const gr_complex* g, unsigned span, gr_complex* y, std::size_t n)
{
    constexpr std::size_t w = V::floats;
    const float* xf = reinterpret_cast<const float*>(x);
    const float* gf = reinterpret_cast<const float*>(g);
    float* yf = reinterpret_cast<float*>(y);
    std::size_t i = 0;
    for (; i + 2 * w <= n; i += 2 * w) { // 4 registers of w / 2 outputs
        auto a0 = V::zero(), a1 = a0, a2 = a0, a3 = a0;
        auto b0 = a0, b1 = a0, b2 = a0, b3 = a0;
        const float* p = xf + 2 * i;
        for (unsigned j = 0; j < span; j++, p += 2) {
            const auto gr = V::broadcast(gf + 2 * j);
            const auto gi = V::broadcast(gf + 2 * j + 1);
            const auto x0 = V::load(p), x1 = V::load(p + w);
            const auto x2 = V::load(p + 2 * w), x3 = V::load(p + 3 * w);
            a0 = V::fmadd(x0, gr, a0);
            b0 = V::fmadd(x0, gi, b0);
            a1 = V::fmadd(x1, gr, a1);
            b1 = V::fmadd(x1, gi, b1);
            a2 = V::fmadd(x2, gr, a2);
            b2 = V::fmadd(x2, gi, b2);
            a3 = V::fmadd(x3, gr, a3);
            b3 = V::fmadd(x3, gi, b3);
        }
        V::store(yf + 2 * i, V::finish(a0, b0));
        V::store(yf + 2 * i + w, V::finish(a1, b1));
        V::store(yf + 2 * i + 2 * w, V::finish(a2, b2));
        V::store(yf + 2 * i + 3 * w, V::finish(a3, b3));
    }
    return i;
}

} // namespace
} // namespace td_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_TD_ECHO_WIDE_H */
