/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// The equaliser pass of kernel::pusch_rx: a generic path and an AVX2 path
// (pusch_rx_avx2.cc, runtime dispatch). Both compute the same floats.

#ifndef INCLUDED_NRSAR_KERNEL_PUSCH_RX_IMPL_H
#define INCLUDED_NRSAR_KERNEL_PUSCH_RX_IMPL_H

#include <gnuradio/gr_complex.h>
#include <cstdint>

namespace gr {
namespace nrsar {
namespace kernel {
namespace pusch_detail {

/*!
 * For k < n: g = max(|h|^2, 1e-20), x = y conj(h) / g, nv = s2 / g, with one division
 * 1 / g per RE and no fused multiply-add. Returns non-zero when a result is inf or NaN.
 */
std::uint32_t equalise_generic(const gr_complex* y,
                               const gr_complex* h,
                               float s2,
                               unsigned n,
                               gr_complex* x,
                               float* nv,
                               float* g);
bool avx2_available();
std::uint32_t equalise_avx2(const gr_complex* y,
                            const gr_complex* h,
                            float s2,
                            unsigned n,
                            gr_complex* x,
                            float* nv,
                            float* g);

} // namespace pusch_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_PUSCH_RX_IMPL_H */
