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
     * R lever, R = Rz(yaw) Ry(pitch) Rx(roll), before interpolation. source names the data in
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

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TRAJECTORY_H */
