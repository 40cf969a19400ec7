/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/trajectory.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

namespace gr {
namespace nrsar {

namespace {

[[noreturn]] void fail(const std::string& source, const std::string& what)
{
    throw std::invalid_argument(source + ": " + what);
}

std::string num_text(double v)
{
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
}

// Slope at node i: derivative of the Lagrange polynomial through the 5 nodes nearest to it
// (4th order for any spacing; one-sided at the ends).
std::vector<double> knot_slopes(const std::vector<double>& t, const std::vector<double>& f)
{
    const std::size_t n = t.size();
    std::vector<double> d(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t lo = std::min(i >= 2 ? i - 2 : 0, n - 5);
        double acc = 0.0;
        for (std::size_t j = lo; j < lo + 5; ++j) {
            double w;
            if (j == i) {
                w = 0.0;
                for (std::size_t m = lo; m < lo + 5; ++m)
                    if (m != i)
                        w += 1.0 / (t[i] - t[m]);
            } else {
                double num = 1.0, den = 1.0;
                for (std::size_t m = lo; m < lo + 5; ++m) {
                    if (m == j)
                        continue;
                    den *= t[j] - t[m];
                    if (m != i)
                        num *= t[i] - t[m];
                }
                w = num / den;
            }
            acc += w * f[j];
        }
        d[i] = acc;
    }
    return d;
}

// R l with R = attitude_matrix(att)
vec3 rotate(const vec3& att, const vec3& l)
{
    const mat3 r = attitude_matrix(att);
    return { r[0] * l[0] + r[1] * l[1] + r[2] * l[2],
             r[3] * l[0] + r[4] * l[1] + r[5] * l[2],
             r[6] * l[0] + r[7] * l[1] + r[8] * l[2] };
}

// One band of a sum-of-tones process: power spectral density proportional to f^-exponent on
// [f_lo, f_hi], total (ensemble) rms `rms`. Tones log-spaced with a random offset in each
// cell and random phases; amplitudes deterministic, so the ensemble mean square is exactly
// rms^2.
struct tone_band {
    double rms, f_lo, f_hi, exponent;
};

struct tones {
    std::vector<double> a, f, ph;

    tones(const tone_band& b, std::mt19937_64& rng, unsigned n = 64)
    {
        std::uniform_real_distribution<double> u(0.0, 1.0);
        const double l0 = std::log(b.f_lo), l1 = std::log(b.f_hi);
        double ms = 0.0;
        for (unsigned i = 0; i < n; ++i) {
            const double e0 = std::exp(l0 + (l1 - l0) * i / n);
            const double e1 = std::exp(l0 + (l1 - l0) * (i + 1) / n);
            const double fi = e0 + (e1 - e0) * u(rng);
            const double s = std::pow(fi, -b.exponent) * (e1 - e0); // S(f) df
            f.push_back(fi);
            a.push_back(std::sqrt(2.0 * s));
            ph.push_back(2.0 * M_PI * u(rng));
            ms += s;
        }
        for (double& ai : a)
            ai *= b.rms / std::sqrt(ms);
    }
    double at(double t) const
    {
        double acc = 0.0;
        for (std::size_t i = 0; i < a.size(); ++i)
            acc += a[i] * std::cos(2.0 * M_PI * f[i] * t + ph[i]);
        return acc;
    }
    //! Integral from 0 to t (a speed variation turned into a displacement).
    double integral(double t) const
    {
        double acc = 0.0;
        for (std::size_t i = 0; i < a.size(); ++i)
            acc += a[i] / (2.0 * M_PI * f[i]) *
                   (std::sin(2.0 * M_PI * f[i] * t + ph[i]) - std::sin(ph[i]));
        return acc;
    }
};

// A model: per axis a list of displacement bands, plus an along-track speed band.
struct model_spec {
    std::array<std::vector<tone_band>, 3> disp;
    tone_band speed{ 0.0, 1.0, 1.0, 0.0 };
};

model_spec motion_spec(motion_model m)
{
    model_spec s;
    // Sway: f^-2 between 0.05 and 1 Hz (gust periods 1-20 s); turbulence: the
    // Kolmogorov / Dryden inertial range f^-5/3 from 0.5 to 5 Hz.
    if (m == motion_model::CALM) {
        for (int ax : { 0, 2 })
            s.disp[ax].push_back({ 0.02, 0.05, 1.0, 2.0 });
        for (int ax = 0; ax < 3; ++ax)
            s.disp[ax].push_back({ 0.003, 0.5, 5.0, 5.0 / 3.0 });
        s.speed = { 0.05, 0.02, 0.2, 0.0 };
    } else if (m == motion_model::GUSTY) {
        for (int ax : { 0, 2 })
            s.disp[ax].push_back({ 0.20, 0.05, 1.0, 2.0 });
        for (int ax = 0; ax < 3; ++ax)
            s.disp[ax].push_back({ 0.02, 0.5, 5.0, 5.0 / 3.0 });
        s.speed = { 0.5, 0.02, 0.2, 0.0 };
    }
    return s;
}

model_spec nav_spec(nav_error_model m)
{
    model_spec s;
    if (m == nav_error_model::RTK) {
        // 1 cm white (flat up to 5 Hz, the band a 10-20 Hz RTK fix resolves) and 2 cm of
        // slow drift (0.005-0.05 Hz, multipath and reference-station changes).
        for (int ax = 0; ax < 3; ++ax) {
            s.disp[ax].push_back({ 0.01, 0.1, 5.0, 0.0 });
            s.disp[ax].push_back({ 0.02, 0.005, 0.05, 0.0 });
        }
    } else if (m == nav_error_model::GNSS) {
        // Standalone GNSS: decimetres at periods of 10 s to minutes (ionosphere,
        // troposphere, orbit), a little more vertically, and 2 cm of receiver noise.
        for (int ax = 0; ax < 3; ++ax) {
            s.disp[ax].push_back({ ax == 2 ? 0.3 : 0.2, 0.002, 0.1, 0.0 });
            s.disp[ax].push_back({ 0.02, 0.1, 2.0, 0.0 });
        }
    }
    return s;
}

// Samples of base(t) + the model's displacement over [0, duration] at rate_hz.
template <typename Base>
trajectory sampled(const Base& base,
                   const model_spec& spec,
                   std::uint64_t seed,
                   double duration_s,
                   double rate_hz,
                   const std::string& source)
{
    check_finite_positive("duration_s", duration_s);
    check_range("rate_hz", rate_hz, trajectory::min_rate_hz, 1e4);
    const double n_d = std::ceil(duration_s * rate_hz) + 1.0;
    if (n_d > 1e8)
        throw_param("duration_s x rate_hz", n_d, "must be below 1e8 samples");
    std::mt19937_64 rng(seed);
    std::array<std::vector<tones>, 3> disp;
    for (int ax = 0; ax < 3; ++ax)
        for (const tone_band& b : spec.disp[ax])
            disp[ax].emplace_back(b, rng);
    const tones speed(spec.speed, rng);
    const std::size_t n = static_cast<std::size_t>(std::max(5.0, n_d));
    std::vector<double> t(n);
    std::vector<vec3> p(n);
    for (std::size_t i = 0; i < n; ++i) {
        t[i] = i / rate_hz;
        p[i] = base(t[i]);
        for (int ax = 0; ax < 3; ++ax)
            for (const tones& d : disp[ax])
                p[i][ax] += d.at(t[i]);
        if (spec.speed.rms > 0.0)
            p[i][1] += speed.integral(t[i]);
    }
    return trajectory::from_samples(t, p, {}, { 0.0, 0.0, 0.0 }, source);
}

const char* const motion_names[] = { "none", "calm", "gusty" };
const char* const nav_names[] = { "none", "rtk", "gnss" };

} // namespace

trajectory trajectory::ideal(const geometry& geo)
{
    geo.validate();
    trajectory tr;
    tr.d_ideal = true;
    tr.d_y0 = geo.track_start_m;
    tr.d_v = geo.velocity_mps;
    tr.d_h = geo.height_m;
    tr.d_source = "ideal line";
    return tr;
}

trajectory trajectory::from_samples(const std::vector<double>& t,
                                    const std::vector<vec3>& position,
                                    const std::vector<vec3>& attitude,
                                    const vec3& lever_arm_m,
                                    const std::string& source,
                                    const std::vector<std::size_t>& row_numbers)
{
    const std::size_t n = t.size();
    auto row = [&](std::size_t i) {
        return "row " + std::to_string(row_numbers.size() == n ? row_numbers[i] : i);
    };
    if (position.size() != n)
        fail(source, std::to_string(position.size()) + " positions for " + std::to_string(n) +
                         " times");
    if (!attitude.empty() && attitude.size() != n)
        fail(source, std::to_string(attitude.size()) + " attitude rows for " +
                         std::to_string(n) + " times");
    if (n < 5)
        fail(source, std::to_string(n) + " samples, at least 5 needed (cubic interpolation)");
    for (int ax = 0; ax < 3; ++ax)
        check_finite("lever_arm_m", lever_arm_m[ax]);
    static const char* const pos_names[] = { "x_m", "y_m", "z_m" };
    static const char* const att_names[] = { "roll_rad", "pitch_rad", "yaw_rad" };
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(t[i]))
            fail(source, row(i) + ": t_s = " + num_text(t[i]) + " must be finite");
        for (int ax = 0; ax < 3; ++ax) {
            if (!std::isfinite(position[i][ax]))
                fail(source, row(i) + ": " + pos_names[ax] + " = " + num_text(position[i][ax]) +
                                 " must be finite");
            if (!attitude.empty() && !std::isfinite(attitude[i][ax]))
                fail(source, row(i) + ": " + att_names[ax] + " = " +
                                 num_text(attitude[i][ax]) + " must be finite");
        }
        if (i > 0) {
            const double dt = t[i] - t[i - 1];
            if (!(dt > 0.0))
                fail(source, row(i) + ": t_s = " + num_text(t[i]) +
                                 " must be greater than the previous row's " +
                                 num_text(t[i - 1]) + " (time not increasing)");
            if (dt > max_gap_s)
                fail(source, row(i) + ": gap of " + num_text(dt) + " s after t_s = " +
                                 num_text(t[i - 1]) + " exceeds " + num_text(max_gap_s) + " s");
        }
    }
    const double rate = (n - 1) / (t[n - 1] - t[0]);
    if (rate < min_rate_hz)
        fail(source, "mean sample rate " + num_text(rate) + " Hz must be at least " +
                         num_text(min_rate_hz) + " Hz");

    std::vector<vec3> pc(position);
    const bool lever = lever_arm_m[0] != 0.0 || lever_arm_m[1] != 0.0 || lever_arm_m[2] != 0.0;
    if (lever)
        for (std::size_t i = 0; i < n; ++i) {
            const vec3 off =
                rotate(attitude.empty() ? vec3{ 0.0, 0.0, 0.0 } : attitude[i], lever_arm_m);
            for (int ax = 0; ax < 3; ++ax)
                pc[i][ax] += off[ax];
        }

    // Speed and acceleration from the finite differences of the phase-centre samples.
    vec3 v_prev{};
    for (std::size_t i = 1; i < n; ++i) {
        const double dt = t[i] - t[i - 1];
        vec3 v;
        for (int ax = 0; ax < 3; ++ax)
            v[ax] = (pc[i][ax] - pc[i - 1][ax]) / dt;
        const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!(speed >= min_speed_mps && speed <= max_speed_mps))
            fail(source, row(i) + ": speed " + num_text(speed) + " m/s since t_s = " +
                             num_text(t[i - 1]) + " must be in [" + num_text(min_speed_mps) +
                             ", " + num_text(max_speed_mps) + "] m/s");
        if (i >= 2) {
            const double dtm = 0.5 * (t[i] - t[i - 2]);
            const double ax_ = (v[0] - v_prev[0]) / dtm, ay = (v[1] - v_prev[1]) / dtm,
                         az = (v[2] - v_prev[2]) / dtm;
            const double acc = std::sqrt(ax_ * ax_ + ay * ay + az * az);
            if (acc > max_accel_mps2)
                fail(source, row(i - 1) + ": acceleration " + num_text(acc) + " m/s^2 at t_s = " +
                                 num_text(t[i - 1]) + " exceeds " + num_text(max_accel_mps2) +
                                 " m/s^2");
        }
        v_prev = v;
    }

    trajectory tr;
    tr.d_source = source;
    tr.d_t = t;
    for (int ax = 0; ax < 3; ++ax) {
        tr.d_p[ax].resize(n);
        for (std::size_t i = 0; i < n; ++i)
            tr.d_p[ax][i] = pc[i][ax];
        tr.d_dp[ax] = knot_slopes(t, tr.d_p[ax]);
        if (!attitude.empty()) {
            tr.d_att[ax].resize(n);
            for (std::size_t i = 0; i < n; ++i)
                tr.d_att[ax][i] = attitude[i][ax];
            tr.d_datt[ax] = knot_slopes(t, tr.d_att[ax]);
        }
    }
    return tr;
}

trajectory trajectory::from_csv(const std::string& path, double required_s, const vec3& lever_arm_m)
{
    check_finite("required_s", required_s);
    std::ifstream f(path);
    if (!f)
        fail("trajectory file '" + path + "'", "cannot be opened");
    const std::string src = "trajectory file '" + path + "'";
    std::string line;
    std::size_t line_no = 0;
    // Header.
    std::vector<std::string> cols;
    while (std::getline(f, line)) {
        ++line_no;
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        if (line.find_first_not_of(" \t") == std::string::npos)
            continue;
        std::stringstream ss(line);
        std::string c;
        while (std::getline(ss, c, ',')) {
            const auto b = c.find_first_not_of(" \t"), e = c.find_last_not_of(" \t");
            cols.push_back(b == std::string::npos ? "" : c.substr(b, e - b + 1));
        }
        break;
    }
    static const std::vector<std::string> want = { "t_s",      "x_m",       "y_m",    "z_m",
                                                   "roll_rad", "pitch_rad", "yaw_rad" };
    if (!(cols.size() == 4 || cols.size() == 7) ||
        !std::equal(cols.begin(), cols.end(), want.begin()))
        fail(src, "line " + std::to_string(line_no) +
                      ": header must be t_s,x_m,y_m,z_m[,roll_rad,pitch_rad,yaw_rad]");
    const std::size_t nc = cols.size();
    std::vector<double> t;
    std::vector<vec3> p, att;
    std::vector<std::size_t> rows;
    while (std::getline(f, line)) {
        ++line_no;
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        if (line.find_first_not_of(" \t") == std::string::npos)
            continue;
        std::stringstream ss(line);
        std::string c;
        std::vector<double> v;
        while (std::getline(ss, c, ',')) {
            const char* s = c.c_str();
            char* end = nullptr;
            const double x = std::strtod(s, &end);
            while (end && (*end == ' ' || *end == '\t'))
                ++end;
            if (end == s || *end != '\0' || c.find_first_not_of(" \t") == std::string::npos)
                fail(src, "line " + std::to_string(line_no) + ": " +
                              (v.size() < nc ? cols[v.size()] : std::string("column ") +
                                                                    std::to_string(v.size() + 1)) +
                              " = '" + c + "' is not a number");
            v.push_back(x);
        }
        if (v.size() != nc)
            fail(src, "line " + std::to_string(line_no) + ": " + std::to_string(v.size()) +
                          " values, the header has " + std::to_string(nc));
        t.push_back(v[0]);
        p.push_back({ v[1], v[2], v[3] });
        if (nc == 7)
            att.push_back({ v[4], v[5], v[6] });
        rows.push_back(line_no);
    }
    trajectory tr = from_samples(t, p, att, lever_arm_m, src, rows);
    if (required_s > 0.0)
        tr.check_covers(0.0, required_s);
    return tr;
}

trajectory trajectory::motion(const geometry& geo,
                              motion_model model,
                              std::uint64_t seed,
                              double duration_s,
                              double rate_hz)
{
    const trajectory line = ideal(geo);
    if (model == motion_model::NONE)
        return line;
    return sampled([&](double t) { return line.position(t); },
                   motion_spec(model),
                   seed,
                   duration_s,
                   rate_hz,
                   std::string("motion model '") + motion_names[static_cast<int>(model)] +
                       "' seed " + std::to_string(seed));
}

trajectory trajectory::navigation(const trajectory& truth,
                                  nav_error_model model,
                                  std::uint64_t seed,
                                  double duration_s,
                                  double rate_hz)
{
    if (truth.empty())
        throw std::invalid_argument("navigation: the true trajectory is empty");
    if (model == nav_error_model::NONE)
        return truth;
    truth.check_covers(0.0, duration_s, "the navigation span");
    return sampled([&](double t) { return truth.position(std::min(t, truth.end_s())); },
                   nav_spec(model),
                   seed,
                   duration_s,
                   rate_hz,
                   std::string("navigation '") + nav_names[static_cast<int>(model)] + "' seed " +
                       std::to_string(seed) + " of " + truth.source());
}

double trajectory::start_s() const
{
    return d_ideal ? -std::numeric_limits<double>::infinity()
                   : (d_t.empty() ? 0.0 : d_t.front());
}

double trajectory::end_s() const
{
    return d_ideal ? std::numeric_limits<double>::infinity() : (d_t.empty() ? 0.0 : d_t.back());
}

void trajectory::check_covers(double t0, double t1, const std::string& what) const
{
    if (d_ideal)
        return;
    if (empty())
        throw std::invalid_argument("trajectory is empty");
    // Sample times are rounded; a nanosecond of slack.
    if (t0 < d_t.front() - 1e-9 || t1 > d_t.back() + 1e-9)
        fail(d_source, "t_s spans [" + num_text(d_t.front()) + ", " + num_text(d_t.back()) +
                           "] s, too short for " + what + " [" + num_text(t0) + ", " +
                           num_text(t1) + "] s");
}

std::size_t trajectory::segment(double t) const
{
    if (empty())
        throw std::invalid_argument("trajectory is empty");
    if (!(t >= d_t.front() - 1e-9 && t <= d_t.back() + 1e-9))
        throw_param(d_source + ": t", t,
                    "must be within the samples [" + num_text(d_t.front()) + ", " +
                        num_text(d_t.back()) + "] s");
    const auto it = std::upper_bound(d_t.begin(), d_t.end(), t);
    const std::size_t i = it == d_t.begin() ? 0 : static_cast<std::size_t>(it - d_t.begin()) - 1;
    return std::min(i, d_t.size() - 2);
}

namespace {
// Cubic Hermite on [t_i, t_i + h] at u = (t - t_i) / h: value and derivative.
inline void hermite(double p0, double p1, double d0, double d1, double h, double u, double& f,
                    double& df)
{
    const double u2 = u * u, u3 = u2 * u;
    f = (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * h * d0 + (-2 * u3 + 3 * u2) * p1 +
        (u3 - u2) * h * d1;
    df = (6 * u2 - 6 * u) / h * (p0 - p1) + (3 * u2 - 4 * u + 1) * d0 + (3 * u2 - 2 * u) * d1;
}
} // namespace

mat3 attitude_matrix(const vec3& att)
{
    const double cr = std::cos(att[0]), sr = std::sin(att[0]);
    const double cp = std::cos(att[1]), sp = std::sin(att[1]);
    const double cy = std::cos(att[2]), sy = std::sin(att[2]);
    // Ry(roll) = [cr 0 sr; 0 1 0; -sr 0 cr], Rx(pitch) = [1 0 0; 0 cp -sp; 0 sp cp],
    // Rz(yaw) = [cy -sy 0; sy cy 0; 0 0 1]; R = Rz Rx Ry.
    const mat3 xy = { cr, 0.0, sr, sp * sr, cp, -sp * cr, -cp * sr, sp, cp * cr };
    return { cy * xy[0] - sy * xy[3], cy * xy[1] - sy * xy[4], cy * xy[2] - sy * xy[5],
             sy * xy[0] + cy * xy[3], sy * xy[1] + cy * xy[4], sy * xy[2] + cy * xy[5],
             xy[6],                   xy[7],                   xy[8] };
}

vec3 trajectory::position(double t) const
{
    if (d_ideal)
        return { 0.0, d_y0 + d_v * t, d_h };
    const std::size_t i = segment(t);
    const double h = d_t[i + 1] - d_t[i], u = (t - d_t[i]) / h;
    vec3 r;
    double df;
    for (int ax = 0; ax < 3; ++ax)
        hermite(d_p[ax][i], d_p[ax][i + 1], d_dp[ax][i], d_dp[ax][i + 1], h, u, r[ax], df);
    return r;
}

vec3 trajectory::velocity(double t) const
{
    if (d_ideal)
        return { 0.0, d_v, 0.0 };
    const std::size_t i = segment(t);
    const double h = d_t[i + 1] - d_t[i], u = (t - d_t[i]) / h;
    vec3 r;
    double f;
    for (int ax = 0; ax < 3; ++ax)
        hermite(d_p[ax][i], d_p[ax][i + 1], d_dp[ax][i], d_dp[ax][i + 1], h, u, f, r[ax]);
    return r;
}

vec3 trajectory::attitude(double t) const
{
    if (!has_attitude())
        return { 0.0, 0.0, 0.0 };
    const std::size_t i = segment(t);
    const double h = d_t[i + 1] - d_t[i], u = (t - d_t[i]) / h;
    vec3 r;
    double df;
    for (int ax = 0; ax < 3; ++ax)
        hermite(d_att[ax][i], d_att[ax][i + 1], d_datt[ax][i], d_datt[ax][i + 1], h, u, r[ax], df);
    return r;
}

double trajectory::rms_deviation_m(double t0, double t1, unsigned n) const
{
    check_at_least("n", n, 2u);
    if (!(t1 > t0))
        throw_param("t1", t1, "must be greater than t0");
    check_covers(t0, t1, "the rms span");
    // Least-squares line p(t) = a + b t per axis (centred time), then the rms residual.
    std::vector<double> ts(n);
    std::vector<vec3> ps(n);
    double tm = 0.0;
    for (unsigned i = 0; i < n; ++i) {
        ts[i] = t0 + (t1 - t0) * i / (n - 1);
        ps[i] = position(ts[i]);
        tm += ts[i] / n;
    }
    double stt = 0.0;
    for (double x : ts)
        stt += (x - tm) * (x - tm);
    double ss = 0.0;
    for (int ax = 0; ax < 3; ++ax) {
        double pm = 0.0, stp = 0.0;
        for (unsigned i = 0; i < n; ++i)
            pm += ps[i][ax] / n;
        for (unsigned i = 0; i < n; ++i)
            stp += (ts[i] - tm) * (ps[i][ax] - pm);
        const double b = stp / stt;
        for (unsigned i = 0; i < n; ++i) {
            const double r = ps[i][ax] - pm - b * (ts[i] - tm);
            ss += r * r;
        }
    }
    return std::sqrt(ss / n);
}

bool flies_ideal_line(const trajectory& path, const geometry& geo)
{
    if (path.empty())
        return true;
    if (path.is_ideal()) {
        // The generators' own line, so the bit-identical code path is the right one.
        const vec3 p0 = path.position(0.0), v = path.velocity(0.0);
        if (p0[1] != geo.track_start_m)
            throw_param("path track start", p0[1], "must be the geometry's track_start_m");
        if (p0[2] != geo.height_m)
            throw_param("path height", p0[2], "must be the geometry's height_m");
        if (v[1] != geo.velocity_mps)
            throw_param("path velocity", v[1], "must be the geometry's velocity_mps");
        return true;
    }
    path.check_covers(0.0, geo.aperture_s);
    return false;
}

std::vector<std::string> check_scenario(const numerology& num,
                                        const geometry& geo,
                                        const scene& scn,
                                        const trajectory& path,
                                        unsigned symbols_per_pulse)
{
    std::vector<std::string> warnings = check_scenario(num, geo, scn, symbols_per_pulse);
    if (flies_ideal_line(path, geo))
        return warnings;
    const double r_cp = num.cp_s() * speed_of_light / 2.0;
    const double r_amb = num.max_unambiguous_range_m();
    const std::size_t steps = static_cast<std::size_t>(std::ceil(geo.aperture_s / 1e-3));
    for (std::size_t i = 0; i <= steps; ++i) {
        const double t = std::min(geo.aperture_s, i * 1e-3);
        const vec3 p = path.position(t);
        for (std::size_t q = 0; q < scn.targets.size(); ++q) {
            const point_target& tg = scn.targets[q];
            auto where = [&] {
                std::ostringstream s;
                s.precision(10);
                s << "target " << q << " (x " << tg.x_m << " m, y " << tg.y_m << " m) at t = "
                  << t << " s, antenna at (" << p[0] << ", " << p[1] << ", " << p[2]
                  << ") m on " << path.source();
                return s.str();
            };
            if (!(tg.x_m > p[0]))
                throw std::invalid_argument(where() + ": the target is behind the antenna "
                                                      "across track (x must exceed the "
                                                      "antenna's x)");
            const double dx = tg.x_m - p[0], dy = p[1] - tg.y_m, dz = p[2];
            const double r = std::sqrt(dx * dx + dz * dz + dy * dy);
            if (r > r_cp) {
                std::ostringstream s;
                s << where() << ": slant range " << r << " m, round trip "
                  << 2e6 * r / speed_of_light << " us is longer than Tcp = " << num.cp_s() * 1e6
                  << " us (ranges up to " << r_cp << " m)";
                throw std::invalid_argument(s.str());
            }
            if (r >= r_amb) {
                std::ostringstream s;
                s << where() << ": slant range " << r
                  << " m is beyond the unambiguous range c / (2 Delta f) = " << r_amb << " m";
                throw std::invalid_argument(s.str());
            }
        }
    }
    return warnings;
}

} // namespace nrsar
} // namespace gr
