/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "test_util.h"
#include <gnuradio/nrsar/params.h>
#include <gtest/gtest.h>
#include <cmath>

using namespace gr::nrsar;

using nrsar_test::error_of;

TEST(Numerology, PaperPresetDerivedQuantities)
{
    const auto num = numerology::preset("paper");
    // SPEC section 2: Tp = 33.33 us, Tcp = 8.33 us, Tsym = 41.67 us, PRF = 24 kHz.
    EXPECT_NEAR(num.useful_symbol_s(), 1.0 / 30e3, 1e-12);
    EXPECT_NEAR(num.cp_s(), 8.333e-6, 1e-9);
    EXPECT_NEAR(num.symbol_s(), 41.667e-6, 1e-9);
    EXPECT_NEAR(num.prf_hz(), 24e3, 1e-6);
    EXPECT_NEAR(num.bandwidth_hz(), 99.99e6, 1.0);
    // rho_r = c / (2 Br) = 1.50 m on the N-point grid.
    EXPECT_NEAR(num.range_bin_m(num.num_subcarriers), 1.4990, 1e-3);
}

TEST(Geometry, PaperApertureAndDoppler)
{
    const auto num = numerology::preset("paper");
    const auto geo = geometry::preset("paper");
    EXPECT_EQ(geo.symbols_per_aperture(num), 48000u);
    EXPECT_NEAR(geo.wavelength_m(), 0.08565, 1e-5);
    // eta = 2 v fc / (c Delta f) = 0.0389 (footnote 3).
    EXPECT_NEAR(geo.normalised_doppler(num), 2 * 50 * 3.5e9 / (speed_of_light * 30e3), 1e-12);
}

TEST(Scene, PaperExtentMatchesExactRanges)
{
    const auto geo = geometry::preset("paper");
    const auto ext = compute_extent(geo, scene::preset("paper3"));
    // Closest approach of T2 (250, 100): sqrt(250^2 + 1000^2) = 1030.78 m.
    EXPECT_NEAR(ext.min_slant_range_m, std::sqrt(250.0 * 250 + 1e6), 1e-9);
    // Farthest: T3 (300, 140) seen from y = 0: sqrt(300^2 + 1000^2 + 140^2).
    EXPECT_NEAR(ext.max_slant_range_m, std::sqrt(300.0 * 300 + 1e6 + 140.0 * 140), 1e-9);
    // The targets are ahead of the track: the Doppler band is positive, about 0..160 Hz.
    EXPECT_GT(ext.min_doppler_hz, -1.0);
    EXPECT_NEAR(ext.max_doppler_hz,
                2 * 50 * 140 / (geo.wavelength_m() * std::sqrt(300.0 * 300 + 1e6 + 140.0 * 140)),
                1e-9);
}

TEST(Scenario, PaperIsAcceptedWithoutWarnings)
{
    const auto warnings = check_scenario(
        numerology::preset("paper"), geometry::preset("paper"), scene::preset("paper3"));
    EXPECT_TRUE(warnings.empty());
}

TEST(Scenario, ShortCpIsRefusedWithTheNumbers)
{
    // nr273 has the standard 2.34 us CP: it covers only 351 m of slant range.
    const auto msg = error_of([] {
        check_scenario(
            numerology::preset("nr273"), geometry::preset("paper"), scene::preset("paper3"));
    });
    EXPECT_NE(msg.find("cyclic prefix too short"), std::string::npos) << msg;
    EXPECT_NE(msg.find("1053"), std::string::npos) << msg; // farthest slant range
    EXPECT_NE(msg.find("2.34"), std::string::npos) << msg; // Tcp in us
}

TEST(Scenario, LargeNormalisedDopplerIsRefused)
{
    auto geo = geometry::preset("paper");
    geo.velocity_mps = 500.0; // eta = 0.39
    geo.aperture_s = 0.2;     // keeps the track (and the round trip) short
    const auto msg = error_of([&] {
        check_scenario(numerology::preset("paper"), geo, scene::preset("single"));
    });
    EXPECT_NE(msg.find("eta"), std::string::npos) << msg;
    EXPECT_NE(msg.find("0.1"), std::string::npos) << msg;
}

TEST(Scenario, SrsEvery20SlotsWarnsAboutAliasing)
{
    const auto num = numerology::preset("paper");
    const auto geo = geometry::preset("paper");
    const auto scn = scene::preset("paper3");
    // SPEC 2: one SRS symbol every 2 slots is 857 Hz (fine), every 20 slots 85.7 Hz,
    // below the ~160 Hz Doppler band of the scene.
    EXPECT_TRUE(check_scenario(num, geo, scn, 14 * 2).empty());
    const auto warnings = check_scenario(num, geo, scn, 14 * 20);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("85.7"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("aliases"), std::string::npos) << warnings[0];
}

TEST(Validation, EveryRuleNamesItsParameter)
{
    auto bad_num = numerology::preset("paper");
    bad_num.fft_size = 1024;
    EXPECT_NE(error_of([&] { bad_num.validate(); }).find("fft_size = 1024"), std::string::npos);

    auto bad_spacing = numerology::preset("paper");
    bad_spacing.subcarrier_spacing_hz = NAN;
    EXPECT_NE(error_of([&] { bad_spacing.validate(); }).find("subcarrier_spacing_hz"),
              std::string::npos);

    auto bad_geo = geometry::preset("paper");
    bad_geo.height_m = -5.0;
    EXPECT_NE(error_of([&] { bad_geo.validate(); }).find("height_m = -5"), std::string::npos);

    EXPECT_NE(error_of([] { scene{}.validate(); }).find("no targets"), std::string::npos);
    scene bad_rcs{ { { 1.0, 2.0, -1.0 } } };
    EXPECT_NE(error_of([&] { bad_rcs.validate(); }).find("rcs = -1"), std::string::npos);

    EXPECT_NE(error_of([] { numerology::preset("bogus"); }).find("paper"), std::string::npos);

    srs_config srs;
    const auto small = numerology::preset("small");
    EXPECT_NE(error_of([&] { srs.validate(small); }).find("does not fit the 512"),
              std::string::npos);
    srs.start_subcarrier = 100;
    EXPECT_NO_THROW(srs.validate(small));
    srs.comb_offset = 4;
    EXPECT_NE(error_of([&] { srs.validate(small); }).find("comb_offset = 4"), std::string::npos);
}

TEST(params, dc_subcarrier_is_even_and_central)
{
    EXPECT_EQ(numerology::preset("paper").dc_subcarrier(), 1666u); // 3333 / 2 = 1666
    EXPECT_EQ(numerology::preset("sdr20").dc_subcarrier(), 306u);  // 612 / 2
    numerology odd_half = numerology::preset("tiny");
    odd_half.num_subcarriers = 54; // 27 -> 26
    EXPECT_EQ(odd_half.dc_subcarrier(), 26u);
}

TEST(params, dmrs_presets_and_rules)
{
    const auto num = numerology::preset("paper");
    const auto nr = dmrs_config::preset("pusch2");
    EXPECT_EQ(nr.symbols, (std::vector<unsigned>{ 2, 11 }));
    EXPECT_TRUE(nr.enabled());
    EXPECT_TRUE(nr.is_dmrs_symbol(11));
    EXPECT_FALSE(nr.is_dmrs_symbol(3));
    EXPECT_NO_THROW(nr.validate(num));
    EXPECT_FALSE(dmrs_config::preset("none").enabled());

    dmrs_config late{ { 2, 14 }, 0 };
    EXPECT_NE(error_of([&] { late.validate(num); }).find("dmrs symbols = 14 must be below"),
              std::string::npos);
    dmrs_config unordered{ { 5, 5 }, 0 };
    EXPECT_NE(error_of([&] { unordered.validate(num); }).find("strictly increasing"),
              std::string::npos);
    dmrs_config big_id{ { 2 }, 70000 };
    EXPECT_NE(error_of([&] { big_id.validate(num); }).find("scrambling_id = 70000"),
              std::string::npos);
}
