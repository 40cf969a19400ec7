/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Inner loop of kernel::scene_echo (eq. 7 over one block of subcarriers): a generic
// path and an AVX2/FMA path (scene_echo_avx2.cc, runtime dispatch).

#ifndef INCLUDED_NRSAR_KERNEL_SCENE_ECHO_IMPL_H
#define INCLUDED_NRSAR_KERNEL_SCENE_ECHO_IMPL_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/kernel/scene_echo.h>
#include <cstddef>

namespace gr {
namespace nrsar {
namespace kernel {
namespace echo_detail {

/*!
 * h[i] (= or +=) sum_q phasor_q[i], i < len, over nq <= max_targets targets; then, if
 * s is not null, y[i] = s[i] h[i]. The caller passes s only with the last target chunk.
 */
void generic_block(const target_lanes* t,
                   unsigned nq,
                   bool accumulate,
                   const gr_complex* s,
                   gr_complex* y,
                   gr_complex* h,
                   std::size_t len);
bool avx2_available();
void avx2_block(const target_lanes* t,
                unsigned nq,
                bool accumulate,
                const gr_complex* s,
                gr_complex* y,
                gr_complex* h,
                std::size_t len);

} // namespace echo_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif
