/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/kernel/bp_autofocus.h>

#include "../param_check.h"
#include "small_solve.h"
#include <gnuradio/nrsar/kernel/fft_plans.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <stdexcept>

namespace gr {
namespace nrsar {
namespace kernel {

using vec3 = std::array<double, 3>;

void trajectory_autofocus_config::validate() const
{
    check_range("max_iterations", max_iterations, 1u, 50u);
    check_range("points", points, 1u, 64u);
    if (!(std::isfinite(points_db) && points_db > 0.0 && points_db <= 60.0))
        throw_param("points_db", points_db, "must be in (0, 60]");
    check_at_least("smooth_pulses", smooth_pulses, 1u);
    if (!(std::isfinite(look_spread_rad) && look_spread_rad >= 0.0 && look_spread_rad <= 1.0))
        throw_param("look_spread_rad", look_spread_rad, "must be in [0, 1]");
    if (!(std::isfinite(tolerance_m) && tolerance_m > 0.0 && tolerance_m < 1.0))
        throw_param("tolerance_m", tolerance_m, "must be in (0, 1)");
    if (!(std::isfinite(significance) && significance >= 0.0 && significance <= 100.0))
        throw_param("significance", significance, "must be in [0, 100]");
    check_finite_points("gcp", gcp, max_gcp);
    if (!(std::isfinite(gcp_along_track_se_m) && gcp_along_track_se_m >= 0.0 &&
          gcp_along_track_se_m <= 1.0))
        throw_param("gcp_along_track_se_m", gcp_along_track_se_m, "must be in [0, 1]");
    if (!(std::isfinite(gcp_speed_se_m) && gcp_speed_se_m >= 0.0 && gcp_speed_se_m <= 1.0))
        throw_param("gcp_speed_se_m", gcp_speed_se_m, "must be in [0, 1]");
    if (!(std::isnan(range_band_cycles) ||
          (range_band_cycles >= 0.0 && range_band_cycles <= 1.0)))
        throw_param("range_band_cycles", range_band_cycles, "must be in [0, 1] (or NaN: auto)");
}

namespace {

double distance(const vec3& a, const vec3& b)
{
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

struct point {
    unsigned line, bin;
    vec3 p;   // the scatterer the pixel stands for
    vec3 q;   // the point itself: p moved to the peak interpolated between the pixels
    double w; // weight: coherent SNR per pulse A^2 / sigma^2 (inverse phase variance)
    double v; // variance of the smoothed history's psi / (2 pi cs) times its length [m^2]
};

// The scatterer of pixel (line j, bin k), as bp_focuser images it; false where the slant
// range does not reach the ground.
bool pixel_position(const bp_grid& g, unsigned j, unsigned k, vec3& p)
{
    const double y = g.first_y_m + j * g.line_spacing_m;
    if (g.ground) {
        p = { g.first_x_m + k * g.x_spacing_m, y, g.ground_height_m };
        return true;
    }
    const double r0 = g.first_range_m + k * g.range_bin_m;
    if (!(r0 > g.reference_height_m))
        return false;
    p = { std::sqrt(r0 * r0 - g.reference_height_m * g.reference_height_m), y, 0.0 };
    return true;
}

// A range error e turns a BP summand by 2 pi cs e: the carrier's 4 pi e / lambda and the
// range spectrum centre's 2 pi fc_r e / rho (BP remodulates the profile, whose point
// response turns by 2 pi fc_r per bin, at the centre: the band's centre, not subcarrier 0,
// is the phase's carrier). lambda / (4 pi) alone is 0.7 % off in focus_scenario.
double phase_cycles_per_m(const bp_grid& g)
{
    return 2.0 / g.wavelength_m + g.range_centre_cycles / g.range_bin_m;
}

struct history {
    double sum; // of the unwrapped history [m]
    double a2;  // coherent power per pulse A^2
    double w;   // A^2 / sigma^2 (0: the smoothed SNR is below 2)
    double v;   // variance of psi / (2 pi cs) per pulse [m^2]
};

// The noise floor sigma^2 of a history next to frequency 0, what its constant and slope
// average: the median of its Hann-windowed periodogram over 1 / L to 4 / L cycles a pulse
// (the path error is slower than 1 / L; at most 1 / 8 to 1 / 2), over the median's
// expectation for complex Gaussian noise (exponential ordinates: the harmonic sum below,
// about ln 2). The deviation from the moving mean weighs all frequencies above 1 / L: it
// counts another target in the same range bins at another along-track position, a line in
// the history (25 m apart: 0.07 cycles a pulse), as noise, and misses presummed noise's
// fall towards the decimated band's edge; the median passes over the line (docs/blocks/
// bp_focuser.md, "Two GCPs in one range bin").
double noise_floor(const std::vector<std::complex<double>>& c, unsigned L)
{
    const unsigned n = static_cast<unsigned>(c.size());
    const fft_fwd fft = make_fft_fwd(int(n));
    double w2 = 0.0;
    for (unsigned p = 0; p < n; ++p) {
        const double s = std::sin(M_PI * (p + 0.5) / n), w = s * s;
        fft->get_inbuf()[p] = gr_complex(w * c[p]);
        w2 += w * w;
    }
    fft->execute();
    const double f0 = std::min(1.0 / L, 0.125), f1 = std::min(4.0 / L, 0.5);
    std::vector<double> pg;
    for (unsigned k = 0; k < n; ++k) {
        const unsigned f = std::min(k, n - k);
        if (f >= f0 * n && f <= f1 * n)
            pg.push_back(std::norm(fft->get_outbuf()[k]) / w2);
    }
    if (pg.empty())
        return 0.0;
    const std::size_t m = pg.size(), j = m / 2;
    std::nth_element(pg.begin(), pg.begin() + j, pg.end());
    double e = 0.0; // the (j + 1)-th smallest of m unit exponentials: sum 1 / i, i = m - j..m
    for (std::size_t i = m - j; i <= m; ++i)
        e += 1.0 / i;
    return pg[j] / e;
}

// c's complex moving sum over len[p] pulses (h each side), its phase unwrapped over the
// pulses in metres (psi to_m, to_m = 1 / (2 pi cs)) into b, and the noise it carries:
// sigma^2 from the deviation from the moving mean, or, given floor_of, noise_floor of that
// history (the GCP stage: c as read, before its neighbours' echoes are taken out, which
// takes the noise within 1 / L of their lines with them: docs/blocks/bp_focuser.md, "The
// noise floor of a GCP with neighbours").
history smoothed_history(const std::vector<std::complex<double>>& c,
                         const std::vector<unsigned>& len,
                         unsigned h,
                         double to_m,
                         std::vector<double>& b,
                         const std::vector<std::complex<double>>* floor_of = nullptr)
{
    // The noise: sigma^2 from each summand's deviation from its moving mean (the
    // path error is slow over the sum; white noise gives sigma^2 (1 - 1 / L));
    // the coherent power A^2: mean |s / L|^2 less the sigma^2 / L noise adds.
    // The smoothed phase's variance is then sigma^2 / (2 L A^2).
    const unsigned n = static_cast<unsigned>(c.size());
    double pw = 0.0, dev = 0.0, dof = 0.0, inv_len = 0.0;
    std::complex<double> s(0.0, 0.0);
    unsigned lo = 0, hi = 0; // s = sum of c[lo, hi)
    double prev = 0.0, sum = 0.0;
    for (unsigned p = 0; p < n; ++p) {
        const unsigned want_lo = p > h ? p - h : 0, want_hi = std::min(n, p + h + 1);
        for (; hi < want_hi; ++hi)
            s += c[hi];
        for (; lo < want_lo; ++lo)
            s -= c[lo];
        const double L = len[p];
        pw += std::norm(s) / (L * L);
        dev += std::norm(c[p] - s / L);
        dof += 1.0 - 1.0 / L;
        inv_len += 1.0 / L;
        const double a = std::arg(s);
        prev = p == 0 ? a : prev + std::remainder(a - prev, 2.0 * M_PI);
        b[p] = prev * to_m;
        sum += b[p];
    }
    pw /= n;
    const double s2 = floor_of ? noise_floor(*floor_of, 2 * h + 1) : dof > 0.0 ? dev / dof : 0.0;
    const double sigma2 = std::max(s2, 1e-12 * pw);
    const double a2 = std::max(pw - sigma2 * inv_len / n, 1e-12 * pw);
    // A history whose smoothed SNR L A^2 / sigma^2 is below 2 (phase noise above
    // 0.5 rad) unwraps into a random walk (a noise peak taken for a point): unused.
    return { sum,
             a2,
             pw > 0.0 && (2 * h + 1) * a2 >= 2.0 * sigma2 ? a2 / sigma2 : 0.0,
             pw > 0.0 ? to_m * to_m * sigma2 / (2.0 * a2) : 0.0 };
}

// The pulses tapered in range: each profile's K-point spectrum times a Hann window of width
// band [cycles/bin] centred at fc_r. A point's single-pulse pixel holds the other targets'
// range sidelobes (the unwindowed 2x oversampled Dirichlet: -18 to -32 dB at 5-25 bins),
// whose phase turns with their Doppler difference; for targets at about one along-track
// position that beat is slower than the moving sum and biases the solve. Hann brings them to
// -32 to -74 dB for 1.76 dB of SNR (docs/blocks/bp_focuser.md, "Range sidelobes").
std::vector<float> taper_weights(const bp_grid& g, double band)
{
    const unsigned K = g.num_range_bins;
    std::vector<float> w(K);
    for (unsigned m = 0; m < K; ++m) {
        const double f = std::remainder(double(m) / K - g.range_centre_cycles, 1.0);
        const double c = std::cos(M_PI * f / band);
        w[m] = std::abs(f) < 0.5 * band ? float(c * c / K) : 0.0f; // the inverse FFT's 1 / K
    }
    return w;
}

std::vector<gr_complex>
tapered(const gr_complex* pulses, unsigned n, const bp_grid& g, const std::vector<float>& w)
{
    const unsigned K = g.num_range_bins;
    std::vector<gr_complex> out(pulses, pulses + std::size_t(n) * K);
    const fft_fwd fwd = make_fft_fwd(int(K));
    const fft_rev rev = make_fft_rev(int(K));
    for (unsigned p = 0; p < n; ++p) {
        gr_complex* row = out.data() + std::size_t(p) * K;
        std::copy(row, row + K, fwd->get_inbuf());
        fwd->execute();
        for (unsigned m = 0; m < K; ++m)
            rev->get_inbuf()[m] = fwd->get_outbuf()[m] * w[m];
        rev->execute();
        std::copy(rev->get_outbuf(), rev->get_outbuf() + K, row);
    }
    return out;
}

// Offset of the peak from sample 0 by a parabola through ln|.| of three samples, in
// [-1/2, 1/2] (0 at an edge or without a maximum).
double peak_offset(double lm, double l0, double lp)
{
    const double den = lm - 2.0 * l0 + lp;
    if (!(den < 0.0))
        return 0.0;
    return std::clamp(0.5 * (lm - lp) / den, -0.5, 0.5);
}

// The brightest pixels within points_db of the strongest, each at least ex_j lines or
// ex_k bins from the ones already taken (so a target's main lobe and near sidelobes give
// one point).
std::vector<point> prominent(const std::vector<gr_complex>& img,
                             const bp_grid& g,
                             const trajectory_autofocus_config& cfg,
                             unsigned ex_j,
                             unsigned ex_k)
{
    const unsigned K = g.num_range_bins;
    std::vector<std::size_t> order(img.size());
    std::iota(order.begin(), order.end(), std::size_t{ 0 });
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return std::norm(img[a]) > std::norm(img[b]);
    });
    const double floor = std::norm(img[order[0]]) * std::pow(10.0, -cfg.points_db / 10.0);
    std::vector<point> pts;
    for (std::size_t i : order) {
        if (pts.size() >= cfg.points || !(std::norm(img[i]) >= floor) || std::norm(img[i]) == 0.0)
            break;
        const unsigned j = static_cast<unsigned>(i / K), k = static_cast<unsigned>(i % K);
        bool near = false;
        for (const point& q : pts)
            near = near || (std::abs(int(j) - int(q.line)) <= int(ex_j) &&
                            std::abs(int(k) - int(q.bin)) <= int(ex_k));
        vec3 p;
        if (near || !pixel_position(g, j, k, p))
            continue;
        // The point's own position: a pixel beside it sees its pulses with the range
        // difference |a - p| - |a - q| (a quadratic over the aperture), not a path error.
        const unsigned M = g.num_lines;
        auto l = [&](unsigned jj, unsigned kk) {
            return std::log(std::max(double(std::norm(img[std::size_t(jj) * K + kk])), 1e-300));
        };
        const double dk =
            (k > 0 && k + 1 < K) ? peak_offset(l(j, k - 1), l(j, k), l(j, k + 1)) : 0.0;
        const double dj =
            (j > 0 && j + 1 < M) ? peak_offset(l(j - 1, k), l(j, k), l(j + 1, k)) : 0.0;
        vec3 q = p;
        q[1] += dj * g.line_spacing_m;
        if (g.ground) {
            q[0] += dk * g.x_spacing_m;
        } else {
            const double r0 = g.first_range_m + (k + dk) * g.range_bin_m;
            const double h = g.reference_height_m;
            if (r0 > h)
                q[0] = std::sqrt(r0 * r0 - h * h);
        }
        pts.push_back({ j, k, p, q, 0.0, 0.0 });
    }
    return pts;
}

// The displacement (x, 0, z) at one pulse (antenna a) that the points' line-of-sight
// values b(i) [m] give: least squares weighted by w in (x, z) (two_d), else along their
// mean line of sight; var: the solution's variance (x + z) for histories smoothed over len
// pulses.
template <class values>
vec3 solve_pulse(const std::vector<point>& pts,
                 const vec3& a,
                 bool two_d,
                 unsigned len,
                 values b,
                 double& var)
{
    auto los = [&](const point& q) {
        const double r = distance(a, q.q);
        return std::array<double, 2>{ (a[0] - q.q[0]) / r, (a[2] - q.q[2]) / r };
    };
    if (two_d) { // normal equations of (d_x, d_z)
        // and the covariance G^-1 H G^-1 of the solution, H = sum w^2 var u u^T
        double axx = 0.0, axz = 0.0, azz = 0.0, bx = 0.0, bz = 0.0;
        double hxx = 0.0, hxz = 0.0, hzz = 0.0;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const auto u = los(pts[i]);
            const double w = pts[i].w, wwv = w * w * pts[i].v / len;
            axx += w * u[0] * u[0];
            axz += w * u[0] * u[1];
            azz += w * u[1] * u[1];
            bx += w * u[0] * b(i);
            bz += w * u[1] * b(i);
            hxx += wwv * u[0] * u[0];
            hxz += wwv * u[0] * u[1];
            hzz += wwv * u[1] * u[1];
        }
        const double det = axx * azz - axz * axz;
        // G^-1 = [azz -axz; -axz axx] / det; trace(G^-1 H G^-1)
        const double gxx = azz / det, gxz = -axz / det, gzz = axx / det;
        const double cxx = gxx * (gxx * hxx + gxz * hxz) + gxz * (gxx * hxz + gxz * hzz);
        const double czz = gxz * (gxz * hxx + gzz * hxz) + gzz * (gxz * hxz + gzz * hzz);
        var = cxx + czz;
        return { (azz * bx - axz * bz) / det, 0.0, (axx * bz - axz * bx) / det };
    }
    // along the mean line of sight m: d = alpha m
    double mx = 0.0, mz = 0.0;
    for (const point& q : pts) {
        const auto u = los(q);
        mx += q.w * u[0];
        mz += q.w * u[1];
    }
    const double mn = std::hypot(mx, mz);
    mx /= mn;
    mz /= mn;
    double num = 0.0, den = 0.0, vn = 0.0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto u = los(pts[i]);
        const double um = u[0] * mx + u[1] * mz;
        num += pts[i].w * um * b(i);
        den += pts[i].w * um * um;
        vn += pts[i].w * pts[i].w * um * um * pts[i].v / len;
    }
    var = vn / (den * den);
    return { num / den * mx, 0.0, num / den * mz };
}

// A GCP's single-pulse history: its pixel kp (range bin kr at the middle pulse) at q's y,
// read along the path moved by p - q (ant).
struct reading {
    vec3 q, p;
    unsigned kp;
    double kr;
    std::vector<std::complex<double>> c0, c; // as read, and less the neighbours' echoes
    std::vector<vec3> ant;
    vec3 du; // least-squares slope of its line of sight over the pulses [1 / pulse]
    std::vector<std::size_t> near;          // the GCPs whose echoes its pixel holds
    std::vector<gr_complex> response;       // per pulse its unit response's K bins at its
                                            // modelled range (if near any)
    std::vector<std::complex<double>> echo; // its echo there: the unit response's amplitude
};

// A unit point's range profile at bin kr as the tapered pulses hold it: the band (spectrum
// width `width` around fc_r) under the taper. Where K is the range IFFT's size (subcarriers
// 0..N-1: 2 fc_r K + 1 = N, an integer up to K) the profile is K-periodic, a flat spectrum
// times the taper; else the K bins are cut from a longer IFFT (nrsar-sim: 35 of 512) and the
// profile is the band-limited e^(2 pi i fc_r d) width sinc(width d), d = k - kr, tapered as
// the pulses are (its K-point spectrum times the taper). The periodic model there put the
// leak 3.4 bins away 9 % high, 1.7 bins away 0.3 % (docs/blocks/bp_focuser.md).
class point_response
{
public:
    point_response(const bp_grid& g, double band, double width)
        : taper_(taper_weights(g, band)),
          fc_(g.range_centre_cycles),
          width_(width),
          fwd_(make_fft_fwd(int(g.num_range_bins))),
          rev_(make_fft_rev(int(g.num_range_bins)))
    {
        const double N = 2.0 * std::abs(fc_) * g.num_range_bins + 1.0;
        periodic_ = std::abs(N - std::round(N)) < 1e-6 && N <= g.num_range_bins + 0.5;
    }

    void row(double kr, gr_complex* out)
    {
        const unsigned K = static_cast<unsigned>(taper_.size());
        if (periodic_) {
            for (unsigned m = 0; m < K; ++m)
                rev_->get_inbuf()[m] = gr_complex(std::polar(
                    double(taper_[m]), -2.0 * M_PI * std::fmod(m * kr, double(K)) / K));
        } else {
            for (unsigned k = 0; k < K; ++k) {
                const double d = k - kr, x = M_PI * width_ * d;
                const double a = width_ * (std::abs(x) < 1e-12 ? 1.0 : std::sin(x) / x);
                fwd_->get_inbuf()[k] = gr_complex(std::polar(a, 2.0 * M_PI * fc_ * d));
            }
            fwd_->execute();
            for (unsigned m = 0; m < K; ++m)
                rev_->get_inbuf()[m] = fwd_->get_outbuf()[m] * taper_[m];
        }
        rev_->execute();
        std::copy(rev_->get_outbuf(), rev_->get_outbuf() + K, out);
    }

private:
    std::vector<float> taper_;
    double fc_, width_;
    bool periodic_;
    fft_fwd fwd_;
    fft_rev rev_;
};

// Within 7 / band bins GCPs hold each other's echoes in their histories (the Hann response's
// sidelobes fall below 1e-3 there: 3.4 bins off, -43 dB, it biased nrsar-sim's drift by 2
// mm/s), a beat at their along-track separation that biases the slopes (docs/blocks/
// bp_focuser.md, "The neighbours' echoes modelled"). Each pulse's pixels are c = g H x: x
// the GCPs' own echoes, H[q][r] r's point response (at r's range along the path) in q's
// pixel over its own (1 on the diagonal; a common navigation error leaves its phase, the
// ranges' difference) times r's own phase turn e^(2 pi i cs e_r), e_r its line-of-sight
// error (known after a pass: c + s (n - n_mid)), and g the pulse's gain. x is solved by
// least squares over each pulse's moving-sum window, and the neighbours' g H x taken off each
// c. Without neighbours the histories are left as read.
bool take_out_neighbours(std::vector<reading>& rd,
                         const bp_grid& grid,
                         const std::vector<vec3>& antenna,
                         const std::vector<std::array<double, 2>>& los,
                         double cs,
                         double band,
                         point_response& unit,
                         bp_focuser& one,
                         unsigned h)
{
    using cx = std::complex<double>;
    const std::size_t G = rd.size();
    if (!(band > 0.0)) // untapered: no main lobe to model
        return false;
    std::vector<char> near(G * G, 0), used(G, 0);
    bool any = false;
    for (std::size_t q = 0; q < G; ++q) {
        rd[q].near.clear();
        for (std::size_t r = 0; r < G; ++r)
            if (q != r && std::abs(rd[q].kr - rd[r].kr) < 7.0 / band) {
                near[q * G + r] = used[r] = 1;
                rd[q].near.push_back(r);
                any = true;
            }
    }
    if (!any)
        return false;
    const unsigned K = grid.num_range_bins, n = static_cast<unsigned>(rd[0].c.size());
    std::vector<gr_complex> line(K);
    gr_complex* row = nullptr; // the unit response being projected
    auto pixel = [&](const reading& g, unsigned i) {
        one.reset(g.q[1]);
        one.add(row, 1, &g.ant[i]);
        one.image(line.data());
        return cx(line[g.kp]);
    };
    const double tm = 0.5 * (n - 1.0);
    std::vector<cx> H(std::size_t(n) * G * G, 0.0); // H[i][q][r]
    std::vector<cx> own(std::size_t(n) * G, 1.0);   // r's unit response in its pixel
    for (std::size_t r = 0; r < G; ++r) {
        rd[r].response.assign(used[r] ? std::size_t(n) * K : 0, gr_complex(0.0f, 0.0f));
        rd[r].echo.assign(used[r] ? n : 0, 0.0);
        for (unsigned i = 0; i < n; ++i) {
            cx* Hi = H.data() + std::size_t(i) * G * G;
            const double err = los[r][0] + los[r][1] * (i - tm);
            const cx turn = std::polar(1.0, 2.0 * M_PI * cs * err);
            Hi[r * G + r] = turn;
            if (!used[r])
                continue;
            // r's true range: the navigated one less its line-of-sight error
            row = rd[r].response.data() + std::size_t(i) * K;
            unit.row((distance(antenna[i], rd[r].q) - err - grid.first_range_m) /
                         grid.range_bin_m,
                     row);
            cx& o = own[std::size_t(i) * G + r];
            o = pixel(rd[r], i);
            for (std::size_t q = 0; q < G; ++q)
                if (near[q * G + r])
                    Hi[q * G + r] = pixel(rd[q], i) / o * turn;
            o /= turn;
        }
    }
    std::vector<std::vector<cx>> c(G);
    for (std::size_t q = 0; q < G; ++q)
        rd[q].c = c[q] = rd[q].c0;
    std::vector<double> g(n, 1.0);
    std::vector<cx> A(G * G), b(G), x(G);
    auto window = [&](unsigned i) { // x over pulse i's window
        const unsigned lo = i > h ? i - h : 0, hi = std::min(n, i + h + 1);
        std::fill(A.begin(), A.end(), 0.0);
        std::fill(b.begin(), b.end(), 0.0);
        for (unsigned j = lo; j < hi; ++j) {
            const cx* Hj = H.data() + std::size_t(j) * G * G;
            for (std::size_t q = 0; q < G; ++q)
                for (std::size_t r = 0; r < G; ++r) {
                    const cx hq = g[j] * std::conj(Hj[q * G + r]);
                    if (hq == 0.0)
                        continue;
                    b[r] += hq * c[q][j];
                    for (std::size_t s2 = 0; s2 < G; ++s2)
                        A[r * G + s2] += hq * g[j] * Hj[q * G + s2];
                }
        }
        return solve_small(A, b, G, 1e-9 * (hi - lo), x); // singular: the pulse is kept
    };
    // A pulse whose echoes are weaker than its window's (a presummer's first outputs, its
    // filter filling: 0.62 and 0.95 in nrsar-sim) would have the window's leak taken off:
    // its gain g, the real least-squares scale of H x to its pixels, where that is more than
    // 2 % and 5 robust deviations (1.4826 median |g - 1|) from 1 and H x not near a null of
    // the beat (its power at least half the median).
    std::vector<double> dev(n, 0.0), pw(n, 0.0);
    for (unsigned i = 0; i < n; ++i) {
        if (!window(i))
            continue;
        const cx* Hi = H.data() + std::size_t(i) * G * G;
        double num = 0.0;
        for (std::size_t q = 0; q < G; ++q) {
            cx m = 0.0;
            for (std::size_t r = 0; r < G; ++r)
                m += Hi[q * G + r] * x[r];
            num += std::real(std::conj(m) * c[q][i]);
            pw[i] += std::norm(m);
        }
        dev[i] = pw[i] > 0.0 ? num / pw[i] - 1.0 : 0.0;
    }
    std::vector<double> ad(n), mp(pw);
    for (unsigned i = 0; i < n; ++i)
        ad[i] = std::abs(dev[i]);
    std::nth_element(ad.begin(), ad.begin() + n / 2, ad.end());
    std::nth_element(mp.begin(), mp.begin() + n / 2, mp.end());
    const double gate = std::max(0.02, 5.0 * 1.4826 * ad[n / 2]);
    for (unsigned i = 0; i < n; ++i)
        if (std::abs(dev[i]) > gate && pw[i] >= 0.5 * mp[n / 2])
            g[i] = 1.0 + dev[i];
    for (unsigned i = 0; i < n; ++i) {
        if (!window(i))
            continue;
        const cx* Hi = H.data() + std::size_t(i) * G * G;
        for (std::size_t r = 0; r < G; ++r)
            if (used[r])
                rd[r].echo[i] = g[i] * x[r] / own[std::size_t(i) * G + r];
        for (std::size_t q = 0; q < G; ++q)
            for (std::size_t r = 0; r < G; ++r)
                if (near[q * G + r])
                    rd[q].c[i] -= g[i] * Hi[q * G + r] * x[r];
    }
    return true;
}

// The tapered pulses less q's neighbours' modelled echoes, for its range peak: their main
// lobes and sidelobes pulled it by more than half the phase's period (a slip of the
// integer, of P along the line of sight for every GCP, which the slopes' du . o turned into
// v P / R of d_y: +1.8 mm/s in nrsar-sim; docs/blocks/bp_focuser.md).
void without_neighbours(const gr_complex* pulses,
                        unsigned K,
                        const std::vector<reading>& rd,
                        std::size_t q,
                        std::vector<gr_complex>& out)
{
    const unsigned n = static_cast<unsigned>(rd[q].c.size());
    out.assign(pulses, pulses + std::size_t(n) * K);
    for (std::size_t r : rd[q].near)
        for (unsigned i = 0; i < n; ++i) {
            const gr_complex* row = rd[r].response.data() + std::size_t(i) * K;
            const gr_complex e(rd[r].echo[i]);
            gr_complex* p = out.data() + std::size_t(i) * K;
            for (unsigned k = 0; k < K; ++k)
                p[k] -= e * row[k];
        }
}

// The ground control points' calibration (docs/blocks/bp_focuser.md, "Ground control
// points"): each GCP q in the image gives, along res.antenna, the constant c and slope s
// over the pulses of its line-of-sight error R_nav - R_true; they fix the navigation
// error's constant and linear trend, which no focus criterion observes. Takes them off
// res.antenna; false when no GCP has a usable history.
bool calibrate_gcp(const gr_complex* pulses,
                   unsigned n,
                   const bp_grid& grid,
                   const std::vector<vec3>& gcps,
                   double gcp_along_track_se_m,
                   double gcp_speed_se_m,
                   bp_focuser& one,
                   const std::vector<unsigned>& len,
                   unsigned h,
                   double band,
                   double width,
                   trajectory_autofocus_result& res)
{
    const unsigned K = grid.num_range_bins;
    const double cs = phase_cycles_per_m(grid);
    const double period = 1.0 / cs, to_m = period / (2.0 * M_PI); // the phase repeats every P
    const double tm = 0.5 * (n - 1.0);
    double stt = 0.0;
    for (unsigned p = 0; p < n; ++p)
        stt += (p - tm) * (p - tm);
    std::vector<gr_complex> line(K);
    std::vector<double> b(n);
    std::vector<vec3> path(n);
    struct fix {
        double ux, uz; // line of sight (x, z) at the middle pulse
        double c, s;   // constant at the middle pulse [m], slope [m / pulse]
        double v;      // per-pulse variance of the history [m^2]
        double a2;     // coherent power per pulse
        double uy;     // line of sight's y at the middle pulse
        vec3 du;       // least-squares slope of the line of sight over the pulses [1 / pulse]
        std::size_t gi; // its reading
    };
    std::vector<fix> fixes;
    constexpr int steps = 6; // the range search: +-1.5 bins in quarter bins
    // The path moved by p - q and toward q by delta + slope (pulse - tm).
    auto moved = [&](const vec3& q, const vec3& p, unsigned i, double delta, double slope) {
        const vec3& a = res.antenna[i];
        const double r = distance(a, q), m = (delta + slope * (i - tm)) / r;
        return vec3{ a[0] + p[0] - q[0] - m * (a[0] - q[0]),
                     a[1] + p[1] - q[1] - m * (a[1] - q[1]),
                     a[2] + p[2] - q[2] - m * (a[2] - q[2]) };
    };
    std::vector<reading> rd;
    std::vector<gr_complex> clean; // the pulses less a GCP's neighbours' echoes
    for (const vec3& q : gcps) {
        const vec3& am = res.antenna[n / 2];
        const double rm = distance(am, q);
        const double jq = (q[1] - grid.first_y_m) / grid.line_spacing_m;
        const double kq = grid.ground ? (q[0] - grid.first_x_m) / grid.x_spacing_m
                                      : (rm - grid.first_range_m) / grid.range_bin_m;
        const double kr = (rm - grid.first_range_m) / grid.range_bin_m;
        // another aperture's (a strip's apertures share the list), or its echo off the bins
        if (!(jq >= 0.0 && jq <= grid.num_lines - 1.0 && kq >= 0.0 && kq <= K - 1.0 &&
              kr >= 2.0 && kr <= K - 3.0))
            continue;
        // Pixel kp of the line at q's y along the path moved by p - q sees exactly q's range
        // history (|a + p - q - p| = |a - q|): BP's own interpolation and phase.
        const unsigned kp = static_cast<unsigned>(std::lround(kq));
        vec3 p;
        if (!pixel_position(grid, 0, kp, p))
            continue;
        p[1] = q[1];
        reading g{ q, p, kp, kr, std::vector<std::complex<double>>(n), {},
                   std::vector<vec3>(n), vec3{} };
        for (unsigned i = 0; i < n; ++i) {
            const vec3& ai = res.antenna[i];
            const double ri = distance(ai, q);
            for (int c3 = 0; c3 < 3; ++c3)
                g.du[c3] += (ai[c3] - q[c3]) / ri * (i - tm) / stt;
            g.ant[i] = moved(q, p, i, 0.0, 0.0);
            one.reset(q[1]);
            one.add(pulses + std::size_t(i) * K, 1, &g.ant[i]);
            one.image(line.data());
            g.c0[i] = std::complex<double>(line[kp]);
        }
        g.c = g.c0;
        rd.push_back(std::move(g));
    }
    // The neighbours' echoes modelled at the navigated ranges, then once more at the ranges
    // the GCPs' own line-of-sight errors put right (their main lobes' slopes turn an error
    // of a tenth of a bin into a few per cent of H, a slow drift of the leak).
    std::vector<std::array<double, 2>> los(rd.size(), { 0.0, 0.0 });
    point_response unit(grid, band, width);
    const bool modelled =
        take_out_neighbours(rd, grid, res.antenna, los, cs, band, unit, one, h);
    for (int pass = 0; pass < (modelled ? 2 : 1); ++pass) {
        if (pass == 1) {
            take_out_neighbours(rd, grid, res.antenna, los, cs, band, unit, one, h);
            fixes.clear();
        }
        for (std::size_t gi = 0; gi < rd.size(); ++gi) {
            const reading& g = rd[gi];
            const vec3 &q = g.q, &p = g.p, &am = res.antenna[n / 2];
            const double rm = distance(am, q);
            const unsigned kp = g.kp;
            const std::vector<std::complex<double>>& c = g.c;
            const history hs = smoothed_history(c, len, h, to_m, b, &g.c0);
            if (hs.w == 0.0)
                continue;
            double slope = 0.0;
            for (unsigned i = 0; i < n; ++i)
                slope += b[i] * (i - tm) / stt;
            // The constant is the phase's, ambiguous by the period 1 / cs: the range peak of q's
            // image along the path less the slope (its envelope |A(delta)|, delta in quarter
            // bins, parabola through ln |A|) picks the integer. Its noise (the resolution over
            // about sqrt(2 SNR) of the image) and the neighbours' range sidelobes may miss it by
            // a few: a range shift of k periods, a small part of the resolution cell, where the
            // phase (what the image's NMSE feels) stays right (docs/blocks/bp_focuser.md).
            // Read without its neighbours' modelled echoes where it has any.
            if (!g.near.empty())
                without_neighbours(pulses, K, rd, gi, clean);
            const gr_complex* src = g.near.empty() ? pulses : clean.data();
            auto envelope = [&](int m) {
                for (unsigned i = 0; i < n; ++i)
                    path[i] = moved(q, p, i, 0.25 * m * grid.range_bin_m, slope);
                one.reset(q[1]);
                one.add(src, n, path.data());
                one.image(line.data());
                return std::log(std::max(double(std::abs(line[kp])), 1e-300));
            };
            std::vector<double> env(2 * steps + 1);
            for (int m = -steps; m <= steps; ++m)
                env[m + steps] = envelope(m);
            const int top = int(std::max_element(env.begin(), env.end()) - env.begin());
            if (top == 0 || top == 2 * steps) // no peak within the search
                continue;
            const double peak =
                (top - steps + peak_offset(env[top - 1], env[top], env[top + 1])) * 0.25 *
                grid.range_bin_m;
            const double fine = hs.sum / n;
            const double constant = fine + period * std::round((peak - fine) / period);
            fixes.push_back({ (am[0] - q[0]) / rm, (am[2] - q[2]) / rm, constant, slope, hs.v,
                              hs.a2, (am[1] - q[1]) / rm, g.du, gi });
        }
        if (fixes.empty())
            return false;
        res.gcp_used = static_cast<unsigned>(fixes.size());
        // The others' integers from the strongest one's (the least noise, and the least pulled
        // by its neighbours' range sidelobes): the lattice point next to what its offset
        // predicts along their line of sight. Their own range peaks would slip; a slip of a
        // period P (about lambda / 2) between two GCPs at look angles d apart tilts the solution
        // by P / d across the line of sight; this needs the navigation's error across it below
        // P / (2 d), 1.2 m at d = 1 degree.
        const auto ref = std::max_element(
            fixes.begin(), fixes.end(), [](const fix& a, const fix& b) { return a.a2 < b.a2; });
        const double ur2 = ref->ux * ref->ux + ref->uz * ref->uz;
        for (fix& f : fixes) {
            const double predicted = ref->c * (f.ux * ref->ux + f.uz * ref->uz) / ur2;
            f.c += period * std::round((predicted - f.c) / period);
        }
        for (const fix& f : fixes)
            los[f.gi] = { f.c, f.s };
    }
    double sw = 0.0, st = 0.0, st2 = 0.0;
    for (const fix& f : fixes) {
        const double th = std::atan2(f.ux, f.uz);
        sw += 1.0 / f.v;
        st += th / f.v;
        st2 += th * th / f.v;
    }
    // Both components when the GCPs' look angles spread (the one across the line of sight
    // comes with the noise times 1 / spread; the constant averages n pulses, so even a
    // degree of spread leaves millimetres); else along their mean line of sight.
    res.gcp_two_dimensional =
        fixes.size() >= 2 && std::sqrt(std::max(0.0, st2 / sw - (st / sw) * (st / sw))) >= 1e-3;
    // Weighted least squares in (x, z), G = sum u u^T / v, or along the mean line of sight m.
    double axx = 0.0, axz = 0.0, azz = 0.0, mx = 0.0, mz = 0.0, den = 0.0;
    for (const fix& f : fixes) {
        axx += f.ux * f.ux / f.v;
        axz += f.ux * f.uz / f.v;
        azz += f.uz * f.uz / f.v;
        mx += f.ux / f.v;
        mz += f.uz / f.v;
    }
    const double det = axx * azz - axz * axz, mn = std::hypot(mx, mz);
    mx /= mn;
    mz /= mn;
    for (const fix& f : fixes) {
        const double um = f.ux * mx + f.uz * mz;
        den += um * um / f.v;
    }
    // (x, z) of the solution of u_i . e = value(fix i); trace of G^-1 (1 / den along m).
    auto solve = [&](auto value) -> std::array<double, 2> {
        if (res.gcp_two_dimensional) {
            double bx = 0.0, bz = 0.0;
            for (const fix& f : fixes) {
                bx += f.ux * value(f) / f.v;
                bz += f.uz * value(f) / f.v;
            }
            return { (azz * bx - axz * bz) / det, (axx * bz - axz * bx) / det };
        }
        double num = 0.0;
        for (const fix& f : fixes)
            num += (f.ux * mx + f.uz * mz) * value(f) / f.v;
        return { num / den * mx, num / den * mz };
    };
    const double g_trace = res.gcp_two_dimensional ? (axx + azz) / det : 1.0 / den;
    std::array<double, 2> e0 = solve([](const fix& f) { return f.c; });
    // The along-track offset e_y: each constant holds u_y e_y (docs/blocks/bp_focuser.md,
    // "The along-track offset"). Its column less its (x, z) fit, r, is what GCPs spread
    // along track add (Frisch-Waugh: e_y = sum r c / v / sum r^2 / v, variance 1 / (n sum
    // r^2 / v)); solved only where that predicted standard error is below
    // gcp_along_track_se_m, else y stays and e_y stays in the drift as before.
    const std::array<double, 2> by = solve([](const fix& f) { return f.uy; });
    double ryy = 0.0, ryc = 0.0;
    for (const fix& f : fixes) {
        const double r = f.uy - (f.ux * by[0] + f.uz * by[1]);
        ryy += r * r / f.v;
        ryc += r * f.c / f.v;
    }
    const double se_y = ryy > 0.0 ? std::sqrt(1.0 / (n * ryy)) : INFINITY;
    res.gcp_along_track = se_y < gcp_along_track_se_m;
    double ey = 0.0, offset_var_y = 0.0, drift_var_y = 0.0;
    std::array<double, 2> bd{};
    if (res.gcp_along_track) {
        ey = ryc / ryy;
        e0 = { e0[0] - ey * by[0], e0[1] - ey * by[1] };
        // The offset o turns each line of sight over the aperture: the slope holds du . o
        // besides the drift (for e_y: v T e_y / R); taken off each s.
        const vec3 o{ e0[0], ey, e0[1] };
        for (fix& f : fixes)
            f.s = f.s - (f.du[0] * o[0] + f.du[1] * o[1] + f.du[2] * o[2]);
        bd = solve([](const fix& f) { return f.du[1]; });
        offset_var_y = (by[0] * by[0] + by[1] * by[1]) * se_y * se_y;
        drift_var_y = (bd[0] * bd[0] + bd[1] * bd[1]) * se_y * se_y;
        res.gcp_offset_y_se_m = se_y;
    }
    std::array<double, 2> e1 = solve([](const fix& f) { return f.s; });
    // The along-track speed error d_y: each slope holds u_y d_y as each constant u_y e_y,
    // so the same r (docs/blocks/bp_focuser.md, "The along-track speed"): d_y = sum r s /
    // v / sum r^2 / v, variance 1 / (sum (p - tm)^2 sum r^2 / v), plus e_y's noise through
    // du . o (kappa e_y). Solved with e_y (r does not take du_y e_y out of the slopes: e_y
    // left would bias d_y by kappa e_y, 10 mm/s for 0.3 m in the test) where n times that
    // standard error (the along-track stretch it would leave over the aperture) is below
    // gcp_speed_se_m.
    const double se_dy0 = ryy > 0.0 ? std::sqrt(1.0 / (stt * ryy)) : INFINITY;
    double kappa = 0.0, rys = 0.0;
    for (const fix& f : fixes) {
        const double r = f.uy - (f.ux * by[0] + f.uz * by[1]);
        kappa += r * f.du[1] / f.v / ryy;
        rys += r * f.s / f.v;
    }
    const double se_dy = std::hypot(se_dy0, kappa * se_y);
    res.gcp_along_track_speed = res.gcp_along_track && n * se_dy < gcp_speed_se_m;
    double dy = 0.0;
    if (res.gcp_along_track_speed) {
        dy = rys / ryy;
        e1 = { e1[0] - dy * by[0], e1[1] - dy * by[1] };
        // The drift's e_y part is now -bd (du . o) + kappa by (d_y's), its slope noise's by
        const double cx = kappa * by[0] - bd[0], cz = kappa * by[1] - bd[1];
        drift_var_y = (by[0] * by[0] + by[1] * by[1]) * se_dy0 * se_dy0 +
                      (cx * cx + cz * cz) * se_y * se_y;
        res.gcp_drift_y_se_m = se_dy;
    }
    // The constant averages n pulses, the slope sum (p - tm)^2 of them; e_y's noise moves
    // both through its (x, z) fits (uncorrelated with the base solution's).
    res.gcp_offset_se_m = std::sqrt(g_trace / n + offset_var_y);
    res.gcp_drift_se_m = std::sqrt(g_trace / stt + drift_var_y);
    res.gcp_offset_m = { e0[0], ey, e0[1] };
    res.gcp_drift_m = { e1[0], dy, e1[1] };
    for (unsigned i = 0; i < n; ++i) {
        res.antenna[i][0] -= e0[0] + e1[0] * (i - tm);
        res.antenna[i][1] -= ey + dy * (i - tm);
        res.antenna[i][2] -= e0[1] + e1[1] * (i - tm);
    }
    return true;
}

// The along-track speed error d_y puts, besides its linear u_y d_y (p - tm), a quadratic
// v T d_y (p - tm)^2 / R (the defocus of a speed error) in every point's history, which
// the displacement took as x and z; with d_y now off the path's y that part would count
// twice (docs/blocks/bp_focuser.md, "The along-track speed"). It is taken out of the
// displacement (and put back on the path) as the points' solve made it: from each point's
// history of d_y's trend along the path, less its mean, per pulse, less the trend.
void take_out_speed_defocus(const std::vector<point>& pts,
                            bool two_d,
                            const std::vector<unsigned>& len,
                            trajectory_autofocus_result& res)
{
    const unsigned n = static_cast<unsigned>(res.antenna.size());
    const double tm = 0.5 * (n - 1.0), dy = res.gcp_drift_m[1];
    std::vector<std::vector<double>> g(pts.size(), std::vector<double>(n));
    for (std::size_t i = 0; i < pts.size(); ++i) {
        double mean = 0.0;
        for (unsigned p = 0; p < n; ++p) {
            const vec3& a = res.antenna[p];
            const vec3 nav{ a[0], a[1] + dy * (p - tm), a[2] };
            g[i][p] = distance(nav, pts[i].q) - distance(a, pts[i].q);
            mean += g[i][p] / n;
        }
        for (double& v : g[i])
            v -= mean;
    }
    std::vector<vec3> d(n);
    double var;
    for (unsigned p = 0; p < n; ++p)
        d[p] = solve_pulse(pts, res.antenna[p], two_d, len[p],
                           [&](std::size_t i) { return g[i][p]; }, var);
    std::array<double, 3> c0{}, c1{};
    double stt = 0.0;
    for (unsigned p = 0; p < n; ++p)
        stt += (p - tm) * (p - tm);
    for (unsigned p = 0; p < n; ++p)
        for (int c3 = 0; c3 < 3; c3 += 2) {
            c0[c3] += d[p][c3] / n;
            c1[c3] += d[p][c3] * (p - tm) / stt;
        }
    for (unsigned p = 0; p < n; ++p)
        for (int c3 = 0; c3 < 3; c3 += 2) {
            const double v = d[p][c3] - c0[c3] - c1[c3] * (p - tm);
            res.displacement_m[p][c3] -= v;
            res.antenna[p][c3] += v;
        }
}

} // namespace

trajectory_autofocus_result trajectory_autofocus(const gr_complex* pulses,
                                                 unsigned n,
                                                 const vec3* antenna,
                                                 const bp_grid& grid,
                                                 const trajectory_autofocus_config& cfg,
                                                 gr_complex* image_out,
                                                 unsigned num_threads)
{
    cfg.validate();
    grid.validate();
    if (grid.line_step != 1) // its points are at line j = first_y_m + j line_spacing_m
        throw_param("line_step", grid.line_step, "must be 1 with trajectory_autofocus");
    if (n < 2)
        throw_param("n (pulses)", n, "must be at least 2");
    if (cfg.smooth_pulses > n)
        throw_param("smooth_pulses", cfg.smooth_pulses, "must be at most the pulses, " +
                                                            std::to_string(n));
    const unsigned K = grid.num_range_bins, M = grid.num_lines;
    // The automatic taper band assumes subcarriers 0..N-1 (the band's lower edge at 0): the
    // chain's numerologies give 0.5-0.8. Under 1 / 4 (a range profile oversampled over 4
    // times) the spectrum is likely centred elsewhere (centred on 0: a one-bin window).
    const double auto_band = std::min(1.0, 2.0 * std::abs(grid.range_centre_cycles) + 1.0 / K);
    if (std::isnan(cfg.range_band_cycles) && auto_band < 0.25)
        throw_param("range_centre_cycles",
                    grid.range_centre_cycles,
                    "gives the automatic range_band_cycles 2 |range_centre_cycles| + 1 / K = " +
                        std::to_string(auto_band) +
                        ", below 0.25 (it assumes subcarriers 0..N-1 from frequency 0): set "
                        "range_band_cycles to the spectrum's width");
    trajectory_autofocus_result res;
    res.antenna.assign(antenna, antenna + n);
    res.displacement_m.assign(n, vec3{ 0.0, 0.0, 0.0 });

    // Exclusion around a point: 4 azimuth resolutions lambda r / (2 L) and 4 range bins.
    const double L = std::hypot(antenna[n - 1][0] - antenna[0][0],
                                antenna[n - 1][1] - antenna[0][1]);
    const double r_mid = grid.first_range_m + 0.5 * K * grid.range_bin_m;
    const double res_lines = grid.wavelength_m * r_mid / (2.0 * std::max(L, 1e-9)) /
                             grid.line_spacing_m;
    const unsigned ex_j = static_cast<unsigned>(std::min(double(M), std::ceil(4.0 * res_lines)));
    const unsigned ex_k = 4;

    // The histories are read from the tapered pulses, the images from the pulses as given.
    const double band = std::isnan(cfg.range_band_cycles) ? auto_band : cfg.range_band_cycles;
    std::vector<gr_complex> tapered_pulses; // none with band 0: the histories read pulses
    if (band > 0.0)
        tapered_pulses = tapered(pulses, n, grid, taper_weights(grid, band));
    const gr_complex* hist_pulses = band > 0.0 ? tapered_pulses.data() : pulses;

    bp_focuser bp(grid, num_threads);
    bp_grid g1 = grid; // one line, exact BP: the per-pulse summands of a pixel
    g1.num_lines = 1;
    g1.subaperture = 0;
    bp_focuser one(g1, 1);
    std::vector<gr_complex> img(std::size_t(M) * K), line(K);
    auto image_along = [&](const std::vector<vec3>& ant) {
        bp.reset(grid.first_y_m);
        bp.add(pulses, n, ant.data());
        bp.image(img.data());
    };

    const double cs = phase_cycles_per_m(grid), to_m = 1.0 / (2.0 * M_PI * cs);
    const unsigned h = cfg.smooth_pulses / 2;
    std::vector<std::complex<double>> c(n);
    std::vector<unsigned> len(n); // pulses in the moving sum at each pulse (fewer at the ends)
    for (unsigned p = 0; p < n; ++p)
        len[p] = std::min(n, p + h + 1) - (p > h ? p - h : 0);
    bool img_is_nav = false; // img holds the image along the navigation
    std::vector<point> solved; // the points of the displacement's iteration
    for (unsigned it = 0; it < cfg.max_iterations; ++it) {
        image_along(res.antenna);
        img_is_nav = it == 0;
        std::vector<point> pts = prominent(img, grid, cfg, ex_j, ex_k);
        if (pts.empty()) // an empty image: nothing to estimate from
            break;
        // b[i][n]: psi_i(n) / (2 pi cs), the navigation's line-of-sight error point i sees.
        std::vector<std::vector<double>> b(pts.size(), std::vector<double>(n));
        for (std::size_t i = 0; i < pts.size(); ++i) {
            point& q = pts[i];
            for (unsigned p = 0; p < n; ++p) {
                one.reset(q.p[1]);
                one.add(hist_pulses + std::size_t(p) * K, 1, &res.antenna[p]);
                one.image(line.data());
                // less the pixel's offset from the point, in the phase BP gave it:
                // 2 pi (2 / lambda + fc_r / rho) (|a - p| - |a - q|)
                const vec3& a = res.antenna[p];
                const double r = distance(a, q.q);
                const double dr = distance(a, q.p) - r;
                // plus the phase the path's correction so far took out, u . D / to_m: the
                // smoothing then sees the whole error each iteration (smoothing only the
                // residual would add its high-pass part back each time, and the estimate
                // would tend to the unsmoothed noise, sqrt(L) times larger)
                const vec3& e = res.displacement_m[p];
                const double ud = ((a[0] - q.q[0]) * e[0] + (a[2] - q.q[2]) * e[2]) / r;
                c[p] = std::complex<double>(line[q.bin]) *
                       std::polar(1.0, ud / to_m - 2.0 * M_PI * cs * dr);
            }
            // sigma^2 from the deviation, which counts the neighbours' echoes in the point's
            // range bins (no model of them here) and weighs their histories down; the floor
            // would not (docs/blocks/bp_focuser.md, "The noise floor in the relative stage").
            const history hs = smoothed_history(c, len, h, to_m, b[i]);
            for (double& v : b[i])
                v -= hs.sum / n;
            q.w = hs.w;
            q.v = hs.v;
        }
        if (std::none_of(pts.begin(), pts.end(), [](const point& q) { return q.w > 0.0; }))
            break;
        res.points.clear();
        for (const point& q : pts)
            if (q.w > 0.0)
                res.points.push_back({ q.line, q.bin });

        // Look-angle spread at the middle pulse decides how many components are solved.
        auto los = [&](const point& q, unsigned p) {
            const vec3& a = res.antenna[p];
            const double r = distance(a, q.q);
            return std::array<double, 2>{ (a[0] - q.q[0]) / r, (a[2] - q.q[2]) / r };
        };
        double sw = 0.0, st = 0.0, st2 = 0.0;
        for (const point& q : pts) {
            const auto u = los(q, n / 2);
            const double th = std::atan2(u[0], u[1]);
            sw += q.w;
            st += q.w * th;
            st2 += q.w * th * th;
        }
        res.look_spread_rad = std::sqrt(std::max(0.0, st2 / sw - (st / sw) * (st / sw)));
        res.two_dimensional = pts.size() >= 2 && res.look_spread_rad >= cfg.look_spread_rad &&
                              cfg.look_spread_rad > 0.0;

        std::vector<vec3> d(n, vec3{ 0.0, 0.0, 0.0 });
        double var = 0.0; // mean over the pulses of the solution's variance (x + z) [m^2]
        for (unsigned p = 0; p < n; ++p) {
            double v;
            d[p] = solve_pulse(pts, res.antenna[p], res.two_dimensional, len[p],
                               [&](std::size_t i) { return b[i][p]; }, v);
            var += v / n;
        }
        // A constant and a linear displacement only move the image (a phase and a Doppler
        // shift): removed, so the image stays where the navigation put it.
        std::array<double, 3> c0{}, c1{};
        const double tm = 0.5 * (n - 1.0);
        double stt = 0.0;
        for (unsigned p = 0; p < n; ++p)
            stt += (p - tm) * (p - tm);
        for (unsigned p = 0; p < n; ++p)
            for (int c3 = 0; c3 < 3; ++c3) {
                c0[c3] += d[p][c3] / n;
                c1[c3] += d[p][c3] * (p - tm) / stt;
            }
        double ss = 0.0;
        for (unsigned p = 0; p < n; ++p)
            for (int c3 = 0; c3 < 3; c3 += 2) {
                const double v = d[p][c3] - c0[c3] - c1[c3] * (p - tm);
                const double step = v - res.displacement_m[p][c3];
                res.antenna[p][c3] = antenna[p][c3] - v;
                res.displacement_m[p][c3] = v;
                ss += step * step;
            }
        res.last_update_rms_m = std::sqrt(ss / n);
        res.standard_error_m = std::sqrt(var);
        res.iterations = it + 1;
        solved = pts;
        // A first correction within its noise: iterating on it would only fit the noise.
        if (res.last_update_rms_m < cfg.tolerance_m ||
            (it == 0 && !(res.last_update_rms_m > cfg.significance * res.standard_error_m)))
            break;
    }
    double total = 0.0;
    for (const vec3& v : res.displacement_m)
        total += (v[0] * v[0] + v[2] * v[2]) / n;
    // Noise corrections sharpen the points they were fitted to (their phases follow the
    // noise), so no focus measure can refuse them; their size against their standard
    // error can.
    res.accepted = res.iterations > 0 && std::sqrt(total) > cfg.significance * res.standard_error_m;
    if (!res.accepted) {
        res.antenna.assign(antenna, antenna + n);
        res.displacement_m.assign(n, vec3{ 0.0, 0.0, 0.0 });
    }
    // The spectrum's width for the GCPs' point response where the K bins are cut from a
    // longer IFFT: 2 |fc_r| (N / fft_size less 1 / fft_size), or the width given.
    const double width = std::isnan(cfg.range_band_cycles)
                             ? std::min(1.0, 2.0 * std::abs(grid.range_centre_cycles))
                             : band;
    const bool calibrated = !cfg.gcp.empty() && calibrate_gcp(hist_pulses, n, grid,
                                                              cfg.gcp, cfg.gcp_along_track_se_m,
                                                              cfg.gcp_speed_se_m, one, len, h,
                                                              band, width, res);
    if (calibrated && res.gcp_along_track_speed && res.accepted)
        take_out_speed_defocus(solved, res.two_dimensional, len, res);
    if (calibrated || !(img_is_nav && !res.accepted))
        image_along(res.antenna);
    std::copy(img.begin(), img.end(), image_out);

    // The estimate on the points' mean line of sight at the middle pulse.
    double mx = 0.0, mz = 0.0;
    for (const auto& pl : res.points) {
        vec3 p;
        pixel_position(grid, pl[0], pl[1], p);
        const vec3& a = res.antenna[n / 2];
        const double r = distance(a, p);
        mx += (a[0] - p[0]) / r;
        mz += (a[2] - p[2]) / r;
    }
    const double mn = std::hypot(mx, mz);
    res.los_m.resize(n);
    for (unsigned p = 0; p < n; ++p)
        res.los_m[p] = mn > 0.0 ? (res.displacement_m[p][0] * mx + res.displacement_m[p][2] * mz) / mn
                                : 0.0;
    return res;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
