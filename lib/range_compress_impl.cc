/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include "range_compress_impl.h"
#include "range_ifft_impl.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>

namespace gr {
namespace nrsar {

range_compress::sptr range_compress::make(const numerology& num,
                                          const range_compress_config& cfg)
{
    // range_ifft's checks (numerology, FFT size, window, crop), then tf_filter's (SNR).
    auto ifft = make_range_ifft_kernel(
        num, cfg.fft_size, cfg.window, cfg.window_param, cfg.r_min_m, cfg.r_max_m);
    kernel::tf_filter filter(
        num.num_subcarriers, cfg.filter, cfg.snr_db, cfg.estimate_snr);
    return gnuradio::make_block_sptr<range_compress_impl>(
        num, kernel::range_compress(std::move(filter), std::move(ifft)), cfg.unit_grid);
}

range_compress_impl::range_compress_impl(const numerology& num,
                                         kernel::range_compress&& kern,
                                         bool unit_grid)
    : gr::sync_block("range_compress",
                     gr::io_signature::make(
                         unit_grid ? 1 : 2, unit_grid ? 1 : 2, sizeof(gr_complex) * kern.n()),
                     gr::io_signature::make(1, 1, sizeof(gr_complex) * kern.num_bins())),
      d_kernel(std::move(kern)),
      d_bin_m(num.range_bin_m(d_kernel.ifft().fft_size())),
      d_ones(unit_grid ? d_kernel.n() : 0, gr_complex(1.0f, 0.0f))
{
    // The echo's tags only (as tf_filter: the reference usually carries the same ones).
    set_tag_propagation_policy(TPP_CUSTOM);
}

void range_compress_impl::set_filter_type(gr::nrsar::filter_type type)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.filter().set_filter_type(type);
}

void range_compress_impl::set_snr_db(double snr_db)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.filter().set_snr_db(snr_db);
}

void range_compress_impl::set_estimate_snr(bool estimate)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.filter().set_estimate_snr(estimate);
}

void range_compress_impl::set_snr_history(const std::vector<double>& history)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.filter().set_snr_history(history);
}

void range_compress_impl::set_constant_modulus_path(bool on)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.filter().set_constant_modulus_path(on);
}

void range_compress_impl::set_window(gr::fft::window::win_type window,
                                     double window_param)
{
    check_finite("window_param", window_param);
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.ifft().set_window(window, window_param);
    d_tag_pending = true;
}

bool range_compress_impl::start()
{
    gr::thread::scoped_lock guard(d_setlock);
    d_tag_pending = true;
    return gr::sync_block::start();
}

int range_compress_impl::work(int noutput_items,
                              gr_vector_const_void_star& input_items,
                              gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto y = static_cast<const gr_complex*>(input_items[0]);
    // unit grid: every item reads the same ones
    const auto s = d_ones.empty() ? static_cast<const gr_complex*>(input_items[1]) : d_ones.data();
    const std::size_t s_step = d_ones.empty() ? d_kernel.n() : 0;
    auto out = static_cast<gr_complex*>(output_items[0]);
    const std::size_t n = d_kernel.n();
    const std::size_t k = d_kernel.num_bins();

    // 1:1 rate: a tag keeps its offset.
    d_tags.clear();
    get_tags_in_range(d_tags, 0, nitems_read(0), nitems_read(0) + noutput_items);
    for (const auto& tag : d_tags)
        add_item_tag(0, tag);
    if (d_tag_pending && noutput_items > 0) {
        add_item_tag(0,
                     nitems_written(0),
                     tags::range_axis_key(),
                     range_axis_value(range_axis_first_m(), d_bin_m, k),
                     alias_pmt());
        d_tag_pending = false;
    }
    for (int i = 0; i < noutput_items; i++) {
        const std::size_t bad = d_kernel.process(y + i * n, s + i * s_step, out + i * k);
        if (bad > 0) {
            const std::uint64_t item = nitems_written(0) + i;
            add_item_tag(0, d_nonfinite.tag(d_logger, bad, item, item, alias_pmt()));
        }
    }
    return noutput_items;
}

} // namespace nrsar
} // namespace gr
