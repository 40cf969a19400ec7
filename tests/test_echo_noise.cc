/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::echo_noise, the noise level of the three echo generators, against SPEC 3 / 8:
// sigma^2 = sum RCS / SNR_lin, SNR_lin = 10^(SNR_dB / 10); +inf turns the noise off; and
// the generator it hands out produces that power.

#include "test_util.h"
#include <gnuradio/nrsar/kernel/echo_noise.h>
#include <gnuradio/nrsar/params.h>
#include <gtest/gtest.h>
#include <cmath>
#include <vector>

using gr::nrsar::kernel::echo_noise;

TEST(echo_noise, variance_is_scene_power_over_linear_snr)
{
    echo_noise n(7);
    EXPECT_EQ(n.variance(), 0.0); // no noise until an SNR is set
    const double rcs = gr::nrsar::scene::preset("paper3").total_rcs(); // 3 unit targets
    ASSERT_EQ(rcs, 3.0);
    n.set_signal_power(rcs);
    for (double snr_db : { -10.0, 0.0, 13.0, 20.0 }) {
        n.set_snr_db(snr_db);
        const double want = rcs / std::pow(10.0, snr_db / 10.0);
        EXPECT_DOUBLE_EQ(n.variance(), want) << snr_db;
        // sigma in float: relative rounding 2^-24 of the root.
        EXPECT_NEAR(n.sigma(), std::sqrt(want), 1e-7 * std::sqrt(want)) << snr_db;
        EXPECT_EQ(n.snr_db(), snr_db);
    }
    EXPECT_DOUBLE_EQ(n.variance(), 0.03); // 20 dB: 3 / 100
    n.set_signal_power(1.5);              // a scene change keeps the SNR
    EXPECT_DOUBLE_EQ(n.variance(), 0.015);
    EXPECT_EQ(n.seed(), 7u);
}

TEST(echo_noise, infinite_snr_is_no_noise_and_bad_values_are_refused)
{
    echo_noise n(0);
    n.set_signal_power(2.0);
    n.set_snr_db(INFINITY);
    EXPECT_EQ(n.variance(), 0.0);
    EXPECT_EQ(n.sigma(), 0.0f);
    EXPECT_NE(nrsar_test::error_of([&] { n.set_snr_db(NAN); }).find("snr_db = nan"),
              std::string::npos);
    EXPECT_NE(nrsar_test::error_of([&] { n.set_snr_db(-INFINITY); }).find("snr_db = -inf"),
              std::string::npos);
    EXPECT_NE(nrsar_test::error_of([&] { n.set_signal_power(-1.0); }).find("= -1"),
              std::string::npos);
    EXPECT_EQ(n.variance(), 0.0); // unchanged by the refused values
}

TEST(echo_noise, generator_produces_the_variance)
{
    echo_noise n(42);
    n.set_signal_power(3.0);
    n.set_snr_db(10.0); // sigma^2 = 0.3
    const std::size_t len = 200000;
    std::vector<gr_complex> z(len);
    n.generator()->generate(5, n.sigma(), z.data(), len);
    double p = 0.0;
    for (const auto& v : z)
        p += std::norm(std::complex<double>(v.real(), v.imag()));
    p /= len;
    // |Z|^2 is exponential with mean sigma^2: standard error sigma^2 / sqrt(len) = 0.22 %;
    // 1 % is 4.5 standard errors.
    EXPECT_NEAR(p, 0.3, 0.01 * 0.3);
}
