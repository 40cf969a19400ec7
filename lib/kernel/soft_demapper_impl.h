/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Shared by the generic and the AVX2 path of kernel::soft_demapper (soft_demapper_avx2.cc,
// runtime dispatch). Both evaluate the same closed form in the same order.

#ifndef INCLUDED_NRSAR_KERNEL_SOFT_DEMAPPER_IMPL_H
#define INCLUDED_NRSAR_KERNEL_SOFT_DEMAPPER_IMPL_H

#include <gnuradio/gr_complex.h>
#include <cstddef>

namespace gr {
namespace nrsar {
namespace kernel {
namespace demap_detail {

/*!
 * One axis of a 38.211 square QAM in units of half the level spacing: levels +-1, +-3, ...,
 * +-(L - 1). The Gray mapping is the fold I = (1 - 2 b0)(L/2 - (1 - 2 b2)(L/4 - ...)), so
 * bit b0 splits the levels at 0 and, on the folded coordinate u_1 = |x|, u_{j+1} = |u_j - T_j|
 * (T_1 = L/2, T_{j+1} = T_j / 2), bit j >= 1 splits the odd levels 1 .. 2 T_j - 1 at T_j (0:
 * inner). A fold maps each level set onto an interval of odd levels without changing the
 * distance to its nearest member, so the nearest level of each bit value is one rounding
 * to an odd integer and a clamp: the exact max-log LLR, no search.
 */
struct axis_shape {
    unsigned na;   // bits per axis
    float top;     // L - 1
    float half;    // T_1 = L / 2
    float to_unit; // 1 / (half the level spacing)
    float unit2;   // (half the level spacing)^2
};

bool avx2_available();
//! The AVX2 path on the first (nsym / 8) * 8 symbols; returns how many it did.
std::size_t demap_avx2(const axis_shape& a,
                       const gr_complex* y,
                       const float* nv,
                       bool per_symbol,
                       std::size_t nsym,
                       float* llr,
                       double* sq_err);

} // namespace demap_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_SOFT_DEMAPPER_IMPL_H */
