/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::gaussian_noise: moments, circularity, Gaussian shape, determinism per seed.
// Bounds are 5 standard errors of each estimate for the sample count used.

#include <gnuradio/nrsar/kernel/gaussian_noise.h>
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <vector>

using gr::nrsar::kernel::gaussian_noise;
using cd = std::complex<double>;

namespace {

constexpr size_t n_block = 3333;
constexpr size_t n_blocks = 301; // ~1.0e6 samples in symbol-sized blocks

std::vector<gr_complex> draw(const gaussian_noise& g, float sigma)
{
    std::vector<gr_complex> z(n_block * n_blocks);
    for (size_t b = 0; b < n_blocks; b++)
        g.generate(b, sigma, z.data() + b * n_block, n_block);
    return z;
}

void check_statistics(const std::vector<gr_complex>& z, double sigma2)
{
    const double n = static_cast<double>(z.size());
    cd mean(0.0, 0.0), pseudo(0.0, 0.0);
    double power = 0.0, re2 = 0.0, re4 = 0.0, tail = 0.0;
    for (const auto& v : z) {
        const cd x(v);
        mean += x;
        pseudo += x * x;
        power += std::norm(x);
        re2 += x.real() * x.real();
        re4 += std::pow(x.real(), 4);
        tail += std::abs(x.real()) > 2.0 * std::sqrt(sigma2 / 2.0);
    }
    mean /= n;
    pseudo /= n;
    power /= n;
    re2 /= n;
    re4 /= n;
    tail /= n;
    // Mean: each component has variance sigma2/2.
    EXPECT_LT(std::abs(mean.real()), 5.0 * std::sqrt(sigma2 / 2.0 / n));
    EXPECT_LT(std::abs(mean.imag()), 5.0 * std::sqrt(sigma2 / 2.0 / n));
    // E|z|^2 = sigma2; |z|^2 is exponential, so its standard deviation is sigma2.
    EXPECT_NEAR(power / sigma2, 1.0, 5.0 / std::sqrt(n));
    // Circular: E{z^2} = 0, with standard error sigma2 / sqrt(n).
    EXPECT_LT(std::abs(pseudo) / sigma2, 5.0 / std::sqrt(n));
    // Real part Gaussian: kurtosis 3 (sd of the estimate ~ sqrt(96 / n)), P(|x| > 2 sd) = 0.0455.
    EXPECT_NEAR(re4 / (re2 * re2), 3.0, 5.0 * std::sqrt(96.0 / n));
    EXPECT_NEAR(tail, 0.0455003, 5.0 * std::sqrt(0.0455 * 0.9545 / n));
}

} // namespace

TEST(GaussianNoise, MomentsCircularityAndShape)
{
    gaussian_noise g(42);
    check_statistics(draw(g, 1.0f), 1.0);
}

TEST(GaussianNoise, SigmaScales)
{
    gaussian_noise g(7);
    check_statistics(draw(g, 0.25f), 0.0625);
}

TEST(GaussianNoise, GenericPathStatistics)
{
    gaussian_noise g(42, false);
    EXPECT_STREQ(g.implementation(), "generic");
    check_statistics(draw(g, 1.0f), 1.0);
}

TEST(GaussianNoise, SimdAndGenericPathsAgree)
{
    gaussian_noise fast(9), slow(9, false);
    std::vector<gr_complex> a(n_block), b(n_block);
    fast.generate(17, 1.0f, a.data(), n_block);
    slow.generate(17, 1.0f, b.data(), n_block);
    for (size_t i = 0; i < n_block; i++)
        ASSERT_LT(std::abs(a[i] - b[i]), 1e-5f) << i;
}

TEST(GaussianNoise, DeterministicPerSeedAndBlock)
{
    gaussian_noise g1(1234), g2(1234), g3(1235);
    std::vector<gr_complex> a(n_block), b(n_block), c(n_block), d(n_block);
    g1.generate(5, 1.0f, a.data(), n_block);
    g2.generate(5, 1.0f, b.data(), n_block);
    g3.generate(5, 1.0f, c.data(), n_block);
    g1.generate(6, 1.0f, d.data(), n_block);
    EXPECT_EQ(a, b);
    size_t same_seed = 0, same_block = 0;
    for (size_t i = 0; i < n_block; i++) {
        same_seed += a[i] == c[i];
        same_block += a[i] == d[i];
    }
    EXPECT_LT(same_seed, 3u);
    EXPECT_LT(same_block, 3u);
}

TEST(GaussianNoise, PrefixAndAddConsistent)
{
    // A shorter request is a prefix of the longer one (odd length exercises the tail),
    // and add() adds exactly the generated samples.
    gaussian_noise g(99);
    std::vector<gr_complex> full(n_block), part(101), acc(n_block, gr_complex(1.0f, -2.0f));
    g.generate(3, 0.5f, full.data(), n_block);
    g.generate(3, 0.5f, part.data(), part.size());
    for (size_t i = 0; i < part.size(); i++)
        EXPECT_EQ(part[i], full[i]) << i;
    g.add(3, 0.5f, acc.data(), n_block);
    for (size_t i = 0; i < n_block; i++)
        EXPECT_EQ(acc[i], full[i] + gr_complex(1.0f, -2.0f)) << i;
}

TEST(GaussianNoise, CrossLaneIndependence)
{
    // Neighbouring samples come from different lanes: lag-1 correlation ~ 0.
    gaussian_noise g(3);
    const auto z = draw(g, 1.0f);
    cd corr(0.0, 0.0);
    for (size_t i = 1; i < z.size(); i++)
        corr += cd(z[i]) * std::conj(cd(z[i - 1]));
    corr /= static_cast<double>(z.size() - 1);
    EXPECT_LT(std::abs(corr), 5.0 / std::sqrt(static_cast<double>(z.size())));
}
