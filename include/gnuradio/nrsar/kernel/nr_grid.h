/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_NR_GRID_H
#define INCLUDED_NRSAR_KERNEL_NR_GRID_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/constellation.h>
#include <gnuradio/nrsar/params.h>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief One column S[:, m] of the transmit grid (SPEC sections 2-3).
 *
 * DATA: every subcarrier carries a data symbol. SRS: only the comb subcarriers
 * start + comb_offset + i comb (i = 0..L-1, inside the num_rb * 12 band) of the SRS symbols
 * carry the pilot r(i) (low_papr_sequence of length L, u = v = 0, alpha = 0); every other RE is
 * 0. DATA_SRS: data everywhere except those SRS REs. Symbol m is an SRS symbol when
 * (m / symbols_per_slot) % period_slots == 0 and m % symbols_per_slot == symbol_in_slot.
 *
 * DMRS (dmrs.enabled()): the symbols dmrs.symbols of every slot carry the PUSCH DMRS of
 * kernel/dmrs.h on the even subcarriers (slot_in_frame = (m / symbols_per_slot) %
 * slots_per_frame) and 0 on the odd ones; they carry no data (data_res() = 0). A DMRS
 * symbol may not also be an SRS symbol.
 *
 * Data symbols are taken in subcarrier order from a packed MSB-first bit stream.
 */
class NRSAR_API nr_grid
{
public:
    //! Validates num (and srs when mode uses SRS); throws std::invalid_argument.
    nr_grid(const numerology& num,
            modulation mod,
            tx_mode mode,
            const srs_config& srs,
            const dmrs_config& dmrs = dmrs_config());
    nr_grid(nr_grid&&) = default;
    nr_grid& operator=(nr_grid&&) = default;
    nr_grid(const nr_grid&) = delete;
    nr_grid& operator=(const nr_grid&) = delete;

    unsigned num_subcarriers() const { return d_num.num_subcarriers; }
    const numerology& num() const { return d_num; }
    tx_mode mode() const { return d_mode; }
    const srs_config& srs() const { return d_srs; }
    const constellation& mapper() const { return d_const; }

    const dmrs_config& dmrs() const { return d_dmrs; }

    bool is_srs_symbol(std::uint64_t m) const;
    bool is_dmrs_symbol(std::uint64_t m) const
    {
        return d_dmrs_in_slot[m % d_num.symbols_per_slot] >= 0;
    }
    //! DMRS values of symbol m (on subcarriers 0, 2, 4, ...); empty when m carries none.
    const std::vector<gr_complex>& dmrs_values(std::uint64_t m) const;
    //! Data REs of symbol m.
    unsigned data_res(std::uint64_t m) const;
    //! Bits symbol m consumes: data_res(m) * bits_per_symbol.
    std::size_t data_bits(std::uint64_t m) const
    {
        return static_cast<std::size_t>(data_res(m)) * d_const.bits_per_symbol();
    }
    //! Bits symbols 0 .. s - 1 consume (sum of data_bits), in O(one SRS period).
    std::uint64_t data_bits_before(std::uint64_t s) const;
    //! Comb subcarriers of the SRS band (empty in DATA mode).
    const std::vector<unsigned>& srs_subcarriers() const { return d_srs_sc; }
    //! Pilot values on srs_subcarriers(), in the same order.
    const std::vector<gr_complex>& srs_sequence() const { return d_srs_seq; }

    /*!
     * Writes num_subcarriers() values of symbol m to out, reading data_bits(m) bits from
     * bytes starting first_bit bits in (MSB first). Returns the bit position after the
     * last bit read.
     */
    std::size_t
    fill(std::uint64_t m, const std::uint8_t* bytes, std::size_t first_bit, gr_complex* out) const;

private:
    numerology d_num;
    tx_mode d_mode;
    srs_config d_srs;
    constellation d_const;
    std::vector<unsigned> d_srs_sc;
    std::vector<gr_complex> d_srs_seq;
    dmrs_config d_dmrs;
    std::vector<int> d_dmrs_in_slot; // per symbol of the slot: index into dmrs.symbols or -1
    // [slot_in_frame * dmrs.symbols.size() + index]: values of that DMRS symbol
    std::vector<std::vector<gr_complex>> d_dmrs_table;
    std::vector<gr_complex> d_no_dmrs;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_NR_GRID_H */
