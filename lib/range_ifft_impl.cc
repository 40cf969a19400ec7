/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "range_ifft_impl.h"
#include "nonfinite_reporter.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>
#include <sstream>

namespace gr {
namespace nrsar {

namespace {

std::string metres(double x)
{
    std::ostringstream s;
    s << x << " m";
    return s.str();
}

} // namespace

kernel::range_ifft make_range_ifft_kernel(const numerology& num,
                                          unsigned fft_size,
                                          gr::fft::window::win_type window,
                                          double window_param,
                                          double r_min_m,
                                          double r_max_m)
{
    num.validate();
    const unsigned n = num.num_subcarriers;
    if (fft_size != 0 && fft_size < n)
        throw_param("fft_size",
                    fft_size,
                    "must be 0 (no padding) or at least num_subcarriers = " +
                        std::to_string(n));
    const unsigned nfft = fft_size == 0 ? n : fft_size;
    check_finite("window_param", window_param);
    const double r_unamb = num.max_unambiguous_range_m();
    check_finite("r_min_m", r_min_m);
    check_finite("r_max_m", r_max_m);
    if (r_min_m < 0.0 || r_min_m >= r_unamb)
        throw_param("r_min_m",
                    r_min_m,
                    "must be in [0, " + metres(r_unamb) +
                        ") (the unambiguous range c / (2 Delta f))");
    if (r_max_m > 0.0 && r_max_m > r_unamb)
        throw_param("r_max_m",
                    r_max_m,
                    "must be at most the unambiguous range c / (2 Delta f) = " +
                        metres(r_unamb) + " (or <= 0 for the last bin)");
    if (r_max_m > 0.0 && r_max_m < r_min_m)
        throw_param("r_max_m", r_max_m, "must be at least r_min_m = " + metres(r_min_m));
    const double bin_m = num.range_bin_m(nfft);
    const auto crop = kernel::range_ifft::crop_bins(bin_m, nfft, r_min_m, r_max_m);
    if (crop.count == 0) {
        std::ostringstream limit;
        limit << "leaves no range bin in [r_min_m, r_max_m] = [" << r_min_m << ", "
              << r_max_m << "] m (bin spacing " << bin_m << " m)";
        throw_param("r_max_m", r_max_m, limit.str());
    }
    return kernel::range_ifft(n, nfft, window, window_param, crop.first, crop.count);
}

pmt::pmt_t range_axis_value(double first_m, double bin_m, std::uint64_t k)
{
    return pmt::make_tuple(
        pmt::from_double(first_m), pmt::from_double(bin_m), pmt::from_uint64(k));
}

range_ifft::sptr range_ifft::make(const numerology& num,
                                  unsigned fft_size,
                                  gr::fft::window::win_type window,
                                  double window_param,
                                  double r_min_m,
                                  double r_max_m)
{
    return gnuradio::make_block_sptr<range_ifft_impl>(
        num, make_range_ifft_kernel(num, fft_size, window, window_param, r_min_m, r_max_m));
}

unsigned range_ifft::fast_fft_size(unsigned n) { return kernel::fast_fft_size(n); }

range_ifft_impl::range_ifft_impl(const numerology& num, kernel::range_ifft&& kern)
    : gr::sync_block("range_ifft",
                     gr::io_signature::make(1, 1, sizeof(gr_complex) * kern.n()),
                     gr::io_signature::make(1, 1, sizeof(gr_complex) * kern.num_bins())),
      d_kernel(std::move(kern)),
      d_bin_m(num.range_bin_m(d_kernel.fft_size()))
{
}

void range_ifft_impl::set_window(gr::fft::window::win_type window, double window_param)
{
    check_finite("window_param", window_param);
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.set_window(window, window_param);
    if (d_helper)
        d_helper->set_window(window, window_param);
    d_tag_pending = true;
}

void range_ifft_impl::set_threads(unsigned threads)
{
    check_range("threads", threads, 1u, 2u);
    gr::thread::scoped_lock guard(d_setlock);
    if (threads == 2 && !d_helper) // planned here, never in work()
        d_helper = std::make_unique<kernel::range_ifft>(d_kernel.n(),
                                                        d_kernel.fft_size(),
                                                        d_kernel.window(),
                                                        d_kernel.window_param(),
                                                        d_kernel.first_bin(),
                                                        d_kernel.num_bins());
    d_threads = threads;
}

bool range_ifft_impl::start()
{
    gr::thread::scoped_lock guard(d_setlock);
    d_tag_pending = true;
    return gr::sync_block::start();
}

int range_ifft_impl::work(int noutput_items,
                          gr_vector_const_void_star& input_items,
                          gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto in = static_cast<const gr_complex*>(input_items[0]);
    auto out = static_cast<gr_complex*>(output_items[0]);
    const std::size_t n = d_kernel.n();
    const std::size_t k = d_kernel.num_bins();

    if (d_tag_pending && noutput_items > 0) {
        add_item_tag(0,
                     nitems_written(0),
                     tags::range_axis_key(),
                     range_axis_value(range_axis_first_m(), d_bin_m, k),
                     alias_pmt());
        d_tag_pending = false;
    }
    d_bad.assign(noutput_items, 0);
    // Each part with its own kernel (own FFTW plan); the kernel zeroes non-finite samples.
    auto part = [&](std::size_t begin, std::size_t end, unsigned p) {
        auto& kern = p == 0 ? d_kernel : *d_helper;
        for (std::size_t i = begin; i < end; i++)
            d_bad[i] = kern.execute(in + i * n, out + i * k);
    };
    if (d_threads == 2 && d_helper && noutput_items >= 4)
        d_split.run(noutput_items, part);
    else
        part(0, noutput_items, 0);
    for (int i = 0; i < noutput_items; i++) {
        if (d_bad[i] > 0) {
            const std::uint64_t item = nitems_written(0) + i;
            add_item_tag(0, d_nonfinite.tag(d_logger, d_bad[i], item, item, alias_pmt()));
        }
    }
    return noutput_items;
}

} // namespace nrsar
} // namespace gr
