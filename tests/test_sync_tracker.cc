/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// sync_tracker (ofdm_sync's gaps and lock check) against sample-by-sample bookkeeping done in
// the test and against the Schmidl & Cox metric computed directly from its definition.

#include <gnuradio/nrsar/kernel/sync_tracker.h>
#include <gtest/gtest.h>
#include <algorithm>
#include <complex>
#include <random>
#include <stdexcept>
#include <vector>

using gr::nrsar::kernel::sync_tracker;

namespace {
constexpr unsigned F = 64, CP = 8, SPS = 14;
constexpr std::uint64_t SYM = F + CP, L = SPS * SYM;
constexpr std::uint64_t DMRS = 2 * SYM + 1; // d0_hat of the slot: symbol 2, backoff 1
constexpr unsigned EARLY = 2;

std::vector<gr_complex> noise(std::size_t n, std::mt19937& rng)
{
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<gr_complex> x(n);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    return x;
}

// M(d) from its definition (sync_tracker.h, sc_acquirer).
double metric(const gr_complex* x, std::size_t d)
{
    std::complex<double> p = 0.0;
    double e = 0.0;
    for (std::size_t m = 0; m < F / 2; m++)
        p += std::conj(std::complex<double>(x[d + m])) * std::complex<double>(x[d + m + F / 2]);
    for (std::size_t m = 0; m < F; m++)
        e += std::norm(std::complex<double>(x[d + m]));
    return std::norm(p) / (0.25 * e * e);
}
} // namespace

TEST(sync_tracker, gap_plan_matches_sample_bookkeeping)
{
    sync_tracker t(F, CP, SPS, DMRS, EARLY);
    EXPECT_EQ(t.slot_length(), L);
    std::mt19937 rng(7);
    for (std::uint64_t lost : std::vector<std::uint64_t>{ 1, 5, 100, 10000, L - 1, L, L + 1, 3 * L }) {
        for (int trial = 0; trial < 200; trial++) {
            const std::uint64_t g = 3 * L + rng() % (2 * L);
            const auto p = t.plan_gap(g, lost);
            // Slots with a lost sample: those intersecting [g, g + lost).
            std::uint64_t first = ~0ull, last = 0;
            for (std::uint64_t s = g; s < g + lost; s++) {
                first = std::min(first, s / L);
                last = std::max(last, s / L);
            }
            EXPECT_EQ(p.first_slot, first);
            EXPECT_EQ(p.resume_slot, last + 1);
            // Output before the gap plus the pad ends on a symbol boundary, within the gap's symbol.
            EXPECT_EQ((g + p.pad) % SYM, 0u);
            EXPECT_LT(p.pad, SYM);
            // The samples after the gap up to the resumed slot are dropped.
            EXPECT_EQ(g + lost + p.drop, p.resume_slot * L);
            std::uint64_t cut = 0; // symbols with a sample in [g, resume)
            for (std::uint64_t s = 0; s < p.resume_slot * SPS; s++)
                cut += (s + 1) * SYM > g;
            EXPECT_EQ(p.skipped_symbols, cut);
        }
    }
    EXPECT_EQ(t.pad_to_symbol(5 * SYM), 0u);
    EXPECT_EQ(t.pad_to_symbol(5 * SYM + 3), SYM - 3);
}

TEST(sync_tracker, relock_finds_the_gap_modulo_a_slot)
{
    sync_tracker t(F, CP, SPS, DMRS, EARLY);
    const std::int64_t rep = 9 * std::int64_t(SYM); // a second DMRS symbol 9 symbols later
    t.set_repeats({ rep });
    for (std::int64_t gap = -std::int64_t(L / 2) + 1; gap <= std::int64_t(L / 2); gap += 7) {
        // slot 10's first DMRS arrives gap samples early (gap samples lost)
        const std::int64_t g = 10 * std::int64_t(L) + std::int64_t(DMRS) - gap;
        auto r = t.relock_at(g, 9 * L, 0);
        EXPECT_EQ(r.shift, gap) << gap;
        EXPECT_EQ(r.slot, 10u) << gap;
        // output already in slot 10: resume at slot 11, the shift unchanged
        r = t.relock_at(g, 10 * L + SYM, 0);
        EXPECT_EQ(r.shift, gap) << gap;
        EXPECT_EQ(r.slot, 11u) << gap;
        // the search found the slot's second DMRS symbol
        r = t.relock_at(g + rep, 9 * L, 1);
        EXPECT_EQ(r.shift, gap) << gap;
        EXPECT_EQ(r.slot, 10u) << gap;
    }
    EXPECT_THROW(t.relock_at(0, 0, 2), std::invalid_argument);
}

TEST(sync_tracker, found_dmrs_is_told_by_the_later_dmrs_symbols_in_the_buffer)
{
    sync_tracker t(F, CP, SPS, DMRS, EARLY);
    const std::int64_t r1 = 3 * SYM, r2 = 5 * SYM, s = 100, b0 = 40;
    t.set_repeats({ r1, r2 });
    std::mt19937 rng(11);
    // a DMRS symbol at p: its two halves equal half a cp into its CP (M = 1 there)
    const auto plant = [](std::vector<gr_complex>& x, std::int64_t p) {
        std::copy_n(x.begin() + p, F / 2, x.begin() + p + F / 2);
    };
    const auto at = [&](std::int64_t p) { return p + std::int64_t(CP / 2) - b0; };
    auto x = noise(8 * SYM, rng);
    plant(x, at(s + r1));
    plant(x, at(s + r2));
    EXPECT_EQ(t.found_dmrs(x.data(), b0, x.size(), s, 0.5), 0u); // the slot's first
    x = noise(8 * SYM, rng);
    plant(x, at(s + r2 - r1)); // found the second: the third follows r2 - r1 later
    EXPECT_EQ(t.found_dmrs(x.data(), b0, x.size(), s, 0.5), 1u);
    x = noise(8 * SYM, rng);
    EXPECT_EQ(t.found_dmrs(x.data(), b0, x.size(), s, 0.5), 2u); // the last: none follows
    // symbols beyond the buffer are no evidence against the first
    EXPECT_EQ(t.found_dmrs(x.data(), b0, std::size_t(at(s + r2 - r1)), s, 0.5), 0u);
}

TEST(sync_tracker, check_windows)
{
    sync_tracker t(F, CP, SPS, DMRS, EARLY);
    EXPECT_EQ(t.check_length(), 3 * CP + F);
    EXPECT_EQ(t.check_start(4), std::int64_t(4 * L + DMRS - CP));
    for (std::uint64_t g = 0; g < 5 * L; g += 13) {
        const auto k = t.first_checkable_slot(g);
        EXPECT_GE(t.check_start(k), std::int64_t(g));
        if (k > 0) {
            EXPECT_LT(t.check_start(k - 1), std::int64_t(g));
        }
    }
}

TEST(sync_tracker, measure_finds_the_plateau_and_its_metric)
{
    sync_tracker t(F, CP, SPS, DMRS, EARLY);
    std::mt19937 rng(3);
    for (int e = -int(CP); e <= int(CP); e++) {
        // window = [d0_hat - cp, ...): a half-periodic symbol with its CP at d0_hat + e
        auto x = noise(t.check_length() + F, rng);
        const auto half = noise(F / 2, rng);
        const std::size_t d0 = std::size_t(int(CP) + e);
        for (std::size_t m = 0; m < CP + F; m++)
            x[d0 + m] = half[(m + F - CP) % (F / 2)];
        const auto c = t.measure(x.data());
        EXPECT_EQ(c.offset, e);
        EXPECT_NEAR(c.mmax, 1.0, 1e-9);
        double direct = 0.0;
        for (std::size_t d = d0; d <= d0 + CP; d++)
            direct = std::max(direct, metric(x.data(), d));
        EXPECT_NEAR(c.mmax, direct, 1e-9);
        for (std::size_t d : { std::size_t(0), d0, d0 + CP / 2, d0 + CP + 1 })
            EXPECT_NEAR(t.metric_at(x.data() + d), metric(x.data(), d), 1e-9);
    }
    // noise only: M ~ Exp(mean 2/F) far below 1
    auto x = noise(t.check_length(), rng);
    const auto c = t.measure(x.data());
    EXPECT_LT(c.mmax, 0.5);
}

TEST(sync_tracker, lock_lost_after_consecutive_misses)
{
    sync_tracker t(F, CP, SPS, DMRS, EARLY, 2);
    const sync_tracker::check good{ 0.9, 1 }, weak{ 0.05, 0 };
    EXPECT_FALSE(t.score(weak, 0.1)); // the peak below the threshold: a miss
    EXPECT_EQ(t.misses(), 1u);
    EXPECT_FALSE(t.score(good, 0.1)); // a good slot in between clears it
    EXPECT_EQ(t.misses(), 0u);
    EXPECT_FALSE(t.score(weak, 0.1));
    EXPECT_TRUE(t.score(weak, 0.1)); // two in a row: the lock is lost
}

TEST(sync_tracker, timing_tests_read_the_mean_offset_of_three_slots)
{
    const std::int64_t early = EARLY, late = CP / 2;
    const auto at = [](std::int64_t offset) { return sync_tracker::check{ 0.9, offset }; };
    sync_tracker t(F, CP, SPS, DMRS, EARLY, 2);
    // after a new lock the first slot's offset is the mean: the limits themselves pass
    EXPECT_FALSE(t.score(at(-early), 0.1));
    EXPECT_EQ(t.misses(), 0u);
    t.clear_misses();
    EXPECT_FALSE(t.score(at(-early - 1), 0.1));
    EXPECT_EQ(t.misses(), 1u);
    t.clear_misses();
    EXPECT_FALSE(t.score(at(late + 1), 0.1));
    EXPECT_EQ(t.misses(), 1u);
    // one slot's plateau far early among good ones (noise) is not a miss: mean -EARLY
    t.clear_misses();
    t.score(at(0), 0.1);
    t.score(at(0), 0.1);
    EXPECT_FALSE(t.score(at(-3 * early), 0.1));
    EXPECT_EQ(t.misses(), 0u);
    // a gap moves every later slot: more than 3 EARLY is a miss at once, lost at the second
    t.clear_misses();
    t.score(at(0), 0.1);
    t.score(at(0), 0.1);
    EXPECT_FALSE(t.score(at(-3 * early - 3), 0.1)); // mean -EARLY - 1
    EXPECT_EQ(t.misses(), 1u);
    EXPECT_TRUE(t.score(at(-3 * early - 3), 0.1));
    // a weak slot's offset is not counted in the mean
    t.clear_misses();
    t.score(at(0), 0.1);
    t.score(sync_tracker::check{ 0.05, -100 }, 0.1);
    EXPECT_EQ(t.misses(), 1u);
    EXPECT_FALSE(t.score(at(-2 * early), 0.1)); // mean of 0 and -2 EARLY: -EARLY, passes
    EXPECT_EQ(t.misses(), 0u);
}

TEST(sync_tracker, parameter_errors)
{
    EXPECT_THROW(sync_tracker(63, CP, SPS, DMRS, EARLY), std::invalid_argument);
    EXPECT_THROW(sync_tracker(F, CP, 0, DMRS, EARLY), std::invalid_argument);
    EXPECT_THROW(sync_tracker(F, CP, SPS, L, EARLY), std::invalid_argument);
    EXPECT_THROW(sync_tracker(F, CP, SPS, DMRS, CP + 1), std::invalid_argument);
    EXPECT_THROW(sync_tracker(F, CP, SPS, DMRS, EARLY, 0), std::invalid_argument);
}
