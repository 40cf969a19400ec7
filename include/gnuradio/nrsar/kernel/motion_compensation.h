/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_MOTION_COMPENSATION_H
#define INCLUDED_NRSAR_KERNEL_MOTION_COMPENSATION_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/trajectory.h>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Line-of-sight ranges from the navigation path to per-range-bin reference points:
 * the geometry that cheby_presum's inter-pulse compensation (eqs. P-25..P-27 on the flown
 * path) and rd_focuser's motion compensation share (docs/flight.md).
 *
 * The reference point of closest-approach slant range R0 (measured from the ideal line) is
 * the ground scatterer at the scene's along-track centre y_ref: (sqrt(R0^2 - H^2), y_ref, 0);
 * for R0 < H (no ground there) the point (0, y_ref, H - R0) below the line. From the ideal
 * line its range is sqrt(R0^2 + (y0 + v t - y_ref)^2), eq. (P-25); from the path p(t),
 * |p(t) - point|, in double precision. An empty path is the ideal line of geo.
 */
class NRSAR_API los_reference
{
public:
    los_reference(const geometry& geo, const trajectory& nav, double y_ref_m);

    //! True when the path is empty or geo's ideal line (no displacement anywhere).
    bool ideal() const { return d_ideal; }
    const trajectory& path() const { return d_nav; }
    double y_ref_m() const { return d_yref; }
    //! Whether the path is defined at slow time t (the ideal line: always).
    bool covers(double t_s) const;

    //! Reference point of the closest-approach slant range r0.
    vec3 point(double r0_m) const;
    //! Distance from the path at slow time t to the reference point of r0 [m].
    double range(double t_s, double r0_m) const;
    //! The same from the ideal line of geo.
    double ideal_range(double t_s, double r0_m) const;
    //! LOS displacement range - ideal_range [m]: what motion compensation removes.
    double displacement(double t_s, double r0_m) const;
    //! range() for the n bins r0 = first + k spacing (one path evaluation).
    void ranges(double t_s, double first_m, double spacing_m, unsigned n, double* out) const;
    //! Distances from the path at slow time t to n reference points the caller kept
    //! (point() of its bins: one path evaluation and one square root per bin).
    void ranges(double t_s, const vec3* points, unsigned n, double* out) const;
    //! displacement() for the n bins r0 = first + k spacing.
    void displacements(double t_s, double first_m, double spacing_m, unsigned n, double* out) const;
    /*!
     * The path time tau at which the path's along-track position is the ideal line's at t,
     * y(tau) = track_start + v t (Newton on y(tau) with the path's velocity; t itself on the
     * ideal line); NaN where the path's span has no such time or its along-track speed
     * falls below v / 10.
     */
    double along_track_time(double t_s) const;

    //! The scene's centre: along-track middle of its targets (y) and middle of their
    //! closest-approach slant ranges (r0).
    static void scene_centre(const geometry& geo, const scene& scn, double& y_m, double& r0_m);

private:
    geometry d_geo;
    trajectory d_nav;
    double d_yref;
    bool d_ideal;

    static double distance(const vec3& p, const vec3& q);
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_MOTION_COMPENSATION_H */
