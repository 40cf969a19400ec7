/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_FFT_PLANS_H
#define INCLUDED_NRSAR_KERNEL_FFT_PLANS_H

#include <gnuradio/fft/fft.h>
#include <gnuradio/nrsar/api.h>
#include <memory>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief The process's pool of gr::fft objects: every kernel takes its FFTs from here.
 *
 * Why: gr::fft's constructor reads and rewrites `~/.gr_fftw_wisdom` under a file lock for
 * every plan, even one whose size the wisdom holds (1.9 ms at best, 7.6-14 ms median and
 * up to 98 ms on the loaded 2-core machine: the file is shared by every process of the
 * user). A Dask task of nrsar-process made 6 (ofdm_demod, range_ifft, rd_focuser's two
 * azimuth FFTs), 11-84 ms against 0.07-0.12 s of compute. Here a kernel's destructor hands
 * its objects back and the next kernel of the same (size, direction, threads) takes one, so
 * a process plans each size once: such a task now makes none after its worker's first, and
 * its median time fell from 0.060-0.091 s to 0.039-0.044 s (docs/scale.md, "The FFT pool").
 *
 * A gr::fft object owns its buffers and is not thread-safe, so each handle is exclusive
 * (a pool, not a shared plan). A reused object's buffers are zeroed, as a new one's are,
 * so its results are a fresh plan's bit for bit. Do not call set_nthreads() on one: the
 * pool files it back under its thread count. The pool is never destroyed (kernels that
 * outlive static destruction can still hand back), and keeps at most max_idle objects
 * of a key.
 */
//! The handles' deleter: gives the object back to the pool.
struct fft_release {
    NRSAR_API void operator()(gr::fft::fft_complex_fwd* fft) const noexcept;
    NRSAR_API void operator()(gr::fft::fft_complex_rev* fft) const noexcept;
};

using fft_fwd = std::unique_ptr<gr::fft::fft_complex_fwd, fft_release>;
using fft_rev = std::unique_ptr<gr::fft::fft_complex_rev, fft_release>;

//! An exclusive forward FFT of `size` points: a released one of the same key, else new.
NRSAR_API fft_fwd make_fft_fwd(int size, int nthreads = 1);
//! An exclusive inverse FFT of `size` points: a released one of the same key, else new.
NRSAR_API fft_rev make_fft_rev(int size, int nthreads = 1);

//! Idle objects kept per key (more are freed on release).
constexpr unsigned fft_pool_max_idle = 16;

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_FFT_PLANS_H */
