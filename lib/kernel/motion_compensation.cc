/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/kernel/motion_compensation.h>
#include <algorithm>
#include <cmath>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
// The path is geo's ideal line when it is one (trajectory::ideal) with geo's start, speed
// and height: then the ideal-line code of the blocks (tables, recurrences) applies.
bool is_ideal_line(const geometry& geo, const trajectory& nav)
{
    if (nav.empty())
        return true;
    if (!nav.is_ideal())
        return false;
    const vec3 p = nav.position(0.0), v = nav.velocity(0.0);
    return p[0] == 0.0 && p[1] == geo.track_start_m && p[2] == geo.height_m && v[0] == 0.0 &&
           v[1] == geo.velocity_mps && v[2] == 0.0;
}
} // namespace

los_reference::los_reference(const geometry& geo, const trajectory& nav, double y_ref_m)
    : d_geo(geo), d_nav(nav), d_yref(y_ref_m), d_ideal(is_ideal_line(geo, nav))
{
}

bool los_reference::covers(double t_s) const
{
    return d_ideal || (t_s >= d_nav.start_s() && t_s <= d_nav.end_s());
}

vec3 los_reference::point(double r0_m) const
{
    const double h = d_geo.height_m;
    if (r0_m >= h)
        return { std::sqrt((r0_m - h) * (r0_m + h)), d_yref, 0.0 };
    return { 0.0, d_yref, h - r0_m };
}

double los_reference::distance(const vec3& p, const vec3& q)
{
    const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

double los_reference::ideal_range(double t_s, double r0_m) const
{
    const double u = d_geo.track_start_m + d_geo.velocity_mps * t_s - d_yref;
    return std::sqrt(r0_m * r0_m + u * u);
}

double los_reference::range(double t_s, double r0_m) const
{
    if (d_ideal)
        return ideal_range(t_s, r0_m);
    return distance(d_nav.position(t_s), point(r0_m));
}

double los_reference::displacement(double t_s, double r0_m) const
{
    if (d_ideal)
        return 0.0;
    return range(t_s, r0_m) - ideal_range(t_s, r0_m);
}

void los_reference::ranges(
    double t_s, double first_m, double spacing_m, unsigned n, double* out) const
{
    if (d_ideal) {
        for (unsigned k = 0; k < n; ++k)
            out[k] = ideal_range(t_s, first_m + k * spacing_m);
        return;
    }
    const vec3 p = d_nav.position(t_s);
    for (unsigned k = 0; k < n; ++k)
        out[k] = distance(p, point(first_m + k * spacing_m));
}

void los_reference::ranges(double t_s, const vec3* points, unsigned n, double* out) const
{
    const vec3 p = d_nav.position(t_s);
    for (unsigned k = 0; k < n; ++k)
        out[k] = distance(p, points[k]);
}

void los_reference::displacements(
    double t_s, double first_m, double spacing_m, unsigned n, double* out) const
{
    if (d_ideal) {
        std::fill(out, out + n, 0.0);
        return;
    }
    ranges(t_s, first_m, spacing_m, n, out);
    for (unsigned k = 0; k < n; ++k)
        out[k] -= ideal_range(t_s, first_m + k * spacing_m);
}

double los_reference::along_track_time(double t_s) const
{
    if (d_ideal)
        return t_s;
    const double y = d_geo.track_start_m + d_geo.velocity_mps * t_s;
    double tau = std::min(std::max(t_s, d_nav.start_s()), d_nav.end_s());
    // Quadratic convergence from a start a few tenths of a second off at most (the
    // along-track displacement over the speed); 1e-12 s is 5e-11 m at 50 m/s.
    for (int it = 0; it < 20; ++it) {
        const double vy = d_nav.velocity(tau)[1];
        if (!(vy > 0.1 * d_geo.velocity_mps))
            return NAN;
        const double step = (d_nav.position(tau)[1] - y) / vy;
        tau -= step;
        if (tau < d_nav.start_s() || tau > d_nav.end_s())
            return NAN;
        if (std::abs(step) < 1e-12)
            return tau;
    }
    return NAN;
}

void los_reference::scene_centre(const geometry& geo, const scene& scn, double& y_m, double& r0_m)
{
    double ylo = INFINITY, yhi = -INFINITY, rlo = INFINITY, rhi = 0.0;
    for (const auto& t : scn.targets) {
        const double r0 = std::sqrt(t.x_m * t.x_m + geo.height_m * geo.height_m);
        ylo = std::min(ylo, t.y_m);
        yhi = std::max(yhi, t.y_m);
        rlo = std::min(rlo, r0);
        rhi = std::max(rhi, r0);
    }
    y_m = 0.5 * (ylo + yhi);
    r0_m = 0.5 * (rlo + rhi);
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
