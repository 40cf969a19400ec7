/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::constellation against the TS 38.211 5.1 formulas of SPEC section 2, written out
// here in double precision one modulation at a time.

#include <gnuradio/nrsar/kernel/constellation.h>
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <random>
#include <vector>

using gr::nrsar::modulation;
using gr::nrsar::kernel::constellation;
using cd = std::complex<double>;

namespace {
// b[j] of index i with b(0) the most significant of k bits
std::vector<int> bits_of(unsigned i, unsigned k)
{
    std::vector<int> b(k);
    for (unsigned j = 0; j < k; j++)
        b[j] = (i >> (k - 1 - j)) & 1;
    return b;
}

cd spec_formula(modulation mod, unsigned i)
{
    auto s = [](int b) { return 1.0 - 2.0 * b; };
    switch (mod) {
    case modulation::QPSK: {
        auto b = bits_of(i, 2);
        return cd(s(b[0]), s(b[1])) / std::sqrt(2.0);
    }
    case modulation::QAM16: {
        auto b = bits_of(i, 4);
        return cd(s(b[0]) * (2 - s(b[2])), s(b[1]) * (2 - s(b[3]))) / std::sqrt(10.0);
    }
    case modulation::QAM64: {
        auto b = bits_of(i, 6);
        return cd(s(b[0]) * (4 - s(b[2]) * (2 - s(b[4]))),
                  s(b[1]) * (4 - s(b[3]) * (2 - s(b[5])))) /
               std::sqrt(42.0);
    }
    case modulation::QAM256: {
        auto b = bits_of(i, 8);
        return cd(s(b[0]) * (8 - s(b[2]) * (4 - s(b[4]) * (2 - s(b[6])))),
                  s(b[1]) * (8 - s(b[3]) * (4 - s(b[5]) * (2 - s(b[7]))))) /
               std::sqrt(170.0);
    }
    default:
        return cd(0, 0);
    }
}

double min_distance(const std::vector<gr_complex>& pts)
{
    double dmin = 1e9;
    for (unsigned i = 0; i < pts.size(); i++)
        for (unsigned j = i + 1; j < pts.size(); j++)
            dmin = std::min(dmin, double(std::abs(pts[i] - pts[j])));
    return dmin;
}

const modulation all_mods[] = { modulation::QPSK,   modulation::QAM16, modulation::QAM64,
                                modulation::QAM256, modulation::PSK8,  modulation::PSK16 };
} // namespace

TEST(Constellation, QamTablesMatchSpecFormulas)
{
    for (auto mod : { modulation::QPSK, modulation::QAM16, modulation::QAM64, modulation::QAM256 }) {
        constellation c(mod);
        ASSERT_EQ(c.size(), 1u << c.bits_per_symbol());
        for (unsigned i = 0; i < c.size(); i++) {
            const cd ref = spec_formula(mod, i);
            EXPECT_NEAR(c.map(i).real(), ref.real(), 1e-6) << "mod " << int(mod) << " i " << i;
            EXPECT_NEAR(c.map(i).imag(), ref.imag(), 1e-6) << "mod " << int(mod) << " i " << i;
        }
    }
}

TEST(Constellation, PskIsGrayCodedUnitModulus)
{
    for (auto mod : { modulation::PSK8, modulation::PSK16 }) {
        constellation c(mod);
        const unsigned m = c.size();
        for (unsigned point = 0; point < m; point++) {
            const unsigned gray = point ^ (point >> 1);
            const cd ref = std::polar(1.0, 2.0 * M_PI * point / m);
            EXPECT_NEAR(c.map(gray).real(), ref.real(), 1e-6);
            EXPECT_NEAR(c.map(gray).imag(), ref.imag(), 1e-6);
            EXPECT_NEAR(std::abs(c.map(point)), 1.0, 1e-6);
        }
    }
}

TEST(Constellation, UnitAveragePower)
{
    for (auto mod : all_mods) {
        constellation c(mod);
        double p = 0;
        for (auto x : c.points())
            p += std::norm(cd(x.real(), x.imag()));
        EXPECT_NEAR(p / c.size(), 1.0, 1e-6) << "mod " << int(mod);
    }
}

TEST(Constellation, GrayNearestNeighboursDifferInOneBit)
{
    for (auto mod : all_mods) {
        constellation c(mod);
        const auto& pts = c.points();
        const double dmin = min_distance(pts);
        unsigned pairs = 0;
        for (unsigned i = 0; i < pts.size(); i++)
            for (unsigned j = i + 1; j < pts.size(); j++)
                if (std::abs(pts[i] - pts[j]) < dmin * 1.001) {
                    pairs++;
                    EXPECT_EQ(__builtin_popcount(i ^ j), 1) << "mod " << int(mod) << " " << i << "," << j;
                }
        EXPECT_GT(pairs, 0u);
    }
}

TEST(Constellation, MapPackedMatchesMapBitsAtAnyOffset)
{
    std::mt19937 rng(7);
    std::vector<std::uint8_t> bytes(200);
    for (auto& b : bytes)
        b = static_cast<std::uint8_t>(rng());
    for (auto mod : all_mods) {
        constellation c(mod);
        const unsigned k = c.bits_per_symbol();
        for (std::size_t first : { 0u, 3u, 8u, 13u }) {
            const std::size_t nsym = (8 * bytes.size() - first) / k - 1;
            std::vector<gr_complex> out(nsym);
            EXPECT_EQ(c.map_packed(bytes.data(), first, nsym, out.data()), first + nsym * k);
            for (std::size_t s = 0; s < nsym; s++) {
                std::vector<std::uint8_t> bits(k);
                for (unsigned j = 0; j < k; j++) {
                    const std::size_t pos = first + s * k + j;
                    bits[j] = (bytes[pos / 8] >> (7 - pos % 8)) & 1u;
                }
                ASSERT_EQ(out[s], c.map_bits(bits.data())) << "mod " << int(mod) << " sym " << s;
            }
        }
    }
}

TEST(Constellation, DemapInvertsMapWithNoise)
{
    std::mt19937 rng(11);
    std::normal_distribution<float> noise(0.0f, 1.0f);
    for (auto mod : all_mods) {
        constellation c(mod);
        const auto& pts = c.points();
        const double dmin = min_distance(pts);
        const float sigma = static_cast<float>(dmin / 10.0);
        for (unsigned i = 0; i < c.size(); i++) {
            EXPECT_EQ(c.demap(c.map(i)), i);
            const gr_complex x = c.map(i) + sigma * gr_complex(noise(rng), noise(rng));
            EXPECT_EQ(c.demap(x), i) << "mod " << int(mod);
        }
        // anywhere in the plane (also far outside): the nearest point, by brute force
        for (int t = 0; t < 100; t++) {
            const gr_complex x(3.0f * noise(rng), 3.0f * noise(rng));
            unsigned best = 0;
            for (unsigned i = 1; i < c.size(); i++)
                if (std::abs(x - pts[i]) < std::abs(x - pts[best]))
                    best = i;
            EXPECT_EQ(c.demap(x), best);
        }
    }
}
