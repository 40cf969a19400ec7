/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::extended_scene (spreading + FFT) against a direct double-precision evaluation of
// eqs. (7)-(8) written here independently of the kernel.

#include <gnuradio/nrsar/kernel/extended_scene.h>
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <vector>

using namespace gr::nrsar;
using cd = std::complex<double>;

namespace {

struct scatterer {
    double x, y;
    cd a;
};

// H[n] = sum_k a_k exp(-j 4 pi (fc + n df) R_k / c), phase of every RE from scratch in double.
std::vector<cd> direct(const numerology& num,
                       const geometry& geo,
                       const std::vector<scatterer>& sc,
                       std::uint64_t m)
{
    const double c = 299792458.0;
    const double tsym = 1.0 / num.subcarrier_spacing_hz +
                        num.cp_samples / (num.fft_size * num.subcarrier_spacing_hz);
    const double yp = geo.track_start_m + geo.velocity_mps * double(m) * tsym;
    std::vector<cd> h(num.num_subcarriers);
    for (const auto& s : sc) {
        const double R =
            std::sqrt(s.x * s.x + geo.height_m * geo.height_m + (yp - s.y) * (yp - s.y));
        // 2 R fc / c reduced mod 1 in long double, then n tau added per subcarrier (< 1e3
        // cycles: error ~1e-13 cycles in double)
        long double c0 = 2.0L * R * geo.carrier_hz / c;
        c0 -= std::floor(c0);
        const double tau = 2.0 * R * num.subcarrier_spacing_hz / c;
        for (unsigned n = 0; n < num.num_subcarriers; n++)
            h[n] += s.a * std::polar(1.0, -2.0 * M_PI * (double(c0) + n * tau));
    }
    return h;
}

double error_db(const std::vector<cd>& ref, const std::vector<gr_complex>& h)
{
    double e = 0, p = 0;
    for (std::size_t n = 0; n < ref.size(); n++) {
        e += std::norm(ref[n] - cd(h[n]));
        p += std::norm(ref[n]);
    }
    return 10 * std::log10(e / p);
}

// A 24 x 20 map with 1 m pixels around (300, 100), random complex amplitudes, some zeros,
// plus two point targets.
void small_scene(kernel::reflectivity_map& map, scene& pts, std::vector<scatterer>& sc)
{
    std::mt19937 gen(7);
    std::normal_distribution<float> g;
    map.nx = 24;
    map.ny = 20;
    map.dx = 0.9;
    map.dy = 1.1;
    map.x0 = 290.0;
    map.y0 = 90.0;
    map.values.resize(map.nx * map.ny);
    for (unsigned j = 0; j < map.ny; j++)
        for (unsigned i = 0; i < map.nx; i++) {
            gr_complex v(g(gen), g(gen));
            if ((i + j) % 7 == 0)
                v = 0.0f;
            map.values[j * map.nx + i] = v;
            sc.push_back({ map.x0 + i * map.dx, map.y0 + j * map.dy, cd(v) });
        }
    pts.targets = { point_target(250.0, 100.0, 4.0, 0.3), point_target(310.0, 95.0, 1.0, -1.0) };
    for (const auto& t : pts.targets)
        sc.push_back({ t.x_m, t.y_m, std::polar(std::sqrt(t.rcs), t.phase_rad) });
}

} // namespace

TEST(ExtendedScene, FastMatchesDirectSumPaper)
{
    const auto num = numerology::preset("paper");
    const auto geo = geometry::preset("paper");
    kernel::reflectivity_map map;
    scene pts;
    std::vector<scatterer> sc;
    small_scene(map, pts, sc);
    for (std::uint64_t m : { 0ull, 24000ull, 47999ull }) {
        const auto ref = direct(num, geo, sc, m);
        kernel::extended_scene k(num, geo, pts, { map });
        std::size_t zeros = 0;
        for (const auto& v : map.values)
            zeros += v == gr_complex(0.0f, 0.0f);
        EXPECT_EQ(k.num_scatterers(), sc.size() - zeros); // zero pixels skipped
        std::vector<gr_complex> h(num.num_subcarriers);
        k.reference(m, h.data());
        const double e = error_db(ref, h);
        // default kernel L = 8, O = 2: at the float floor (measured about -130 dB)
        EXPECT_LT(e, -100.0) << "m = " << m;
        // a short kernel (L = 4) is a run-time-vs-error knob: worse, still below -50 dB
        kernel::extended_scene k4(num, geo, pts, { map }, kernel::antenna_beam(), 4, 2.0);
        k4.reference(m, h.data());
        const double e4 = error_db(ref, h);
        EXPECT_LT(e4, -50.0);
        EXPECT_GT(e4, e + 20.0);
        // the slow exact path of the kernel agrees with this test's direct sum
        k.reference_exact(m, h.data());
        EXPECT_LT(error_db(ref, h), -100.0);
    }
}

TEST(ExtendedScene, EchoMultipliesAndCountsNonFinite)
{
    const auto num = numerology::preset("tiny");
    const auto geo = geometry::preset("paper");
    kernel::extended_scene k(num, geo, scene::preset("paper3"), {});
    const unsigned N = num.num_subcarriers;
    std::vector<gr_complex> s(N, gr_complex(0.5f, -0.5f)), y(N), h(N);
    s[3] = gr_complex(NAN, 0.0f);
    EXPECT_EQ(k.echo(10, s.data(), y.data(), h.data()), 1u);
    for (unsigned n = 0; n < N; n++) {
        const gr_complex want = n == 3 ? gr_complex(0.0f) : s[n] * h[n];
        EXPECT_NEAR(std::abs(y[n] - want), 0.0, 1e-6);
    }
}

TEST(ExtendedScene, AzimuthNullsOfEq1)
{
    auto geo = geometry::preset("paper");
    kernel::antenna_beam beam;
    beam.mode = kernel::beam_mode::AZIMUTH;
    beam.az_aperture_m = 1.0;
    const double lambda = geo.wavelength_m();
    const double x = 300.0, R0 = std::hypot(x, geo.height_m);
    // u = D dy / (R lambda) = 1: dy = R lambda / D / sqrt(1 - (lambda / D)^2)
    const double s1 = lambda / beam.az_aperture_m;
    const double dy = R0 * s1 / std::sqrt(1 - s1 * s1);
    EXPECT_NEAR(beam.azimuth_gain(geo, dy, std::hypot(R0, dy)), 0.0, 1e-12);
    EXPECT_NEAR(beam.azimuth_gain(geo, 0.0, R0), 1.0, 1e-15);
    // half-power (one-way) edge of eq. (1): two-way amplitude 0.5
    const double s3 = 0.443 * lambda / beam.az_aperture_m;
    const double dy3 = R0 * s3 / std::sqrt(1 - s3 * s3);
    EXPECT_NEAR(beam.azimuth_gain(geo, dy3, std::hypot(R0, dy3)), 0.5, 2e-3);
    // eq. (2), eq. (3) at the paper's values (D = 0.1 m, theta_c = pi / 4)
    kernel::antenna_beam paper;
    const double th = 0.886 * lambda / 0.1;
    EXPECT_NEAR(paper.azimuth_coverage_m(geo), 2000.0 / std::cos(M_PI / 4) * std::tan(th / 2), 1e-9);
    EXPECT_NEAR(paper.elevation_coverage_m(geo),
                1000.0 * (std::tan(M_PI / 4 + th / 2) - std::tan(M_PI / 4 - th / 2)),
                1e-9);
}

TEST(ExtendedScene, InvalidParameters)
{
    const auto num = numerology::preset("tiny");
    const auto geo = geometry::preset("paper");
    kernel::reflectivity_map map;
    EXPECT_THROW(kernel::extended_scene(num, geo, scene(), { map }), std::invalid_argument);
    map.nx = 2;
    map.ny = 2;
    map.values.assign(3, gr_complex(1.0f));
    EXPECT_THROW(kernel::extended_scene(num, geo, scene(), { map }), std::invalid_argument);
    map.values.assign(4, gr_complex(1.0f));
    map.dx = 0.0;
    EXPECT_THROW(kernel::extended_scene(num, geo, scene(), { map }), std::invalid_argument);
    map.dx = 1.0;
    EXPECT_THROW(kernel::extended_scene(num, geo, scene(), { map }, {}, 7), std::invalid_argument);
    EXPECT_THROW(kernel::extended_scene(num, geo, scene(), { map }, {}, 8, 1.0),
                 std::invalid_argument);
    kernel::antenna_beam beam;
    beam.az_aperture_m = -1.0;
    EXPECT_THROW(kernel::extended_scene(num, geo, scene(), { map }, beam), std::invalid_argument);
}
