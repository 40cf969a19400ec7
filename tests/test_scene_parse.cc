/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// scene::parse / point_target::parse: the scene text grammar of GRC, the apps and
// Python's make_scene ("X,Y[,RCS[,PHASE_DEG]];...", fields as Python's float() reads them).

#include "test_util.h"
#include <gnuradio/nrsar/params.h>
#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include <string>

using namespace gr::nrsar;

namespace {

std::string error_of(const std::string& text)
{
    return nrsar_test::error_of([&] { scene::parse(text); });
}

} // namespace

TEST(SceneParse, TargetsWithDefaultsAndPhaseInDegrees)
{
    const auto scn = scene::parse("300,100; 250 , 100 ,2;;300,140,0.5,90;");
    ASSERT_EQ(scn.targets.size(), 3u);
    EXPECT_EQ(scn.targets[0].x_m, 300.0);
    EXPECT_EQ(scn.targets[0].y_m, 100.0);
    EXPECT_EQ(scn.targets[0].rcs, 1.0);
    EXPECT_EQ(scn.targets[0].phase_rad, 0.0);
    EXPECT_EQ(scn.targets[1].x_m, 250.0);
    EXPECT_EQ(scn.targets[1].rcs, 2.0);
    EXPECT_EQ(scn.targets[2].rcs, 0.5);
    EXPECT_NEAR(scn.targets[2].phase_rad, std::acos(0.0), 1e-15); // 90 degrees = pi / 2
}

TEST(SceneParse, PresetNamesAndEmptyText)
{
    const auto scn = scene::parse(" paper3 ");
    const auto ref = scene::preset("paper3");
    ASSERT_EQ(scn.targets.size(), ref.targets.size());
    for (std::size_t i = 0; i < ref.targets.size(); ++i) {
        EXPECT_EQ(scn.targets[i].x_m, ref.targets[i].x_m);
        EXPECT_EQ(scn.targets[i].y_m, ref.targets[i].y_m);
    }
    EXPECT_TRUE(scene::parse("").targets.empty());
    EXPECT_TRUE(scene::parse(" ; ;").targets.empty());
}

TEST(SceneParse, NumbersAsPythonFloatReadsThem)
{
    // Python: float("+1e3") == 1000, float("1_000.5") == 1000.5, float(".5") == 0.5,
    // float("5.") == 5, float("-INF") == -inf, float("NaN") is nan.
    const auto scn = scene::parse("+1e3,1_000.5,.5,5.;-INF,NaN");
    ASSERT_EQ(scn.targets.size(), 2u);
    EXPECT_EQ(scn.targets[0].x_m, 1000.0);
    EXPECT_EQ(scn.targets[0].y_m, 1000.5);
    EXPECT_EQ(scn.targets[0].rcs, 0.5);
    EXPECT_NEAR(scn.targets[0].phase_rad, 5.0 * std::acos(-1.0) / 180.0, 1e-15);
    EXPECT_TRUE(std::isinf(scn.targets[1].x_m) && scn.targets[1].x_m < 0);
    EXPECT_TRUE(std::isnan(scn.targets[1].y_m));
    // Underflow reads as 0 or a denormal (Python: float("1e-400") == 0.0,
    // float("-5e-324") == -5e-324), overflow is refused (Python's inf, which validate refuses).
    const auto tiny = scene::parse("1e-400,-5e-324");
    EXPECT_EQ(tiny.targets[0].x_m, 0.0);
    EXPECT_EQ(tiny.targets[0].y_m, -std::numeric_limits<double>::denorm_min());
    // ... and refuses what Python refuses.
    for (const char* bad : { "0x10,1", "1__0,1", "_1,1", "1_,1", "+-1,1", "++1,1", "1 0,1",
                             "nan(1),1", "1e,1", ",1", "1,", "+,1", "1.2.3,1" })
        EXPECT_NE(error_of(bad).find("is not a number"), std::string::npos) << bad;
}

TEST(SceneParse, ErrorsNameIndexFieldAndText)
{
    EXPECT_EQ(error_of("300,100;250,abc"), "target 1 '250,abc': y_m 'abc' is not a number");
    EXPECT_EQ(error_of("300,100,1,x"), "target 0 '300,100,1,x': phase_deg 'x' is not a number");
    EXPECT_EQ(error_of("1,2;3,4; ;5,6,1e999"),
              "target 2 '5,6,1e999': rcs '1e999' is out of the range of a double");
    const std::string one = error_of("paper9");
    EXPECT_NE(one.find("target 0 'paper9': has 1 field; must be X,Y[,RCS[,PHASE_DEG]]"),
              std::string::npos)
        << one;
    EXPECT_NE(one.find("paper3"), std::string::npos) << one; // lists the presets
    EXPECT_NE(error_of("1,2,3,4,5").find("target 0 '1,2,3,4,5': has 5 fields"),
              std::string::npos);
}

TEST(SceneParse, MessagesArePrintableAndBounded)
{
    const std::string text = std::string("1,\xff\x01\\") + std::string(200, '9') + "x";
    const std::string msg = error_of(text);
    EXPECT_LT(msg.size(), 200u);
    for (char c : msg)
        EXPECT_TRUE(c >= 0x20 && c < 0x7f) << msg;
    EXPECT_NE(msg.find("\\xff\\x01\\x5c999"), std::string::npos) << msg;
}

TEST(SceneParse, ValidateStillRejectsNonFiniteValues)
{
    EXPECT_THROW(scene::parse("nan,1").validate(), std::invalid_argument);
    EXPECT_THROW(scene::parse("1,1,-1").validate(), std::invalid_argument);
    EXPECT_NO_THROW(scene::parse("1,1,0,-720").validate());
}
