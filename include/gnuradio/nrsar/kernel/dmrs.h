/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_DMRS_H
#define INCLUDED_NRSAR_KERNEL_DMRS_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief c_init of the PUSCH DMRS of 3GPP TS 38.211 6.4.1.1.1 (transform precoding off,
 * n_SCID = 0, lambda-bar = 0):
 *   c_init = (2^17 (14 n_s + l + 1) (2 N_ID + 1) + 2 N_ID) mod 2^31
 * with n_s = slot within the frame, l = symbol within the slot.
 */
NRSAR_API std::uint32_t
dmrs_c_init(unsigned scrambling_id, unsigned slot_in_frame, unsigned symbol);

/*!
 * \brief DMRS values r(i), i = 0 .. count-1, of 38.211 6.4.1.1.1:
 *   r(i) = [(1 - 2 c(2i)) + j (1 - 2 c(2i + 1))] / sqrt(2)
 * Configuration type 1, CDM group 0, so r(i) sits on subcarrier 2 i (38.211 6.4.1.1.3,
 * k = 4 n + 2 k' with i = 2 n + k'); unit magnitude.
 */
NRSAR_API std::vector<gr_complex>
dmrs_values(unsigned scrambling_id, unsigned slot_in_frame, unsigned symbol, unsigned count);

//! DMRS REs of one symbol of an N-subcarrier grid: the even subcarriers, ceil(N / 2).
inline unsigned dmrs_count(unsigned num_subcarriers) { return (num_subcarriers + 1) / 2; }

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_DMRS_H */
