/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::scene_echo against a direct double-precision evaluation of eqs. (7)-(8)
// written here independently of the kernel.

#include <gnuradio/nrsar/kernel/scene_echo.h>
#include <gnuradio/nrsar/trajectory.h>
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

using namespace gr::nrsar;
using cd = std::complex<double>;

namespace {

// eq. (7) with (8) in float64: Y[n] = sum_q alpha_q S[n] exp(-j 4 pi (fc + n df) R_q / c).
std::vector<cd> direct_echo(const numerology& num,
                            const geometry& geo,
                            const scene& scn,
                            std::uint64_t m,
                            const std::vector<gr_complex>& s)
{
    const double tsym = 1.0 / num.subcarrier_spacing_hz +
                        num.cp_samples / (num.fft_size * num.subcarrier_spacing_hz);
    const double yp = geo.track_start_m + geo.velocity_mps * static_cast<double>(m) * tsym;
    const double c = 299792458.0;
    std::vector<cd> y(num.num_subcarriers, cd(0.0, 0.0));
    for (const auto& t : scn.targets) {
        const double dy = yp - t.y_m;
        const double R = std::sqrt(t.x_m * t.x_m + geo.height_m * geo.height_m + dy * dy);
        const cd alpha = std::polar(std::sqrt(t.rcs), t.phase_rad);
        for (unsigned n = 0; n < num.num_subcarriers; n++) {
            const double f = geo.carrier_hz + n * num.subcarrier_spacing_hz;
            y[n] += alpha * cd(s[n]) * std::polar(1.0, -4.0 * M_PI * f * R / c);
        }
    }
    return y;
}

double rel_error_db(const std::vector<gr_complex>& got, const std::vector<cd>& ref)
{
    double err = 0.0, pow = 0.0;
    for (size_t i = 0; i < ref.size(); i++) {
        err += std::norm(cd(got[i]) - ref[i]);
        pow += std::norm(ref[i]);
    }
    return 10.0 * std::log10(err / pow);
}

std::vector<gr_complex> random_qam(unsigned n, unsigned seed)
{
    std::mt19937 gen(seed);
    std::uniform_int_distribution<int> level(0, 15);
    std::vector<gr_complex> s(n);
    for (auto& v : s) // 256-QAM levels, unit mean power
        v = gr_complex((2 * level(gen) - 15) / std::sqrt(170.0f),
                       (2 * level(gen) - 15) / std::sqrt(170.0f));
    return s;
}

scene test_scene()
{
    scene scn = scene::preset("paper3");
    scn.targets[1].rcs = 0.5;
    scn.targets[1].phase_rad = 1.0;
    scn.targets[2].rcs = 2.0;
    scn.targets[2].phase_rad = -2.5;
    return scn;
}

} // namespace

class EchoAtSymbol : public ::testing::TestWithParam<std::uint64_t>
{
};

// The kernel's echo and reference outputs at symbol m against direct_echo, both < -80 dB.
static void expect_echo_below_80db(const scene& scn, std::uint64_t m, unsigned seed, const char* what)
{
    const auto num = numerology::preset("paper");
    const auto geo = geometry::preset("paper");
    kernel::scene_echo k(num, geo, scn);
    const auto s = random_qam(num.num_subcarriers, seed);
    std::vector<gr_complex> y(num.num_subcarriers), h(num.num_subcarriers);
    k.echo(m, s.data(), y.data(), h.data());

    const double err_y = rel_error_db(y, direct_echo(num, geo, scn, m, s));
    const std::vector<gr_complex> ones(num.num_subcarriers, gr_complex(1.0f, 0.0f));
    const double err_h = rel_error_db(h, direct_echo(num, geo, scn, m, ones));
    ::testing::Test::RecordProperty("error_y_db", std::to_string(err_y));
    std::printf("%sm = %llu: echo error %.1f dB, reference error %.1f dB\n",
                what,
                static_cast<unsigned long long>(m),
                err_y,
                err_h);
    EXPECT_LT(err_y, -80.0);
    EXPECT_LT(err_h, -80.0);
}

TEST_P(EchoAtSymbol, MatchesDirectFloat64Below80dB)
{
    expect_echo_below_80db(test_scene(), GetParam(), 7, "");
}

// Start, end of the paper's 2 s aperture, and a long stream (no drift).
INSTANTIATE_TEST_SUITE_P(Paper,
                         EchoAtSymbol,
                         ::testing::Values(0ull, 48000ull, 10000000ull));

TEST(SceneEcho, ReferenceEqualsEchoOfOnes)
{
    const auto num = numerology::preset("small");
    kernel::scene_echo k(num, geometry::preset("paper"), scene::preset("paper3"));
    std::vector<gr_complex> ones(num.num_subcarriers, gr_complex(1.0f, 0.0f));
    std::vector<gr_complex> y(num.num_subcarriers), h(num.num_subcarriers);
    k.echo(123, ones.data(), y.data());
    k.reference(123, h.data());
    for (unsigned n = 0; n < num.num_subcarriers; n++)
        EXPECT_EQ(y[n], h[n]) << n;
}

TEST(SceneEcho, ZeroRcsSceneIsSilent)
{
    const auto num = numerology::preset("tiny");
    scene scn;
    scn.targets = { point_target(300.0, 100.0, 0.0) };
    kernel::scene_echo k(num, geometry::preset("paper"), scn);
    std::vector<gr_complex> h(num.num_subcarriers, gr_complex(5.0f, 5.0f));
    k.reference(0, h.data());
    for (const auto& v : h)
        EXPECT_EQ(v, gr_complex(0.0f, 0.0f));
}

TEST(SceneEcho, PlatformMovesWithSymbolIndex)
{
    const auto num = numerology::preset("paper");
    const auto geo = geometry::preset("paper");
    kernel::scene_echo k(num, geo, scene::preset("paper3"));
    EXPECT_DOUBLE_EQ(k.platform_y(0), 0.0);
    // 48000 symbols of 41.67 us at 50 m/s: 100 m.
    EXPECT_NEAR(k.platform_y(48000), 100.0, 1e-9);
}

TEST(SceneEcho, RejectsInvalidScene)
{
    const auto num = numerology::preset("tiny");
    kernel::scene_echo k(num, geometry::preset("paper"), scene::preset("paper3"));
    scene bad;
    EXPECT_THROW(k.set_scene(bad), std::invalid_argument);
    bad.targets = { point_target(300.0, NAN) };
    EXPECT_THROW(k.set_scene(bad), std::invalid_argument);
    EXPECT_EQ(k.get_scene().targets.size(), 3u); // unchanged after a refused update
}

TEST(SceneEcho, GenericPathMatchesDirectFloat64)
{
    const auto num = numerology::preset("paper");
    const auto geo = geometry::preset("paper");
    const auto scn = test_scene();
    kernel::scene_echo k(num, geo, scn);
    k.set_simd(false);
    EXPECT_STREQ(k.implementation(), "generic");
    const auto s = random_qam(num.num_subcarriers, 8);
    std::vector<gr_complex> y(num.num_subcarriers);
    k.echo(48000, s.data(), y.data());
    EXPECT_LT(rel_error_db(y, direct_echo(num, geo, scn, 48000, s)), -80.0);
}

TEST(SceneEcho, ManyTargetsAccumulateAcrossChunks)
{
    // 9 targets: three passes of at most 4 targets over every block.
    const auto num = numerology::preset("small");
    const auto geo = geometry::preset("paper");
    scene scn;
    for (int i = 0; i < 9; i++)
        scn.targets.push_back(point_target(240.0 + 10.0 * i, 90.0 + 5.0 * i, 0.5 + 0.1 * i, 0.3 * i));
    kernel::scene_echo k(num, geo, scn);
    const auto s = random_qam(num.num_subcarriers, 9);
    std::vector<gr_complex> y(num.num_subcarriers);
    k.echo(777, s.data(), y.data());
    EXPECT_LT(rel_error_db(y, direct_echo(num, geo, scn, 777, s)), -80.0);
}

TEST(SceneEcho, FusedNoiseIsTheGeneratorsStream)
{
    // echo(..., noise, sigma) adds exactly noise.generate(m, sigma) (both paths; N = 3333
    // leaves a partial group at the end).
    const auto num = numerology::preset("paper");
    const auto s = random_qam(num.num_subcarriers, 10);
    for (bool simd : { true, false }) {
        kernel::scene_echo k(num, geometry::preset("paper"), test_scene());
        k.set_simd(simd);
        kernel::gaussian_noise g(77, simd);
        std::vector<gr_complex> fused(num.num_subcarriers), separate(num.num_subcarriers);
        k.echo(4321, s.data(), fused.data(), nullptr, &g, 0.3f);
        k.echo(4321, s.data(), separate.data());
        g.add(4321, 0.3f, separate.data(), separate.size());
        for (unsigned n = 0; n < num.num_subcarriers; n++)
            ASSERT_EQ(fused[n], separate[n]) << "simd " << simd << " n " << n;
    }
}

TEST(SceneEcho, NonFiniteInputCountsAsZero)
{
    const auto num = numerology::preset("small");
    const auto geo = geometry::preset("paper");
    const auto scn = test_scene();
    for (bool simd : { true, false }) {
        kernel::scene_echo k(num, geo, scn);
        k.set_simd(simd);
        auto s = random_qam(num.num_subcarriers, 11);
        s[3] = gr_complex(NAN, 0.0f);
        s[100] = gr_complex(0.0f, INFINITY);
        s[511] = gr_complex(-INFINITY, NAN);
        std::vector<gr_complex> y(num.num_subcarriers);
        EXPECT_EQ(k.echo(5, s.data(), y.data()), 3u);
        s[3] = s[100] = s[511] = gr_complex(0.0f, 0.0f);
        EXPECT_LT(rel_error_db(y, direct_echo(num, geo, scn, 5, s)), -80.0);
        EXPECT_EQ(k.echo(5, s.data(), y.data()), 0u);
    }
}

// stress: very long streams and large target phases (docs/stress.md). Symbol 10^8 (70 min
// of stream, platform 208 km on, range phase 3e7 rad) and just past 2^32 symbols (50 h; a
// 32-bit symbol counter would wrap here: phase 1.3e9 rad, where the float64 reference still
// holds ~3e-7 rad), with target phases of 1e5 .. 3e6 rad on top.
class StressEchoAtSymbol : public ::testing::TestWithParam<std::uint64_t>
{
};

TEST_P(StressEchoAtSymbol, LargePhasesMatchDirectFloat64Below80dB)
{
    auto scn = scene::preset("paper3");
    scn.targets[0].phase_rad = 1.0e5;
    scn.targets[1].phase_rad = -2.5e5;
    scn.targets[1].rcs = 0.25;
    scn.targets[2].phase_rad = 3.0e6;
    expect_echo_below_80db(scn, GetParam(), 11, "stress ");
}

INSTANTIATE_TEST_SUITE_P(LongStream,
                         StressEchoAtSymbol,
                         ::testing::Values(0ull, 10000000ull, 100000000ull,
                                           4294967296ull + 12345ull));

namespace {
// A swaying flight: x = A sin(w t), z = H + A cos(w t), y = v t (A = 0.3 m, w = pi rad/s),
// sampled at 100 Hz (interpolation error below 2e-8 m, i.e. -115 dB of phase here).
constexpr double sway_a = 0.3, sway_w = M_PI;

vec3 sway_at(const geometry& geo, double t)
{
    return { sway_a * std::sin(sway_w * t),
             geo.track_start_m + geo.velocity_mps * t,
             geo.height_m + sway_a * std::cos(sway_w * t) };
}

trajectory sway_path(const geometry& geo)
{
    std::vector<double> t;
    std::vector<vec3> p;
    for (int i = 0; i <= 300; i++) {
        t.push_back(0.01 * i);
        p.push_back(sway_at(geo, 0.01 * i));
    }
    return trajectory::from_samples(t, p);
}

// eq. (7) in float64 with the exact range from the antenna at p.
std::vector<cd> direct_echo_at(const numerology& num,
                               const geometry& geo,
                               const scene& scn,
                               const vec3& p,
                               const std::vector<gr_complex>& s)
{
    const double c = 299792458.0;
    std::vector<cd> y(num.num_subcarriers, cd(0.0, 0.0));
    for (const auto& t : scn.targets) {
        const double R = std::sqrt((t.x_m - p[0]) * (t.x_m - p[0]) +
                                   (t.y_m - p[1]) * (t.y_m - p[1]) + p[2] * p[2]);
        const cd alpha = std::polar(std::sqrt(t.rcs), t.phase_rad);
        for (unsigned n = 0; n < num.num_subcarriers; n++) {
            const double f = geo.carrier_hz + n * num.subcarrier_spacing_hz;
            y[n] += alpha * cd(s[n]) * std::polar(1.0, -4.0 * M_PI * f * R / c);
        }
    }
    return y;
}
} // namespace

TEST(SceneEcho, SwayingPathMatchesDirectFloat64Below80dB)
{
    const auto num = numerology::preset("paper");
    const auto geo = geometry::preset("paper");
    const auto scn = test_scene();
    kernel::scene_echo k(num, geo, scn, sway_path(geo));
    const auto s = random_qam(num.num_subcarriers, 9);
    std::vector<gr_complex> y(num.num_subcarriers);
    for (bool simd : { true, false }) {
        k.set_simd(simd);
        for (std::uint64_t m : { 0ull, 12345ull, 47999ull }) {
            k.echo(m, s.data(), y.data());
            const double t = static_cast<double>(m) * num.symbol_s();
            EXPECT_LT(rel_error_db(y, direct_echo_at(num, geo, scn, sway_at(geo, t), s)), -80.0)
                << "symbol " << m << " " << k.implementation();
            // the test can tell: the ideal line's echo is far off (the sway is ~7 wavelengths)
            EXPECT_GT(rel_error_db(y, direct_echo(num, geo, scn, m, s)), -10.0);
        }
    }
}

// stress (docs/stress.md): a 2000 s flight, 100 km of track, sampled at 10 Hz (a GNSS/INS
// record's rate): slow sway of 1 m (0.05 Hz) across, 0.5 m (0.1 Hz) vertically and 4 m
// (0.02 Hz, 0.5 m/s of speed variation) along track, whose interpolation error is below
// 3e-9 m (h^4 max|p''''| / 384). The echo near the end (symbol 4.8e7) of targets where the
// platform then is, against eq. (7) in float64 from the analytic position: as at the start.
TEST(SceneEcho, LongFlightLateEchoMatchesDirectFloat64Below80dB)
{
    const auto num = numerology::preset("paper");
    const auto geo = geometry::preset("paper");
    const double w1 = 2 * M_PI * 0.05, w2 = 2 * M_PI * 0.02, w3 = 2 * M_PI * 0.1;
    auto at = [&](double t) {
        return vec3{ std::sin(w1 * t),
                     geo.track_start_m + geo.velocity_mps * t + 4.0 * std::sin(w2 * t),
                     geo.height_m + 0.5 * std::cos(w3 * t) };
    };
    std::vector<double> t;
    std::vector<vec3> p;
    for (int i = 0; i <= 20000; i++) {
        t.push_back(0.1 * i);
        p.push_back(at(0.1 * i));
    }
    kernel::scene_echo k(num, geo, test_scene(), trajectory::from_samples(t, p));
    const auto s = random_qam(num.num_subcarriers, 12);
    std::vector<gr_complex> y(num.num_subcarriers);
    for (std::uint64_t m : { 12345ull, 47960123ull }) {
        const double tm = static_cast<double>(m) * num.symbol_s();
        scene scn = test_scene();
        for (auto& q : scn.targets)
            q.y_m += geo.velocity_mps * std::floor(tm);
        k.set_scene(scn);
        for (bool simd : { true, false }) {
            k.set_simd(simd);
            k.echo(m, s.data(), y.data());
            const double err = rel_error_db(y, direct_echo_at(num, geo, scn, at(tm), s));
            EXPECT_LT(err, -80.0) << "symbol " << m << " " << k.implementation();
            std::printf("long flight: echo at %.3f s (y %.0f m) %s: %.1f dB\n", tm,
                        at(tm)[1], k.implementation(), err);
        }
    }
}

TEST(SceneEcho, IdealLinePathIsBitIdentical)
{
    const auto num = numerology::preset("small");
    const auto geo = geometry::preset("paper");
    const auto scn = test_scene();
    kernel::scene_echo plain(num, geo, scn), line(num, geo, scn, trajectory::ideal(geo));
    const auto s = random_qam(num.num_subcarriers, 10);
    std::vector<gr_complex> a(num.num_subcarriers), b(num.num_subcarriers);
    for (std::uint64_t m : { 0ull, 777ull, 40000ull }) {
        plain.echo(m, s.data(), a.data());
        line.echo(m, s.data(), b.data());
        EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(gr_complex)));
    }
    geometry other = geo;
    other.velocity_mps = 40.0;
    EXPECT_THROW(kernel::scene_echo(num, geo, scn, trajectory::ideal(other)),
                 std::invalid_argument);
}
