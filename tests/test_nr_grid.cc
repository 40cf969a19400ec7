/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::nr_grid: SRS comb positions, periodicity, zeros, data order; the ZC pilot vs
// TS 38.211 5.2.2 evaluated here in double precision.

#include <gnuradio/nrsar/kernel/low_papr_sequence.h>
#include <gnuradio/nrsar/kernel/nr_grid.h>
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

using namespace gr::nrsar;
using gr::nrsar::kernel::nr_grid;

namespace {
std::vector<std::uint8_t> random_bytes(std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::vector<std::uint8_t> b(n);
    for (auto& x : b)
        x = static_cast<std::uint8_t>(rng());
    return b;
}
srs_config make_srs(unsigned start, unsigned num_rb, unsigned comb, unsigned offset,
                    unsigned period, unsigned symbol)
{
    srs_config srs;
    srs.start_subcarrier = start;
    srs.num_rb = num_rb;
    srs.comb = comb;
    srs.comb_offset = offset;
    srs.period_slots = period;
    srs.symbol_in_slot = symbol;
    return srs;
}
} // namespace

TEST(NrGrid, PaperSrsCombPositions)
{
    nr_grid g(numerology::preset("paper"), modulation::QAM256, tx_mode::SRS, srs_config());
    const auto& sc = g.srs_subcarriers();
    ASSERT_EQ(sc.size(), 72u); // 288 subcarriers, comb 4
    for (std::size_t i = 0; i < sc.size(); i++)
        EXPECT_EQ(sc[i], 1667u + 4u * i);
    EXPECT_LE(sc.back(), 1954u);
}

TEST(NrGrid, SrsSymbolsPeriodicity)
{
    const srs_config srs = make_srs(10, 4, 4, 0, 3, 5);
    nr_grid g(numerology::preset("small"), modulation::QPSK, tx_mode::SRS, srs);
    for (std::uint64_t m = 0; m < 14 * 30; m++) {
        const bool expect = (m % 14 == 5) && ((m / 14) % 3 == 0);
        EXPECT_EQ(g.is_srs_symbol(m), expect) << m;
        EXPECT_EQ(g.data_res(m), 0u);
    }
}

TEST(NrGrid, SrsModeZerosElsewhere)
{
    const srs_config srs = make_srs(7, 2, 2, 1, 1, 0);
    nr_grid g(numerology::preset("tiny"), modulation::QAM16, tx_mode::SRS, srs);
    std::vector<gr_complex> col(64, gr_complex(9, 9));
    EXPECT_EQ(g.fill(0, nullptr, 0, col.data()), 0u);
    std::set<unsigned> pilots;
    for (unsigned k = 1; k < 24; k += 2)
        pilots.insert(7 + k);
    std::size_t i = 0;
    for (unsigned n = 0; n < 64; n++) {
        if (pilots.count(n)) {
            EXPECT_NEAR(std::abs(col[n]), 1.0f, 1e-6f);
            EXPECT_EQ(col[n], g.srs_sequence()[i++]);
        } else {
            EXPECT_EQ(col[n], gr_complex(0, 0)) << n;
        }
    }
    g.fill(1, nullptr, 0, col.data());
    for (auto x : col)
        EXPECT_EQ(x, gr_complex(0, 0));
}

TEST(NrGrid, DataSrsCarriesDataInOrderAroundPilots)
{
    const srs_config srs = make_srs(5, 3, 4, 2, 2, 13);
    const auto num = numerology::preset("tiny");
    nr_grid g(num, modulation::QAM64, tx_mode::DATA_SRS, srs);
    const auto bytes = random_bytes(200, 3);
    const std::uint64_t m = 13; // slot 0, symbol 13: SRS
    ASSERT_TRUE(g.is_srs_symbol(m));
    ASSERT_FALSE(g.is_srs_symbol(13 + 14));
    ASSERT_EQ(g.data_res(m), 64u - 9u);
    std::vector<gr_complex> col(64);
    const std::size_t end = g.fill(m, bytes.data(), 3, col.data());
    EXPECT_EQ(end, 3u + 6u * 55u);
    std::vector<gr_complex> data(55);
    g.mapper().map_packed(bytes.data(), 3, 55, data.data());
    std::size_t d = 0, p = 0;
    for (unsigned n = 0; n < 64; n++) {
        const bool pilot = n >= 5 && n < 5 + 36 && (n - 5) % 4 == 2;
        if (pilot)
            EXPECT_EQ(col[n], g.srs_sequence()[p++]) << n;
        else
            EXPECT_EQ(col[n], data[d++]) << n;
    }
    EXPECT_EQ(p, 9u);
    // a non-SRS symbol is all data
    EXPECT_EQ(g.fill(14, bytes.data(), 0, col.data()), 6u * 64u);
}

TEST(NrGrid, DataBitsBeforeIsTheSumOfDataBits)
{
    const auto num = numerology::preset("tiny");
    const auto dmrs = dmrs_config::preset("pusch2");
    const srs_config srs = make_srs(5, 3, 4, 2, 3, 13);
    for (tx_mode mode : { tx_mode::DATA, tx_mode::DATA_SRS, tx_mode::SRS }) {
        nr_grid g(num, modulation::QAM64, mode, srs, dmrs);
        std::uint64_t sum = 0;
        for (std::uint64_t s = 0; s <= 1000003; s++) {
            if (s < 200 || s % 99991 == 0 || s == 1000003) {
                ASSERT_EQ(g.data_bits_before(s), sum) << "mode " << int(mode) << " s " << s;
            }
            sum += g.data_bits(s);
        }
    }
}

TEST(NrGrid, LowPaprSequenceMatchesZcFormula)
{
    for (unsigned len : { 72u, 36u, 144u, 50u }) {
        for (unsigned u : { 0u, 5u, 29u }) {
            for (unsigned v : { 0u, 1u }) {
                const auto r = kernel::low_papr_sequence(len, u, v);
                unsigned nzc = len - 1;
                auto is_prime = [](unsigned x) {
                    for (unsigned d = 2; d * d <= x; d++)
                        if (x % d == 0)
                            return false;
                    return x >= 2;
                };
                while (!is_prime(nzc))
                    nzc--;
                const double qbar = nzc * (u + 1) / 31.0;
                const double q = std::floor(qbar + 0.5) + v * std::pow(-1.0, std::floor(2 * qbar));
                for (unsigned n = 0; n < len; n++) {
                    const double mm = n % nzc;
                    const std::complex<double> ref = std::polar(1.0, -M_PI * q * mm * (mm + 1) / nzc);
                    ASSERT_NEAR(r[n].real(), ref.real(), 2e-5) << len << " " << u << " " << v << " " << n;
                    ASSERT_NEAR(r[n].imag(), ref.imag(), 2e-5);
                }
            }
        }
    }
    EXPECT_EQ(kernel::largest_prime_below(72), 71u);
    EXPECT_EQ(kernel::largest_prime_below(2), 0u);
}

TEST(NrGrid, RejectsBadConfig)
{
    const auto num = numerology::preset("tiny");
    srs_config srs; // start 1667 does not fit 64 subcarriers
    EXPECT_THROW(nr_grid(num, modulation::QPSK, tx_mode::SRS, srs), std::invalid_argument);
    EXPECT_NO_THROW(nr_grid(num, modulation::QPSK, tx_mode::DATA, srs)); // DATA ignores srs
    srs.start_subcarrier = 0;
    srs.num_rb = 1;
    srs.comb = 16;
    srs.comb_offset = 13; // beyond the 12-subcarrier band
    EXPECT_THROW(nr_grid(num, modulation::QPSK, tx_mode::DATA_SRS, srs), std::invalid_argument);
}
