/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_LOW_PAPR_SEQUENCE_H
#define INCLUDED_NRSAR_KERNEL_LOW_PAPR_SEQUENCE_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Zadoff-Chu based low-PAPR sequence of 3GPP TS 38.211 5.2.2.1 (SRS pilots).
 *
 *   r(n)   = exp(j alpha n) rbar(n),           n = 0..length-1
 *   rbar(n) = x_q(n mod N_ZC),  x_q(m) = exp(-j pi q m (m+1) / N_ZC)
 *   q = floor(qbar + 1/2) + v (-1)^floor(2 qbar),  qbar = N_ZC (u + 1) / 31
 *
 * N_ZC is the largest prime below length (cyclic extension to length). 38.211 uses this
 * formula for lengths >= 36 and computer-generated tables for 6..30; we use the formula
 * for every length >= 3 (the values differ from 38.211 below 36, the unit modulus does
 * not) and all-ones for length 1 or 2 (no prime below). Group u in [0, 29], sequence v in
 * {0, 1}, cyclic shift alpha [rad]. Every value has |r(n)| = 1.
 */
NRSAR_API std::vector<gr_complex>
low_papr_sequence(unsigned length, unsigned u = 0, unsigned v = 0, double alpha = 0.0);

//! Largest prime strictly below n (0 when there is none, n <= 2).
NRSAR_API unsigned largest_prime_below(unsigned n);

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_LOW_PAPR_SEQUENCE_H */
