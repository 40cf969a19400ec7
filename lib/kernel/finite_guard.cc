/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/kernel/finite_guard.h>
#include <volk/volk.h>
#include <cmath>
#include <stdexcept>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
inline bool finite(const gr_complex& x)
{
    return std::isfinite(x.real()) && std::isfinite(x.imag());
}
} // namespace

std::size_t count_nonfinite(const gr_complex* in, std::size_t n)
{
    std::size_t bad = 0;
    for (std::size_t i = 0; i < n; i++)
        bad += finite(in[i]) ? 0 : 1;
    return bad;
}

const gr_complex*
finite_guard::guard(const gr_complex* in, std::size_t n, std::size_t& zeroed, unsigned slot)
{
    if (slot > 1)
        throw std::out_of_range("finite_guard slot must be 0 or 1");
    zeroed = 0;
    if (n == 0)
        return in;
    // Fast path: any NaN or Inf makes the sum non-finite.
    float sum = 0.0f;
    volk_32f_accumulator_s32f(&sum, reinterpret_cast<const float*>(in), 2 * n);
    if (std::isfinite(sum))
        return in;
    if (count_nonfinite(in, n) == 0)
        return in; // the sum only overflowed
    auto& copy = d_copy[slot];
    if (copy.size() < n)
        copy.resize(n);
    for (std::size_t i = 0; i < n; i++) {
        if (finite(in[i])) {
            copy[i] = in[i];
        } else {
            copy[i] = gr_complex(0.0f, 0.0f);
            zeroed++;
        }
    }
    return copy.data();
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
