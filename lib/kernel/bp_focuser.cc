/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "../param_check.h"
#include "bp_focuser_impl.h"
#include "gaussian_noise_impl.h" // noise_detail::avx2_available
#include <gnuradio/nrsar/bp_config.h>
#include <gnuradio/nrsar/kernel/bp_focuser.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <thread>

namespace gr {
namespace nrsar {

void bp_config::validate() const
{
    check_at_least("symbols_per_pulse", symbols_per_pulse, 1u);
    check_range("upsample", upsample, 1u, 64u);
    if (!std::isfinite(band_margin_hz))
        throw_param("band_margin_hz", band_margin_hz, "must be finite (< 0: automatic)");
    if (!std::isnan(range_centre_cycles))
        check_range("range_centre_cycles", range_centre_cycles, -1.0, 1.0);
    check_range("num_threads", num_threads, 1u, 2u);
}

namespace kernel {

void bp_grid::validate() const
{
    check_at_least("num_range_bins", num_range_bins, 2u);
    if (!std::isfinite(first_range_m) || first_range_m < 0.0)
        throw_param("first_range_m", first_range_m, "must be finite and >= 0");
    check_finite_positive("range_bin_m", range_bin_m);
    check_finite_positive("wavelength_m", wavelength_m);
    check_range("range_centre_cycles", range_centre_cycles, -1.0, 1.0);
    check_range("upsample", upsample, 1u, 64u);
    check_at_least("num_lines", num_lines, 1u);
    check_finite("first_y_m", first_y_m);
    check_finite_positive("line_spacing_m", line_spacing_m);
    check_finite_positive("reference_height_m", reference_height_m);
}

// Per-thread FFT plans and scratch.
struct bp_focuser::worker {
    gr::fft::fft_complex_fwd fwd;
    gr::fft::fft_complex_rev rev;
    std::vector<int> idx;
    std::vector<float> mu, frac, sine;
    std::vector<gr_complex> demod; // K: exp(-j 2 pi fc_r k) / K (inverse-FFT scale folded in)

    worker(const bp_grid& g)
        : fwd(g.num_range_bins, 1),
          rev(g.num_range_bins * g.upsample, 1),
          idx(g.num_range_bins),
          mu(g.num_range_bins),
          frac(g.num_range_bins),
          sine(g.num_range_bins),
          demod(g.num_range_bins)
    {
        for (unsigned k = 0; k < g.num_range_bins; ++k) {
            const double ph = -2.0 * M_PI * g.range_centre_cycles * k;
            demod[k] = gr_complex(static_cast<float>(std::cos(ph) / g.num_range_bins),
                                  static_cast<float>(std::sin(ph) / g.num_range_bins));
        }
    }
};

namespace {
constexpr unsigned chunk_pulses = 64; // pulses upsampled at once (U K x 64 samples)
} // namespace

bp_focuser::bp_focuser(const bp_grid& grid, unsigned num_threads, bool allow_simd)
    : d_grid(grid),
      d_threads(num_threads),
      d_simd(allow_simd && noise_detail::avx2_available())
{
    d_grid.validate();
    check_range("num_threads", num_threads, 1u, 2u);
    const unsigned K = grid.num_range_bins;
    d_ground.resize(K);
    d_valid.resize(K);
    const double h = grid.reference_height_m;
    for (unsigned k = 0; k < K; ++k) {
        const double r0 = grid.first_range_m + k * grid.range_bin_m;
        const bool ok = r0 > h;
        d_ground[k] = ok ? std::sqrt((r0 - h) * (r0 + h)) : 0.0;
        d_valid[k] = ok ? 1.0f : 0.0f;
    }
    d_image.assign(static_cast<size_t>(grid.num_lines) * K, gr_complex(0.0f, 0.0f));
    for (unsigned t = 0; t < num_threads; ++t)
        d_workers.push_back(std::make_unique<worker>(d_grid));
}

bp_focuser::~bp_focuser() = default;

void bp_focuser::reset(double first_y_m)
{
    check_finite("first_y_m", first_y_m);
    d_grid.first_y_m = first_y_m;
    std::fill(d_image.begin(), d_image.end(), gr_complex(0.0f, 0.0f));
    d_pulses = 0;
}

// Demodulate, K-point FFT, zero padding in the middle (the spectrum is centred at 0 after
// demodulation), U K-point inverse FFT: out[U k] = pulse[k] exp(-j 2 pi fc_r k).
void bp_focuser::upsample(worker& w, const gr_complex* pulse, gr_complex* out)
{
    const unsigned K = d_grid.num_range_bins;
    const unsigned L = K * d_grid.upsample;
    gr_complex* ib = w.fwd.get_inbuf();
    for (unsigned k = 0; k < K; ++k)
        ib[k] = pulse[k] * w.demod[k];
    w.fwd.execute();
    const gr_complex* spec = w.fwd.get_outbuf();
    gr_complex* rb = w.rev.get_inbuf();
    const unsigned pos = (K + 1) / 2, neg = K / 2;
    std::memcpy(rb, spec, sizeof(gr_complex) * pos);
    std::fill(rb + pos, rb + L - neg, gr_complex(0.0f, 0.0f));
    std::memcpy(rb + L - neg, spec + K - neg, sizeof(gr_complex) * neg);
    w.rev.execute();
    std::memcpy(out, w.rev.get_outbuf(), sizeof(gr_complex) * L);
}

void bp_focuser::project_lines(worker& w,
                               unsigned line0,
                               unsigned line1,
                               const gr_complex* profiles,
                               unsigned n,
                               const std::array<double, 3>* antenna)
{
    const unsigned K = d_grid.num_range_bins;
    const unsigned U = d_grid.upsample;
    const size_t L = static_cast<size_t>(K) * U;
    bp_detail::line_job j;
    j.ground = d_ground.data();
    j.valid = d_valid.data();
    j.pos_scale = U / d_grid.range_bin_m;
    j.pos_offset = U * d_grid.first_range_m / d_grid.range_bin_m;
    j.cyc_scale = 2.0 / d_grid.wavelength_m + d_grid.range_centre_cycles / d_grid.range_bin_m;
    j.cyc_offset = d_grid.range_centre_cycles * d_grid.first_range_m / d_grid.range_bin_m;
    j.last = static_cast<int>(U * (K - 1)) - 1;
    j.K = K;
    j.idx = w.idx.data();
    j.mu = w.mu.data();
    j.frac = w.frac.data();
    j.sine = w.sine.data();
    // Tiles of lines: a pulse's profile (U K samples) is read for every line of the tile
    // while it is in L1, and the tile's accumulators stay in L2.
    const unsigned tile = std::max(1u, 16384u / K);
    for (unsigned t0 = line0; t0 < line1; t0 += tile) {
        const unsigned t1 = std::min(line1, t0 + tile);
        for (unsigned p = 0; p < n; ++p) {
            j.ax = antenna[p][0];
            j.profile = profiles + p * L;
            for (unsigned line = t0; line < t1; ++line) {
                const double dy = d_grid.first_y_m + line * d_grid.line_spacing_m - antenna[p][1];
                j.c = dy * dy + antenna[p][2] * antenna[p][2];
                j.acc = &d_image[static_cast<size_t>(line) * K];
                if (d_simd)
                    bp_detail::project_line_avx2(j);
                else
                    bp_detail::project_line_body(j);
            }
        }
    }
}

void bp_focuser::add(const gr_complex* pulses, unsigned n, const std::array<double, 3>* antenna)
{
    const unsigned K = d_grid.num_range_bins;
    const size_t L = static_cast<size_t>(K) * d_grid.upsample;
    for (unsigned p = 0; p < n; ++p)
        for (int ax = 0; ax < 3; ++ax)
            check_finite("antenna position", antenna[p][ax]);
    std::vector<gr_complex> prof(L * std::min(n, chunk_pulses));
    for (unsigned p0 = 0; p0 < n; p0 += chunk_pulses) {
        const unsigned c = std::min(chunk_pulses, n - p0);
        const unsigned M = d_grid.num_lines;
        if (d_threads == 1 || M < 2) {
            for (unsigned p = 0; p < c; ++p)
                upsample(*d_workers[0], pulses + static_cast<size_t>(p0 + p) * K, &prof[p * L]);
            project_lines(*d_workers[0], 0, M, prof.data(), c, antenna + p0);
            continue;
        }
        // Two threads: each upsamples half of the chunk, then each projects half the lines.
        auto half_up = [&](unsigned t) {
            for (unsigned p = t; p < c; p += 2)
                upsample(*d_workers[t], pulses + static_cast<size_t>(p0 + p) * K, &prof[p * L]);
        };
        std::thread up(half_up, 1u);
        half_up(0);
        up.join();
        const unsigned mid = M / 2;
        std::thread pr([&] { project_lines(*d_workers[1], mid, M, prof.data(), c, antenna + p0); });
        project_lines(*d_workers[0], 0, mid, prof.data(), c, antenna + p0);
        pr.join();
    }
    d_pulses += n;
}

void bp_focuser::image(gr_complex* out) const
{
    const float s = static_cast<float>(1.0 / std::sqrt(static_cast<double>(d_grid.num_lines)));
    for (size_t i = 0; i < d_image.size(); ++i)
        out[i] = d_image[i] * s;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
