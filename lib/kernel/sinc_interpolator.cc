/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include "bessel_i0.h"
#include <gnuradio/nrsar/kernel/sinc_interpolator.h>
#include <cmath>

namespace gr {
namespace nrsar {
namespace kernel {

sinc_interpolator::sinc_interpolator(unsigned taps,
                                     gr::fft::window::win_type win,
                                     double window_param,
                                     unsigned phases)
    : d_taps(taps), d_phases(phases), d_window(win), d_window_param(window_param)
{
    using window = gr::fft::window;
    if (taps < 2 || taps > 64 || taps % 2 != 0)
        throw_param("rcmc_taps", taps, "must be even and in [2, 64]");
    check_range("phases", phases, 1u, 65536u);
    switch (win) {
    case window::WIN_NONE:
    case window::WIN_RECTANGULAR:
    case window::WIN_HANN:
    case window::WIN_HAMMING:
    case window::WIN_BLACKMAN:
        break;
    case window::WIN_KAISER:
        check_range("rcmc_window_param", window_param, 0.0, 50.0);
        break;
    default:
        throw_param("rcmc_window",
                    static_cast<int>(win),
                    "must be WIN_RECTANGULAR, WIN_HANN, WIN_HAMMING, WIN_BLACKMAN or "
                    "WIN_KAISER");
    }
    d_i0_beta = bessel_i0(window_param);

    // Tap j (0..L-1) of phase q multiplies in[i + j - L/2 + 1]; its offset from the
    // interpolation point is x = j - L/2 + 1 - mu, mu = q / phases.
    d_table.resize(static_cast<size_t>(phases + 1) * taps);
    const int half = static_cast<int>(taps / 2);
    for (unsigned q = 0; q <= phases; ++q) {
        const double mu = double(q) / phases;
        double sum = 0.0;
        for (unsigned j = 0; j < taps; ++j)
            sum += kernel(int(j) - half + 1 - mu);
        for (unsigned j = 0; j < taps; ++j)
            d_table[q * taps + j] = static_cast<float>(kernel(int(j) - half + 1 - mu) / sum);
    }
}

double sinc_interpolator::window(double u) const
{
    using win = gr::fft::window;
    switch (d_window) {
    case win::WIN_HANN:
        return 0.5 + 0.5 * std::cos(M_PI * u);
    case win::WIN_HAMMING:
        return 0.54 + 0.46 * std::cos(M_PI * u);
    case win::WIN_BLACKMAN:
        return 0.42 + 0.5 * std::cos(M_PI * u) + 0.08 * std::cos(2.0 * M_PI * u);
    case win::WIN_KAISER:
        return bessel_i0(d_window_param * std::sqrt(std::max(0.0, 1.0 - u * u))) /
               d_i0_beta;
    default:
        return 1.0;
    }
}

double sinc_interpolator::kernel(double x) const
{
    const double half = d_taps / 2.0;
    if (std::abs(x) >= half)
        return 0.0;
    const double s = (x == 0.0) ? 1.0 : std::sin(M_PI * x) / (M_PI * x);
    return s * window(x / half);
}

const float* sinc_interpolator::phase_taps(double mu) const
{
    const unsigned q = static_cast<unsigned>(mu * d_phases + 0.5);
    return &d_table[static_cast<size_t>(q) * d_taps];
}

gr_complex sinc_interpolator::at(const gr_complex* in, int n, double pos) const
{
    const double fl = std::floor(pos);
    const int first = static_cast<int>(fl) - static_cast<int>(d_taps / 2) + 1;
    const float* h = phase_taps(pos - fl);
    gr_complex acc(0.0f, 0.0f);
    for (int j = 0; j < static_cast<int>(d_taps); ++j) {
        const int idx = first + j;
        if (idx >= 0 && idx < n)
            acc += in[idx] * h[j];
    }
    return acc;
}

void sinc_interpolator::resample(const gr_complex* in,
                                 int n,
                                 const float* shift,
                                 gr_complex* out) const
{
    const int L = static_cast<int>(d_taps);
    const int half = L / 2;
    const float* table = d_table.data();
    for (int k = 0; k < n; ++k) {
        const double pos = k + static_cast<double>(shift[k]);
        const double fl = std::floor(pos);
        const int first = static_cast<int>(fl) - half + 1;
        const size_t ph = static_cast<size_t>((pos - fl) * d_phases + 0.5);
        const float* h = table + ph * L;
        if (first >= 0 && first + L <= n) {
            // Interior: no bounds checks (the hot path of RCMC).
            const gr_complex* x = in + first;
            float re = 0.0f, im = 0.0f;
            for (int j = 0; j < L; ++j) {
                re += x[j].real() * h[j];
                im += x[j].imag() * h[j];
            }
            out[k] = gr_complex(re, im);
        } else if (first + L <= 0 || first >= n) {
            out[k] = gr_complex(0.0f, 0.0f);
        } else {
            gr_complex acc(0.0f, 0.0f);
            for (int j = 0; j < L; ++j) {
                const int idx = first + j;
                if (idx >= 0 && idx < n)
                    acc += in[idx] * h[j];
            }
            out[k] = acc;
        }
    }
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
