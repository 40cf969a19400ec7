/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/dmrs.h>
#include <gnuradio/nrsar/kernel/low_papr_sequence.h>
#include <gnuradio/nrsar/kernel/nr_grid.h>
#include <algorithm>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
int checked_mode(tx_mode mode)
{
    const int value = static_cast<int>(mode);
    if (value < 0 || value > static_cast<int>(tx_mode::DATA_SRS))
        throw_param("mode", value, "is not a known tx_mode (0..2)");
    return value;
}
} // namespace

nr_grid::nr_grid(const numerology& num,
                 modulation mod,
                 tx_mode mode,
                 const srs_config& srs,
                 const dmrs_config& dmrs)
    : d_num(num), d_mode(mode), d_srs(srs), d_const(mod), d_dmrs(dmrs)
{
    d_num.validate();
    checked_mode(mode);
    d_dmrs.validate(d_num);
    d_dmrs_in_slot.assign(d_num.symbols_per_slot, -1);
    for (std::size_t i = 0; i < d_dmrs.symbols.size(); i++)
        d_dmrs_in_slot[d_dmrs.symbols[i]] = static_cast<int>(i);
    const unsigned n_dmrs = dmrs_count(d_num.num_subcarriers);
    for (unsigned slot = 0; d_dmrs.enabled() && slot < d_num.slots_per_frame; slot++)
        for (unsigned l : d_dmrs.symbols)
            d_dmrs_table.push_back(
                kernel::dmrs_values(d_dmrs.scrambling_id, slot, l, n_dmrs));
    if (mode == tx_mode::DATA)
        return;
    if (d_dmrs.is_dmrs_symbol(d_srs.symbol_in_slot))
        throw_param("srs symbol_in_slot",
                    d_srs.symbol_in_slot,
                    "must not be a DMRS symbol of the slot");
    d_srs.validate(d_num);
    if (d_srs.comb_offset >= d_srs.num_subcarriers())
        throw_param("srs comb_offset",
                    d_srs.comb_offset,
                    "must be below the band width num_rb * 12 = " +
                        std::to_string(d_srs.num_subcarriers()));
    for (unsigned k = d_srs.comb_offset; k < d_srs.num_subcarriers(); k += d_srs.comb)
        d_srs_sc.push_back(d_srs.start_subcarrier + k);
    d_srs_seq = low_papr_sequence(static_cast<unsigned>(d_srs_sc.size()));
}

bool nr_grid::is_srs_symbol(std::uint64_t m) const
{
    if (d_mode == tx_mode::DATA)
        return false;
    const std::uint64_t sps = d_num.symbols_per_slot;
    return (m % sps) == d_srs.symbol_in_slot && ((m / sps) % d_srs.period_slots) == 0;
}

const std::vector<gr_complex>& nr_grid::dmrs_values(std::uint64_t m) const
{
    const std::uint64_t sps = d_num.symbols_per_slot;
    const int idx = d_dmrs_in_slot[m % sps];
    if (idx < 0)
        return d_no_dmrs;
    const std::uint64_t slot = (m / sps) % d_num.slots_per_frame;
    return d_dmrs_table[slot * d_dmrs.symbols.size() + static_cast<std::size_t>(idx)];
}

std::uint64_t nr_grid::data_bits_before(std::uint64_t s) const
{
    // data_res repeats every slot (DMRS), or every SRS period in DATA_SRS.
    const std::uint64_t period = std::uint64_t{ d_num.symbols_per_slot } *
                                 (d_mode == tx_mode::DATA_SRS ? d_srs.period_slots : 1u);
    std::uint64_t per_period = 0, rest = 0;
    for (std::uint64_t m = 0; m < period; m++) {
        per_period += data_bits(m);
        if (m < s % period)
            rest += data_bits(m);
    }
    return s / period * per_period + rest;
}

unsigned nr_grid::data_res(std::uint64_t m) const
{
    if (is_dmrs_symbol(m))
        return 0;
    switch (d_mode) {
    case tx_mode::DATA:
        return d_num.num_subcarriers;
    case tx_mode::SRS:
        return 0;
    case tx_mode::DATA_SRS:
        break;
    }
    return is_srs_symbol(m) ? d_num.num_subcarriers - static_cast<unsigned>(d_srs_sc.size())
                            : d_num.num_subcarriers;
}

std::size_t nr_grid::fill(std::uint64_t m,
                          const std::uint8_t* bytes,
                          std::size_t first_bit,
                          gr_complex* out) const
{
    const unsigned n_sc = d_num.num_subcarriers;
    if (is_dmrs_symbol(m)) {
        // type 1, CDM group 0: r(i) on subcarrier 2 i, odd subcarriers empty
        const auto& r = dmrs_values(m);
        std::fill(out, out + n_sc, gr_complex(0.0f, 0.0f));
        for (std::size_t i = 0; i < r.size(); i++)
            out[2 * i] = r[i];
        return first_bit;
    }
    const bool srs_here = is_srs_symbol(m);
    if (d_mode == tx_mode::SRS) {
        std::fill(out, out + n_sc, gr_complex(0.0f, 0.0f));
        if (srs_here)
            for (std::size_t i = 0; i < d_srs_sc.size(); i++)
                out[d_srs_sc[i]] = d_srs_seq[i];
        return first_bit;
    }
    if (!srs_here)
        return d_const.map_packed(bytes, first_bit, n_sc, out);
    // DATA_SRS symbol with pilots: data runs between the comb positions.
    std::size_t bit = first_bit;
    unsigned pos = 0;
    for (std::size_t i = 0; i < d_srs_sc.size(); i++) {
        const unsigned p = d_srs_sc[i];
        bit = d_const.map_packed(bytes, bit, p - pos, out + pos);
        out[p] = d_srs_seq[i];
        pos = p + 1;
    }
    return d_const.map_packed(bytes, bit, n_sc - pos, out + pos);
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
