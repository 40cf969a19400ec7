/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Helpers shared by the kernel tests.

#ifndef INCLUDED_NRSAR_TEST_UTIL_H
#define INCLUDED_NRSAR_TEST_UTIL_H

#include <gnuradio/gr_complex.h>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace nrsar_test {

//! n complex samples with independent N(0, 1) real and imaginary parts, seeded.
inline std::vector<gr_complex> gaussian_samples(std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<gr_complex> x(n);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    return x;
}

//! Runs f and returns the std::invalid_argument message (empty if nothing was thrown).
template <typename F>
std::string error_of(F f)
{
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

} // namespace nrsar_test

#endif /* INCLUDED_NRSAR_TEST_UTIL_H */
