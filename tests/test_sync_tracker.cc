/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// sync_tracker (ofdm_sync's gaps and lock check) against sample-by-sample bookkeeping done in
// the test and against the Schmidl & Cox metric computed directly from its definition;
// dmrs_matcher against OFDM symbols of the 38.211 DMRS made here and its noise model.

#include <gnuradio/nrsar/kernel/dmrs.h>
#include <gnuradio/nrsar/kernel/sync_tracker.h>
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <vector>

using gr::nrsar::kernel::dmrs_matcher;
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

TEST(sync_tracker, relock_counts_whole_slots_by_the_slot_number)
{
    sync_tracker t(F, CP, SPS, DMRS, EARLY);
    for (std::uint64_t m = 0; m < 20; m++) {
        for (std::int64_t gap = -std::int64_t(L / 2) + 1; gap <= std::int64_t(L / 2); gap += 97) {
            // slot 10 + m's first DMRS arrives gap + m L early; its DMRS names slot (10 + m) % 20
            const std::int64_t g = 10 * std::int64_t(L) + std::int64_t(DMRS) - gap;
            const auto r = t.relock_at(g, 9 * L, 0, int((10 + m) % 20), 20);
            EXPECT_EQ(r.shift, gap + std::int64_t(m * L)) << m << " " << gap;
            EXPECT_EQ(r.slot, 10 + m) << m << " " << gap;
            EXPECT_EQ(r.whole_slots, m);
        }
    }
    EXPECT_THROW(t.relock_at(0, 0, 0, 20, 20), std::invalid_argument);
}

TEST(sync_tracker, check_windows)
{
    sync_tracker t(F, CP, SPS, DMRS, EARLY);
    EXPECT_EQ(t.check_length(), F);
    EXPECT_EQ(t.check_start(4), std::int64_t(4 * L + DMRS + CP / 2));
    for (std::uint64_t g = 0; g < 5 * L; g += 13) {
        const auto k = t.first_checkable_slot(g);
        EXPECT_GE(t.check_start(k), std::int64_t(g));
        if (k > 0) {
            EXPECT_LT(t.check_start(k - 1), std::int64_t(g));
        }
    }
    std::mt19937 rng(1);
    const auto x = noise(2 * F, rng);
    for (std::size_t d : { std::size_t(0), std::size_t(3), std::size_t(F - 1) })
        EXPECT_NEAR(t.metric_at(x.data() + d), metric(x.data(), d), 1e-9);
}

TEST(sync_tracker, lock_lost_after_consecutive_misses)
{
    sync_tracker t(F, CP, SPS, DMRS, EARLY, 2);
    const dmrs_matcher::match good{ 0.9, 1.0 }, weak{ 0.05, 0.0 };
    EXPECT_FALSE(t.score(weak, 0.1)); // rho below the threshold: a miss
    EXPECT_EQ(t.misses(), 1u);
    EXPECT_FALSE(t.score(good, 0.1)); // a good slot in between clears it
    EXPECT_EQ(t.misses(), 0u);
    EXPECT_FALSE(t.score(weak, 0.1));
    EXPECT_TRUE(t.score(weak, 0.1)); // two in a row: the lock is lost
    // the timing limits: max_early early, cp / 2 late
    const auto at = [](double offset) { return dmrs_matcher::match{ 0.9, offset }; };
    for (double e : { -double(EARLY), 0.0, double(CP / 2) }) {
        t.clear_misses();
        EXPECT_FALSE(t.score(at(e), 0.1));
        EXPECT_EQ(t.misses(), 0u) << e;
    }
    for (double e : { -double(EARLY) - 0.5, double(CP / 2) + 0.5 }) {
        t.clear_misses();
        EXPECT_FALSE(t.score(at(e), 0.1));
        EXPECT_EQ(t.misses(), 1u) << e;
    }
}

namespace {
// One OFDM symbol (cp + F samples) of the 38.211 DMRS of a slot and symbol, unit power per RE.
std::vector<gr_complex> dmrs_symbol(const gr::nrsar::numerology& num, unsigned slot, unsigned l)
{
    const unsigned n = num.num_subcarriers;
    const auto r = gr::nrsar::kernel::dmrs_values(0, slot, l, gr::nrsar::kernel::dmrs_count(n));
    std::vector<gr_complex> grid(n, 0.0f), x(num.cp_samples + num.fft_size);
    for (std::size_t i = 0; i < r.size(); i++)
        grid[2 * i] = r[i];
    gr::nrsar::kernel::ofdm_modulator mod(n, num.fft_size, num.cp_samples, num.dc_subcarrier());
    mod.execute(grid.data(), x.data());
    return x;
}
} // namespace

TEST(dmrs_matcher, finds_the_slot_and_the_timing_noise_free)
{
    const auto num = gr::nrsar::numerology::preset("sdr20");
    const auto dmrs = gr::nrsar::dmrs_config::preset("pusch2");
    dmrs_matcher m(num, dmrs);
    const unsigned cp = num.cp_samples, nd = (num.num_subcarriers + 1) / 2;
    for (unsigned slot : { 0u, 7u, 19u }) {
        for (unsigned k = 0; k < 2; k++) {
            const auto x = dmrs_symbol(num, slot, dmrs.symbols[k]);
            for (int e : { -int(cp) / 2, -17, 0, 5, int(cp) / 2 - 1 }) {
                // the symbol starts e samples after the expected start: the window begins
                // cp/2 - e samples into it, inside the cyclic symbol
                const gr_complex* w = x.data() + (int(cp) / 2 - e);
                dmrs_matcher::match best;
                EXPECT_EQ(m.identify(w, k, best), slot) << slot << " " << e;
                EXPECT_NEAR(best.rho, double(nd - 1) / nd, 1e-5); // |Z| equal: (n - 1) / n
                EXPECT_NEAR(best.offset, e, 1e-3);
                const auto other = m.test(w, slot + 1, k); // another slot's sequence
                EXPECT_LT(other.rho, m.threshold());
            }
        }
    }
}

TEST(dmrs_matcher, noise_model_and_threshold)
{
    const auto num = gr::nrsar::numerology::preset("sdr20");
    dmrs_matcher m(num, gr::nrsar::dmrs_config::preset("pusch2"));
    const double n = (num.num_subcarriers + 1) / 2;
    // P(rho > t) = exp(-t^2 n^2 / (n - 1)) = 1e-9 at the threshold
    EXPECT_NEAR(m.threshold(), std::sqrt(std::log(1e9) * (n - 1)) / n, 1e-12);
    // noise alone: the fraction above the t of P = 0.1 (binomial, 4 sigma)
    const double t = std::sqrt(std::log(10.0) * (n - 1)) / n;
    std::mt19937 rng(5);
    const int trials = 4000;
    int above = 0;
    for (int i = 0; i < trials; i++) {
        const auto x = noise(num.fft_size, rng);
        above += m.test(x.data(), unsigned(i) % 20, 0).rho > t;
    }
    EXPECT_NEAR(double(above) / trials, 0.1, 4.0 * std::sqrt(0.1 * 0.9 / trials));
}

TEST(dmrs_matcher, timing_scatter_at_3_db)
{
    // per-RE SNR s = 2, flat channel: rho -> s / (1 + s). With Z_i = e^(j theta i) (1 + u_i),
    // u_i ~ CN(0, v = 1/s), the first-order noise of Im(C e^(-j theta)) telescopes to
    // Im(u_{n-1}) - Im(u_0): the angle's variance is ((n - 1) v^2 / 2 + v) / (n - 1)^2, the
    // offset's std F / (4 pi) times its root.
    const auto num = gr::nrsar::numerology::preset("sdr20");
    dmrs_matcher m(num, gr::nrsar::dmrs_config::preset("pusch2"));
    const double n = (num.num_subcarriers + 1) / 2, v = 0.5;
    const auto x = dmrs_symbol(num, 4, 2);
    // per-sample noise: per-RE variance v on REs of unit power (unitary modulator)
    std::mt19937 rng(9);
    std::normal_distribution<float> g(0.0f, float(std::sqrt(v / 2.0)));
    const int trials = 400;
    double rho = 0.0, e2 = 0.0;
    for (int i = 0; i < trials; i++) {
        const auto w0 = x.begin() + num.cp_samples / 2;
        std::vector<gr_complex> w(w0, w0 + num.fft_size);
        for (auto& s : w)
            s += gr_complex(g(rng), g(rng));
        const auto r = m.test(w.data(), 4, 0);
        rho += r.rho / trials;
        e2 += r.offset * r.offset / trials;
    }
    const double sd =
        std::sqrt((n - 1) * v * v / 2 + v) / (n - 1) * num.fft_size / (4 * M_PI);
    EXPECT_NEAR(rho, 2.0 / 3.0, 0.02);
    EXPECT_NEAR(std::sqrt(e2), sd, 0.15 * sd); // 1.66 samples
}

namespace {
// sdr20 slots [k0, k0 + slots) whose first DMRS symbol (pusch2: symbol 2) holds slot
// number[k]'s sequence at its place (the rest zeros), grid sample k0 L at x[0].
std::vector<gr_complex> dmrs_slots(const gr::nrsar::numerology& num,
                                   const std::vector<unsigned>& number)
{
    const std::size_t sym = num.cp_samples + num.fft_size, len = num.symbols_per_slot * sym;
    std::vector<gr_complex> x(number.size() * len, 0.0f);
    for (std::size_t k = 0; k < number.size(); k++) {
        const auto d = dmrs_symbol(num, number[k], 2);
        std::copy(d.begin(), d.end(), x.begin() + k * len + 2 * sym);
    }
    return x;
}

// The output x (grid sample g at x[0]) passed to the check in chunks of at most chunk samples,
// as ofdm_sync passes its drained and tracked output: the slots tested.
std::vector<sync_tracker::slot_check> check_stream(sync_tracker& t,
                                                   dmrs_matcher& m,
                                                   const std::vector<gr_complex>& x,
                                                   std::uint64_t g,
                                                   std::size_t chunk)
{
    std::vector<sync_tracker::slot_check> tested;
    for (std::size_t i = 0; i < x.size();) {
        const std::size_t n =
            std::min({ chunk, x.size() - i, std::size_t(t.until_check_end(g + i)) });
        const auto c = t.check(x.data() + i, g + i, n, m, 20);
        if (c.tested)
            tested.push_back(c);
        i += n;
    }
    return tested;
}
} // namespace

TEST(sync_tracker, slots_are_checked_from_the_lock_on)
{
    // A lock's first output slots come from the acquirer's buffer; the check starts with them.
    const auto num = gr::nrsar::numerology::preset("sdr20");
    dmrs_matcher m(num, gr::nrsar::dmrs_config::preset("pusch2"));
    const unsigned cp = num.cp_samples, sym = cp + num.fft_size;
    const std::uint64_t len = num.symbols_per_slot * sym;
    sync_tracker t(num.fft_size, cp, num.symbols_per_slot, 2 * sym, cp / 8);
    const double nd = (num.num_subcarriers + 1) / 2;

    // Clean slots 7..11 (a lock at slot 7 of the frame), in odd chunks and whole: every slot
    // is tested with its own sequence, from the first one, and passes at the exact timing.
    const auto clean = dmrs_slots(num, { 7, 8, 9, 10, 11 });
    for (std::size_t chunk : { std::size_t(777), clean.size() }) {
        t.start_check(7 * len);
        const auto c = check_stream(t, m, clean, 7 * len, chunk);
        ASSERT_EQ(c.size(), 5u);
        for (std::size_t k = 0; k < c.size(); k++) {
            EXPECT_EQ(c[k].slot, 7 + k);
            EXPECT_NEAR(c[k].match.rho, (nd - 1) / nd, 1e-5);
            EXPECT_NEAR(c[k].match.offset, 0.0, 1e-3);
            EXPECT_FALSE(c[k].lost);
        }
        EXPECT_EQ(t.misses(), 0u);
    }
    // A lock starting past slot 7's check window: slot 8 is the first tested.
    t.start_check(7 * len + 2 * sym + cp / 2 + 1);
    const std::vector<gr_complex> tail(clean.begin() + 2 * sym + cp / 2 + 1, clean.end());
    const auto c8 = check_stream(t, m, tail, 7 * len + 2 * sym + cp / 2 + 1, 1000);
    ASSERT_EQ(c8.size(), 4u);
    EXPECT_EQ(c8[0].slot, 8u);

    // A wrong slot number (a false lock): one is a miss, cleared by the good slot after it;
    // two in a row lose the lock at the second.
    t.start_check(0);
    auto c = check_stream(t, m, dmrs_slots(num, { 0, 5, 2, 3 }), 0, 1000);
    ASSERT_EQ(c.size(), 4u);
    EXPECT_LT(c[1].match.rho, m.threshold());
    EXPECT_FALSE(c[1].lost);
    EXPECT_EQ(t.misses(), 0u);
    t.start_check(0);
    c = check_stream(t, m, dmrs_slots(num, { 0, 5, 6, 3 }), 0, 1000);
    EXPECT_TRUE(c[2].lost);
    EXPECT_EQ(c[2].slot, 2u);

    // G = 100 samples lost without a tag inside slot 1, before its DMRS: slots 1 and 2 start
    // G early (beyond max_early = cp / 8): the lock is lost at slot 2.
    auto gap = dmrs_slots(num, { 0, 1, 2, 3 });
    const std::size_t G = 100;
    gap.erase(gap.begin() + len + 10, gap.begin() + len + 10 + G);
    t.start_check(0);
    c = check_stream(t, m, gap, 0, 1000);
    ASSERT_GE(c.size(), 3u);
    EXPECT_FALSE(c[0].lost);
    EXPECT_GE(c[1].match.rho, m.threshold());
    EXPECT_NEAR(c[1].match.offset, -double(G), 1e-3);
    EXPECT_FALSE(c[1].lost);
    EXPECT_TRUE(c[2].lost);
    EXPECT_EQ(c[2].slot, 2u);

    // Memory: a check never takes more than the samples to the window's end.
    t.start_check(0);
    EXPECT_EQ(t.until_check_end(0), 2 * sym + cp / 2 + num.fft_size);
    EXPECT_THROW(t.check(clean.data(), 0, 2 * sym + cp / 2 + num.fft_size + 1, m, 20),
                 std::invalid_argument);
}

TEST(sync_tracker, parameter_errors)
{
    EXPECT_THROW(sync_tracker(63, CP, SPS, DMRS, EARLY), std::invalid_argument);
    EXPECT_THROW(sync_tracker(F, CP, 0, DMRS, EARLY), std::invalid_argument);
    EXPECT_THROW(sync_tracker(F, CP, SPS, L, EARLY), std::invalid_argument);
    EXPECT_THROW(sync_tracker(F, CP, SPS, DMRS, CP + 1), std::invalid_argument);
    EXPECT_THROW(sync_tracker(F, CP, SPS, DMRS, EARLY, 0), std::invalid_argument);
}
