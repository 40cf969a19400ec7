/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/constellation.h>
#include <algorithm>
#include <cmath>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
// One axis of the 38.211 5.1 QAM formulas: bits (b_a, b_{a+2}, ...) of the symbol give
// (1-2b_a)[2^(p-1) - (1-2b_{a+2})[2^(p-2) - ...]], an odd integer in [-(2^p - 1), 2^p - 1].
int qam_axis(unsigned index, unsigned k, unsigned first)
{
    const unsigned p = k / 2; // bits per axis
    auto bit = [&](unsigned j) { return static_cast<int>((index >> (k - 1 - j)) & 1u); };
    // innermost term: (1 - 2 b_last), then wrap outwards
    int value = 1 - 2 * bit(first + 2 * (p - 1));
    for (int q = static_cast<int>(p) - 2; q >= 0; q--) {
        const int sign = 1 - 2 * bit(first + 2 * static_cast<unsigned>(q));
        value = sign * ((1 << (p - 1 - static_cast<unsigned>(q))) - value);
    }
    return value;
}
} // namespace

unsigned constellation::bits_per_symbol(modulation mod)
{
    switch (mod) {
    case modulation::QPSK:
        return 2;
    case modulation::QAM16:
        return 4;
    case modulation::QAM64:
        return 6;
    case modulation::QAM256:
        return 8;
    case modulation::PSK8:
        return 3;
    case modulation::PSK16:
        return 4;
    }
    throw_param("modulation", static_cast<int>(mod), "is not a known modulation (0..5)");
}

constellation::constellation(modulation mod)
    : d_mod(mod),
      d_bits(bits_per_symbol(mod)),
      d_psk(mod == modulation::PSK8 || mod == modulation::PSK16),
      d_levels(0),
      d_scale(0.0f)
{
    const unsigned m = 1u << d_bits;
    d_table.resize(m);
    if (d_psk) {
        d_slice.resize(m);
        for (unsigned point = 0; point < m; point++) {
            const unsigned index = point ^ (point >> 1); // Gray code of the phase number
            const double phi = 2.0 * M_PI * point / m;
            d_table[index] = gr_complex(static_cast<float>(std::cos(phi)),
                                        static_cast<float>(std::sin(phi)));
            d_slice[point] = static_cast<std::uint16_t>(index);
        }
        return;
    }
    // QAM (QPSK is the p = 1 case): normalisation 2 (M - 1) / 3 = 2, 10, 42, 170.
    const unsigned p = d_bits / 2;
    d_levels = 1u << p;
    const double norm = 2.0 * (m - 1) / 3.0;
    d_scale = static_cast<float>(std::sqrt(norm));
    d_slice.resize(d_levels * d_levels);
    for (unsigned index = 0; index < m; index++) {
        const int re = qam_axis(index, d_bits, 0);
        const int im = qam_axis(index, d_bits, 1);
        d_table[index] = gr_complex(static_cast<float>(re / std::sqrt(norm)),
                                    static_cast<float>(im / std::sqrt(norm)));
        const unsigned li = static_cast<unsigned>((re + static_cast<int>(d_levels) - 1) / 2);
        const unsigned lq = static_cast<unsigned>((im + static_cast<int>(d_levels) - 1) / 2);
        d_slice[li * d_levels + lq] = static_cast<std::uint16_t>(index);
    }
}

gr_complex constellation::map_bits(const std::uint8_t* bits) const
{
    unsigned index = 0;
    for (unsigned j = 0; j < d_bits; j++)
        index = (index << 1) | (bits[j] ? 1u : 0u);
    return d_table[index];
}

std::size_t constellation::map_packed(const std::uint8_t* bytes,
                                      std::size_t first_bit,
                                      std::size_t nsym,
                                      gr_complex* out) const
{
    const gr_complex* table = d_table.data();
    const unsigned k = d_bits;
    if (k == 8 && first_bit % 8 == 0) {
        // 256-QAM on byte boundaries: one byte is one table index.
        const std::uint8_t* p = bytes + first_bit / 8;
        for (std::size_t i = 0; i < nsym; i++)
            out[i] = table[p[i]];
        return first_bit + 8 * nsym;
    }
    // General case: a bit accumulator, MSB first; refilled a byte at a time.
    const std::uint8_t* p = bytes + first_bit / 8;
    const unsigned skip = static_cast<unsigned>(first_bit % 8);
    std::uint32_t acc = 0;
    unsigned nbits = 0;
    if (skip) {
        acc = *p++ & (0xffu >> skip);
        nbits = 8 - skip;
    }
    const std::uint32_t mask = (1u << k) - 1;
    for (std::size_t i = 0; i < nsym; i++) {
        if (nbits < k) {
            acc = (acc << 8) | *p++;
            nbits += 8;
        }
        nbits -= k;
        out[i] = table[(acc >> nbits) & mask];
    }
    return first_bit + k * nsym;
}

unsigned constellation::demap(gr_complex x) const
{
    if (d_psk) {
        const unsigned m = size();
        double phase = std::atan2(static_cast<double>(x.imag()), static_cast<double>(x.real()));
        long sector = std::lround(phase * m / (2.0 * M_PI));
        sector = ((sector % static_cast<long>(m)) + m) % m;
        return d_slice[static_cast<unsigned>(sector)];
    }
    // PAM level l of -(L-1) + 2 l, nearest by rounding, clamped to the outer levels.
    auto level = [&](float v) {
        const float l = std::nearbyint((v * d_scale + static_cast<float>(d_levels - 1)) * 0.5f);
        return static_cast<unsigned>(
            std::clamp(l, 0.0f, static_cast<float>(d_levels - 1)));
    };
    return d_slice[level(x.real()) * d_levels + level(x.imag())];
}

void constellation::demap(const gr_complex* in, std::size_t nsym, std::uint16_t* indices) const
{
    for (std::size_t i = 0; i < nsym; i++)
        indices[i] = static_cast<std::uint16_t>(demap(in[i]));
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
