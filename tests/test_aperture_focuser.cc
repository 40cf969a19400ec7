/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::aperture_focuser (the rd_focuser block's buffering and overlap-save layout)
// against a direct reference: aperture i is kernel::rd_focuser applied to the P input
// lines [o + i M, o + i M + P) of the stream, o = line_shift - before (0 without overlap),
// zero outside the stream, of which lines [before, before + M) are kept. The reference
// focuses the same samples with the same arithmetic (line-major input, transposed by the
// kernel itself), so the comparisons are exact. Also: chunk sizes, end-of-stream flush,
// non-finite samples, guard bins and axis changes.

#include "test_util.h"
#include <gnuradio/nrsar/kernel/aperture_focuser.h>
#include <gnuradio/nrsar/kernel/rd_focuser.h>
#include <gnuradio/nrsar/params.h>
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using gr::nrsar::focuser_config;
using gr::nrsar::geometry;
using gr::nrsar::numerology;
using gr::nrsar::scene;
using gr::nrsar::kernel::aperture_focuser;
using gr::nrsar::kernel::rd_block;
using gr::nrsar::kernel::rd_focuser;

namespace {

constexpr unsigned K = 16;          // range bins
constexpr double T = 4e-3;          // pulse interval: PRF 250 Hz above the scene band
constexpr double first_range = 1000.0;
constexpr double range_bin = 5.0;   // bins over [1000, 1075] m: the paper3 targets

// Paper geometry with a 0.1 s aperture centred on the scene (along-track 100 m), so the
// band is about +-23 Hz: a few hundred lines of overlap on both sides.
geometry test_geometry()
{
    geometry geo = geometry::preset("paper");
    geo.aperture_s = 0.1;
    geo.track_start_m = 100.0 - 0.5 * geo.velocity_mps * geo.aperture_s;
    return geo;
}

focuser_config test_config(int overlap)
{
    focuser_config cfg;
    cfg.overlap_lines = overlap;
    cfg.range_centre_cycles = 0.0; // the same for the reference (no numerology default)
    return cfg;
}

aperture_focuser make_focuser(const focuser_config& cfg)
{
    return aperture_focuser(numerology::preset("tiny"),
                            test_geometry(),
                            scene::preset("paper3"),
                            K,
                            cfg,
                            T,
                            first_range,
                            range_bin);
}

struct aperture {
    std::vector<gr_complex> image;
    double y0 = 0.0;
};

// Feeds lines in chunks of the given sizes (cycled), focusing whenever a block is full and
// flushing at the end, as the block does.
std::vector<aperture> stream(aperture_focuser& f,
                             const std::vector<gr_complex>& lines,
                             const std::vector<unsigned>& chunks)
{
    std::vector<aperture> out;
    auto take = [&] {
        aperture a;
        a.image.resize(static_cast<size_t>(f.image_lines()) * f.num_output_bins());
        f.read_image(a.image.data(), 0, f.image_lines());
        a.y0 = f.image_first_y_m();
        out.push_back(std::move(a));
    };
    const size_t n = lines.size() / K;
    size_t pos = 0, c = 0;
    while (pos < n) {
        f.prepare();
        const unsigned want = chunks[c++ % chunks.size()];
        const unsigned m = static_cast<unsigned>(std::min<size_t>({ want, f.room(), n - pos }));
        f.ingest(&lines[pos * K], m);
        pos += m;
        if (f.block_full()) {
            f.focus(false);
            take();
        }
    }
    while (f.flush_due()) {
        f.focus(false);
        take();
    }
    return out;
}

// The direct reference: aperture i from the P stream lines starting at o + i M.
std::vector<gr_complex> reference(const aperture_focuser& f,
                                  const std::vector<gr_complex>& lines,
                                  unsigned i)
{
    const unsigned M = f.lines_per_aperture();
    const unsigned before = f.overlap_before();
    const unsigned P = before + M + f.overlap_after();
    const bool circular = P == M;
    rd_block blk;
    blk.num_range_bins = K;
    blk.num_lines = P;
    blk.pulse_interval_s = T;
    blk.velocity_mps = test_geometry().velocity_mps;
    blk.wavelength_m = test_geometry().wavelength_m();
    blk.first_range_m = first_range;
    blk.range_bin_m = range_bin;
    blk.band_lo_hz = f.band_lo_hz();
    blk.band_hi_hz = f.band_hi_hz();
    blk.range_centre_cycles = 0.0;
    blk.line_shift = circular ? f.line_shift() : 0;
    rd_focuser direct(f.config(), blk);

    const long long o = circular ? 0 : f.line_shift() - static_cast<long long>(before);
    const long long n = static_cast<long long>(lines.size() / K);
    std::vector<gr_complex> in(static_cast<size_t>(P) * K, gr_complex(0.0f, 0.0f));
    for (unsigned p = 0; p < P; ++p) {
        const long long t = o + static_cast<long long>(i) * M + p;
        if (t >= 0 && t < n)
            std::copy_n(&lines[static_cast<size_t>(t) * K], K, &in[static_cast<size_t>(p) * K]);
    }
    std::vector<gr_complex> out(static_cast<size_t>(M) * K);
    direct.focus(in.data(), out.data(), before, M);
    return out;
}

void expect_equal(const std::vector<gr_complex>& a, const std::vector<gr_complex>& b)
{
    ASSERT_EQ(a.size(), b.size());
    size_t bad = 0;
    for (size_t j = 0; j < a.size(); ++j)
        bad += a[j] != b[j];
    EXPECT_EQ(bad, 0u) << "of " << a.size() << " samples differ";
}

class aperture_focuser_overlap : public ::testing::TestWithParam<int>
{
};

} // namespace

// Auto overlap (history and look-ahead from the band), a fixed overlap, none (circular).
TEST_P(aperture_focuser_overlap, streamed_apertures_equal_direct_blocks)
{
    aperture_focuser f = make_focuser(test_config(GetParam()));
    f.prepare();
    const unsigned M = f.lines_per_aperture();
    EXPECT_EQ(M, 25u); // round(Ta / T) = round(0.1 / 4e-3)
    if (GetParam() >= 0) {
        EXPECT_EQ(f.overlap_before(), static_cast<unsigned>(GetParam()));
        EXPECT_EQ(f.overlap_after(), static_cast<unsigned>(GetParam()));
    }
    // Not a multiple of M: the last aperture is flushed zero-padded.
    const unsigned n = 7 * M + 11;
    const auto lines = nrsar_test::gaussian_samples(static_cast<size_t>(n) * K, 3);
    const auto got = stream(f, lines, { n });
    ASSERT_EQ(got.size(), (n + M - 1) / M); // every aperture whose pulses were received
    EXPECT_EQ(f.lines_in(), n);
    EXPECT_EQ(f.lines_emitted(), static_cast<std::uint64_t>(got.size()) * M);
    const double dy = test_geometry().velocity_mps * T;
    for (unsigned i = 0; i < got.size(); ++i) {
        SCOPED_TRACE("aperture " + std::to_string(i));
        expect_equal(got[i].image, reference(f, lines, i));
        // Along-track axis: the window [i M + s, i M + s + M) of the track.
        EXPECT_NEAR(got[i].y0,
                    test_geometry().track_start_m + (i * M + f.line_shift()) * dy,
                    1e-9 * (1.0 + std::abs(got[i].y0))); // accumulated rounding only
    }
}

INSTANTIATE_TEST_SUITE_P(overlaps, aperture_focuser_overlap, ::testing::Values(-1, 9, 0));

// A fixed overlap shorter than the scene band's extent, on a track that starts far past
// the scene, puts the output window's first block more than a whole block ahead of the
// stream (automatic overlap covers the extent, so -o < P there): those lines enter as
// zeros (room() is 0 while they fill a block; ingest(lines, 0) enters them), and every
// aperture is still the direct reference of the zero-extended stream (before: the block's
// fill ran past its end, a heap overflow seen in one graph over a 1 s sdr20 recording
// with --strip-overlap-s 0.0125).
TEST(aperture_focuser, window_far_ahead_of_the_stream_enters_zero_lines)
{
    for (int overlap : { 9, 2 }) {
        SCOPED_TRACE("overlap " + std::to_string(overlap));
        geometry geo = test_geometry();
        geo.track_start_m += 30.0 * geo.velocity_mps * 0.1; // 30 apertures past the scene
        aperture_focuser f(numerology::preset("tiny"),
                           geo,
                           scene::preset("paper3"),
                           K,
                           test_config(overlap),
                           T,
                           first_range,
                           range_bin);
        f.prepare();
        const unsigned M = f.lines_per_aperture();
        const long long P = f.overlap_before() + M + f.overlap_after();
        const long long o = f.line_shift() - static_cast<long long>(f.overlap_before());
        ASSERT_GT(-o, 2 * P); // the case: two blocks and more of zeros before the stream
        const unsigned n = 7 * M + 11;
        const auto lines = nrsar_test::gaussian_samples(static_cast<size_t>(n) * K, 5);
        const auto got = stream(f, lines, { 13 });
        EXPECT_EQ(f.lines_in(), n);
        size_t zero_apertures = 0;
        for (unsigned i = 0; i < got.size(); ++i) {
            SCOPED_TRACE("aperture " + std::to_string(i));
            const auto ref = reference(f, lines, i);
            expect_equal(got[i].image, ref);
            zero_apertures += std::all_of(ref.begin(), ref.end(), [](gr_complex v) {
                return v == gr_complex(0.0f, 0.0f);
            });
        }
        // Apertures whose blocks end before the stream are zero; the ones after are not.
        EXPECT_EQ(zero_apertures, static_cast<size_t>((-o - P) / M + 1));
        EXPECT_GT(got.size(), zero_apertures);
    }
}

// A strip's task (cfg.first_aperture = a, cfg.apertures = 1) fed the stream from
// stream_first_line() on makes aperture a of the whole stream, bit for bit, and stops.
TEST_P(aperture_focuser_overlap, first_aperture_equals_the_whole_streams)
{
    const unsigned n = 1000; // 40 apertures of 25 lines
    const auto lines = nrsar_test::gaussian_samples(static_cast<size_t>(n) * K, 7);
    aperture_focuser whole = make_focuser(test_config(GetParam()));
    const auto ref = stream(whole, lines, { n });
    const unsigned M = whole.lines_per_aperture();
    bool mid_flight = false;
    for (unsigned a = 0; a < ref.size(); ++a) {
        SCOPED_TRACE("aperture " + std::to_string(a));
        focuser_config cfg = test_config(GetParam());
        cfg.first_aperture = a;
        cfg.apertures = 1;
        aperture_focuser f = make_focuser(cfg);
        const std::uint64_t first = f.stream_first_line();
        const long long block = static_cast<long long>(a) * M +
                                (GetParam() == 0 ? 0 : f.line_shift() - (long long)f.overlap_before());
        EXPECT_EQ(first, a == 0 ? 0u : static_cast<std::uint64_t>(std::max(0ll, block)));
        mid_flight |= first > 0;
        std::vector<aperture> got;
        for (size_t pos = first; pos < n && !f.done();) {
            f.prepare();
            const unsigned m = static_cast<unsigned>(std::min<size_t>({ 13, f.room(), n - pos }));
            f.ingest(&lines[pos * K], m);
            pos += m;
            if (f.block_full()) {
                f.focus(false);
                got.push_back({ std::vector<gr_complex>(static_cast<size_t>(M) * K), 0.0 });
                f.read_image(got.back().image.data(), 0, M);
                got.back().y0 = f.image_first_y_m();
            }
        }
        while (f.flush_due()) { // (a block past the stream's end: no line at all, zeros)
            f.prepare();
            f.focus(false);
            got.push_back({ std::vector<gr_complex>(static_cast<size_t>(M) * K), 0.0 });
            f.read_image(got.back().image.data(), 0, M);
            got.back().y0 = f.image_first_y_m();
        }
        EXPECT_TRUE(f.done());
        EXPECT_FALSE(f.flush_due());
        ASSERT_EQ(got.size(), 1u);
        expect_equal(got[0].image, ref[a].image);
        EXPECT_NEAR(got[0].y0, ref[a].y0, 1e-9 * (1.0 + std::abs(ref[a].y0)));
    }
    EXPECT_TRUE(mid_flight); // some task started past the flight's first line
}

TEST(aperture_focuser, auto_overlap_covers_the_band_extent)
{
    aperture_focuser f = make_focuser(test_config(-1));
    // The band's azimuth extent E(f, R) = f lambda R / (2 v^2 T) at the band edges and the
    // scene's slant ranges bounds the history (upper edge) and look-ahead (lower edge).
    const geometry geo = test_geometry();
    const auto ext = gr::nrsar::compute_extent(geo, scene::preset("paper3"));
    const double v = geo.velocity_mps;
    auto e = [&](double fd, double r) { return fd * geo.wavelength_m() * r / (2 * v * v * T); };
    const double e_hi = std::max(e(f.band_hi_hz(), ext.min_slant_range_m),
                                 e(f.band_hi_hz(), ext.max_slant_range_m));
    const double e_lo = std::min(e(f.band_lo_hz(), ext.min_slant_range_m),
                                 e(f.band_lo_hz(), ext.max_slant_range_m));
    EXPECT_GE(f.overlap_before(), e_hi);
    EXPECT_GE(f.overlap_after(), -e_lo);
    EXPECT_GE(f.line_shift(), std::floor(e_lo));
    EXPECT_LE(f.line_shift(), std::ceil(e_hi));
    EXPECT_GT(f.overlap_before(), 0u);
    EXPECT_GT(f.overlap_after(), 0u);
}

TEST(aperture_focuser, chunk_sizes_do_not_change_apertures)
{
    const unsigned n = 180;
    const auto lines = nrsar_test::gaussian_samples(static_cast<size_t>(n) * K, 5);
    aperture_focuser whole = make_focuser(test_config(-1));
    const auto ref = stream(whole, lines, { n });
    std::mt19937 rng(11);
    std::uniform_int_distribution<unsigned> size(1, 40);
    std::vector<unsigned> chunks(64);
    for (auto& c : chunks)
        c = size(rng);
    for (const auto& sizes : { std::vector<unsigned>{ 1 }, std::vector<unsigned>{ 7, 3 }, chunks }) {
        aperture_focuser f = make_focuser(test_config(-1));
        const auto got = stream(f, lines, sizes);
        ASSERT_EQ(got.size(), ref.size());
        for (size_t i = 0; i < got.size(); ++i)
            expect_equal(got[i].image, ref[i].image);
    }
}

TEST(aperture_focuser, nonfinite_samples_are_zeroed_and_located)
{
    const unsigned n = 120;
    auto lines = nrsar_test::gaussian_samples(static_cast<size_t>(n) * K, 8);
    auto zeroed = lines;
    const size_t bad1 = 40 * K + 3, bad2 = 41 * K + 15;
    lines[bad1] = gr_complex(std::numeric_limits<float>::quiet_NaN(), 0.0f);
    lines[bad2] = gr_complex(0.0f, std::numeric_limits<float>::infinity());
    zeroed[bad1] = zeroed[bad2] = gr_complex(0.0f, 0.0f);

    aperture_focuser f = make_focuser(test_config(0));
    // Without overlap no pulse is skipped. One call over lines [30, 50): the first bad
    // sample is on input line 40.
    const unsigned skip = 30;
    aperture_focuser g = make_focuser(test_config(0));
    g.prepare();
    unsigned pos = 0;
    while (pos < skip) {
        const unsigned m = std::min(g.room(), skip - pos);
        EXPECT_EQ(g.ingest(&lines[pos * K], m).nonfinite, 0u);
        pos += m;
        if (g.block_full())
            g.focus(false);
        g.prepare();
    }
    ASSERT_GE(g.room(), 20u);
    const auto res = g.ingest(&lines[pos * K], 20);
    EXPECT_EQ(res.nonfinite, 2u);
    EXPECT_EQ(res.first_bad_line, 40u);

    const auto got = stream(f, lines, { n });
    aperture_focuser h = make_focuser(test_config(0));
    const auto ref = stream(h, zeroed, { n });
    ASSERT_EQ(got.size(), ref.size());
    for (size_t i = 0; i < got.size(); ++i)
        expect_equal(got[i].image, ref[i].image);
}

TEST(aperture_focuser, guard_bins_keep_the_inner_bins)
{
    const unsigned n = 100, g = 3;
    const auto lines = nrsar_test::gaussian_samples(static_cast<size_t>(n) * K, 9);
    aperture_focuser full = make_focuser(test_config(4));
    const auto ref = stream(full, lines, { n });
    focuser_config cfg = test_config(4);
    cfg.guard_bins = g;
    aperture_focuser f = make_focuser(cfg);
    EXPECT_EQ(f.num_output_bins(), K - 2 * g);
    const auto got = stream(f, lines, { n });
    ASSERT_EQ(got.size(), ref.size());
    const unsigned ko = K - 2 * g;
    for (size_t i = 0; i < got.size(); ++i) {
        std::vector<gr_complex> inner;
        for (size_t m = 0; m < ref[i].image.size() / K; ++m)
            inner.insert(inner.end(), &ref[i].image[m * K + g], &ref[i].image[m * K + g + ko]);
        expect_equal(got[i].image, inner);
    }
}

TEST(aperture_focuser, axes_apply_at_once_before_the_first_line_else_at_the_next_aperture)
{
    aperture_focuser f = make_focuser(test_config(4));
    using change = aperture_focuser::axes_change;
    EXPECT_EQ(f.set_axes(T, first_range, range_bin), change::NONE);
    EXPECT_EQ(f.set_axes(2.5 * T, first_range, range_bin), change::APPLIED);
    EXPECT_EQ(f.pulse_interval_s(), 2.5 * T);
    EXPECT_EQ(f.lines_per_aperture(), 10u); // round(Ta / T) = round(0.1 / 0.01)

    f.prepare();
    const auto lines = nrsar_test::gaussian_samples(static_cast<size_t>(5) * K, 1);
    f.ingest(lines.data(), 5);
    EXPECT_EQ(f.set_axes(T, first_range + 10.0, range_bin), change::PENDING);
    EXPECT_EQ(f.pulse_interval_s(), 2.5 * T); // still the current aperture's
    EXPECT_EQ(f.next_pulse_interval_s(), T);
    EXPECT_EQ(f.next_first_range_m(), first_range + 10.0);
    f.focus(false); // the flush of the partial aperture applies them
    EXPECT_EQ(f.pulse_interval_s(), T);
    EXPECT_EQ(f.first_range_m(), first_range + 10.0);
    EXPECT_EQ(f.lines_per_aperture(), 25u);
    EXPECT_EQ(f.image_line_spacing_m(), test_geometry().velocity_mps * 2.5 * T);
}

TEST(aperture_focuser, refuses_bad_axes_naming_them)
{
    EXPECT_NE(nrsar_test::error_of([] {
                  aperture_focuser(numerology::preset("tiny"),
                                   test_geometry(),
                                   scene::preset("paper3"),
                                   K,
                                   test_config(-1),
                                   T,
                                   -1.0,
                                   range_bin);
              }).find("first_range_m = -1"),
              std::string::npos);
    aperture_focuser f = make_focuser(test_config(-1));
    EXPECT_NE(nrsar_test::error_of([&] { f.set_axes(0.0, first_range, range_bin); })
                  .find("pulse_interval_s = 0"),
              std::string::npos);
}
