/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/constellation.h>
#include <gnuradio/nrsar/kernel/soft_demapper.h>
#include "soft_demapper_impl.h"
#include <algorithm>
#include <cmath>
#include <stdexcept>

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
    const unsigned na = d_bits / 2;
    const unsigned levels = 1u << na;
    // Read the in-phase PAM from the mapper itself (index bits b(0), b(2), ... at the even
    // positions, b(0) = MSB, odd bits 0) and check that it is the fold of demap_detail.
    std::vector<float> level(levels);
    for (unsigned a = 0; a < levels; a++) {
        unsigned index = 0;
        for (unsigned j = 0; j < na; j++)
            if (a & (1u << (na - 1 - j)))
                index |= 1u << (d_bits - 1 - 2 * j);
        level[a] = c.map(index).real();
    }
    float outer = 0.0f;
    for (float v : level)
        outer = std::max(outer, std::abs(v));
    const float unit = outer / static_cast<float>(levels - 1); // half the level spacing
    d_na = na;
    d_top = static_cast<float>(levels - 1);
    d_half = static_cast<float>(levels / 2);
    d_to_unit = 1.0f / unit;
    d_unit2 = unit * unit;
    for (unsigned a = 0; a < levels; a++) {
        const float x = level[a] / unit;
        const long xi = std::lround(x);
        unsigned bits = x < 0 ? 1u : 0u;
        long u = std::labs(xi), t = levels / 2;
        for (unsigned j = 1; j < na; j++, t /= 2) {
            bits = (bits << 1) | (u > t ? 1u : 0u);
            u = std::labs(u - t);
        }
        if (std::abs(x - static_cast<float>(xi)) > 1e-4f || (xi & 1) == 0 || bits != a)
            throw std::logic_error("soft_demapper: the constellation is not the 38.211 "
                                   "Gray-mapped square QAM");
    }
    d_simd = demap_detail::avx2_available();
}

demap_detail::axis_shape soft_demapper::shape() const
{
    return demap_detail::axis_shape{ d_na, d_top, d_half, d_to_unit, d_unit2 };
}

namespace {
inline float clampf(float v, float lo, float hi) { return std::min(std::max(v, lo), hi); }
// nearest odd integer (ties up)
inline float odd_round(float u) { return 2.0f * std::floor(0.5f * u) + 1.0f; }
} // namespace

void soft_demapper::demap_generic(const gr_complex* y,
                                  const float* nv,
                                  bool per_symbol,
                                  std::size_t nsym,
                                  float* llr,
                                  double* sq_err) const
{
    const demap_detail::axis_shape s = shape();
    for (std::size_t i = 0; i < nsym; i++) {
        const float scale = s.unit2 / (per_symbol ? nv[i] : nv[0]);
        float* out = llr + i * d_bits;
        float e = 0.0f;
        for (unsigned axis = 0; axis < 2; axis++) {
            const float x = (axis == 0 ? y[i].real() : y[i].imag()) * s.to_unit;
            const float a = std::abs(x);
            // b(axis): nearest level of the other sign at distance |x| + 1
            const float dn = a - clampf(odd_round(a), 1.0f, s.top);
            const float l0 = (a + 1.0f) * (a + 1.0f) - dn * dn;
            out[axis] = std::copysign(l0, x) * scale;
            e += dn * dn;
            float u = a, t = s.half;
            for (unsigned j = 1; j < s.na; j++) {
                const float r = odd_round(u);
                const float din = u - clampf(r, 1.0f, t - 1.0f);
                const float dout = u - clampf(r, t + 1.0f, 2.0f * t - 1.0f);
                out[2 * j + axis] = (dout * dout - din * din) * scale;
                u = std::abs(u - t);
                t *= 0.5f;
            }
        }
        if (sq_err)
            *sq_err += static_cast<double>(e * s.unit2);
    }
}

void soft_demapper::run(const gr_complex* y,
                        const float* nv,
                        bool per_symbol,
                        std::size_t nsym,
                        float* llr,
                        double* sq_err) const
{
    if (sq_err)
        *sq_err = 0.0;
    std::size_t done = 0;
    if (d_simd)
        done = demap_detail::demap_avx2(shape(), y, nv, per_symbol, nsym, llr, sq_err);
    demap_generic(y + done,
                  per_symbol ? nv + done : nv,
                  per_symbol,
                  nsym - done,
                  llr + done * d_bits,
                  sq_err);
}

void soft_demapper::demap(const gr_complex* y,
                          const float* noise_var,
                          std::size_t nsym,
                          float* llr,
                          double* sq_err) const
{
    run(y, noise_var, true, nsym, llr, sq_err);
}

void soft_demapper::demap(const gr_complex* y, float noise_var, std::size_t nsym, float* llr) const
{
    run(y, &noise_var, false, nsym, llr, nullptr);
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
