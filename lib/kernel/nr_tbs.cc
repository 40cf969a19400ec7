/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/nr_tbs.h>
#include <algorithm>
#include <cmath>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {

// TS 38.214 Table 5.1.3.1-1, MCS 0 .. 28 (29 .. 31 reserved).
const nr_mcs_entry mcs_qam64[29] = {
    { 2, 120 }, { 2, 157 }, { 2, 193 }, { 2, 251 }, { 2, 308 }, { 2, 379 }, { 2, 449 }, { 2, 526 },
    { 2, 602 }, { 2, 679 }, { 4, 340 }, { 4, 378 }, { 4, 434 }, { 4, 490 }, { 4, 553 }, { 4, 616 },
    { 4, 658 }, { 6, 438 }, { 6, 466 }, { 6, 517 }, { 6, 567 }, { 6, 616 }, { 6, 666 }, { 6, 719 },
    { 6, 772 }, { 6, 822 }, { 6, 873 }, { 6, 910 }, { 6, 948 },
};

// TS 38.214 Table 5.1.3.1-2, MCS 0 .. 27 (28 .. 31 reserved).
const nr_mcs_entry mcs_qam256[28] = {
    { 2, 120 }, { 2, 193 }, { 2, 308 }, { 2, 449 }, { 2, 602 }, { 4, 378 }, { 4, 434 },
    { 4, 490 }, { 4, 553 }, { 4, 616 }, { 4, 658 }, { 6, 466 }, { 6, 517 }, { 6, 567 },
    { 6, 616 }, { 6, 666 }, { 6, 719 }, { 6, 772 }, { 6, 822 }, { 6, 873 }, { 8, 682.5 },
    { 8, 711 }, { 8, 754 }, { 8, 797 }, { 8, 841 }, { 8, 885 }, { 8, 916.5 }, { 8, 948 },
};

// TS 38.214 Table 5.1.3.2-1: TBS for N_info <= 3824.
const unsigned tbs_table[93] = {
    24,   32,   40,   48,   56,   64,   72,   80,   88,   96,   104,  112,  120,  128,  136,  144,
    152,  160,  168,  176,  184,  192,  208,  224,  240,  256,  272,  288,  304,  320,  336,  352,
    368,  384,  408,  432,  456,  480,  504,  528,  552,  576,  608,  640,  672,  704,  736,  768,
    808,  848,  888,  928,  984,  1032, 1064, 1128, 1160, 1192, 1224, 1256, 1288, 1320, 1352, 1416,
    1480, 1544, 1608, 1672, 1736, 1800, 1864, 1928, 2024, 2088, 2152, 2216, 2280, 2408, 2472, 2536,
    2600, 2664, 2728, 2792, 2856, 2976, 3104, 3240, 3368, 3496, 3624, 3752, 3824,
};

std::size_t ceil_div(std::size_t a, std::size_t b) { return (a + b - 1) / b; }

} // namespace

nr_mcs_table nr_parse_mcs_table(const std::string& name)
{
    if (name == "qam64")
        return nr_mcs_table::qam64;
    if (name == "qam256")
        return nr_mcs_table::qam256;
    throw_param("mcs_table", "'" + name + "'", "must be \"qam64\" (38.214 Table 5.1.3.1-1) or \"qam256\" (Table 5.1.3.1-2)");
}

nr_mcs_entry nr_mcs(nr_mcs_table table, unsigned mcs)
{
    if (table == nr_mcs_table::qam64) {
        check_range("mcs", mcs, 0u, 28u);
        return mcs_qam64[mcs];
    }
    check_range("mcs", mcs, 0u, 27u);
    return mcs_qam256[mcs];
}

std::size_t nr_tbs_from_n_info(double n_info, double code_rate)
{
    if (!(n_info > 0.0) || !std::isfinite(n_info))
        throw_param("n_info", n_info, "must be finite and > 0");
    if (n_info <= 3824) {
        // Step 3: quantise to a multiple of 2^n, then the smallest table entry not below it.
        const int n = std::max(3, static_cast<int>(std::floor(std::log2(n_info))) - 6);
        const double q = std::ldexp(1.0, n);
        const double n_info_p = std::max(24.0, q * std::floor(n_info / q));
        return *std::lower_bound(std::begin(tbs_table), std::end(tbs_table), n_info_p);
    }
    // Step 4: round to a multiple of 2^n (halves up), then whole bytes per code block.
    const int n = static_cast<int>(std::floor(std::log2(n_info - 24))) - 5;
    const double q = std::ldexp(1.0, n);
    const auto n_info_p = static_cast<std::size_t>(std::max(3840.0, q * std::floor((n_info - 24) / q + 0.5)));
    if (code_rate <= 0.25) {
        const std::size_t C = ceil_div(n_info_p + 24, 3816);
        return 8 * C * ceil_div(n_info_p + 24, 8 * C) - 24;
    }
    if (n_info_p > 8424) {
        const std::size_t C = ceil_div(n_info_p + 24, 8424);
        return 8 * C * ceil_div(n_info_p + 24, 8 * C) - 24;
    }
    return 8 * ceil_div(n_info_p + 24, 8) - 24;
}

std::size_t nr_tbs(nr_mcs_table table,
                   unsigned mcs,
                   unsigned n_prb,
                   unsigned n_symbols,
                   unsigned n_dmrs_re_per_prb,
                   unsigned n_layers,
                   unsigned n_oh)
{
    const nr_mcs_entry m = nr_mcs(table, mcs);
    check_range("n_prb", n_prb, 1u, 275u);
    check_range("n_symbols", n_symbols, 1u, 14u);
    check_range("n_layers", n_layers, 1u, 4u);
    const int n_re_p = 12 * static_cast<int>(n_symbols) - static_cast<int>(n_dmrs_re_per_prb) - static_cast<int>(n_oh);
    if (n_re_p <= 0)
        throw_param("n_dmrs_re_per_prb", n_dmrs_re_per_prb, "plus n_oh leaves no data RE in 12 n_symbols");
    const double n_re = std::min(156, n_re_p) * double(n_prb);
    return nr_tbs_from_n_info(n_re * m.code_rate() * m.qm * n_layers, m.code_rate());
}

std::uint32_t nr_scrambling_c_init(unsigned n_rnti, unsigned n_id)
{
    check_range("n_rnti", n_rnti, 0u, 65535u);
    check_range("n_id", n_id, 0u, 1023u);
    return (static_cast<std::uint32_t>(n_rnti) << 15) + n_id;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
