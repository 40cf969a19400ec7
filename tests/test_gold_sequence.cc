/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::gold_sequence against a straightforward bit-by-bit TS 38.211 5.2.1 generator.

#include <gnuradio/nrsar/kernel/gold_sequence.h>
#include <gtest/gtest.h>
#include <cstdint>
#include <stdexcept>
#include <vector>

using gr::nrsar::kernel::gold_sequence;

namespace {
// c(n) for n = 0..len-1, one register value per array element, exactly as 38.211 writes it.
std::vector<std::uint8_t> reference_gold(std::uint32_t c_init, std::size_t len)
{
    const std::size_t nc = 1600;
    std::vector<std::uint8_t> x1(len + nc + 31, 0), x2(len + nc + 31, 0);
    x1[0] = 1;
    for (int i = 0; i < 31; i++)
        x2[i] = (c_init >> i) & 1u;
    for (std::size_t n = 0; n + 31 < x1.size(); n++) {
        x1[n + 31] = (x1[n + 3] + x1[n]) % 2;
        x2[n + 31] = (x2[n + 3] + x2[n + 2] + x2[n + 1] + x2[n]) % 2;
    }
    std::vector<std::uint8_t> c(len);
    for (std::size_t n = 0; n < len; n++)
        c[n] = (x1[n + nc] + x2[n + nc]) % 2;
    return c;
}
} // namespace

TEST(GoldSequence, WordsMatchBitByBit)
{
    for (std::uint32_t c_init : { 0u, 1u, 0x12345u, 511u, 0x7fffffffu }) {
        const std::size_t len = 32 * 400;
        const auto ref = reference_gold(c_init, len);
        gold_sequence g(c_init);
        for (std::size_t w = 0; w < len / 32; w++) {
            const std::uint32_t word = g.next_word();
            for (unsigned b = 0; b < 32; b++)
                ASSERT_EQ((word >> b) & 1u, ref[32 * w + b]) << "c_init " << c_init << " n " << 32 * w + b;
        }
        EXPECT_EQ(g.position(), len);
    }
}

TEST(GoldSequence, PackedIsMsbFirstAndContinuousAcrossOddCalls)
{
    const std::uint32_t c_init = 0x2a5a5u;
    const auto ref = reference_gold(c_init, 8 * 1000);
    gold_sequence g(c_init);
    std::vector<std::uint8_t> bytes;
    // odd-sized calls exercise the partial-word buffer
    for (std::size_t chunk : { 1u, 3u, 7u, 13u, 333u, 2u, 641u }) {
        std::vector<std::uint8_t> part(chunk);
        g.generate_packed(part.data(), chunk);
        bytes.insert(bytes.end(), part.begin(), part.end());
    }
    for (std::size_t i = 0; i < bytes.size(); i++)
        for (unsigned b = 0; b < 8; b++)
            ASSERT_EQ((bytes[i] >> (7 - b)) & 1u, ref[8 * i + b]) << "bit " << 8 * i + b;
}

TEST(GoldSequence, UnpackedAndMixedCalls)
{
    const std::uint32_t c_init = 77u;
    const auto ref = reference_gold(c_init, 4000);
    gold_sequence g(c_init);
    std::vector<std::uint8_t> bits(5);
    g.generate_unpacked(bits.data(), 5);
    std::size_t n = 0;
    for (auto b : bits)
        EXPECT_EQ(b, ref[n++]);
    const std::uint32_t w = g.next_word();
    for (unsigned b = 0; b < 32; b++)
        EXPECT_EQ((w >> b) & 1u, ref[n++]);
    bits.resize(1000);
    g.generate_unpacked(bits.data(), bits.size());
    for (auto b : bits)
        ASSERT_EQ(b, ref[n++]);
    g.reset(c_init);
    EXPECT_EQ(g.next_bits(7), (ref[0] | ref[1] << 1 | ref[2] << 2 | ref[3] << 3 | ref[4] << 4 |
                               ref[5] << 5 | ref[6] << 6));
}

TEST(GoldSequence, RejectsWideCInit)
{
    EXPECT_THROW(gold_sequence(0x80000000u), std::invalid_argument);
}

TEST(GoldSequence, DiscardEqualsTheSkippedStream)
{
    // Jumps inside the 32-bit buffer, across it, off the word grid, and far (1e6).
    for (std::uint32_t c_init : { 0u, 0x12345u, 0x7fffffffu }) {
        const std::size_t len = 256;
        const auto ref = reference_gold(c_init, 1000000 + 64 + len);
        for (std::uint64_t lead : { 0u, 5u, 32u }) {
            for (std::uint64_t n : { 0u, 3u, 27u, 33u, 1000u, 1000000u }) {
                gold_sequence g(c_init);
                for (std::uint64_t i = 0; i < lead; i++)
                    g.next_bits(1);
                g.discard(n);
                ASSERT_EQ(g.position(), lead + n);
                for (std::size_t i = 0; i < len; i++)
                    ASSERT_EQ(g.next_bits(1), ref[lead + n + i])
                        << "c_init " << c_init << " lead " << lead << " n " << n << " i " << i;
            }
        }
    }
}

TEST(GoldSequence, DiscardByWholePeriodsReturnsToTheStart)
{
    // Both registers are m-sequences of period 2^31 - 1 (primitive polynomials), so a jump
    // of k periods plus t lands on c(t): checks jumps far beyond any stream we could step.
    const std::uint64_t period = (std::uint64_t{ 1 } << 31) - 1;
    const auto ref = reference_gold(0x5a5a5u, 512);
    for (std::uint64_t k : { 1u, 3u, 1000u }) {
        gold_sequence g(0x5a5a5u);
        g.discard(k * period + 100);
        for (std::size_t i = 100; i < 512; i++)
            ASSERT_EQ(g.next_bits(1), ref[i]) << "k " << k << " i " << i;
    }
}
