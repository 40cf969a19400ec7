/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_FFT_SIZE_H
#define INCLUDED_NRSAR_KERNEL_FFT_SIZE_H

#include <gnuradio/nrsar/api.h>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Smallest 7-smooth size >= n (n = 2^a 3^b 5^c 7^d), for every FFT of the module.
 *
 * Why 7-smooth rather than the next power of two: FFTW has hard-coded codelets for the
 * radices 2, 3, 5, 7, so every such size runs at about the n log n speed of a power of two;
 * SPEC 5's 3333 = 3 * 11 * 101 is slow (14.9 k vs 40.4 k FFT/s at 4096) because of the
 * prime 101, not because it is not a power of two. The 7-smooth size is never larger than
 * the next power of two and usually much closer (3333 -> 3360 = 2^5 3 5 7, 0.8 % padding,
 * vs 4096, 23 %), so it loses less to padding.
 */
NRSAR_API unsigned fast_fft_size(unsigned n);

//! Next power of two >= n.
NRSAR_API unsigned pow2_fft_size(unsigned n);

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_FFT_SIZE_H */
