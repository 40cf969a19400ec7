/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/constellation.h>
#include <gnuradio/nrsar/kernel/soft_demapper.h>
#include <algorithm>
#include <limits>

namespace gr {
namespace nrsar {
namespace kernel {

bool soft_demapper::supported(modulation mod)
{
    return mod == modulation::QPSK || mod == modulation::QAM16 || mod == modulation::QAM64 ||
           mod == modulation::QAM256;
}

soft_demapper::soft_demapper(modulation mod) : d_mod(mod)
{
    if (!supported(mod))
        throw_param("mod",
                    static_cast<int>(mod),
                    "has no soft demapper (QPSK, QAM16, QAM64, QAM256 only)");
    const constellation c(mod);
    d_bits = c.bits_per_symbol();
    d_axis = d_bits / 2;
    d_levels = 1u << d_axis;
    d_level.assign(d_levels, 0.0f);
    d_level_bits.assign(d_levels, 0);
    // Read the in-phase PAM from the mapper itself: index bits b(0), b(2), ... (even
    // positions, b(0) = MSB of the index) with the odd bits 0.
    for (unsigned a = 0; a < d_levels; a++) {
        unsigned index = 0;
        for (unsigned j = 0; j < d_axis; j++)
            if (a & (1u << (d_axis - 1 - j)))
                index |= 1u << (d_bits - 1 - 2 * j);
        d_level[a] = c.map(index).real();
        d_level_bits[a] = a;
    }
}

template <bool PerSymbol>
void soft_demapper::demap_impl(const gr_complex* y,
                               const float* nv,
                               std::size_t nsym,
                               float* llr) const
{
    constexpr float inf = std::numeric_limits<float>::infinity();
    float min0[8], min1[8];
    for (std::size_t i = 0; i < nsym; i++) {
        const float inv = 1.0f / (PerSymbol ? nv[i] : nv[0]);
        float* out = llr + i * d_bits;
        for (unsigned axis = 0; axis < 2; axis++) {
            const float v = axis == 0 ? y[i].real() : y[i].imag();
            std::fill(min0, min0 + d_axis, inf);
            std::fill(min1, min1 + d_axis, inf);
            for (unsigned a = 0; a < d_levels; a++) {
                const float d = v - d_level[a];
                const float d2 = d * d;
                for (unsigned j = 0; j < d_axis; j++) {
                    if (a & (1u << (d_axis - 1 - j)))
                        min1[j] = std::min(min1[j], d2);
                    else
                        min0[j] = std::min(min0[j], d2);
                }
            }
            // axis bit j is b(2 j + axis)
            for (unsigned j = 0; j < d_axis; j++)
                out[2 * j + axis] = (min1[j] - min0[j]) * inv;
        }
    }
}

void soft_demapper::demap(const gr_complex* y,
                          const float* noise_var,
                          std::size_t nsym,
                          float* llr) const
{
    demap_impl<true>(y, noise_var, nsym, llr);
}

void soft_demapper::demap(const gr_complex* y, float noise_var, std::size_t nsym, float* llr) const
{
    demap_impl<false>(y, &noise_var, nsym, llr);
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
