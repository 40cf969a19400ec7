/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "gaussian_noise_impl.h"
#include <gnuradio/nrsar/kernel/gaussian_noise.h>
#include <algorithm>

namespace gr {
namespace nrsar {
namespace kernel {

using namespace noise_detail;

namespace {

void generic_run(lane_state& st, float sigma, gr_complex* out, std::size_t n, bool add)
{
    gr_complex z[lanes];
    for (std::size_t i0 = 0; i0 < n; i0 += lanes) {
        generic_group(st, sigma, z);
        const std::size_t len = std::min<std::size_t>(lanes, n - i0);
        for (std::size_t l = 0; l < len; l++) {
            if (add)
                out[i0 + l] += z[l];
            else
                out[i0 + l] = z[l];
        }
    }
}

void run(std::uint64_t seed,
         std::uint64_t block,
         float sigma,
         gr_complex* out,
         std::size_t n,
         bool add,
         bool simd)
{
    lane_state st;
    seed_lanes(seed, block, st);
    if (!simd) {
        generic_run(st, sigma, out, n, add);
        return;
    }
    const std::size_t groups = n / lanes;
    avx2_run(st, sigma, out, groups, add);
    const std::size_t done = groups * lanes;
    if (done < n) {
        // The tail through the same path, so a sample does not depend on n.
        gr_complex last[lanes];
        avx2_run(st, sigma, last, 1, false);
        for (std::size_t i = done; i < n; i++) {
            if (add)
                out[i] += last[i - done];
            else
                out[i] = last[i - done];
        }
    }
}

} // namespace

gaussian_noise::gaussian_noise(std::uint64_t seed, bool allow_simd)
    : d_seed(seed), d_simd(allow_simd && avx2_available())
{
}

void gaussian_noise::generate(std::uint64_t block,
                              float sigma,
                              gr_complex* out,
                              std::size_t n) const
{
    run(d_seed, block, sigma, out, n, false, d_simd);
}

void gaussian_noise::add(std::uint64_t block,
                         float sigma,
                         gr_complex* inout,
                         std::size_t n) const
{
    run(d_seed, block, sigma, inout, n, true, d_simd);
}

const char* gaussian_noise::implementation() const { return d_simd ? "avx2" : "generic"; }

} // namespace kernel
} // namespace nrsar
} // namespace gr
