/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_SOFT_DEMAPPER_H
#define INCLUDED_NRSAR_KERNEL_SOFT_DEMAPPER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Max-log LLRs of the 3GPP TS 38.211 5.1 square QAM constellations (QPSK, 16/64/256-QAM
 * of kernel::constellation).
 *
 * The 38.211 Gray mapping is separable: the even bits b(0), b(2), ... select the in-phase PAM
 * level, the odd bits the quadrature level, so |y - s|^2 splits into two one-dimensional terms
 * and the max-log LLR of a bit needs only its axis:
 *   L(b) = [min_{s: b = 1} (y_a - s_a)^2 - min_{s: b = 0} (y_a - s_a)^2] / sigma^2
 * (positive = bit 0 more likely), sigma^2 the complex noise variance of the (equalised) symbol.
 * PSK is not supported (std::invalid_argument).
 */
class NRSAR_API soft_demapper
{
public:
    explicit soft_demapper(modulation mod = modulation::QAM256);

    unsigned bits_per_symbol() const { return d_bits; }
    modulation mod() const { return d_mod; }
    //! True when mod has a soft demapper here (QPSK, QAM16/64/256).
    static bool supported(modulation mod);

    /*!
     * LLRs of nsym symbols y into llr (nsym * bits_per_symbol(), b(0) of y[0] first);
     * noise_var[i] > 0 is the complex noise variance of y[i] (sigma^2 / |h|^2 after zero-forcing
     * equalisation).
     */
    void demap(const gr_complex* y, const float* noise_var, std::size_t nsym, float* llr) const;
    //! Same with one noise variance for all symbols.
    void demap(const gr_complex* y, float noise_var, std::size_t nsym, float* llr) const;

private:
    modulation d_mod;
    unsigned d_bits;   // per symbol
    unsigned d_axis;   // bits per axis
    unsigned d_levels; // PAM levels per axis
    std::vector<float> d_level;          // PAM level values
    std::vector<unsigned> d_level_bits;  // axis bits of each level, first axis bit = MSB
    std::vector<float> d_sorted;         // levels in increasing order
    std::vector<unsigned> d_sorted_bits; // their axis bits
    std::vector<std::int8_t> d_flip;     // [(pos * axis_bits + j) * 2 + side]
    float d_step = 1.0f;
    template <bool PerSymbol>
    void demap_impl(const gr_complex* y, const float* nv, std::size_t nsym, float* llr) const;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_SOFT_DEMAPPER_H */
