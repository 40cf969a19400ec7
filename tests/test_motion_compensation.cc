/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Processing from navigation (issue #14): the line of sight from a path to the per-bin
// reference points (los_reference) against the distance formula written here, and
// cheby_presum's coherent sum along a swaying path against eqs. (P-25..29) evaluated in
// double on that path.

#include <gnuradio/nrsar/kernel/aperture_focuser.h>
#include <gnuradio/nrsar/kernel/cheby_presum.h>
#include <gnuradio/nrsar/kernel/motion_compensation.h>
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <vector>

using namespace gr::nrsar;
using cd = std::complex<double>;

namespace {

const geometry geo = geometry::preset("paper");

// The ideal line plus a constant offset d and a sway of amplitude a (x) and a / 2 (z),
// period 1.5 s, sampled at 100 Hz over [0, span].
trajectory swaying(const vec3& d, double a, double span)
{
    std::vector<double> t;
    std::vector<vec3> p;
    for (double s = 0.0; s <= span + 1e-9; s += 0.01) {
        const double w = a * std::sin(2.0 * M_PI * s / 1.5);
        t.push_back(s);
        p.push_back({ d[0] + w, geo.track_start_m + geo.velocity_mps * s + d[1], geo.height_m + d[2] + 0.5 * w });
    }
    return trajectory::from_samples(t, p, {}, { 0.0, 0.0, 0.0 }, "sway");
}

} // namespace

TEST(motion_compensation, ideal_line_is_eq25)
{
    const double yref = 120.0;
    for (const trajectory& nav : { trajectory(), trajectory::ideal(geo) }) {
        kernel::los_reference los(geo, nav, yref);
        EXPECT_TRUE(los.ideal());
        for (double t : { 0.0, 0.7, 1.9 })
            for (double r0 : { 1020.0, 1100.0 }) {
                const double u = geo.track_start_m + geo.velocity_mps * t - yref;
                EXPECT_NEAR(los.range(t, r0), std::sqrt(r0 * r0 + u * u), 1e-9);
                EXPECT_EQ(los.displacement(t, r0), 0.0);
            }
    }
    geometry other = geo;
    other.height_m += 1.0; // an ideal line, but not geo's: a path like any other
    EXPECT_FALSE(kernel::los_reference(geo, trajectory::ideal(other), yref).ideal());
}

TEST(motion_compensation, offset_path_is_the_distance)
{
    // A constant offset (interpolated exactly): the range to the ground point
    // (sqrt(R0^2 - H^2), y_ref, 0) and the displacement from eq. (P-25).
    const vec3 d = { 0.31, -0.12, 0.27 };
    const double yref = 80.0;
    kernel::los_reference los(geo, swaying(d, 0.0, 3.0), yref);
    EXPECT_FALSE(los.ideal());
    std::vector<double> r(4), dr(4);
    for (double t : { 0.0, 0.55, 2.5 }) {
        los.ranges(t, 1100.0, 7.5, 4, r.data());
        los.displacements(t, 1100.0, 7.5, 4, dr.data());
        for (unsigned k = 0; k < 4; ++k) {
            const double r0 = 1100.0 + 7.5 * k;
            const double x = std::sqrt(r0 * r0 - geo.height_m * geo.height_m);
            const double y = geo.track_start_m + geo.velocity_mps * t + d[1] - yref;
            const double z = geo.height_m + d[2];
            const double want = std::sqrt((x - d[0]) * (x - d[0]) + y * y + z * z);
            EXPECT_NEAR(r[k], want, 1e-8);
            EXPECT_NEAR(los.range(t, r0), want, 1e-8);
            const double u = y - d[1];
            EXPECT_NEAR(dr[k], want - std::sqrt(r0 * r0 + u * u), 1e-8);
        }
    }
    // Below the line's height: the point under the track at H - R0.
    EXPECT_NEAR(los.range(1.0, 400.0),
                std::hypot(std::hypot(-d[0], geo.track_start_m + 50.0 + d[1] - yref),
                           geo.height_m + d[2] - (geo.height_m - 400.0)),
                1e-8);
}

TEST(motion_compensation, along_track_time_finds_the_ideal_position)
{
    // A constant along-track offset d_y (interpolated exactly): y(tau) = y0 + v t at
    // tau = t - d_y / v; the ideal line: tau = t; outside the path's span: NaN.
    const double dy = -0.37;
    kernel::los_reference los(geo, swaying({ 0.1, dy, 0.0 }, 0.2, 3.0), 80.0);
    for (double t : { 0.3, 1.1, 2.6 })
        EXPECT_NEAR(los.along_track_time(t), t - dy / geo.velocity_mps, 1e-12);
    EXPECT_TRUE(std::isnan(los.along_track_time(2.999)));
    kernel::los_reference ideal(geo, trajectory(), 80.0);
    EXPECT_EQ(ideal.along_track_time(1.7), 1.7);
}

TEST(motion_compensation, cheby_presum_sums_along_the_path)
{
    // Input: every bin's reference scatterer seen from a swaying path (2 m at 0.67 Hz in x,
    // 1 m in z: up to 8 m/s and 39 m/s^2); output g must be D times its history at the
    // window centre. (At 28 k pulses/s the ideal line's compensation would err by 1 % here:
    // the low-pass passes the sway's Doppler; qa_motion_compensation shows where it loses.)
    const numerology num = numerology::preset("small");
    const scene scn = scene::preset("paper3");
    const unsigned K = 16, d = 12, pulses = 2400;
    const double first_m = 1020.0, bin_m = 1.5, t = num.symbol_s();
    const trajectory path = swaying({ 0.1, 0.0, -0.05 }, 2.0, 0.2);
    kernel::presum_config cfg;
    cfg.decim = d;
    kernel::cheby_presum k(num, geo, scn, K, first_m, bin_m, cfg, path);
    ASSERT_TRUE(k.follows_path());
    const double yc = 0.5 * (100.0 + 140.0); // paper3 targets at y = 100, 100, 140
    const double f = geo.carrier_hz + 0.5 * (num.num_subcarriers - 1) * num.subcarrier_spacing_hz;
    auto phase = [&](unsigned n, double time) {
        const double r0 = first_m + n * bin_m;
        const double x = std::sqrt(r0 * r0 - geo.height_m * geo.height_m);
        const vec3 p = path.position(time);
        const double dx = p[0] - x, dy = p[1] - yc, dz = p[2];
        return 4 * M_PI * f * std::sqrt(dx * dx + dy * dy + dz * dz) / speed_of_light;
    };
    std::vector<gr_complex> x(std::size_t(pulses) * K);
    for (unsigned p = 0; p < pulses; ++p)
        for (unsigned n = 0; n < K; ++n)
            x[std::size_t(p) * K + n] = gr_complex(std::polar(1.0, -phase(n, p * t)));
    std::vector<gr_complex> o(K);
    double worst = 0.0;
    unsigned g = 0;
    const unsigned g0 = (k.num_taps() + d - 1) / d; // past the zero history
    for (unsigned p = 0; p < pulses; ++p) {
        if (!k.push(x.data() + std::size_t(p) * K, o.data()))
            continue;
        if (g >= g0)
            for (unsigned n = 0; n < K; ++n) {
                const cd want = double(d) * std::polar(1.0, -phase(n, (g * d + k.centre_offset()) * t));
                worst = std::max(worst, std::abs(cd(o[n]) - want) / d);
            }
        ++g;
    }
    ASSERT_GT(g, 100u);
    EXPECT_LT(worst, 2e-3);
}

TEST(motion_compensation, cheby_presum_tf_domain_along_the_path)
{
    // TF domain: subcarrier n of the scene centre's echo, exp(-j 4 pi (fc + n Delta f) R / c),
    // R from the swaying path to the scene centre; output g = D x its value at the window centre.
    const numerology num = numerology::preset("tiny");
    const scene scn = scene::preset("paper3");
    const unsigned d = 8, pulses = 1600, n_sc = num.num_subcarriers;
    const double t = num.symbol_s();
    const trajectory path = swaying({ -0.2, 0.0, 0.1 }, 2.0, 0.2);
    kernel::presum_config cfg;
    cfg.decim = d;
    cfg.domain = presum_domain::TF;
    kernel::cheby_presum k(num, geo, scn, n_sc, 0.0, 1.0, cfg, path);
    double yc = 0.0, rc = 0.0;
    kernel::los_reference::scene_centre(geo, scn, yc, rc);
    const double xc = std::sqrt(rc * rc - geo.height_m * geo.height_m);
    auto phase = [&](unsigned n, double time) {
        const vec3 p = path.position(time);
        const double r = std::sqrt((p[0] - xc) * (p[0] - xc) + (p[1] - yc) * (p[1] - yc) + p[2] * p[2]);
        return 4 * M_PI * (geo.carrier_hz + n * num.subcarrier_spacing_hz) * r / speed_of_light;
    };
    std::vector<gr_complex> x(std::size_t(pulses) * n_sc), o(n_sc);
    for (unsigned p = 0; p < pulses; ++p)
        for (unsigned n = 0; n < n_sc; ++n)
            x[std::size_t(p) * n_sc + n] = gr_complex(std::polar(1.0, -phase(n, p * t)));
    double worst = 0.0;
    const unsigned g0 = (k.num_taps() + d - 1) / d;
    for (unsigned p = 0; p < pulses; ++p)
        if (k.push(x.data() + std::size_t(p) * n_sc, o.data()) && k.pulses_out() > g0) {
            const unsigned g = k.pulses_out() - 1;
            for (unsigned n = 0; n < n_sc; ++n) {
                const cd want = double(d) * std::polar(1.0, -phase(n, (g * d + k.centre_offset()) * t));
                worst = std::max(worst, std::abs(cd(o[n]) - want) / d);
            }
        }
    ASSERT_GT(k.pulses_out(), 100u);
    EXPECT_LT(worst, 2e-3);
}

TEST(motion_compensation, rd_focuser_moco_restores_the_ideal_image)
{
    // The exact range-compressed echo (eqs. 8, 29) of the scene-centre target seen from a
    // swaying path (20 cm, 1.5 s), motion-compensated and focused by the streaming focuser,
    // against the same target's echo from the ideal line focused without compensation.
    // 1.5 m range bins (32 subcarriers, a 64-point range IFFT), PRF 400 Hz.
    numerology num = numerology::preset("tiny");
    num.subcarrier_spacing_hz = speed_of_light / (2 * 64 * 1.5);
    num.num_subcarriers = 32;
    num.cp_samples = 0;
    const unsigned spp = 3903, K = 16, N = num.num_subcarriers, nfft = num.fft_size;
    const double T = num.symbol_s() * spp, rho = num.range_bin_m(nfft);
    geometry g = geo;
    g.aperture_s = 0.5;
    const double x_t = 800.0, y_t = 12.5;
    const double r0 = std::hypot(x_t, g.height_m), first = r0 - 5.3 * rho;
    scene scn;
    scn.targets.push_back(point_target(x_t, y_t));
    const unsigned M = static_cast<unsigned>(std::lround(g.aperture_s / T));
    const trajectory path = swaying({ 0.05, 0.0, 0.1 }, 0.2, 1.0);
    auto echo = [&](bool flown) {
        std::vector<gr_complex> e(std::size_t(M) * K);
        for (unsigned m = 0; m < M; ++m) {
            const vec3 p = flown ? path.position(m * T)
                                 : vec3{ 0.0, g.track_start_m + g.velocity_mps * m * T, g.height_m };
            const double r = std::sqrt((p[0] - x_t) * (p[0] - x_t) + (p[1] - y_t) * (p[1] - y_t) + p[2] * p[2]);
            const double kq = (r - first) / rho;
            for (unsigned k = 0; k < K; ++k) {
                cd s = 0.0;
                for (unsigned n = 0; n < N; ++n)
                    s += std::polar(1.0, 2 * M_PI * n * (k - kq) / nfft);
                s *= std::polar(1.0 / std::sqrt(double(N)), -4 * M_PI * g.carrier_hz * r / speed_of_light);
                e[std::size_t(m) * K + k] = gr_complex(s);
            }
        }
        return e;
    };
    auto image = [&](const std::vector<gr_complex>& e, moco_order moco, const trajectory& nav) {
        focuser_config cfg;
        cfg.symbols_per_pulse = spp;
        cfg.lines_per_aperture = M;
        cfg.overlap_lines = 0;
        cfg.moco = moco;
        kernel::aperture_focuser f(num, g, scn, K, cfg, T, first, rho, nav);
        f.prepare();
        f.ingest(e.data(), M);
        f.focus(false);
        std::vector<gr_complex> img(std::size_t(M) * K);
        f.read_image(img.data(), 0, M);
        return img;
    };
    const auto ref = image(echo(false), moco_order::OFF, trajectory());
    const auto flown = echo(true);
    auto nmse = [&](const std::vector<gr_complex>& img) {
        double num_ = 0.0, den = 0.0;
        for (std::size_t i = 0; i < img.size(); ++i) {
            num_ += std::norm(cd(img[i]) - cd(ref[i]));
            den += std::norm(cd(ref[i]));
        }
        return num_ / den;
    };
    // The target sits at the reference range: the first order restores it exactly (up to
    // float32 and the interpolator). The second order gives every bin its own residual, so the
    // target's range sidelobes (0.3 bin off-grid) get their bins' phases: d (dtheta / dR) dR
    // = 0.2 m x 1e-3 / m x 15 m = 0.4 rad ten bins away, about 0.5 % of the image energy.
    EXPECT_LT(nmse(image(flown, moco_order::FIRST, path)), 1e-4);
    EXPECT_LT(nmse(image(flown, moco_order::SECOND, path)), 1e-2);
    EXPECT_GT(nmse(image(flown, moco_order::OFF, path)), 0.1);
}
