/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "../param_check.h"
#include <gnuradio/nrsar/kernel/uplink_channel.h>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace gr {
namespace nrsar {

void uplink_channel_config::validate() const
{
    if (taps.empty() || taps.size() > 256)
        throw_param("taps", taps.size(), "taps given: must be 1 .. 256");
    for (std::size_t l = 0; l < taps.size(); l++)
        if (!std::isfinite(taps[l].real()) || !std::isfinite(taps[l].imag()))
            throw_param("taps[" + std::to_string(l) + "]", taps[l], "must be finite");
    if (!std::isfinite(cfo) || std::abs(cfo) >= 0.5)
        throw_param("cfo", cfo, "cycles per sample: must be finite and below 0.5 in magnitude");
    if (!std::isfinite(noise_voltage) || noise_voltage < 0.0)
        throw_param("noise_voltage", noise_voltage, "must be finite and >= 0");
    if (delay_samples > (std::uint64_t{ 1 } << 40))
        throw_param("delay_samples", delay_samples, "must be at most 2^40");
}

namespace kernel {

namespace {
constexpr double TWO_PI = 6.283185307179586476925286766559;

//! multipath_fir of the taps as integer-lag paths (max_lag >= its 2 taps).
multipath_fir make_fir(const uplink_channel_config& cfg)
{
    cfg.validate();
    const auto lags = static_cast<unsigned>(cfg.taps.size());
    multipath_fir fir(2, 0.0, std::max(2u, lags + 1));
    std::vector<echo_path> paths;
    for (unsigned l = 0; l < lags; l++)
        if (cfg.taps[l] != gr_complex(0.0f, 0.0f))
            paths.push_back({ double(l), std::complex<double>(cfg.taps[l]) });
    fir.set_paths(paths.data(), paths.size());
    return fir;
}
} // namespace

uplink_channel::uplink_channel(const uplink_channel_config& cfg)
    : d_fir(make_fir(cfg)),
      d_lag(d_fir.max_lag()),
      d_line(d_lag + CHUNK, gr_complex(0.0f, 0.0f)),
      d_cfo(cfg.cfo),
      d_step(ROT_BLOCK),
      d_noise(cfg.seed),
      d_sigma(static_cast<float>(cfg.noise_voltage)),
      d_z(NOISE_BLOCK)
{
    for (std::size_t k = 0; k < ROT_BLOCK; k++) {
        const double p = TWO_PI * d_cfo * double(k);
        d_step[k] = gr_complex(float(std::cos(p)), float(std::sin(p)));
    }
}

void uplink_channel::rotate(gr_complex* y, std::size_t n, std::uint64_t first) const
{
    if (d_cfo == 0.0)
        return;
    std::size_t i = 0;
    while (i < n) {
        const std::uint64_t s = first + i;
        const std::uint64_t n0 = s - s % ROT_BLOCK;
        const std::size_t k0 = static_cast<std::size_t>(s - n0);
        const std::size_t len = std::min(n - i, ROT_BLOCK - k0);
        // frac(cfo n0) in double: the phase stays exact over any stream length
        const double turns = d_cfo * double(n0);
        const double p = TWO_PI * (turns - std::floor(turns));
        const float br = float(std::cos(p)), bi = float(std::sin(p));
        auto* v = reinterpret_cast<float*>(y + i);
        const auto* t = reinterpret_cast<const float*>(d_step.data() + k0);
        for (std::size_t k = 0; k < len; k++) { // written out: no __mulsc3 NaN checks
            const float pr = br * t[2 * k] - bi * t[2 * k + 1];
            const float pi = br * t[2 * k + 1] + bi * t[2 * k];
            const float yr = v[2 * k], yi = v[2 * k + 1];
            v[2 * k] = yr * pr - yi * pi;
            v[2 * k + 1] = yr * pi + yi * pr;
        }
        i += len;
    }
}

void uplink_channel::add_noise(gr_complex* y, std::size_t n, std::uint64_t first)
{
    if (d_sigma == 0.0f)
        return;
    std::size_t i = 0;
    while (i < n) {
        const std::uint64_t s = first + i;
        const std::uint64_t b = s / NOISE_BLOCK;
        const std::size_t o = static_cast<std::size_t>(s % NOISE_BLOCK);
        const std::size_t len = std::min(n - i, NOISE_BLOCK - o);
        if (o == 0 && len == NOISE_BLOCK) {
            d_noise.add(b, d_sigma, y + i, len);
        } else { // a call that cuts the block: the whole block, kept for the next call
            if (d_z_block != b) {
                d_noise.generate(b, d_sigma, d_z.data(), NOISE_BLOCK);
                d_z_block = b;
            }
            for (std::size_t k = 0; k < len; k++)
                y[i + k] += d_z[o + k];
        }
        i += len;
    }
}

void uplink_channel::process(const gr_complex* x, gr_complex* y, std::size_t n)
{
    for (std::size_t done = 0; done < n;) {
        const std::size_t len = std::min(CHUNK, n - done);
        gr_complex* chunk = d_line.data() + d_lag;
        if (x)
            std::memcpy(chunk, x + done, len * sizeof(gr_complex));
        else
            std::fill(chunk, chunk + len, gr_complex(0.0f, 0.0f));
        d_fir.filter(chunk, y + done, len);
        // the last d_lag input samples are the next chunk's history
        std::memmove(d_line.data(), d_line.data() + len, d_lag * sizeof(gr_complex));
        rotate(y + done, len, d_n);
        add_noise(y + done, len, d_n);
        d_n += len;
        done += len;
    }
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
