/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Inner loops of kernel::multipath_fir shared by td_echo.cc, td_echo_avx2.cc and
// td_echo_avx512.cc.

#ifndef INCLUDED_NRSAR_KERNEL_TD_ECHO_IMPL_H
#define INCLUDED_NRSAR_KERNEL_TD_ECHO_IMPL_H

#include <gnuradio/gr_complex.h>
#include <cstddef>

namespace gr {
namespace nrsar {
namespace kernel {
namespace td_detail {

//! sum_j g[j] x[j], j < span (the tail of the AVX2 loop).
inline gr_complex fir_generic_one(const gr_complex* x, const gr_complex* g, unsigned span)
{
    float re = 0.0f, im = 0.0f;
    for (unsigned j = 0; j < span; j++) {
        re += x[j].real() * g[j].real() - x[j].imag() * g[j].imag();
        im += x[j].real() * g[j].imag() + x[j].imag() * g[j].real();
    }
    return gr_complex(re, im);
}

//! y[i] = sum_j g[j] x[i + j], i < n, j < span (AVX2/FMA; call after avx2_available()).
//! tail: scratch of span + 3 samples for the last n % 4 outputs.
void fir_avx2(const gr_complex* x,
              const gr_complex* g,
              unsigned span,
              gr_complex* y,
              std::size_t n,
              gr_complex* tail);

//! fir_avx2's outputs bit for bit, 32 at a time with AVX-512F (call after avx512_available()).
void fir_avx512(const gr_complex* x,
                const gr_complex* g,
                unsigned span,
                gr_complex* y,
                std::size_t n,
                gr_complex* tail);

//! Whether the CPU runs AVX-512F (and the library was built for x86).
bool avx512_available();

} // namespace td_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_TD_ECHO_IMPL_H */
