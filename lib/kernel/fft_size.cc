/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/kernel/fft_size.h>
#include <initializer_list>

namespace gr {
namespace nrsar {
namespace kernel {

unsigned fast_fft_size(unsigned n)
{
    if (n <= 1)
        return 1;
    for (unsigned long m = n;; m++) {
        unsigned long r = m;
        for (unsigned p : { 2u, 3u, 5u, 7u })
            while (r % p == 0)
                r /= p;
        if (r == 1)
            return unsigned(m);
    }
}

unsigned pow2_fft_size(unsigned n)
{
    unsigned m = 1;
    while (m < n)
        m <<= 1;
    return m;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
