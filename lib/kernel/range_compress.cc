/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/range_compress.h>
#include <string>

namespace gr {
namespace nrsar {
namespace kernel {

range_compress::range_compress(tf_filter&& filter, range_ifft&& ifft)
    : d_filter(std::move(filter)), d_ifft(std::move(ifft))
{
    if (d_filter.vlen() != d_ifft.n())
        throw_param("vlen",
                    d_filter.vlen(),
                    "must equal the range IFFT's subcarriers " +
                        std::to_string(d_ifft.n()));
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
