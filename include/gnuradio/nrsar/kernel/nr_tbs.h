/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_NR_TBS_H
#define INCLUDED_NRSAR_KERNEL_NR_TBS_H

#include <gnuradio/nrsar/api.h>
#include <cstddef>
#include <cstdint>
#include <string>

namespace gr {
namespace nrsar {
namespace kernel {

//! The PUSCH/PDSCH MCS tables of TS 38.214: Table 5.1.3.1-1 (qam64) and 5.1.3.1-2 (qam256).
enum class nr_mcs_table { qam64, qam256 };

//! One row of an MCS table: modulation order and target code rate R x 1024.
struct nr_mcs_entry {
    unsigned qm;
    double rate_x1024;
    double code_rate() const { return rate_x1024 / 1024.0; }
};

//! "qam64" or "qam256" (the RRC names of mcs-Table); std::invalid_argument otherwise.
NRSAR_API nr_mcs_table nr_parse_mcs_table(const std::string& name);

//! Row mcs of the table: 0 .. 28 (qam64) or 0 .. 27 (qam256); the reserved rows are refused.
NRSAR_API nr_mcs_entry nr_mcs(nr_mcs_table table, unsigned mcs);

//! TBS from N_info (TS 38.214 5.1.3.2 steps 3 and 4), for a code rate R.
NRSAR_API std::size_t nr_tbs_from_n_info(double n_info, double code_rate);

/*!
 * \brief Transport block size of TS 38.214 5.1.3.2:
 *   N'_RE = 12 N_symb - N_DMRS - N_oh,  N_RE = min(156, N'_RE) n_PRB,  N_info = N_RE R Qm v.
 * \param n_symbols          N_symb^sh, OFDM symbols of the allocation (1 .. 14)
 * \param n_dmrs_re_per_prb  N_DMRS^PRB, DMRS REs per PRB incl. CDM groups without data
 * \param n_oh               N_oh^PRB (xOverhead: 0, 6, 12, 18)
 */
NRSAR_API std::size_t nr_tbs(nr_mcs_table table,
                             unsigned mcs,
                             unsigned n_prb,
                             unsigned n_symbols,
                             unsigned n_dmrs_re_per_prb,
                             unsigned n_layers = 1,
                             unsigned n_oh = 0);

//! c_init of the PUSCH / PDSCH scrambler (TS 38.211 6.3.1.1 / 7.3.1.1): n_RNTI 2^15 + n_ID.
NRSAR_API std::uint32_t nr_scrambling_c_init(unsigned n_rnti, unsigned n_id);

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_NR_TBS_H */
