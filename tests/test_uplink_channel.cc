/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::uplink_channel against the channel's formula evaluated here in double:
// y[n] = e^{j 2 pi cfo n} sum_l h[l] x[n - l] + sigma z[n].

#include <gnuradio/nrsar/kernel/uplink_channel.h>
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <vector>

using namespace gr::nrsar;
using cd = std::complex<double>;

namespace {

std::vector<gr_complex> random_signal(std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<gr_complex> x(n);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    return x;
}

uplink_channel_config nrsar_isac_channel(double sigma)
{
    uplink_channel_config cfg; // nrsar-isac's default taps and 9 kHz at 122.88 Msps
    cfg.taps = { { 1.0f, 0.0f }, {}, {}, { 0.3f, 0.2f }, {}, {}, {}, {}, { 0.0f, -0.1f } };
    cfg.cfo = 9000.0 / 122.88e6;
    cfg.noise_voltage = sigma;
    cfg.seed = 3;
    return cfg;
}

// y of the kernel fed x in calls of the given sizes (cycled)
std::vector<gr_complex> run(const uplink_channel_config& cfg,
                            const std::vector<gr_complex>& x,
                            const std::vector<std::size_t>& calls)
{
    kernel::uplink_channel ch(cfg);
    std::vector<gr_complex> y(x.size());
    for (std::size_t i = 0, c = 0; i < x.size(); c++) {
        const std::size_t n = std::min(calls[c % calls.size()], x.size() - i);
        ch.process(x.data() + i, y.data() + i, n);
        i += n;
    }
    EXPECT_EQ(ch.samples(), x.size());
    return y;
}

} // namespace

TEST(uplink_channel, matches_the_formula_in_double)
{
    const auto cfg = nrsar_isac_channel(0.0);
    // long enough that the phase n cfo passes many rotator blocks and whole turns
    const std::size_t n = 300000;
    const auto x = random_signal(n, 1);
    const auto y = run(cfg, x, { 100000 });
    double err = 0.0, ref_power = 0.0;
    for (std::size_t k = 0; k < n; k++) {
        cd acc = 0.0;
        for (std::size_t l = 0; l < cfg.taps.size() && l <= k; l++)
            acc += cd(cfg.taps[l]) * cd(x[k - l]);
        const double turns = cfg.cfo * double(k);
        const cd ref = acc * std::polar(1.0, 2.0 * M_PI * (turns - std::floor(turns)));
        err = std::max(err, std::abs(cd(y[k]) - ref));
        ref_power += std::norm(ref);
    }
    const double rms = std::sqrt(ref_power / n);
    // float products of O(1) values: a few float ulps of the rms
    EXPECT_LT(err / rms, 1e-5) << "worst error " << err << " rms " << rms;
}

TEST(uplink_channel, output_does_not_depend_on_the_call_sizes)
{
    const auto cfg = nrsar_isac_channel(0.05);
    const auto x = random_signal(70001, 2);
    const auto whole = run(cfg, x, { 70001 });
    for (const auto& calls : std::vector<std::vector<std::size_t>>{ { 1 }, { 3, 4095, 7 },
                                                                    { 8192, 1 } }) {
        const auto cut = run(cfg, x, calls);
        for (std::size_t k = 0; k < x.size(); k++)
            ASSERT_EQ(cut[k], whole[k]) << "sample " << k << " with calls of " << calls[0];
    }
}

TEST(uplink_channel, noise_has_the_given_power_and_is_white)
{
    const double sigma = 0.5;
    const std::size_t n = 400000;
    const auto y = run(nrsar_isac_channel(sigma), std::vector<gr_complex>(n), { 65536 });
    double p = 0.0;
    cd r1 = 0.0;
    for (std::size_t k = 0; k < n; k++) {
        p += std::norm(cd(y[k]));
        if (k)
            r1 += cd(y[k]) * std::conj(cd(y[k - 1]));
    }
    p /= n;
    // the estimate of sigma^2 from n samples has a relative standard deviation 1/sqrt(n):
    // 0.16 %; 5 standard deviations, and the lag-1 correlation within 5 / sqrt(n)
    EXPECT_NEAR(p / (sigma * sigma), 1.0, 5.0 / std::sqrt(double(n)));
    EXPECT_LT(std::abs(r1) / (n * sigma * sigma), 5.0 / std::sqrt(double(n)));
}

TEST(uplink_channel, refuses_bad_parameters)
{
    auto cfg = nrsar_isac_channel(0.0);
    cfg.cfo = 0.5;
    EXPECT_THROW(kernel::uplink_channel{ cfg }, std::invalid_argument);
    cfg = nrsar_isac_channel(-1.0);
    EXPECT_THROW(kernel::uplink_channel{ cfg }, std::invalid_argument);
    cfg = nrsar_isac_channel(0.0);
    cfg.taps.clear();
    EXPECT_THROW(kernel::uplink_channel{ cfg }, std::invalid_argument);
    cfg.taps = { { NAN, 0.0f } };
    EXPECT_THROW(kernel::uplink_channel{ cfg }, std::invalid_argument);
}
