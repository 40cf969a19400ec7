/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// rx_time_aligner against integer arithmetic done in the test (times as integer counts of
// nanoseconds at a sample rate where a sample is a whole number of them).

#include <gnuradio/nrsar/kernel/rx_time_aligner.h>
#include <gtest/gtest.h>
#include <random>
#include <stdexcept>

using gr::nrsar::kernel::rx_time_aligner;

TEST(rx_time_aligner, stamp_before_start_skips_to_symbol_zero)
{
    // 30.72 Msps, L = 1280; TX at 1e6 + 0.5 s, RX stamped 1e6 + 0.25 s: 0.25 s = 7,680,000 samples.
    rx_time_aligner a(30.72e6, 1280, 1000000, 0.5);
    const auto r = a.align(1000000, 0.25, 0);
    EXPECT_EQ(r.skip, 7680000u);
    EXPECT_EQ(r.next_symbol, 0u);
    EXPECT_EQ(r.lost_symbols, 0);
    EXPECT_EQ(r.tx_start_offset, 7680000);
}

TEST(rx_time_aligner, stamp_across_a_second_boundary)
{
    // TX at 1e6 + 0.1 s, RX at 999999.9 s: 0.2 s = 6,144,000 samples.
    rx_time_aligner a(30.72e6, 1280, 1000000, 0.1);
    const auto r = a.align(999999, 0.9, 0);
    EXPECT_EQ(r.skip, 6144000u);
    EXPECT_EQ(r.next_symbol, 0u);
}

TEST(rx_time_aligner, late_stamp_starts_at_next_whole_symbol)
{
    rx_time_aligner a(1.0e6, 100, 5, 0.0); // 1 sample = 1 us
    // 250 samples after the start: symbol 2 is incomplete (200..299), next whole = 3 at 300.
    auto r = a.align(5, 250e-6, 0);
    EXPECT_EQ(r.tx_start_offset, -250);
    EXPECT_EQ(r.skip, 50u);
    EXPECT_EQ(r.next_symbol, 3u);
    EXPECT_EQ(r.lost_symbols, 3);
    // Exactly on a boundary: nothing to skip.
    r = a.align(5, 300e-6, 2);
    EXPECT_EQ(r.skip, 0u);
    EXPECT_EQ(r.next_symbol, 3u);
    EXPECT_EQ(r.lost_symbols, 1);
}

TEST(rx_time_aligner, random_stamps_match_integer_reference)
{
    // fs = 1e6, times on a 1 us grid: reference in int64 microseconds.
    std::mt19937_64 rng(7);
    const std::uint64_t len = 137;
    for (int i = 0; i < 2000; i++) {
        const std::int64_t t0_us = 1700000000LL * 1000000 + std::int64_t(rng() % 2000000000);
        const std::int64_t t_us = t0_us + std::int64_t(rng() % 4000000) - 2000000;
        rx_time_aligner a(1e6, len, std::uint64_t(t0_us / 1000000), double(t0_us % 1000000) * 1e-6);
        const auto r = a.align(std::uint64_t(t_us / 1000000), double(t_us % 1000000) * 1e-6, 7);
        const std::int64_t off = t0_us - t_us; // samples
        ASSERT_EQ(r.tx_start_offset, off);
        if (off >= 0) {
            EXPECT_EQ(r.skip, std::uint64_t(off));
            EXPECT_EQ(r.next_symbol, 0u);
        } else {
            // first whole symbol start at or after the stamp
            std::int64_t k = 0;
            while (k * std::int64_t(len) < -off)
                k++;
            EXPECT_EQ(r.next_symbol, std::uint64_t(k));
            EXPECT_EQ(std::int64_t(r.skip), k * std::int64_t(len) + off);
        }
        EXPECT_EQ(r.lost_symbols, std::int64_t(r.next_symbol) - 7);
    }
}

TEST(rx_time_aligner, split_and_fold)
{
    std::uint64_t full;
    double frac;
    rx_time_aligner::split_seconds(1e6 + 0.5, full, frac);
    EXPECT_EQ(full, 1000000u);
    EXPECT_EQ(frac, 0.5);
    rx_time_aligner a(1e6, 10, 3, 1.25); // fraction > 1 folded
    EXPECT_EQ(a.tx_start_full_s(), 4u);
    EXPECT_DOUBLE_EQ(a.tx_start_frac_s(), 0.25);
    EXPECT_THROW(rx_time_aligner(0.0, 10, 0, 0.0), std::invalid_argument);
    EXPECT_THROW(rx_time_aligner(1e6, 0, 0, 0.0), std::invalid_argument);
    EXPECT_THROW(rx_time_aligner::split_seconds(-1.0, full, frac), std::invalid_argument);
}
