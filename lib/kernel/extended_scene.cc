/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/extended_scene.h>
#include <gnuradio/nrsar/kernel/fft_size.h>
#include <volk/volk.h>
#include <algorithm>
#include <cmath>
#include <type_traits>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
constexpr double two_pi = 6.283185307179586476925286766559;
constexpr double pi = 3.14159265358979323846264338328;

double sinc(double u) { return u == 0.0 ? 1.0 : std::sin(pi * u) / (pi * u); }

// Kaiser-Bessel shape parameter for L taps at oversampling O (Beatty et al., IEEE TMI
// 2005, eq. 5): puts the first zero of the kernel's transform where the first alias starts.
double kb_beta(unsigned L, double O)
{
    const double t = (L / O) * (L / O) * (O - 0.5) * (O - 0.5) - 0.8;
    return pi * std::sqrt(std::max(t, 1.0));
}

// Continuous Fourier transform of the truncated Kaiser-Bessel window
// I0(beta sqrt(1 - (2 d / L)^2)), |d| <= L / 2, at frequency u (cycles per grid cell).
double kb_transform(unsigned L, double beta, double u)
{
    const double a = pi * L * u;
    const double s = beta * beta - a * a;
    if (s > 0) {
        const double r = std::sqrt(s);
        return L * std::sinh(r) / r;
    }
    if (s < 0) {
        const double r = std::sqrt(-s);
        return L * std::sin(r) / r;
    }
    return L;
}
} // namespace

void reflectivity_map::validate() const
{
    check_at_least("map.nx", nx, 1u);
    check_at_least("map.ny", ny, 1u);
    check_finite_positive("map.dx", dx);
    check_finite_positive("map.dy", dy);
    check_finite("map.x0", x0);
    check_finite("map.y0", y0);
    if (values.size() != std::size_t(nx) * ny)
        throw_param("map.values.size()", values.size(), "must equal nx * ny");
    for (std::size_t i = 0; i < values.size(); i++)
        if (!std::isfinite(values[i].real()) || !std::isfinite(values[i].imag()))
            throw_param("map.values[" + std::to_string(i) + "]", values[i], "must be finite");
}

void antenna_beam::validate() const
{
    check_finite_positive("beam.az_aperture_m", az_aperture_m);
    check_finite_positive("beam.el_aperture_m", el_aperture_m);
    check_range("beam.el_center_rad", el_center_rad, 0.0, pi / 2);
    check_finite_positive("beam.cutoff", cutoff);
}

double antenna_beam::azimuth_beamwidth_rad(const geometry& geo) const
{
    return 0.886 * geo.wavelength_m() / az_aperture_m; // eq. (1)
}

double antenna_beam::elevation_beamwidth_rad(const geometry& geo) const
{
    return 0.886 * geo.wavelength_m() / el_aperture_m; // eq. (1)
}

double antenna_beam::azimuth_coverage_m(const geometry& geo) const
{
    // eq. (2)
    return 2.0 * geo.height_m / std::cos(el_center_rad) *
           std::tan(azimuth_beamwidth_rad(geo) / 2.0);
}

double antenna_beam::elevation_coverage_m(const geometry& geo) const
{
    // eq. (3)
    const double half = elevation_beamwidth_rad(geo) / 2.0;
    return geo.height_m * (std::tan(el_center_rad + half) - std::tan(el_center_rad - half));
}

double antenna_beam::elevation_of_look(const geometry& geo, double look_rad) const
{
    if (mode != beam_mode::AZIMUTH_ELEVATION)
        return 1.0;
    const double u = el_aperture_m * std::sin(look_rad - el_center_rad) / geo.wavelength_m();
    if (std::abs(u) > cutoff)
        return 0.0;
    const double s = sinc(u);
    return s * s; // two-way amplitude = one-way power pattern
}

double antenna_beam::azimuth_of_sine(const geometry& geo, double sin_squint) const
{
    if (mode == beam_mode::WHOLE_BLOCK)
        return 1.0;
    const double u = az_aperture_m * sin_squint / geo.wavelength_m();
    if (std::abs(u) > cutoff)
        return 0.0;
    const double s = sinc(u);
    return s * s;
}

double antenna_beam::elevation_gain(const geometry& geo, double x_m) const
{
    return elevation_of_look(geo, std::atan2(x_m, geo.height_m));
}

double antenna_beam::azimuth_gain(const geometry& geo, double dy_m, double range_m) const
{
    if (mode == beam_mode::WHOLE_BLOCK)
        return 1.0;
    const double u = az_aperture_m * dy_m / (range_m * geo.wavelength_m());
    if (std::abs(u) > cutoff)
        return 0.0;
    const double s = sinc(u);
    return s * s;
}

double antenna_beam::gain(const geometry& geo,
                          const antenna_pose& pose,
                          double x_q,
                          double y_q,
                          double range_m) const
{
    if (mode == beam_mode::WHOLE_BLOCK)
        return 1.0;
    const vec3& p = pose.position;
    if (!pose.steered) {
        const double g = azimuth_gain(geo, y_q - p[1], range_m);
        return g == 0.0 ? 0.0 : g * elevation_of_look(geo, std::atan2(x_q - p[0], p[2]));
    }
    // Line of sight into the body: l = R^T (q - p) / |q - p|.
    const mat3& r = pose.rotation;
    const double d[3] = { (x_q - p[0]) / range_m, (y_q - p[1]) / range_m, -p[2] / range_m };
    const double lx = r[0] * d[0] + r[3] * d[1] + r[6] * d[2];
    const double ly = r[1] * d[0] + r[4] * d[1] + r[7] * d[2];
    const double lz = r[2] * d[0] + r[5] * d[1] + r[8] * d[2];
    const double g = azimuth_of_sine(geo, ly);
    return g == 0.0 ? 0.0 : g * elevation_of_look(geo, std::atan2(lx, -lz));
}

antenna_pose antenna_pose::of(const trajectory& path, double t)
{
    antenna_pose pose;
    pose.position = path.position(t);
    pose.steered = path.has_attitude();
    if (pose.steered)
        pose.rotation = attitude_matrix(path.attitude(t));
    return pose;
}

extended_scene::extended_scene(const numerology& num,
                               const geometry& geo,
                               const scene& points,
                               const std::vector<reflectivity_map>& maps,
                               const antenna_beam& beam,
                               unsigned taps,
                               double oversampling,
                               const trajectory& path)
    : d_num(num), d_geo(geo), d_beam(beam), d_path(path), d_line(true), d_L(taps)
{
    num.validate();
    geo.validate();
    d_line = flies_ideal_line(path, geo);
    if (!points.targets.empty()) // an extended scene may have maps only
        points.validate();
    beam.validate();
    for (const auto& map : maps)
        map.validate();
    if (taps < 2 || taps > 32 || taps % 2)
        throw_param("taps", taps, "must be even and in [2, 32]");
    check_range("oversampling", oversampling, 1.25, 8.0);

    const unsigned N = num.num_subcarriers;
    d_n0 = N / 2;
    d_P = fast_fft_size(static_cast<unsigned>(std::ceil(oversampling * N)));
    const double O = double(d_P) / N; // the actual oversampling after rounding P up
    const double beta = kb_beta(d_L, O);
    const double i0_beta = std::cyl_bessel_i(0.0, beta);

    // Scatterers: map pixels (speckle, zero cells skipped) then point targets.
    auto add = [this, &geo](double x, double y, std::complex<double> a) {
        if (d_line)
            a *= d_beam.elevation_gain(geo, x); // constant over the ideal line's aperture
        if (a == std::complex<double>(0.0, 0.0))
            return;
        d_x.push_back(x);
        d_y.push_back(y);
        d_xh2.push_back(x * x + geo.height_m * geo.height_m);
        d_amp.push_back(a);
        d_ampf.push_back(gr_complex(a));
    };
    for (const auto& map : maps) {
        std::vector<gr_complex> spk;
        if (map.speckle) {
            spk.resize(map.values.size());
            gaussian_noise(map.speckle_seed).generate(0, 1.0f, spk.data(), spk.size());
        }
        for (unsigned j = 0; j < map.ny; j++)
            for (unsigned i = 0; i < map.nx; i++) {
                const std::size_t idx = std::size_t(j) * map.nx + i;
                std::complex<double> a(map.values[idx]);
                if (map.speckle)
                    a *= std::complex<double>(spk[idx]);
                d_total_power += std::norm(a);
                add(map.x0 + i * map.dx, map.y0 + j * map.dy, a);
            }
    }
    for (const auto& t : points.targets) {
        const std::complex<double> a = std::polar(std::sqrt(t.rcs), t.phase_rad);
        d_total_power += std::norm(a);
        add(t.x_m, t.y_m, a);
    }

    // Kernel table: row f holds the L weights for the fractional offset f / rows; the
    // weights of an offset in between are interpolated linearly (error ~ -110 dB at 1024).
    d_rows = 1024;
    d_table.resize(std::size_t(d_rows + 1) * d_L);
    const double half = d_L / 2.0;
    for (unsigned f = 0; f <= d_rows; f++)
        for (unsigned t = 0; t < d_L; t++) {
            const double d = t - half + 1.0 - double(f) / d_rows;
            const double r = 1.0 - (2.0 * d / d_L) * (2.0 * d / d_L);
            d_table[std::size_t(f) * d_L + t] =
                r < 0 ? 0.0f
                      : static_cast<float>(std::cyl_bessel_i(0.0, beta * std::sqrt(r)) / i0_beta);
        }
    // Deapodisation: 1 / Phi(n' / P) for n = n0 + n'.
    d_deapod.resize(N);
    for (unsigned n = 0; n < N; n++) {
        const double u = (double(n) - d_n0) / d_P;
        d_deapod[n] = static_cast<float>(i0_beta / kb_transform(d_L, beta, u));
    }
    d_grid.resize(d_P + d_L);
    d_Rb.resize(block);
    d_cycb.resize(block);
    d_posb.resize(block);
    d_snb.resize(block);
    d_csb.resize(block);
    d_h.resize(N);
    d_fft = make_fft_fwd(d_P);
}

double extended_scene::platform_y(std::uint64_t m) const
{
    return d_geo.track_start_m + d_geo.velocity_mps * (double(m) * d_num.symbol_s());
}

void extended_scene::reference(std::uint64_t m, gr_complex* h)
{
    double yp = platform_y(m);
    antenna_pose pose;
    if (!d_line) { // the true path: ranges from this symbol's phase centre
        pose = antenna_pose::of(d_path, double(m) * d_num.symbol_s());
        yp = pose.position[1];
        const double xp = pose.position[0], zz = pose.position[2] * pose.position[2];
        for (std::size_t k = 0; k < d_x.size(); k++) {
            const double dx = d_x[k] - xp;
            d_xh2[k] = dx * dx + zz;
        }
    }
    const double fc_n0 = d_geo.carrier_hz + d_n0 * d_num.subcarrier_spacing_hz;
    const double tau_scale = 2.0 * d_num.subcarrier_spacing_hz / speed_of_light;
    const double cyc_scale = 2.0 * fc_n0 / speed_of_light;
    const unsigned L = d_L;
    const double P = d_P;
    std::fill(d_grid.begin(), d_grid.end(), gr_complex(0.0f, 0.0f));
    gr_complex* grid = d_grid.data();
    const float* table = d_table.data();
    const std::size_t K = d_amp.size();
    const bool beam = d_beam.mode != beam_mode::WHOLE_BLOCK;
    double* Rb = d_Rb.data();
    double* cycb = d_cycb.data();
    double* posb = d_posb.data();
    float* snb = d_snb.data();
    float* csb = d_csb.data();
    for (std::size_t k0 = 0; k0 < K; k0 += block) {
        const std::size_t nb = std::min<std::size_t>(block, K - k0);
        const double* y = d_y.data() + k0;
        const double* xh2 = d_xh2.data() + k0;
        // Pass 1, double, vectorised by the compiler (this file has -fno-math-errno):
        // eq. (8) exact range; phase of b_k = exp(-j 2 pi 2 R (fc + n0 Delta f) / c) as
        // cycles reduced to [-0.5, 0.5] in double (1.5e5 rad, SPEC 3); position on the
        // periodic tau grid (exp(-j 2 pi n' tau) has period 1 in tau). (c + 1.5 2^52) - 1.5 2^52
        // rounds to the nearest integer without a call to floor (no SSE4.1 in the baseline).
        constexpr double round_magic = 6755399441055744.0;
        for (std::size_t i = 0; i < nb; i++) {
            const double dy = y[i] - yp;
            const double R = std::sqrt(xh2[i] + dy * dy);
            Rb[i] = R;
            double c = R * cyc_scale;
            c -= (c + round_magic) - round_magic;
            cycb[i] = c;
            double t = R * tau_scale;
            t -= (t + round_magic) - round_magic;
            t += t < 0.0 ? 1.0 : 0.0;
            posb[i] = t * P;
        }
        // Pass 2, float, vectorised: sin and cos of 2 pi c, c in [-0.5, 0.5]: quadrant
        // q = round(4 c), Taylor polynomials on [-pi/4, pi/4] (error < 3e-8; the float c
        // adds < 2e-7 rad, about -130 dB).
        constexpr float fmagic = 12582912.0f; // 1.5 2^23
        for (std::size_t i = 0; i < nb; i++) {
            const float c = static_cast<float>(cycb[i]);
            const float q = (4.0f * c + fmagic) - fmagic;
            const float a = 6.28318530717958648f * (c - 0.25f * q);
            const float a2 = a * a;
            const float sa =
                a * (1.0f + a2 * (-1.0f / 6 + a2 * (1.0f / 120 + a2 * (-1.0f / 5040 +
                                                                        a2 * (1.0f / 362880)))));
            const float ca =
                1.0f + a2 * (-0.5f + a2 * (1.0f / 24 + a2 * (-1.0f / 720 + a2 * (1.0f / 40320))));
            const int qi = static_cast<int>(q) & 3;
            const float sv = (qi & 1) ? ca : sa;
            const float cv = (qi & 1) ? sa : ca;
            snb[i] = (qi & 2) ? -sv : sv;
            csb[i] = ((qi + 1) & 2) ? -cv : cv;
        }
        // Pass 3: beam gain, b_k, kernel weights, accumulation on the grid. The tap count
        // is a template constant for the usual L (the compiler unrolls and vectorises the
        // taps), a run-time one otherwise.
        auto spread = [&](auto taps_tag) {
            constexpr unsigned LT = decltype(taps_tag)::value;
            const unsigned nt = LT ? LT : L;
            for (std::size_t i = 0; i < nb; i++) {
                const std::size_t k = k0 + i;
                float g = 1.0f;
                if (beam) {
                    g = static_cast<float>(
                        d_line ? d_beam.azimuth_gain(d_geo, y[i] - yp, Rb[i])
                               : d_beam.gain(d_geo, pose, d_x[k], y[i], Rb[i]));
                    if (g == 0.0f)
                        continue; // outside the beam (beyond the cutoff)
                }
                // b = a g exp(-j phi), written out (std::complex's operator* adds a NaN branch)
                const float ar = d_ampf[k].real() * g, ai = d_ampf[k].imag() * g;
                const float cs = csb[i], sn = snb[i];
                const float br = ar * cs + ai * sn, bi = ai * cs - ar * sn;
                const double xpos = posb[i];
                double ix = std::floor(xpos);
                if (ix >= P)    // tau rounded up to 1
                    ix = P - 1; // then the fractional offset is 1: the same point, p = P = 0
                const double ff = (xpos - ix) * d_rows;
                const unsigned f = std::min(static_cast<unsigned>(ff), d_rows - 1);
                const float a = static_cast<float>(ff - f);
                // Taps p = ix - L/2 + 1 + t; shifted by L/2 so the index is never negative.
                const std::size_t p0 = static_cast<std::size_t>(ix) + 1; // + L/2 - L/2
                const float* w0 = table + std::size_t(f) * nt;
                const float* w1 = w0 + nt;
                float* cell = reinterpret_cast<float*>(grid + p0);
                for (unsigned t = 0; t < nt; t++) {
                    const float w = w0[t] + a * (w1[t] - w0[t]);
                    cell[2 * t] += w * br;
                    cell[2 * t + 1] += w * bi;
                }
            }
        };
        switch (L) {
        case 4:
            spread(std::integral_constant<unsigned, 4>());
            break;
        case 6:
            spread(std::integral_constant<unsigned, 6>());
            break;
        case 8:
            spread(std::integral_constant<unsigned, 8>());
            break;
        case 12:
            spread(std::integral_constant<unsigned, 12>());
            break;
        default:
            spread(std::integral_constant<unsigned, 0>());
        }
    }
    // Fold the periodic grid: storage index s = p + L/2, p in [-L/2 + 1, P + L/2).
    const unsigned off = L / 2;
    gr_complex* in = d_fft->get_inbuf();
    for (unsigned p = 0; p < d_P; p++)
        in[p] = grid[p + off];
    for (unsigned s = 0; s < off; s++) // p = s - off < 0 -> p + P
        in[d_P - off + s] += grid[s];
    for (unsigned s = d_P + off; s < d_P + L; s++) // p >= P -> p - P
        in[s - off - d_P] += grid[s];
    d_fft->execute(); // G[n'] = sum_p g[p] exp(-j 2 pi n' p / P)
    const gr_complex* out = d_fft->get_outbuf();
    const unsigned N = d_num.num_subcarriers;
    for (unsigned n = 0; n < N; n++) {
        const unsigned bin = n >= d_n0 ? n - d_n0 : d_P - (d_n0 - n);
        h[n] = out[bin] * d_deapod[n];
    }
}

void extended_scene::reference_exact(std::uint64_t m, gr_complex* h) const
{
    const unsigned N = d_num.num_subcarriers;
    std::vector<std::complex<double>> acc(N);
    double yp = platform_y(m);
    antenna_pose pose;
    if (!d_line) {
        pose = antenna_pose::of(d_path, double(m) * d_num.symbol_s());
        yp = pose.position[1];
    }
    for (std::size_t k = 0; k < d_amp.size(); k++) {
        const double dy = d_y[k] - yp;
        double xh2 = d_xh2[k];
        if (!d_line) {
            const double dx = d_x[k] - pose.position[0];
            xh2 = dx * dx + pose.position[2] * pose.position[2];
        }
        const double R = std::sqrt(xh2 + dy * dy);
        const double g = d_line ? d_beam.azimuth_gain(d_geo, dy, R)
                                : d_beam.gain(d_geo, pose, d_x[k], d_y[k], R);
        if (g == 0.0)
            continue;
        double c0 = 2.0 * R * d_geo.carrier_hz / speed_of_light;
        c0 -= std::floor(c0);
        const double tau = 2.0 * R * d_num.subcarrier_spacing_hz / speed_of_light;
        // eq. (7): exp(-j 2 pi 2 R (fc + n Delta f) / c), double recurrence in n.
        std::complex<double> e = d_amp[k] * g * std::polar(1.0, -two_pi * c0);
        const std::complex<double> step = std::polar(1.0, -two_pi * tau);
        for (unsigned n = 0; n < N; n++) {
            acc[n] += e;
            e *= step;
        }
    }
    for (unsigned n = 0; n < N; n++)
        h[n] = gr_complex(acc[n]);
}

std::size_t extended_scene::echo(std::uint64_t m,
                                 const gr_complex* s,
                                 gr_complex* y,
                                 gr_complex* h,
                                 const gaussian_noise* noise,
                                 float sigma)
{
    gr_complex* hb = h ? h : d_h.data();
    reference(m, hb);
    const unsigned N = d_num.num_subcarriers;
    std::size_t bad = 0;
    const gr_complex* clean = d_guard.guard(s, N, bad); // non-finite S counts as 0
    volk_32fc_x2_multiply_32fc(y, clean, hb, N);         // eq. (7): Y = S H
    if (noise && sigma > 0.0f)
        noise->add(m, sigma, y, N);
    return bad;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
