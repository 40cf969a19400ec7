/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_UPLINK_CHANNEL_H
#define INCLUDED_NRSAR_KERNEL_UPLINK_CHANNEL_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/gaussian_noise.h>
#include <gnuradio/nrsar/kernel/td_echo.h>
#include <gnuradio/nrsar/uplink_channel_config.h>
#include <volk/volk_alloc.hh>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief The backhaul's channel in one pass over the samples,
 *
 *     y[n] = e^{j 2 pi cfo n} sum_l h[l] x[n - D - l] + sigma z[n],   z ~ CN(0, 1),
 *
 * n counted from the first output sample, x[i] = 0 for i < 0 (D = delay_samples). The
 * taps are multipath_fir's integer-lag paths (exact); the CFO phasor of sample n is the
 * float product of e^{j 2 pi frac(cfo n0)} (double, n0 = n rounded down to a multiple of
 * ROT_BLOCK) and a table of e^{j 2 pi cfo k}, k < ROT_BLOCK; the noise of sample n is
 * element n mod NOISE_BLOCK of gaussian_noise block n / NOISE_BLOCK. So the output is a
 * function of the input stream only, however it is cut into calls.
 */
class NRSAR_API uplink_channel
{
public:
    static constexpr std::size_t ROT_BLOCK = 1024;
    static constexpr std::size_t NOISE_BLOCK = 4096;

    //! cfg.delay_samples is the caller's (the block feeds that many zeros first).
    explicit uplink_channel(const uplink_channel_config& cfg);

    //! The next n output samples from the next n samples x of the delayed input
    //! (x = nullptr: zeros).
    void process(const gr_complex* x, gr_complex* y, std::size_t n);

    //! Output samples so far.
    std::uint64_t samples() const { return d_n; }

private:
    static constexpr std::size_t CHUNK = 8192;
    multipath_fir d_fir;
    unsigned d_lag;                      //!< history the FIR reads (multipath_fir::max_lag)
    volk::vector<gr_complex> d_line;     //!< d_lag samples of history, then the chunk
    double d_cfo;
    std::vector<gr_complex> d_step;      //!< e^{j 2 pi cfo k}, k < ROT_BLOCK
    gaussian_noise d_noise;
    float d_sigma;
    volk::vector<gr_complex> d_z;        //!< one noise block for calls that cut it
    std::uint64_t d_z_block = UINT64_MAX;
    std::uint64_t d_n = 0;

    void rotate(gr_complex* y, std::size_t n, std::uint64_t first) const;
    void add_noise(gr_complex* y, std::size_t n, std::uint64_t first);
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_UPLINK_CHANNEL_H */
