/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_FINITE_GUARD_H
#define INCLUDED_NRSAR_KERNEL_FINITE_GUARD_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <volk/volk_alloc.hh>
#include <cstddef>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Zeroes non-finite complex samples of a buffer before it reaches the DSP.
 *
 * A NaN or Inf entering a filter or an FFT spreads over a whole vector (or image), so
 * blocks replace such samples by 0 and count them. The fast path is one VOLK sum of
 * the buffer's floats: it is finite whenever every sample is (a sum that overflows only
 * costs a second, exact scan), so clean data costs one read pass.
 */
class NRSAR_API finite_guard
{
public:
    finite_guard() = default;
    finite_guard(const finite_guard&) = delete;
    finite_guard& operator=(const finite_guard&) = delete;
    finite_guard(finite_guard&&) = default;
    finite_guard& operator=(finite_guard&&) = default;

    /*!
     * Returns \p in itself when all n samples are finite, otherwise a pointer to an
     * internal copy (valid until the next call on this slot) in which every sample
     * with a non-finite real or imaginary part is 0. \p zeroed receives the number of
     * samples replaced. slot (0 or 1) selects one of two scratch buffers so that two
     * inputs can be guarded at the same time.
     */
    const gr_complex*
    guard(const gr_complex* in, std::size_t n, std::size_t& zeroed, unsigned slot = 0);

private:
    volk::vector<gr_complex> d_copy[2];
};

//! Number of samples with a non-finite real or imaginary part (exact scan).
NRSAR_API std::size_t count_nonfinite(const gr_complex* in, std::size_t n);

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_FINITE_GUARD_H */
