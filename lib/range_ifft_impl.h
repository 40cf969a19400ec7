/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_RANGE_IFFT_IMPL_H
#define INCLUDED_NRSAR_RANGE_IFFT_IMPL_H

#include <gnuradio/nrsar/kernel/range_ifft.h>
#include <gnuradio/nrsar/kernel/split_worker.h>
#include <gnuradio/nrsar/range_ifft.h>
#include "nonfinite_reporter.h"
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {

/*!
 * Validates range_ifft::make()'s parameters (each error names the parameter, its value and
 * the limit) and builds the kernel with the crop in bins (range_ifft, range_compress).
 */
kernel::range_ifft make_range_ifft_kernel(const numerology& num,
                                          unsigned fft_size,
                                          gr::fft::window::win_type window,
                                          double window_param,
                                          double r_min_m,
                                          double r_max_m);

//! The range_axis tag's value: (first bin range [m], bin spacing [m], K).
pmt::pmt_t range_axis_value(double first_m, double bin_m, std::uint64_t k);

class range_ifft_impl : public range_ifft
{
private:
    kernel::range_ifft d_kernel;
    double d_bin_m;
    bool d_tag_pending = true;
    nonfinite_reporter d_nonfinite;
    // Two-core split (set_threads(2)): the second half of each work() call's symbols on
    // the split worker with its own kernel (own FFTW plan).
    unsigned d_threads = 1;
    std::unique_ptr<kernel::range_ifft> d_helper;
    kernel::split_worker d_split; // last: joined before the kernels go
    std::vector<std::size_t> d_bad;

public:
    range_ifft_impl(const numerology& num, kernel::range_ifft&& kern);

    void set_window(gr::fft::window::win_type window, double window_param) override;
    //! Re-arms the range-axis tag: every run starts a new stream for the blocks downstream.
    bool start() override;

    gr::fft::window::win_type window() const override { return d_kernel.window(); }
    double window_param() const override { return d_kernel.window_param(); }
    unsigned num_bins() const override { return d_kernel.num_bins(); }
    unsigned first_bin() const override { return d_kernel.first_bin(); }
    double range_axis_first_m() const override { return d_kernel.first_bin() * d_bin_m; }
    double range_bin_m() const override { return d_bin_m; }
    unsigned fft_size() const override { return d_kernel.fft_size(); }
    double coherent_gain() const override { return d_kernel.coherent_gain(); }
    std::uint64_t nonfinite_count() const override { return d_nonfinite.count(); }
    void set_threads(unsigned threads) override;
    unsigned threads() const override { return d_threads; }

    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_RANGE_IFFT_IMPL_H */
