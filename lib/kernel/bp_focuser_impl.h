/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Inner loop of kernel::bp_focuser: one pulse onto one image line. The body is compiled
// twice, generic (bp_focuser.cc) and with AVX2/FMA (bp_focuser_avx2.cc), chosen at run time;
// it has internal linkage so that the two builds never merge.

#ifndef INCLUDED_NRSAR_KERNEL_BP_FOCUSER_IMPL_H
#define INCLUDED_NRSAR_KERNEL_BP_FOCUSER_IMPL_H

#include <gnuradio/gr_complex.h>
#include <cmath>
#include <cstdint>

namespace gr {
namespace nrsar {
namespace kernel {
namespace bp_detail {

//! One pulse onto one line of K pixels.
struct line_job {
    const double* ground = nullptr; //!< K: scatterer x of every range bin
    const float* valid = nullptr;   //!< K: 1 where the pixel has a ground point
    double ax = 0.0;                //!< antenna x
    double c = 0.0;                 //!< (y - a_y)^2 + a_z^2
    double pos_scale = 0.0;         //!< upsampled samples per metre, U / rho
    double pos_offset = 0.0;        //!< U first_range / rho
    double cyc_scale = 0.0;         //!< cycles per metre, 2 / lambda + fc_r / rho
    double cyc_offset = 0.0;        //!< fc_r first_range / rho
    const gr_complex* profile = nullptr; //!< upsampled, demodulated profile
    int last = 0;                   //!< last sample an interpolation may start at: U (K - 1) - 1
    unsigned K = 0;
    gr_complex* acc = nullptr;      //!< K accumulators of the line
    int* idx = nullptr;             //!< K scratch
    float* mu = nullptr;            //!< K scratch
    float* frac = nullptr;          //!< K scratch
    float* sine = nullptr;          //!< K scratch
};

void project_line_avx2(const line_job& j);

namespace {

inline void project_line_body(const line_job& j)
{
    // Locals with __restrict: the stores to the scratch and accumulator arrays cannot alias
    // the inputs, so both passes vectorise.
    const unsigned K = j.K;
    const double* __restrict ground = j.ground;
    int* __restrict idx = j.idx;
    float* __restrict mus = j.mu;
    float* __restrict fracs = j.frac;
    const double ax = j.ax, c = j.c, ps = j.pos_scale, po = j.pos_offset, cs_ = j.cyc_scale,
                 co = j.cyc_offset;
    // Pass 1, double: exact distance, interpolation position, carrier phase in cycles.
    for (unsigned k = 0; k < K; ++k) {
        const double dx = ground[k] - ax;
        const double r = std::sqrt(dx * dx + c);
        const double p = r * ps - po;
        const double fl = std::floor(p);
        const double cyc = r * cs_ - co;
        const double rc = std::nearbyint(cyc);
        idx[k] = static_cast<int>(fl);
        mus[k] = static_cast<float>(p - fl);
        fracs[k] = static_cast<float>(cyc - rc);
    }
    // Pass 2, float: exp(j 2 pi frac) by the half angle a = pi frac in [-pi/2, pi/2]
    // (Taylor to degree 11 / 12: error below 6e-8), then the double-angle formulas; the
    // cosine replaces frac.
    float* __restrict sines = j.sine;
    for (unsigned k = 0; k < K; ++k) {
        const float a = 3.14159265358979f * fracs[k];
        const float a2 = a * a;
        const float s = a * (1.0f + a2 * (-1.0f / 6 + a2 * (1.0f / 120 + a2 * (-1.0f / 5040 +
                        a2 * (1.0f / 362880 + a2 * (-1.0f / 39916800))))));
        const float co2 = 1.0f + a2 * (-0.5f + a2 * (1.0f / 24 + a2 * (-1.0f / 720 +
                          a2 * (1.0f / 40320 + a2 * (-1.0f / 3628800 + a2 * (1.0f / 479001600))))));
        sines[k] = 2.0f * s * co2;
        fracs[k] = 1.0f - 2.0f * s * s;
    }
    // Pass 3: linear interpolation of the profile, complex multiply-accumulate.
    const float* __restrict prof = reinterpret_cast<const float*>(j.profile);
    const float* __restrict valid = j.valid;
    float* __restrict acc = reinterpret_cast<float*>(j.acc);
    const int last = j.last;
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

} // namespace
} // namespace bp_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_BP_FOCUSER_IMPL_H */
