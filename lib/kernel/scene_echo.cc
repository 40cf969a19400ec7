/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "fmod_two_pi.h"
#include "scene_echo_impl.h"
#include <gnuradio/nrsar/kernel/scene_echo.h>
#include <algorithm>
#include <cmath>
#include <complex>

namespace gr {
namespace nrsar {
namespace kernel {

using namespace echo_detail;

namespace echo_detail {

void generic_block(const target_lanes* t, unsigned nq, block_io& io, std::size_t len)
{
    // Same recurrence as the AVX2 path: 8 lanes advanced by step^8.
    gr_complex p[max_targets][lanes], step[max_targets], z[lanes];
    for (unsigned q = 0; q < nq; q++) {
        for (unsigned l = 0; l < lanes; l++)
            p[q][l] = gr_complex(t[q].v[2 * l], t[q].v[2 * l + 1]);
        step[q] = gr_complex(t[q].step[0], t[q].step[1]);
    }
    const bool noise = io.s && io.noise;
    for (std::size_t i0 = 0; i0 < len; i0 += lanes) {
        const std::size_t n = std::min<std::size_t>(lanes, len - i0);
        if (noise)
            noise_detail::generic_group(*io.noise, io.sigma, z);
        for (std::size_t l = 0; l < n; l++) {
            gr_complex acc = io.accumulate ? io.h[i0 + l] : gr_complex(0.0f, 0.0f);
            for (unsigned q = 0; q < nq; q++)
                acc += p[q][l];
            if (io.h)
                io.h[i0 + l] = acc;
            if (io.s) {
                const gr_complex sv = io.s[i0 + l];
                io.nonfinite |= !(std::isfinite(sv.real()) && std::isfinite(sv.imag()));
                io.y[i0 + l] = noise ? sv * acc + z[l] : sv * acc; // eq. (7)
            }
        }
        for (unsigned q = 0; q < nq; q++)
            for (unsigned l = 0; l < lanes; l++)
                p[q][l] *= step[q];
    }
}

} // namespace echo_detail

scene_echo::scene_echo(const numerology& num,
                       const geometry& geo,
                       const scene& scn,
                       const trajectory& path)
    : d_num(num), d_geo(geo), d_path(path), d_line(true), d_simd(avx2_available())
{
    d_num.validate();
    d_geo.validate();
    d_line = flies_ideal_line(path, d_geo);
    set_scene(scn);
    d_h.resize(d_num.num_subcarriers);
    d_clean.resize(d_num.num_subcarriers);
}

void scene_echo::set_scene(const scene& scn)
{
    scn.validate();
    d_scene = scn;
    d_active.clear();
    for (const auto& t : d_scene.targets)
        if (t.rcs > 0.0)
            d_active.push_back(t);
    d_lanes.resize(std::max<size_t>(1, d_active.size()));
    d_anchor.resize(d_active.size());
    d_block_step.resize(d_active.size());
    d_sc_pow.resize(d_active.size() * lanes);
}

double scene_echo::platform_y(std::uint64_t m) const
{
    // eq. (8): y_p = v t_m, t_m = m Tsym (double: m reaches 1e7 and beyond).
    return d_geo.track_start_m +
           d_geo.velocity_mps * (static_cast<double>(m) * d_num.symbol_s());
}

std::size_t scene_echo::echo(std::uint64_t m,
                             const gr_complex* s,
                             gr_complex* y,
                             gr_complex* h,
                             const gaussian_noise* noise,
                             float sigma)
{
    const std::size_t n_sc = d_num.num_subcarriers;
    const std::size_t nq = d_active.size();
    const bool with_noise = s && noise && sigma > 0.0f;
    if (nq == 0) { // every target has zero RCS: Y = Z
        if (h)
            std::fill(h, h + n_sc, gr_complex(0.0f, 0.0f));
        if (!s)
            return 0;
        std::fill(y, y + n_sc, gr_complex(0.0f, 0.0f));
        if (with_noise)
            noise->add(m, sigma, y, n_sc);
        return static_cast<std::size_t>(std::count_if(s, s + n_sc, [](const gr_complex& v) {
            return !(std::isfinite(v.real()) && std::isfinite(v.imag()));
        }));
    }
    const double yp = platform_y(m);
    const vec3 p = d_line ? vec3{} : d_path.position(double(m) * d_num.symbol_s());
    const double fc = d_geo.carrier_hz;
    const double df = d_num.subcarrier_spacing_hz;
    constexpr unsigned L = anchor_interval;

    // Per target, in double: the phasor at subcarrier 0, the step to the next anchor
    // (L subcarriers on) and the powers of the per-subcarrier step for the 8 lanes.
    for (std::size_t q = 0; q < nq; q++) {
        const auto& t = d_active[q];
        double R = t.slant_range_m(d_geo, yp); // eq. (8)
        if (!d_line) {                         // the true path: exact range from p(t_m)
            const double dx = t.x_m - p[0], dy = p[1] - t.y_m;
            R = std::sqrt(dx * dx + p[2] * p[2] + dy * dy);
        }
        const double k = 4.0 * M_PI * R / speed_of_light; // eq. (7): phase = -k f
        d_anchor[q] = std::polar(std::sqrt(t.rcs), t.phase_rad - fmod_two_pi(k * fc));
        d_block_step[q] = std::polar(1.0, -fmod_two_pi(k * df * L));
        const double dphi = -fmod_two_pi(k * df);
        for (unsigned l = 0; l < lanes; l++)
            d_sc_pow[q * lanes + l] = std::polar(1.0, dphi * l);
        const std::complex<double> step8 = std::polar(1.0, dphi * lanes);
        d_lanes[q].step[0] = static_cast<float>(step8.real());
        d_lanes[q].step[1] = static_cast<float>(step8.imag());
    }

    noise_detail::lane_state st;
    if (with_noise) // the same stream as noise->add(m, ...): block index m
        noise_detail::seed_lanes(noise->seed(), m, st);
    // H is stored when asked for, or when targets come in several passes.
    gr_complex* hbuf = h ? h : (nq > max_targets ? d_h.data() : nullptr);
    block_io io;
    io.noise = with_noise ? &st : nullptr;
    io.sigma = sigma;
    for (std::size_t n0 = 0; n0 < n_sc; n0 += L) {
        const std::size_t len = std::min<std::size_t>(L, n_sc - n0);
        for (std::size_t q = 0; q < nq; q++) {
            for (unsigned l = 0; l < lanes; l++) {
                const std::complex<double> v = d_anchor[q] * d_sc_pow[q * lanes + l];
                d_lanes[q].v[2 * l] = static_cast<float>(v.real());
                d_lanes[q].v[2 * l + 1] = static_cast<float>(v.imag());
            }
            d_anchor[q] *= d_block_step[q]; // double recurrence: drift ~1e-16 per block
        }
        for (std::size_t q0 = 0; q0 < nq; q0 += max_targets) {
            const unsigned chunk =
                static_cast<unsigned>(std::min<std::size_t>(max_targets, nq - q0));
            const bool last = q0 + chunk == nq;
            io.s = (s && last) ? s + n0 : nullptr;
            io.y = y ? y + n0 : nullptr;
            io.h = hbuf ? hbuf + n0 : nullptr;
            io.accumulate = q0 > 0;
            if (d_simd)
                avx2_block(&d_lanes[q0], chunk, io, len);
            else
                generic_block(&d_lanes[q0], chunk, io, len);
        }
    }
    if (!io.nonfinite)
        return 0;
    // Rare path: zero the non-finite samples of S and compute the symbol again (the
    // noise is a function of (seed, m), so it comes out the same).
    std::size_t count = 0;
    for (std::size_t n = 0; n < n_sc; n++) {
        const bool ok = std::isfinite(s[n].real()) && std::isfinite(s[n].imag());
        d_clean[n] = ok ? s[n] : gr_complex(0.0f, 0.0f);
        count += !ok;
    }
    echo(m, d_clean.data(), y, h, noise, sigma);
    return count;
}

void scene_echo::set_simd(bool allow) { d_simd = allow && avx2_available(); }

void scene_echo::reference(std::uint64_t m, gr_complex* h)
{
    echo(m, nullptr, nullptr, h, nullptr, 0.0f);
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
