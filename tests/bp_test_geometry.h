/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// focus_scenario's geometry for the back-projection tests: N = 32 subcarriers, 64-point
// range IFFT, 1.5 m bins from 955 m, H = 600 m, v = 50 m/s, PRF 400 Hz.

#ifndef INCLUDED_NRSAR_TESTS_BP_TEST_GEOMETRY_H
#define INCLUDED_NRSAR_TESTS_BP_TEST_GEOMETRY_H

#include <gnuradio/nrsar/kernel/bp_focuser.h>

namespace bp_test {

constexpr double C = 299792458.0, FC = 3.5e9, LAM = C / FC, V = 50.0, H = 600.0;
constexpr unsigned N = 32, NFFT = 64, K = 64;
constexpr double RHO = 1.5, FIRST = 955.0, T = 2.5e-3;
constexpr double FCR = (N - 1) / (2.0 * NFFT); // range spectrum centre [cycles/bin]

//! The slant-range grid of `lines` lines from y = 0, one per pulse.
inline gr::nrsar::kernel::bp_grid grid(unsigned upsample, unsigned lines)
{
    gr::nrsar::kernel::bp_grid g;
    g.num_range_bins = K;
    g.first_range_m = FIRST;
    g.range_bin_m = RHO;
    g.wavelength_m = LAM;
    g.range_centre_cycles = FCR;
    g.upsample = upsample;
    g.num_lines = lines;
    g.first_y_m = 0.0;
    g.line_spacing_m = V * T;
    g.reference_height_m = H;
    return g;
}

} // namespace bp_test

#endif /* INCLUDED_NRSAR_TESTS_BP_TEST_GEOMETRY_H */
