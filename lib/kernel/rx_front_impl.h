/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// One-pass inner loops of the receive front end (tf_filter, range_ifft): each reads its
// input once and folds the non-finite check into the same pass as a running sum (a NaN or
// Inf makes it non-finite; the caller then takes its guarded path). The generic loops are
// in rx_front.cc, the AVX2 ones (same operations in the same order, no FMA, so the same
// results) in rx_front_avx2.cc, chosen at run time. Without AVX2 the VOLK passes are faster
// than one loop built for the baseline ISA (tf_filter WF 11 us against 7 us per 3333 REs):
// window_pass runs two of them and tf_filter keeps its VOLK path (one_pass()).

#ifndef INCLUDED_NRSAR_KERNEL_RX_FRONT_IMPL_H
#define INCLUDED_NRSAR_KERNEL_RX_FRONT_IMPL_H

#include <gnuradio/gr_complex.h>
#include <cstddef>

namespace gr {
namespace nrsar {
namespace kernel {
namespace rx_front {

//! The per-RE weight of eq. (25) applied to y conj(s): MF 1, RF 1/|s|^2 (0 on an empty
//! RE), WF 1/(|s|^2 + 1/SNR_in); scale: one given c for every RE (tf_filter's
//! constant-modulus shortcut), checking that every |s|^2 is 0 or within tol of m0.
enum class weight_rule { mf, rf, wf, scale };

struct pass_sums {
    std::size_t empty = 0; //!< REs with |s|^2 below FLT_MIN
    float sum = 0.0f; //!< sum of every float of y and s: finite iff all are (or overflow)
    bool off_modulus = false; //!< scale rule: some |s|^2 is neither 0 nor within tol of m0
};

/*!
 * out[i] = y[i] conj(s[i]) w(|s[i]|^2) for i < n in one pass (inv_snr: WF's 1/SNR_in, or
 * the scale rule's c) (the product first, then the
 * weight, as tf_filter's VOLK path rounds), with the sums of pass_sums. taps2 (optional, as
 * window_pass's): each product also times taps2, after the weight, so the result is the
 * filter's output windowed by window_pass, bit for bit (range_compress's fused pass).
 */
pass_sums filter_pass(weight_rule rule,
                      const gr_complex* y,
                      const gr_complex* s,
                      float inv_snr,
                      gr_complex* out,
                      std::size_t n,
                      const float* taps2 = nullptr,
                      float m0 = 0.0f,
                      float tol = 0.0f);

/*!
 * dst[i] = in[i] * taps2[i] over 2n floats (taps2: each complex sample's real tap twice);
 * returns the sum of every float of in (finite iff all are, or overflow).
 */
float window_pass(const gr_complex* in,
                  const float* taps2,
                  gr_complex* dst,
                  std::size_t n);

/*!
 * dst[i] = in[i], i < n (no overlap); returns the sum of every float of in (finite iff all
 * are, or overflow): ofdm_demod's copy into the FFT input carries its finite check.
 */
float copy_pass(const gr_complex* in, gr_complex* dst, std::size_t n);

//! Whether the AVX2 loops run here; without them filter_pass is slower than tf_filter's
//! VOLK passes (a loop built for the baseline ISA), so tf_filter keeps those.
bool one_pass();

bool avx2_available();
//! The AVX2 loops on the first (n / 8) * 8 samples; return how many they did.
std::size_t filter_pass_avx2(weight_rule rule,
                             const gr_complex* y,
                             const gr_complex* s,
                             float inv_snr,
                             gr_complex* out,
                             std::size_t n,
                             const float* taps2,
                             float m0,
                             float tol,
                             pass_sums& sums);
std::size_t window_pass_avx2(
    const gr_complex* in, const float* taps2, gr_complex* dst, std::size_t n, float& sum);
std::size_t copy_pass_avx2(const gr_complex* in, gr_complex* dst, std::size_t n, float& sum);

} // namespace rx_front
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_RX_FRONT_IMPL_H */
