/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// One layer of kernel::nr_ldpc_decoder: a generic path and an AVX2 path
// (nr_ldpc_decoder_avx2.cc, runtime dispatch), each in int8 and int16. Both paths compute the
// same integers.

#ifndef INCLUDED_NRSAR_KERNEL_NR_LDPC_DECODER_IMPL_H
#define INCLUDED_NRSAR_KERNEL_NR_LDPC_DECODER_IMPL_H

#include <cstddef>
#include <cstdint>

namespace gr {
namespace nrsar {
namespace kernel {
namespace ldpc_detail {

constexpr unsigned lanes = 32; //!< int8 lanes of an AVX2 register; zp is a multiple of it

/*!
 * The two message widths: int8 (32 lanes per AVX2 register) where the a-posteriori sums fit
 * (high rate, few rows), int16 (16 lanes) where int8 saturates them (docs/nr_coding.md).
 * max: the saturation bound of every value; in_max: the bound of a quantised channel LLR;
 * target_gain: the input scale target relative to int8's (more resolution).
 */
template <typename T>
struct fixed;
template <>
struct fixed<std::int8_t> {
    static constexpr int max = 127;
    static constexpr float in_max = 63.0f;
    static constexpr double target_gain = 1.0;
};
template <>
struct fixed<std::int16_t> {
    static constexpr int max = 32767;
    static constexpr float in_max = 252.0f;
    static constexpr double target_gain = 4.0;
};

/*!
 * Offset min-sum update of one layer (messages max(min' - offset, 0), offset >= 0): t holds
 * the deg gathered a-posteriori columns (deg x zp, column e at t + e zp), r their
 * check-to-variable messages; both are updated in place, every value saturating at
 * +-fixed<T>::max. Returns true when, after the update, the product of the signs of t is
 * positive in every lane below zc (the row's parity check holds on its new hard decisions).
 */
template <typename T>
bool layer_generic(T* t, T* r, unsigned deg, unsigned zp, unsigned zc, T offset);
bool avx2_available();
bool layer_avx2(std::int8_t* t, std::int8_t* r, unsigned deg, unsigned zp, unsigned zc, std::int8_t offset);
bool layer_avx2(std::int16_t* t, std::int16_t* r, unsigned deg, unsigned zp, unsigned zc, std::int16_t offset);

/*!
 * out[k] = round(clamp(in[k] scale, -in_max, in_max)) (to nearest, ties to even), NaN -> 0,
 * +inf -> max and -inf -> -max (known bits), for k < n (fixed<T>'s bounds).
 */
template <typename T>
void quantize_generic(const float* in, unsigned n, float scale, T* out);
void quantize_avx2(const float* in, unsigned n, float scale, std::int8_t* out);
void quantize_avx2(const float* in, unsigned n, float scale, std::int16_t* out);

//! True when one of the n values is non-zero and not NaN (a column that received something).
bool any_received_generic(const float* in, unsigned n);
bool any_received_avx2(const float* in, unsigned n);

/*!
 * Sums of sqrt|x| and counts over the finite non-zero in[k], k < n8 (a multiple of 8), in 8
 * partial sums part[k % 8], cnt[k % 8] (added to): both paths add in the same order, so
 * they give the same floats.
 */
void root_sums_generic(const float* in, std::size_t n8, float* part, float* cnt);
void root_sums_avx2(const float* in, std::size_t n8, float* part, float* cnt);

/*!
 * The mutual information of a bit with its LLR L, 1 - h2(1 / (1 + e^|L|)) (calibrated LLRs):
 * info_table()[i] for |L| in [i / info_step, (i + 1) / info_step), at the bin's middle, 0 for
 * i = 0 (unreceived zeros add nothing), 1 for the last bin (|L| >= 32, +-inf).
 */
constexpr unsigned info_bins = 256;
constexpr float info_step = 8.0f;
const float* info_table();

/*!
 * Sums of info_table()'s value of in[k] (NaN counts as 0) and counts of the non-zero non-NaN
 * in[k], k < n8 (a multiple of 8), in 8 partial sums part[k % 8], cnt[k % 8] (added to), the
 * same floats in both paths.
 */
void info_sums_generic(const float* in, std::size_t n8, float* part, float* cnt);
void info_sums_avx2(const float* in, std::size_t n8, float* part, float* cnt);

//! The number of lanes below zc in which the product of the signs of the deg gathered
//! columns of t is negative (a row's unsatisfied parity checks on its hard decisions).
template <typename T>
unsigned unsatisfied_generic(const T* t, unsigned deg, unsigned zp, unsigned zc);
unsigned unsatisfied_avx2(const std::int8_t* t, unsigned deg, unsigned zp, unsigned zc);
unsigned unsatisfied_avx2(const std::int16_t* t, unsigned deg, unsigned zp, unsigned zc);

} // namespace ldpc_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif
