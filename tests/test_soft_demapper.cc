/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "test_util.h"
#include <gnuradio/nrsar/kernel/constellation.h>
#include <gnuradio/nrsar/kernel/soft_demapper.h>
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

using namespace gr::nrsar;
using namespace gr::nrsar::kernel;

namespace {
// (min over points with bit j = 1) - (min over bit j = 0) of |y - s|^2, and the minimum
// over all points, by a search over every constellation point in double.
struct search {
    double llr_num;
    double nearest;
};
search bruteforce(const constellation& c, gr_complex y, unsigned j)
{
    const unsigned k = c.bits_per_symbol();
    const std::complex<double> yd(y.real(), y.imag());
    double m0 = std::numeric_limits<double>::infinity(), m1 = m0;
    for (unsigned p = 0; p < c.size(); p++) {
        const std::complex<double> s(c.points()[p].real(), c.points()[p].imag());
        const double dist = std::norm(yd - s);
        if ((p >> (k - 1 - j)) & 1u)
            m1 = std::min(m1, dist);
        else
            m0 = std::min(m0, dist);
    }
    return { m1 - m0, std::min(m0, m1) };
}
} // namespace

// Brute force max-log over every constellation point, in double.
TEST(soft_demapper, matches_bruteforce_maxlog)
{
    for (auto mod : { modulation::QPSK, modulation::QAM16, modulation::QAM64, modulation::QAM256 }) {
        const constellation c(mod);
        const soft_demapper d(mod);
        const unsigned k = c.bits_per_symbol();
        const auto noise = nrsar_test::gaussian_samples(500, 11);
        std::vector<gr_complex> y(500);
        std::vector<float> nv(500);
        for (int i = 0; i < 500; i++) {
            y[i] = c.map(static_cast<unsigned>(i * 37) % c.size()) + 0.3f * noise[i];
            nv[i] = 0.01f + 0.002f * static_cast<float>(i % 50);
        }
        std::vector<float> llr(500 * k);
        d.demap(y.data(), nv.data(), 500, llr.data());
        for (int i = 0; i < 500; i++)
            for (unsigned j = 0; j < k; j++) {
                const double ref = bruteforce(c, y[i], j).llr_num / nv[i];
                EXPECT_NEAR(llr[i * k + j], ref, 1e-3 * (1.0 + std::abs(ref)))
                    << "mod " << static_cast<int>(mod) << " sym " << i << " bit " << j;
            }
        // scalar noise variance overload gives the same values for equal variances
        std::vector<float> a(500 * k), b(500 * k);
        std::vector<float> same(500, 0.05f);
        d.demap(y.data(), same.data(), 500, a.data());
        d.demap(y.data(), 0.05f, 500, b.data());
        EXPECT_EQ(a, b);
    }
}

TEST(soft_demapper, far_outside_and_hard_decision_error_match_bruteforce)
{
    // symbols up to 3x beyond the outer points (every clamp of the closed form active) and
    // the summed squared distance to the nearest point, against a double-precision search
    for (auto mod : { modulation::QPSK, modulation::QAM16, modulation::QAM64, modulation::QAM256 }) {
        const constellation c(mod);
        const soft_demapper d(mod);
        const unsigned k = c.bits_per_symbol();
        const int n = 301; // not a multiple of 8: a SIMD path and its tail
        const auto noise = nrsar_test::gaussian_samples(n, 5);
        std::vector<gr_complex> y(n);
        for (int i = 0; i < n; i++)
            y[i] = 1.5f * noise[i];
        std::vector<float> nv(n, 0.02f), llr(n * k);
        double sq_err = -1.0;
        d.demap(y.data(), nv.data(), n, llr.data(), &sq_err);
        double ref_err = 0.0;
        for (int i = 0; i < n; i++) {
            for (unsigned j = 0; j < k; j++) {
                const double ref = bruteforce(c, y[i], j).llr_num / nv[i];
                EXPECT_NEAR(llr[i * k + j], ref, 1e-3 * (1.0 + std::abs(ref)))
                    << "mod " << static_cast<int>(mod) << " sym " << i << " bit " << j;
            }
            ref_err += bruteforce(c, y[i], 0).nearest;
        }
        EXPECT_NEAR(sq_err, ref_err, 1e-5 * (1.0 + ref_err)) << "mod " << static_cast<int>(mod);
    }
}

TEST(soft_demapper, hard_decision_of_llr_signs_is_the_mapper)
{
    const constellation c(modulation::QAM256);
    const soft_demapper d(modulation::QAM256);
    std::vector<float> llr(8 * 256);
    d.demap(c.points().data(), 1.0f, 256, llr.data());
    for (unsigned p = 0; p < 256; p++)
        for (unsigned j = 0; j < 8; j++)
            EXPECT_EQ(llr[p * 8 + j] < 0, ((p >> (7 - j)) & 1u) != 0);
}

TEST(soft_demapper, refuses_psk)
{
    EXPECT_THROW(soft_demapper(modulation::PSK8), std::invalid_argument);
    EXPECT_FALSE(soft_demapper::supported(modulation::PSK16));
}
