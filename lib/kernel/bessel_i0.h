/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// I0 of the Kaiser windows (sinc_interpolator, td_echo's multipath_fir).

#ifndef INCLUDED_NRSAR_KERNEL_BESSEL_I0_H
#define INCLUDED_NRSAR_KERNEL_BESSEL_I0_H

namespace gr {
namespace nrsar {
namespace kernel {

//! Modified Bessel function of the first kind, order 0 (power series; converges fast for
//! the beta <= 50 a Kaiser window uses).
inline double bessel_i0(double x)
{
    double sum = 1.0, term = 1.0;
    const double q = x * x / 4.0;
    for (int k = 1; k < 300; ++k) {
        term *= q / (double(k) * k);
        sum += term;
        if (term < 1e-17 * sum)
            break;
    }
    return sum;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_BESSEL_I0_H */
