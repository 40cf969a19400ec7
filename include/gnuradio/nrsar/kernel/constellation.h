/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_CONSTELLATION_H
#define INCLUDED_NRSAR_KERNEL_CONSTELLATION_H

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
 * \brief Bits -> complex symbol mapper (lookup table) and hard-decision demapper.
 *
 * A symbol carries k = bits_per_symbol() bits b(0..k-1), b(0) first; its table index is
 * i = sum_j b(j) 2^(k-1-j) (b(0) is the most significant bit), so a packed MSB-first byte
 * stream reads straight into indices.
 *
 * QPSK, 16/64/256-QAM: 3GPP TS 38.211 5.1.3-5.1.6 (formulas in SPEC section 2), E{|d|^2} = 1.
 * PSK8, PSK16: Gray-coded M-PSK, d = exp(j 2 pi m / M) for the point m whose Gray code
 * m ^ (m >> 1) equals the index i, so neighbouring phases differ in one bit; |d| = 1.
 */
class NRSAR_API constellation
{
public:
    explicit constellation(modulation mod = modulation::QAM256);

    modulation mod() const { return d_mod; }
    unsigned bits_per_symbol() const { return d_bits; }
    unsigned size() const { return static_cast<unsigned>(d_table.size()); }
    //! Table of size() points, indexed as described above.
    const std::vector<gr_complex>& points() const { return d_table; }

    //! Symbol of index i (0 <= i < size()).
    gr_complex map(unsigned index) const { return d_table[index]; }
    //! Symbol of bits b(0..k-1), one bit per byte (non-zero = 1).
    gr_complex map_bits(const std::uint8_t* bits) const;
    /*!
     * Maps nsym symbols from a packed MSB-first bit stream starting first_bit bits into
     * bytes; reads exactly nsym * k bits. Returns the bit position after the last bit read.
     */
    std::size_t map_packed(const std::uint8_t* bytes,
                           std::size_t first_bit,
                           std::size_t nsym,
                           gr_complex* out) const;

    //! Index of the nearest point (hard decision: per-axis slicing for QAM, phase for PSK).
    unsigned demap(gr_complex x) const;
    //! Demaps nsym symbols to indices.
    void demap(const gr_complex* in, std::size_t nsym, std::uint16_t* indices) const;

    //! Bits per symbol of a modulation (2, 4, 6, 8, 3, 4).
    static unsigned bits_per_symbol(modulation mod);

private:
    modulation d_mod;
    unsigned d_bits;
    bool d_psk;
    unsigned d_levels;              // QAM: PAM levels per axis (sqrt of size)
    float d_scale;                  // QAM: sqrt(normalisation), PAM level = x * d_scale
    std::vector<gr_complex> d_table;
    std::vector<std::uint16_t> d_slice; // QAM: [level_i * d_levels + level_q]; PSK: [phase]
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_CONSTELLATION_H */
