/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_TRAJECTORY_H
#define INCLUDED_NRSAR_TRAJECTORY_H

// Its own header, not params.h: params.h is included by every block and kernel, and the
// flight path grows with issue #14 (attitude, footprint, navigation sources); only the
// blocks that fly a path include this one (docs/flight.md).

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace nrsar {

//! Built-in platform motion added to the ideal line (docs/flight.md has the spectra).
enum class motion_model {
    NONE,  //!< the ideal line itself
    CALM,  //!< centimetres: light-wind hover-steady flight
    GUSTY  //!< decimetres of cross-track and vertical sway, along-track speed variation,
           //!< broadband turbulence
};

//! Navigation measurement error added to the true path (docs/flight.md).
enum class nav_error_model {
    NONE, //!< perfect navigation: the truth
    RTK,  //!< centimetre band-limited white error and slow drift
    GNSS  //!< decimetre low-frequency error
};

using vec3 = std::array<double, 3>;
using mat3 = std::array<double, 9>; //!< row-major 3 x 3

/*!
 * Body-to-frame rotation of an attitude (roll, pitch, yaw) [rad] in SPEC 3's frame (x
 * cross-track towards the scene, y along track = the flight direction, z up):
 * R = Rz(yaw) Rx(pitch) Ry(roll), each a right-handed rotation about the frame's axis, so
 * roll turns about the flight direction (positive: the scene side goes down, the beam
 * looks closer to nadir), pitch about the cross-track axis (positive: nose up, a
 * down-looking beam moves forward), yaw about z (positive: nose left, the beam swings
 * forward). A vector v of the body (the frame at zero attitude) is R v in the frame.
 */
NRSAR_API mat3 attitude_matrix(const vec3& roll_pitch_yaw_rad);

/*!
 * \brief The antenna phase centre's path: position and velocity as functions of slow time.
 *
 * Frame of SPEC 3: x cross-track towards the scene, y along track, z up, metres; t = 0 at the
 * first OFDM symbol, seconds. Two kinds:
 *  - the ideal line of a geometry, (0, track_start + v t, H), exact at every t;
 *  - samples (t_i, p_i) at 10 Hz or more, interpolated in double precision by a cubic Hermite
 *    spline whose knot slopes are the derivative of the 4th-degree Lagrange polynomial
 *    through the 5 nearest samples: position error <= h^4 max|p''''| / 384 + h^5 max|p'''''|
 *    / 20 for sample spacing h, velocity continuous (the same slope on both sides of a
 *    knot). Outside [start_s(), end_s()] position() and velocity() throw.
 * A default-constructed trajectory is empty: the blocks then fly their geometry's ideal line.
 *
 * Samples are validated once, here (std::invalid_argument naming the source, the row and the
 * value): at least 5, finite, time strictly increasing, no gap above max_gap_s, mean rate at
 * least min_rate_hz, speed within [min_speed_mps, max_speed_mps], acceleration at most
 * max_accel_mps2 (from the finite differences of the samples).
 */
class NRSAR_API trajectory
{
public:
    static constexpr double min_rate_hz = 10.0;    //!< mean sample rate, at least
    static constexpr double max_gap_s = 0.5;       //!< largest interval between two samples
    static constexpr double min_speed_mps = 1.0;   //!< a SAR platform moves
    static constexpr double max_speed_mps = 200.0; //!< beyond any UAV
    static constexpr double max_accel_mps2 = 50.0; //!< about 5 g, beyond a UAV airframe

    trajectory() = default;

    //! The ideal line of geo: (0, track_start_m + velocity_mps t, height_m), exact.
    static trajectory ideal(const geometry& geo);

    /*!
     * From samples; attitude (roll, pitch, yaw [rad], one triple per sample) optional (empty
     * or t.size() triples). lever_arm_m: the phase centre's offset from the navigated point in
     * the body frame (x, y, z of the frame at zero attitude); the samples are moved by
     * R lever, R = attitude_matrix(roll, pitch, yaw), before interpolation. source names the data in
     * error messages; row_numbers (optional, one per sample) the rows it reports.
     */
    static trajectory from_samples(const std::vector<double>& t,
                                   const std::vector<vec3>& position,
                                   const std::vector<vec3>& attitude = {},
                                   const vec3& lever_arm_m = { 0.0, 0.0, 0.0 },
                                   const std::string& source = "trajectory samples",
                                   const std::vector<std::size_t>& row_numbers = {});

    /*!
     * A CSV file with the header t_s,x_m,y_m,z_m[,roll_rad,pitch_rad,yaw_rad] (columns in
     * this order). Errors name the file, the line and the value. required_s > 0: the samples
     * must cover [0, required_s] (the aperture), otherwise "too short".
     */
    static trajectory from_csv(const std::string& path,
                               double required_s = 0.0,
                               const vec3& lever_arm_m = { 0.0, 0.0, 0.0 });

    /*!
     * The ideal line of geo plus a seeded motion model, sampled at rate_hz over
     * [0, duration_s] (NONE: the ideal line itself).
     */
    static trajectory motion(const geometry& geo,
                             motion_model model,
                             std::uint64_t seed,
                             double duration_s,
                             double rate_hz = 100.0);

    /*!
     * What the platform believes: truth plus a seeded measurement error, sampled at rate_hz
     * over [0, duration_s] (NONE: truth itself).
     */
    static trajectory navigation(const trajectory& truth,
                                 nav_error_model model,
                                 std::uint64_t seed,
                                 double duration_s,
                                 double rate_hz = 100.0);

    bool empty() const { return !d_ideal && d_t.empty(); }
    bool is_ideal() const { return d_ideal; }
    bool has_attitude() const { return !d_att[0].empty(); }
    const std::string& source() const { return d_source; }
    //! Time span of the samples (ideal line: -inf, +inf).
    double start_s() const;
    double end_s() const;
    std::size_t num_samples() const { return d_t.size(); }

    vec3 position(double t) const;
    vec3 velocity(double t) const;
    //! Interpolated roll, pitch, yaw [rad] (zeros without attitude).
    vec3 attitude(double t) const;
    //! Throws (naming the source and both spans) unless [t0, t1] lies within the samples.
    void check_covers(double t0, double t1, const std::string& what = "the aperture") const;
    //! rms distance of the path, sampled n times over [t0, t1], from its least-squares line.
    double rms_deviation_m(double t0, double t1, unsigned n = 1000) const;

private:
    bool d_ideal = false;
    double d_y0 = 0.0, d_v = 0.0, d_h = 0.0; // ideal line
    std::string d_source;
    std::vector<double> d_t;
    std::array<std::vector<double>, 3> d_p, d_dp;   // position and knot slopes
    std::array<std::vector<double>, 3> d_att, d_datt; // attitude (optional) and slopes

    std::size_t segment(double t) const; // i with t_i <= t <= t_{i+1}
};

/*!
 * Whether the echo generators fly geo's ideal line with path: true for an empty path and
 * for trajectory::ideal(geo) (their outputs are then bit-identical to a block without a
 * path), false for a sampled path, which must cover [0, geo.aperture_s]. Throws
 * std::invalid_argument for the ideal line of another geometry (naming the field) and for
 * a sampled path that is too short.
 */
NRSAR_API bool flies_ideal_line(const trajectory& path, const geometry& geo);

/*!
 * check_scenario(num, geo, scn, symbols_per_pulse) plus what a sampled path (not the ideal
 * line) adds, over t in [0, geo.aperture_s] on a 1 ms grid (between grid points the range
 * departs from the sampled values by at most (a_max + v^2 / R) dt^2 / 8 < 1e-5 m):
 * every target in front of the antenna across track (x_q > the antenna's x at every
 * instant, SPEC 3: the scene lies at x > 0 of the track), and every round trip 2 R / c
 * within the CP and every range within c / (2 Delta f). Errors name the target, its x, the
 * time, the antenna's position, the path's source and the limit.
 */
NRSAR_API std::vector<std::string> check_scenario(const numerology& num,
                                                  const geometry& geo,
                                                  const scene& scn,
                                                  const trajectory& path,
                                                  unsigned symbols_per_pulse = 1);

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TRAJECTORY_H */
