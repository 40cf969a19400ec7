/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include "rx_front_impl.h"
#include <gnuradio/nrsar/kernel/range_ifft.h>
#include <volk/volk.h>
#include <cmath>
#include <algorithm>
#include <cstring>
#include <limits>

namespace gr {
namespace nrsar {
namespace kernel {

range_ifft::range_ifft(unsigned n,
                       unsigned fft_size,
                       gr::fft::window::win_type window,
                       double window_param,
                       unsigned first_bin,
                       unsigned num_bins)
    : d_n(n), d_fft_size(fft_size == 0 ? n : fft_size), d_first(first_bin), d_count(num_bins)
{
    check_at_least("num_subcarriers", n, 1u);
    check_at_least("fft_size", d_fft_size, n);
    if (d_first >= d_fft_size)
        throw_param("first_bin", d_first, "must be below fft_size " + std::to_string(d_fft_size));
    if (d_count == 0)
        d_count = d_fft_size - d_first;
    if (d_count > d_fft_size - d_first)
        throw_param("num_bins",
                    d_count,
                    "must be at most fft_size - first_bin = " +
                        std::to_string(d_fft_size - d_first));
    // The plan is owned here (never in work()); FFTW planning is not thread safe, and
    // gr::fft takes its planner mutex itself.
    d_fft = make_fft_rev(int(d_fft_size), 1);
    // The padding is zero once and stays so: only the first n inputs are ever written
    // and FFTW's out-of-place c2c plans preserve their input.
    std::fill_n(d_fft->get_inbuf(), d_fft_size, gr_complex(0.0f, 0.0f));
    set_window(window, window_param);
}

void range_ifft::set_window(gr::fft::window::win_type window, double window_param)
{
    std::vector<float> w;
    if (window == gr::fft::window::WIN_NONE)
        w.assign(d_n, 1.0f);
    else {
        try {
            w = gr::fft::window::build(window, int(d_n), window_param, false);
        } catch (const std::invalid_argument&) {
            throw;
        } catch (const std::exception& e) {
            // gr::fft::window throws std::out_of_range (Python IndexError) for a missing
            // Kaiser beta, Tukey alpha, ...: report it as the parameter error it is.
            throw_param("window_param", window_param, std::string("is invalid: ") + e.what());
        }
    }
    if (w.size() != d_n)
        throw_param("window", int(window), "gave a window of the wrong length");
    double sum = 0.0;
    for (float x : w) {
        if (!std::isfinite(x))
            throw_param("window_param", window_param, "gives a non-finite window");
        sum += x;
    }
    d_window_type = window;
    d_window_param = window_param;
    d_coherent_gain = sum / d_n;
    // eq. (29): the unitary 1/sqrt(N) folded into the window, one multiply per sample.
    const double scale = 1.0 / std::sqrt(double(d_n));
    d_taps.resize(2 * std::size_t(d_n));
    for (unsigned i = 0; i < d_n; i++)
        d_taps[2 * i] = d_taps[2 * i + 1] = float(w[i] * scale);
}

std::vector<float> range_ifft::window_taps() const
{
    std::vector<float> w(d_n);
    const double root = std::sqrt(double(d_n));
    for (unsigned i = 0; i < d_n; i++)
        w[i] = float(d_taps[2 * i] * root);
    return w;
}

std::size_t range_ifft::execute(const gr_complex* in, gr_complex* out)
{
    // The window and the finite check in one pass, straight into FFTW's padded input.
    gr_complex* x = d_fft->get_inbuf();
    std::size_t zeroed = 0;
    if (!std::isfinite(rx_front::window_pass(in, d_taps.data(), x, d_n))) {
        for (unsigned i = 0; i < d_n; i++) {
            if (!std::isfinite(in[i].real()) || !std::isfinite(in[i].imag())) {
                x[i] = gr_complex(0.0f, 0.0f);
                zeroed++;
            }
        }
    }
    transform(out);
    return zeroed;
}

void range_ifft::transform(gr_complex* out)
{
    d_fft->execute(); // FFTW backward: sum_n x[n] exp(+j 2 pi n k / fft_size)
    std::memcpy(out, d_fft->get_outbuf() + d_first, sizeof(gr_complex) * d_count);
}

bin_range range_ifft::crop_bins(double bin_m, unsigned fft_size, double r_min_m, double r_max_m)
{
    constexpr double tol = 1e-9;
    const double lo = std::max(0.0, std::ceil(r_min_m / bin_m - tol));
    double hi = fft_size - 1.0;
    if (r_max_m > 0.0)
        hi = std::min(hi, std::floor(r_max_m / bin_m + tol));
    bin_range b;
    if (!(lo <= hi))
        return b;
    b.first = unsigned(lo);
    b.count = unsigned(hi - lo) + 1;
    return b;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
