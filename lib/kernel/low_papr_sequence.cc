/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/low_papr_sequence.h>
#include <cmath>

namespace gr {
namespace nrsar {
namespace kernel {

unsigned largest_prime_below(unsigned n)
{
    for (unsigned p = n; p-- > 2;) {
        bool prime = true;
        for (unsigned d = 2; d * d <= p; d++) {
            if (p % d == 0) {
                prime = false;
                break;
            }
        }
        if (prime)
            return p;
    }
    return 0;
}

std::vector<gr_complex> low_papr_sequence(unsigned length, unsigned u, unsigned v, double alpha)
{
    check_at_least("sequence length", length, 1u);
    check_range("sequence group u", u, 0u, 29u);
    check_range("sequence number v", v, 0u, 1u);
    check_finite("cyclic shift alpha", alpha);
    std::vector<gr_complex> r(length, gr_complex(1.0f, 0.0f));
    const unsigned nzc = largest_prime_below(length);
    if (nzc == 0)
        return r;
    const double qbar = static_cast<double>(nzc) * (u + 1) / 31.0;
    const long q = static_cast<long>(std::floor(qbar + 0.5)) +
                   static_cast<long>(v) * ((static_cast<long>(std::floor(2.0 * qbar)) % 2) ? -1 : 1);
    for (unsigned n = 0; n < length; n++) {
        const long m = static_cast<long>(n % nzc);
        // m (m + 1) q mod 2 N_ZC keeps the phase argument small (exact in integers).
        const long num = (m * (m + 1) % (2 * static_cast<long>(nzc))) * q % (2 * static_cast<long>(nzc));
        const double phase = -M_PI * static_cast<double>(num) / nzc + alpha * n;
        r[n] = gr_complex(static_cast<float>(std::cos(phase)), static_cast<float>(std::sin(phase)));
    }
    return r;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
