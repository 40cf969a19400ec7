/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_RANGE_COMPRESS_IMPL_H
#define INCLUDED_NRSAR_RANGE_COMPRESS_IMPL_H

#include "nonfinite_reporter.h"
#include <gnuradio/nrsar/kernel/range_compress.h>
#include <gnuradio/nrsar/range_compress.h>
#include <vector>

namespace gr {
namespace nrsar {

class range_compress_impl : public range_compress
{
private:
    kernel::range_compress d_kernel;
    double d_bin_m;
    bool d_tag_pending = true;
    nonfinite_reporter d_nonfinite;
    std::vector<tag_t> d_tags;
    std::vector<gr_complex> d_ones; // S of cfg.unit_grid (empty: the reference input)

    const kernel::tf_filter& filt() const { return d_kernel.filter(); }
    const kernel::range_ifft& ifft() const { return d_kernel.ifft(); }

public:
    range_compress_impl(const numerology& num, kernel::range_compress&& kern, bool unit_grid);

    void set_filter_type(gr::nrsar::filter_type type) override;
    void set_snr_db(double snr_db) override;
    void set_estimate_snr(bool estimate) override;
    void set_snr_history(const std::vector<double>& history) override;
    std::vector<double> snr_history() const override { return filt().snr_history(); }
    void set_constant_modulus_path(bool on) override;
    void set_window(gr::fft::window::win_type window, double window_param) override;
    //! Re-arms the range-axis tag: every run starts a new stream for the blocks
    //! downstream.
    bool start() override;

    gr::nrsar::filter_type filter_type() const override { return filt().type(); }
    double snr_db() const override { return filt().snr_db(); }
    bool estimate_snr() const override { return filt().estimate_snr(); }
    double estimated_snr_db() const override { return filt().estimated_snr_db(); }
    bool constant_modulus_path() const override { return filt().constant_modulus_path(); }
    std::uint64_t constant_modulus_items() const override
    {
        return filt().constant_modulus_vectors();
    }
    std::uint64_t empty_re_count() const override { return filt().empty_re_count(); }
    std::uint64_t nonfinite_count() const override { return d_nonfinite.count(); }

    gr::fft::window::win_type window() const override { return ifft().window(); }
    double window_param() const override { return ifft().window_param(); }
    unsigned num_bins() const override { return ifft().num_bins(); }
    unsigned first_bin() const override { return ifft().first_bin(); }
    double range_axis_first_m() const override { return ifft().first_bin() * d_bin_m; }
    double range_bin_m() const override { return d_bin_m; }
    unsigned fft_size() const override { return ifft().fft_size(); }
    double coherent_gain() const override { return ifft().coherent_gain(); }

    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_RANGE_COMPRESS_IMPL_H */
