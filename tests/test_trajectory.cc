/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// The trajectory type: the ideal line exact, Hermite interpolation of a known smooth path
// within the bound of its header, a continuous derivative, the CSV parser's errors, and the
// motion / navigation models' ensemble rms against their stated spectra.

#include "test_util.h"
#include <gnuradio/nrsar/trajectory.h>
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

using gr::nrsar::geometry;
using gr::nrsar::motion_model;
using gr::nrsar::nav_error_model;
using gr::nrsar::trajectory;
using gr::nrsar::vec3;
using nrsar_test::error_of;

namespace {

// Sinusoidal sway: x = A sin(w t), z = H + A cos(w t), y = v t.
constexpr double A = 0.3, W = M_PI, V = 50.0, H = 1000.0;

vec3 sway(double t) { return { A * std::sin(W * t), V * t, H + A * std::cos(W * t) }; }
vec3 sway_v(double t) { return { A * W * std::cos(W * t), V, -A * W * std::sin(W * t) }; }

trajectory sway_samples(double rate, double span)
{
    std::vector<double> t;
    std::vector<vec3> p;
    for (int i = 0; i <= static_cast<int>(std::lround(span * rate)); ++i) {
        t.push_back(i / rate);
        p.push_back(sway(t.back()));
    }
    return trajectory::from_samples(t, p);
}

std::string write_csv(const std::string& name, const std::string& text)
{
    const std::string path = ::testing::TempDir() + name;
    std::ofstream(path) << text;
    return path;
}

std::string csv_error(const std::string& text, double required_s = 0.0)
{
    const std::string path = write_csv("traj.csv", text);
    return error_of([&] { trajectory::from_csv(path, required_s); });
}

// A valid 10 Hz straight flight of n rows: "t,0,50 t,1000".
std::string rows(int n, int first = 0)
{
    std::string s;
    char buf[128];
    for (int i = first; i < first + n; ++i) {
        std::snprintf(buf, sizeof buf, "%.3f,0,%.3f,1000\n", i * 0.1, 5.0 * i);
        s += buf;
    }
    return s;
}

} // namespace

TEST(trajectory, ideal_line_is_exact)
{
    geometry geo = geometry::preset("paper");
    geo.track_start_m = -12.5;
    const trajectory tr = trajectory::ideal(geo);
    for (double t : { -3.0, 0.0, 1e-7, 0.731, 2.0, 1e4 }) {
        const vec3 p = tr.position(t), v = tr.velocity(t);
        EXPECT_EQ(p[0], 0.0);
        EXPECT_EQ(p[1], geo.track_start_m + geo.velocity_mps * t);
        EXPECT_EQ(p[2], geo.height_m);
        EXPECT_EQ(v[0], 0.0);
        EXPECT_EQ(v[1], geo.velocity_mps);
        EXPECT_EQ(v[2], 0.0);
    }
    // The motion model NONE is the ideal line itself.
    EXPECT_TRUE(trajectory::motion(geo, motion_model::NONE, 1, 2.0).is_ideal());
    EXPECT_NEAR(tr.rms_deviation_m(0.0, 2.0), 0.0, 1e-9);
}

TEST(trajectory, interpolation_error_within_bound)
{
    // Header bound: h^4 max|p''''| / 384 + h^5 max|p'''''| / 20 (Hermite with exact slopes
    // plus h / 4 times the 5-point slope error, worst at the one-sided ends h^4 p''''' / 5).
    for (double rate : { 10.0, 20.0, 50.0 }) {
        const double h = 1.0 / rate;
        const double bound = std::pow(h, 4) * A * std::pow(W, 4) / 384.0 +
                             std::pow(h, 5) * A * std::pow(W, 5) / 20.0;
        const trajectory tr = sway_samples(rate, 4.0);
        double worst = 0.0;
        for (int i = 0; i <= 40000; ++i) {
            const double t = 4.0 * i / 40000;
            const vec3 p = tr.position(t), q = sway(t);
            for (int ax = 0; ax < 3; ++ax)
                worst = std::max(worst, std::abs(p[ax] - q[ax]));
        }
        EXPECT_LT(worst, bound) << "rate " << rate;
        // The bound is not loose by orders of magnitude (it is the right order).
        EXPECT_GT(worst, bound / 100.0) << "rate " << rate;
    }
}

TEST(trajectory, velocity_continuous_and_accurate)
{
    const trajectory tr = sway_samples(10.0, 4.0);
    const double h = 0.1;
    // Derivative of the Hermite interpolant: sqrt(3) / 216 h^3 max|p''''| with exact
    // slopes, plus the slope error h^4 max|p'''''| / 5.
    const double bound = std::sqrt(3.0) / 216.0 * std::pow(h, 3) * A * std::pow(W, 4) +
                         std::pow(h, 4) * A * std::pow(W, 5) / 5.0;
    for (int k = 1; k < 40; ++k) {
        const double tk = k * h;
        const vec3 lo = tr.velocity(tk - 1e-9), hi = tr.velocity(tk + 1e-9);
        for (int ax = 0; ax < 3; ++ax) {
            // Across a knot the slope is the same on both sides: the jump is the change of
            // the derivative over 2 ns, |p''| 2e-9 < 1e-8 m/s.
            EXPECT_NEAR(lo[ax], hi[ax], 1e-8) << "knot " << k << " axis " << ax;
            EXPECT_NEAR(tr.velocity(tk + 0.37 * h)[ax], sway_v(tk + 0.37 * h)[ax], bound);
        }
    }
}

TEST(trajectory, csv_parser_reads_and_rejects)
{
    const std::string hdr = "t_s,x_m,y_m,z_m\n";
    const std::string ok = write_csv("ok.csv", hdr + rows(30));
    const trajectory tr = trajectory::from_csv(ok, 2.0);
    EXPECT_EQ(tr.num_samples(), 30u);
    EXPECT_NEAR(tr.position(1.234)[1], 5.0 * 12.34, 1e-9); // a straight line is reproduced
    EXPECT_NEAR(tr.velocity(1.234)[1], 50.0, 1e-9);

    // Attitude columns and a lever arm: a 1 m arm along x rolled by 0 and yawed by 90 deg
    // moves the phase centre by +1 m in y.
    std::string att = "t_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad\n";
    for (int i = 0; i < 30; ++i)
        att += std::to_string(i * 0.1) + ",0," + std::to_string(5.0 * i) + ",1000,0,0," +
               std::to_string(M_PI / 2) + "\n";
    const trajectory ta =
        trajectory::from_csv(write_csv("att.csv", att), 2.0, vec3{ 1.0, 0.0, 0.0 });
    EXPECT_TRUE(ta.has_attitude());
    // (yaw written with 6 decimals: 3e-7 rad off pi / 2)
    EXPECT_NEAR(ta.position(1.0)[1], 51.0, 1e-9);
    EXPECT_NEAR(ta.position(1.0)[0], 0.0, 1e-6);
    EXPECT_NEAR(ta.attitude(1.0)[2], M_PI / 2, 1e-6);

    auto has = [](const std::string& msg, const std::string& part) {
        return msg.find(part) != std::string::npos;
    };
    std::string e = csv_error("t,x,y,z\n" + rows(30));
    EXPECT_TRUE(has(e, "line 1") && has(e, "header")) << e;
    e = csv_error(hdr + rows(3) + "0.300,0,abc,1000\n" + rows(20, 4));
    EXPECT_TRUE(has(e, "traj.csv") && has(e, "line 5") && has(e, "y_m = 'abc'")) << e;
    e = csv_error(hdr + rows(3) + "0.200,0,15,1000\n" + rows(20, 4));
    EXPECT_TRUE(has(e, "row 5") && has(e, "time not increasing")) << e;
    e = csv_error(hdr + rows(10) + rows(10, 20));
    EXPECT_TRUE(has(e, "row 12") && has(e, "gap of 1.1 s")) << e;
    e = csv_error(hdr + rows(3) + "0.300,nan,15,1000\n" + rows(20, 4));
    EXPECT_TRUE(has(e, "row 5") && has(e, "x_m = nan")) << e;
    e = csv_error(hdr + rows(10), 2.0);
    EXPECT_TRUE(has(e, "too short") && has(e, "[0, 0.9]")) << e;
    e = csv_error(hdr + rows(3));
    EXPECT_TRUE(has(e, "3 samples")) << e;
    e = csv_error(hdr + "0,0,0,1000\n0.1,0,0,1000\n" + rows(20, 2));
    EXPECT_TRUE(has(e, "row 3") && has(e, "speed 0 m/s")) << e;
    // A 2 m jump at 10 Hz: 20 m/s of speed change in 0.1 s = 200 m/s^2.
    e = csv_error(hdr + rows(10) + "1.000,2,50,1000\n" + rows(10, 11));
    EXPECT_TRUE(has(e, "acceleration") && has(e, "exceeds 50")) << e;
    e = error_of([] { trajectory::from_csv("/nonexistent/f.csv"); });
    EXPECT_TRUE(has(e, "cannot be opened")) << e;
}

TEST(trajectory, motion_models_ensemble_rms)
{
    // Each model's displacement is a sum of tones with deterministic amplitudes and random
    // phases: its ensemble mean square per axis is the sum of its bands' rms^2 (docs/
    // flight.md). z-test of the mean over seeds of the mean square over a 20 s flight
    // against that value, 4 standard errors (estimated from the seeds) wide.
    const geometry geo = geometry::preset("paper");
    const trajectory line = trajectory::ideal(geo);
    struct expect {
        motion_model m;
        double ms_x, ms_z;
    };
    for (const expect& ex : { expect{ motion_model::CALM, 0.02 * 0.02 + 0.003 * 0.003,
                                      0.02 * 0.02 + 0.003 * 0.003 },
                              expect{ motion_model::GUSTY, 0.2 * 0.2 + 0.02 * 0.02,
                                      0.2 * 0.2 + 0.02 * 0.02 } }) {
        const int seeds = 48;
        std::vector<double> ms_x, ms_z;
        for (int s = 0; s < seeds; ++s) {
            const trajectory tr = trajectory::motion(geo, ex.m, s, 20.0);
            double sx = 0.0, sz = 0.0;
            const int n = 2000;
            for (int i = 0; i < n; ++i) {
                const double t = 20.0 * i / n;
                const vec3 p = tr.position(t), q = line.position(t);
                sx += (p[0] - q[0]) * (p[0] - q[0]) / n;
                sz += (p[2] - q[2]) * (p[2] - q[2]) / n;
            }
            ms_x.push_back(sx);
            ms_z.push_back(sz);
        }
        for (auto [v, want] : { std::pair{ &ms_x, ex.ms_x }, std::pair{ &ms_z, ex.ms_z } }) {
            double mean = 0.0, var = 0.0;
            for (double x : *v)
                mean += x / seeds;
            for (double x : *v)
                var += (x - mean) * (x - mean) / (seeds - 1);
            EXPECT_NEAR(mean, want, 4.0 * std::sqrt(var / seeds))
                << "model " << static_cast<int>(ex.m);
        }
    }
    // Same seed, same path; another seed, another path.
    const vec3 a = trajectory::motion(geo, motion_model::GUSTY, 7, 3.0).position(1.3);
    const vec3 b = trajectory::motion(geo, motion_model::GUSTY, 7, 3.0).position(1.3);
    const vec3 c = trajectory::motion(geo, motion_model::GUSTY, 8, 3.0).position(1.3);
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
}

TEST(trajectory, navigation_error_ensemble_rms)
{
    const geometry geo = geometry::preset("paper");
    const trajectory truth = trajectory::motion(geo, motion_model::GUSTY, 3, 20.0);
    EXPECT_EQ(trajectory::navigation(truth, nav_error_model::NONE, 1, 20.0).position(1.0),
              truth.position(1.0));
    // Per axis: RTK 1 cm + 2 cm -> 5e-4 m^2; GNSS x: 0.2 m + 2 cm -> 0.0404 m^2.
    for (auto [m, want] : { std::pair{ nav_error_model::RTK, 0.01 * 0.01 + 0.02 * 0.02 },
                            std::pair{ nav_error_model::GNSS, 0.2 * 0.2 + 0.02 * 0.02 } }) {
        const int seeds = 48;
        std::vector<double> ms;
        for (int s = 0; s < seeds; ++s) {
            const trajectory nav = trajectory::navigation(truth, m, s, 20.0);
            double acc = 0.0;
            for (int i = 0; i < 2000; ++i) {
                const double t = 0.01 * i;
                const double d = nav.position(t)[0] - truth.position(t)[0];
                acc += d * d / 2000;
            }
            ms.push_back(acc);
        }
        double mean = 0.0, var = 0.0;
        for (double x : ms)
            mean += x / seeds;
        for (double x : ms)
            var += (x - mean) * (x - mean) / (seeds - 1);
        EXPECT_NEAR(mean, want, 4.0 * std::sqrt(var / seeds)) << static_cast<int>(m);
    }
}

TEST(trajectory, outside_samples_refused)
{
    const trajectory tr = sway_samples(10.0, 2.0);
    const std::string e = error_of([&] { tr.position(2.5); });
    EXPECT_NE(e.find("t = 2.5"), std::string::npos) << e;
    EXPECT_NE(error_of([&] { tr.check_covers(0.0, 3.0); }).find("too short"), std::string::npos);
    EXPECT_TRUE(trajectory().empty());
}

TEST(trajectory, attitude_matrix_turns_about_the_named_axes)
{
    // Roll about the flight direction y: the scene side (+x) goes down. Pitch about the
    // cross-track axis x: the nose (+y) goes up. Yaw about z: the nose turns left (-x).
    auto apply = [](const gr::nrsar::mat3& r, const vec3& v) {
        return vec3{ r[0] * v[0] + r[1] * v[1] + r[2] * v[2],
                     r[3] * v[0] + r[4] * v[1] + r[5] * v[2],
                     r[6] * v[0] + r[7] * v[1] + r[8] * v[2] };
    };
    const double a = 0.1;
    vec3 v = apply(gr::nrsar::attitude_matrix({ a, 0.0, 0.0 }), { 1.0, 0.0, 0.0 });
    EXPECT_NEAR(v[0], std::cos(a), 1e-15);
    EXPECT_NEAR(v[2], -std::sin(a), 1e-15);
    v = apply(gr::nrsar::attitude_matrix({ 0.0, a, 0.0 }), { 0.0, 1.0, 0.0 });
    EXPECT_NEAR(v[1], std::cos(a), 1e-15);
    EXPECT_NEAR(v[2], std::sin(a), 1e-15);
    v = apply(gr::nrsar::attitude_matrix({ 0.0, 0.0, a }), { 0.0, 1.0, 0.0 });
    EXPECT_NEAR(v[0], -std::sin(a), 1e-15);
    EXPECT_NEAR(v[1], std::cos(a), 1e-15);
    // Any attitude: orthonormal, determinant +1 (R^T R = I).
    const gr::nrsar::mat3 r = gr::nrsar::attitude_matrix({ 0.3, -0.2, 1.1 });
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double d = 0.0;
            for (int k = 0; k < 3; ++k)
                d += r[3 * k + i] * r[3 * k + j];
            EXPECT_NEAR(d, i == j ? 1.0 : 0.0, 1e-15);
        }
}

TEST(trajectory, check_scenario_refuses_targets_behind_the_antenna_or_beyond_the_cp)
{
    using gr::nrsar::check_scenario;
    const auto num = gr::nrsar::numerology::preset("tiny"); // Tcp 8.33 us: R up to 1249 m
    geometry geo = geometry::preset("paper");
    geo.aperture_s = 2.0;
    const auto scn = gr::nrsar::scene::preset("paper3");
    auto shifted = [&](double dx, double dz) {
        std::vector<double> t;
        std::vector<vec3> p;
        for (int i = 0; i <= 30; ++i) {
            t.push_back(0.1 * i);
            const vec3 s = sway(0.1 * i);
            p.push_back({ s[0] + dx, s[1], s[2] + dz });
        }
        return trajectory::from_samples(t, p, {}, { 0.0, 0.0, 0.0 }, "test path");
    };
    EXPECT_NO_THROW(check_scenario(num, geo, scn, shifted(0.0, 0.0)));
    EXPECT_NO_THROW(check_scenario(num, geo, scn, trajectory()));
    // x_p = 260 +- 0.3 m: T2 (x = 250) lies behind the antenna across track
    std::string e = error_of([&] { check_scenario(num, geo, scn, shifted(260.0, 0.0)); });
    EXPECT_NE(e.find("target 1"), std::string::npos) << e;
    EXPECT_NE(e.find("behind the antenna"), std::string::npos) << e;
    EXPECT_NE(e.find("test path"), std::string::npos) << e;
    // z_p = 1300 m: T1 at sqrt(300^2 + 1300^2 + 100^2) = 1338 m > 1249 m of the CP
    e = error_of([&] { check_scenario(num, geo, scn, shifted(0.0, 300.0)); });
    EXPECT_NE(e.find("longer than Tcp"), std::string::npos) << e;
    EXPECT_NE(e.find("target 0"), std::string::npos) << e;
    // the ideal line of another geometry is refused, the geometry's own accepted
    geometry other = geo;
    other.height_m = 900.0;
    EXPECT_THROW(gr::nrsar::flies_ideal_line(trajectory::ideal(other), geo),
                 std::invalid_argument);
    EXPECT_TRUE(gr::nrsar::flies_ideal_line(trajectory::ideal(geo), geo));
    EXPECT_FALSE(gr::nrsar::flies_ideal_line(shifted(0.0, 0.0), geo));
}
