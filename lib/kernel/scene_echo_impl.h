/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Inner loop of kernel::scene_echo (eq. 7 over one block of subcarriers, noise and the
// non-finite test of S fused in the same pass): a generic path and an AVX2/FMA path
// (scene_echo_avx2.cc, runtime dispatch).

#ifndef INCLUDED_NRSAR_KERNEL_SCENE_ECHO_IMPL_H
#define INCLUDED_NRSAR_KERNEL_SCENE_ECHO_IMPL_H

#include "gaussian_noise_impl.h"
#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/kernel/scene_echo.h>
#include <cstddef>
#include <cstdint>

namespace gr {
namespace nrsar {
namespace kernel {
namespace echo_detail {

//! Buffers and options of one pass over a block of subcarriers.
struct block_io {
    const gr_complex* s = nullptr; //!< with the last target chunk: y = s h (+ noise)
    gr_complex* y = nullptr;
    gr_complex* h = nullptr;       //!< null: H is not stored
    bool accumulate = false;       //!< h += targets of this chunk (h must be set)
    noise_detail::lane_state* noise = nullptr; //!< null: no noise
    float sigma = 0.0f;
    bool nonfinite = false;        //!< set when s held a non-finite value
};

/*!
 * h[i] (= or +=) sum_q phasor_q[i], i < len, over nq <= max_targets targets; then, if
 * io.s is set, y[i] = s[i] h[i] + sigma z_i with z from io.noise (continuing its lanes).
 */
void generic_block(const target_lanes* t, unsigned nq, block_io& io, std::size_t len);
bool avx2_available();
void avx2_block(const target_lanes* t, unsigned nq, block_io& io, std::size_t len);

} // namespace echo_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif
