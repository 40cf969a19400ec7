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

namespace gr {
namespace nrsar {
namespace kernel {

namespace demap_detail {
struct axis_shape;
}

/*!
 * \brief Max-log LLRs of the 3GPP TS 38.211 5.1 square QAM constellations (QPSK, 16/64/256-QAM
 * of kernel::constellation).
 *
 * The 38.211 Gray mapping is separable: the even bits b(0), b(2), ... select the in-phase PAM
 * level, the odd bits the quadrature level, so |y - s|^2 splits into two one-dimensional terms
 * and the max-log LLR of a bit needs only its axis:
 *   L(b) = [min_{s: b = 1} (y_a - s_a)^2 - min_{s: b = 0} (y_a - s_a)^2] / sigma^2
 * (positive = bit 0 more likely), sigma^2 the complex noise variance of the (equalised) symbol.
 * The two minima are found without a search (soft_demapper_impl.h: the Gray mapping is a
 * fold, so each is a rounding and a clamp); AVX2 when the CPU has it, a generic path otherwise.
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
     * equalisation). With sq_err, also the sum over the symbols of |y - nearest point|^2
     * (the hard decision's error, for an EVM).
     */
    void demap(const gr_complex* y,
               const float* noise_var,
               std::size_t nsym,
               float* llr,
               double* sq_err = nullptr) const;
    //! Same with one noise variance for all symbols.
    void demap(const gr_complex* y, float noise_var, std::size_t nsym, float* llr) const;

private:
    modulation d_mod;
    unsigned d_bits; // per symbol
    // one axis in units of half the level spacing (see soft_demapper_impl.h)
    unsigned d_na;    // bits per axis
    float d_top;      // outer level L - 1
    float d_half;     // L / 2
    float d_to_unit;  // 1 / (half the level spacing)
    float d_unit2;    // (half the level spacing)^2
    bool d_simd;      // AVX2 path (runtime check)
    demap_detail::axis_shape shape() const;
    void run(const gr_complex* y,
             const float* nv,
             bool per_symbol,
             std::size_t nsym,
             float* llr,
             double* sq_err) const;
    void demap_generic(const gr_complex* y,
                       const float* nv,
                       bool per_symbol,
                       std::size_t nsym,
                       float* llr,
                       double* sq_err) const;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_SOFT_DEMAPPER_H */
