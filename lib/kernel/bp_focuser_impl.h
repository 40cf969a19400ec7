/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Inner loops of kernel::bp_focuser: one pulse onto one image line (or FFBP polar beam), one
// FFBP subimage onto one image line (or a larger subaperture's polar beam). The bodies are
// compiled twice, generic (bp_focuser.cc) and with AVX2/FMA (bp_focuser_avx2.cc), chosen at
// run time;
// it has internal linkage so that the two builds never merge.

#ifndef INCLUDED_NRSAR_KERNEL_BP_FOCUSER_IMPL_H
#define INCLUDED_NRSAR_KERNEL_BP_FOCUSER_IMPL_H

#include <gnuradio/gr_complex.h>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace gr {
namespace nrsar {
namespace kernel {
namespace bp_detail {

//! One pulse onto one line of K pixels.
struct line_job {
    const double* ground = nullptr; //!< K: pixel x of every column
    const double* py = nullptr;     //!< K: pixel y per column (FFBP's polar beams), or null
    const float* valid = nullptr;   //!< K: 1 where the pixel has a ground point
    double ax = 0.0;                //!< antenna x
    double ay = 0.0;                //!< antenna y (with py)
    double c = 0.0;                 //!< (y - a_y)^2 + (z - a_z)^2; with py: (z - a_z)^2
    double pos_scale = 0.0;         //!< upsampled samples per metre, U / rho
    double pos_offset = 0.0;        //!< U first_range / rho
    double cyc_scale = 0.0;         //!< cycles per metre, 2 / lambda + fc_r / rho
    double cyc_offset = 0.0;        //!< fc_r first_range / rho
    const gr_complex* profile = nullptr; //!< upsampled, demodulated profile
    int last = 0;                   //!< last sample an interpolation may start at: U (K - 1) - 1
    unsigned K = 0;
    //! Short sinc: the interpolator's table ((phases + 1) x taps), or null (linear); the
    //! profile is then zero padded, sample n at n + taps / 2.
    const float* sinc_table = nullptr;
    unsigned sinc_taps = 0;
    float sinc_phases = 0.0f;
    gr_complex* acc = nullptr;      //!< K accumulators of the line
    //! K: the pixels' distances on the pulse's last line, or null (then not kept)
    double* r = nullptr;
    double* h = nullptr;            //!< K: their 1 / (2 r)
    double c_last = -1.0;           //!< c of that line (< 0: none, r and h not yet set)
    int* idx = nullptr;             //!< K scratch
    float* mu = nullptr;            //!< K scratch
    float* frac = nullptr;          //!< K scratch
    float* sine = nullptr;          //!< K scratch
};

//! FFBP's last stage: one subaperture's polar subimage onto one line of K pixels; recursive
//! FFBP: onto one beam of a larger subaperture's subimage (l.py: its points' y).
struct merge_job {
    line_job l;         //!< ax: the subaperture centre's x; c: (y - c_y)^2 + (z - c_z)^2,
                        //!< with l.py (z - c_z)^2 and l.ay = c_y
    double dy = 0.0;    //!< y - c_y of the line (without l.py)
    double u0 = 0.0;    //!< direction cosine of beam 0
    double inv_du = 0.0; //!< 1 / beam spacing
    int last_beam = 0;  //!< last beam an interpolation may start at: B - 2
    size_t row = 0;     //!< samples per upsampled beam, U K
    int* beam = nullptr; //!< K scratch
    float* nu = nullptr; //!< K scratch
};

void project_line_avx2(const line_job& j);
void merge_line_avx2(const merge_job& m);

namespace {

// exp(j 2 pi frac) by the half angle a = pi frac in [-pi/2, pi/2] (least-squares fits on
// Chebyshev nodes, degree 9 / 8: 3.4e-9 and 4.7e-8 from sin and cos, below the float
// rounding of a; 5e-7 at most for cos and sin of 2 pi frac in float, as the Taylor
// polynomials of degree 11 / 12 before), then the double-angle formulas; the cosine replaces
// frac.
inline void phase_pass(unsigned K, float* __restrict fracs, float* __restrict sines)
{
    for (unsigned k = 0; k < K; ++k) {
        const float a = 3.14159265358979f * fracs[k];
        const float a2 = a * a;
        const float s = a * (9.999999765e-01f + a2 * (-1.666664759e-01f + a2 * (8.332899194e-03f +
                        a2 * (-1.980086351e-04f + a2 * 2.590426379e-06f))));
        const float co2 = 9.999999533e-01f + a2 * (-4.999990508e-01f + a2 * (4.166357912e-02f +
                          a2 * (-1.385366745e-03f + a2 * 2.315317453e-05f)));
        sines[k] = 2.0f * s * co2;
        fracs[k] = 1.0f - 2.0f * s * s;
    }
}

// The distance from the pulse's last line in the tile: r^2 changes by dc = c - c_last, so
// s = r_last + dc h predicts r within dr^2 / (2 r) (dr: the change of r), and one Newton step
// with h = 1 / (2 r_last) leaves |dr / r|^3 / 2 of r; h follows r by a Newton step of 1 / (2 r).
// Taken where |dr / r| <= |dc| / (2 min c) <= 1.25e-5 (r^2 >= c): relative error below 1e-15
// (GTest bp_focuser.line_recurrence_distance_is_exact measures 2.2e-16, one rounding); else
// std::sqrt.
inline bool recur_distance(const line_job& j)
{
    const double cmin = std::min(j.c, j.c_last);
    return j.r && cmin > 0.0 && std::abs(j.c - j.c_last) <= 2.5e-5 * cmin;
}

// Passes 1 and 2 of one pulse onto one line: idx, mu, and the phase's cosine (in frac) and
// sine. dist: 0 sqrt, 1 sqrt kept in r and h for the next line, 2 from the last line's.
template <bool per_pixel_y, int dist>
inline void position_phase_passes(const line_job& j)
{
    // Locals with __restrict: the stores to the scratch and accumulator arrays cannot alias
    // the inputs, so both passes vectorise.
    const unsigned K = j.K;
    const double* __restrict ground = j.ground;
    const double* __restrict py = j.py;
    double* __restrict rs = j.r;
    double* __restrict hs = j.h;
    int* __restrict idx = j.idx;
    float* __restrict mus = j.mu;
    float* __restrict fracs = j.frac;
    const double ax = j.ax, ay = j.ay, c = j.c, ps = j.pos_scale, po = j.pos_offset,
                 cs_ = j.cyc_scale, co = j.cyc_offset, dc = j.c - j.c_last;
    // Pass 1, double: exact distance, interpolation position, carrier phase in cycles. ivdep:
    // inlined, GCC loses the __restrict and has too many pointers to check at run time.
#pragma GCC ivdep
    for (unsigned k = 0; k < K; ++k) {
        const double dx = ground[k] - ax;
        double r2 = dx * dx + c;
        if (per_pixel_y) {
            const double dy = py[k] - ay;
            r2 += dy * dy;
        }
        double r;
        if (dist == 2) {
            const double h = hs[k], s = rs[k] + dc * h;
            r = s - (s * s - r2) * h;
            rs[k] = r;
            hs[k] = h * (2.0 - 2.0 * r * h);
        } else {
            r = std::sqrt(r2);
            if (dist == 1) {
                rs[k] = r;
                hs[k] = 0.5 / r;
            }
        }
        const double p = r * ps - po;
        const double fl = std::floor(p);
        const double cyc = r * cs_ - co;
        const double rc = std::nearbyint(cyc);
        idx[k] = static_cast<int>(fl);
        mus[k] = static_cast<float>(p - fl);
        fracs[k] = static_cast<float>(cyc - rc);
    }
    // Pass 2, float: the phase's cosine and sine.
    phase_pass(K, fracs, j.sine);
}

// from_last_line: the distances from the last line where recur_distance allows (the AVX2
// build: 0.91 of the time with std::sqrt); the generic build (SSE2, no FMA) keeps std::sqrt,
// which is cheaper there (the recurrence took it 1.08x the time).
inline void position_phase_passes(const line_job& j, bool from_last_line)
{
    if (j.py)
        position_phase_passes<true, 0>(j);
    else if (!j.r || !from_last_line)
        position_phase_passes<false, 0>(j);
    else if (recur_distance(j))
        position_phase_passes<false, 2>(j);
    else
        position_phase_passes<false, 1>(j);
}

// Pass 3: the profile at the positions (short sinc or linear), times the phase, summed.
inline void interpolate_pass(const line_job& j)
{
    const unsigned K = j.K;
    const int* __restrict idx = j.idx;
    const float* __restrict mus = j.mu;
    const float* __restrict fracs = j.frac;
    const float* __restrict sines = j.sine;
    const float* __restrict prof = reinterpret_cast<const float*>(j.profile);
    const float* __restrict valid = j.valid;
    float* __restrict acc = reinterpret_cast<float*>(j.acc);
    const int last = j.last;
    if (j.sinc_table) {
        // Pass 3, short sinc: the taps of the nearest tabulated phase on the padded profile.
        const unsigned T = j.sinc_taps;
        const float P = j.sinc_phases;
        for (unsigned k = 0; k < K; ++k) {
            const int i = idx[k];
            const bool in = i >= 0 && i <= last;
            const int ic = in ? i : 0;
            const float w = valid[k] * (in ? 1.0f : 0.0f);
            const float* h = j.sinc_table + static_cast<size_t>(mus[k] * P + 0.5f) * T;
            const float* x = prof + 2 * (ic + 1);
            float re = 0.0f, im = 0.0f;
            for (unsigned t = 0; t < T; ++t) {
                re += h[t] * x[2 * t];
                im += h[t] * x[2 * t + 1];
            }
            re *= w;
            im *= w;
            const float cs = fracs[k], sn = sines[k];
            acc[2 * k] += re * cs - im * sn;
            acc[2 * k + 1] += re * sn + im * cs;
        }
        return;
    }
    // Pass 3: linear interpolation of the profile, complex multiply-accumulate.
    for (unsigned k = 0; k < K; ++k) {
        const int i = idx[k];
        const bool in = i >= 0 && i <= last;
        const int ic = in ? i : 0;
        const float w = valid[k] * (in ? 1.0f : 0.0f);
        const float mu = mus[k];
        const float re0 = prof[2 * ic], im0 = prof[2 * ic + 1];
        const float re1 = prof[2 * ic + 2], im1 = prof[2 * ic + 3];
        const float re = w * (re0 + mu * (re1 - re0));
        const float im = w * (im0 + mu * (im1 - im0));
        const float cs = fracs[k], sn = sines[k];
        acc[2 * k] += re * cs - im * sn;
        acc[2 * k + 1] += re * sn + im * cs;
    }
}

inline void project_line_body(const line_job& j)
{
    position_phase_passes(j, false);
    interpolate_pass(j);
}

template <bool per_pixel_y>
inline void merge_line_body(const merge_job& m)
{
    const line_job& j = m.l;
    const unsigned K = j.K;
    const double* __restrict ground = j.ground;
    const double* __restrict py = j.py;
    int* __restrict idx = j.idx;
    int* __restrict beam = m.beam;
    float* __restrict mus = j.mu;
    float* __restrict nus = m.nu;
    float* __restrict fracs = j.frac;
    const double ax = j.ax, ay = j.ay, c = j.c, ps = j.pos_scale, po = j.pos_offset,
                 cs_ = j.cyc_scale, co = j.cyc_offset, line_dy = m.dy, u0 = m.u0,
                 inv_du = m.inv_du;
    // Pass 1, double: distance from the subaperture centre, range position, beam position,
    // phase in cycles.
    for (unsigned k = 0; k < K; ++k) {
        const double dx = ground[k] - ax;
        const double dy = per_pixel_y ? py[k] - ay : line_dy;
        const double r = std::sqrt(per_pixel_y ? dx * dx + dy * dy + c : dx * dx + c);
        const double p = r * ps - po;
        const double fl = std::floor(p);
        const double b = (dy / r - u0) * inv_du;
        const double bf = std::floor(b);
        const double cyc = r * cs_ - co;
        const double rc = std::nearbyint(cyc);
        idx[k] = static_cast<int>(fl);
        mus[k] = static_cast<float>(p - fl);
        beam[k] = static_cast<int>(bf);
        nus[k] = static_cast<float>(b - bf);
        fracs[k] = static_cast<float>(cyc - rc);
    }
    float* __restrict sines = j.sine;
    phase_pass(K, fracs, sines);
    // Pass 3: bilinear interpolation (range, beam) of the subimage, remodulation, sum.
    const float* __restrict sub = reinterpret_cast<const float*>(j.profile);
    const float* __restrict valid = j.valid;
    float* __restrict acc = reinterpret_cast<float*>(j.acc);
    const int last = j.last, last_beam = m.last_beam;
    const size_t row2 = 2 * m.row;
    for (unsigned k = 0; k < K; ++k) {
        const int i = idx[k], b = beam[k];
        const bool in = i >= 0 && i <= last && b >= 0 && b <= last_beam;
        const float w = valid[k] * (in ? 1.0f : 0.0f);
        const float* s0 = sub + (in ? b * row2 + 2 * i : 0);
        const float* s1 = s0 + row2;
        const float mu = mus[k], nu = nus[k];
        const float re0 = s0[0] + mu * (s0[2] - s0[0]), im0 = s0[1] + mu * (s0[3] - s0[1]);
        const float re1 = s1[0] + mu * (s1[2] - s1[0]), im1 = s1[1] + mu * (s1[3] - s1[1]);
        const float re = w * (re0 + nu * (re1 - re0));
        const float im = w * (im0 + nu * (im1 - im0));
        const float cs = fracs[k], sn = sines[k];
        acc[2 * k] += re * cs - im * sn;
        acc[2 * k + 1] += re * sn + im * cs;
    }
}

inline void merge_line_body(const merge_job& m)
{
    if (m.l.py)
        merge_line_body<true>(m);
    else
        merge_line_body<false>(m);
}

} // namespace
} // namespace bp_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_BP_FOCUSER_IMPL_H */
