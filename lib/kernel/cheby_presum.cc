/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "fmod_two_pi.h"
#include "param_check.h"
#include <gnuradio/filter/pm_remez.h>
#include <gnuradio/nrsar/kernel/cheby_presum.h>
#include <volk/volk.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
constexpr double two_pi = 2.0 * M_PI;

double closest_range(const geometry& geo, const point_target& t)
{
    return std::sqrt(t.x_m * t.x_m + geo.height_m * geo.height_m);
}

double scene_centre_y(const geometry& geo, const scene& scn)
{
    double y = 0.0, r0 = 0.0;
    los_reference::scene_centre(geo, scn, y, r0);
    return y;
}

constexpr double max_path_phase_error_rad = 1e-4; // linear interpolation within a segment
constexpr unsigned max_segment = 64;
} // namespace

unsigned cheby_presum::max_decim(const numerology& num,
                                 const geometry& geo,
                                 const scene& scn,
                                 unsigned symbols_per_pulse)
{
    check_at_least("symbols_per_pulse", symbols_per_pulse, 1u);
    scn.validate();
    double r0 = std::numeric_limits<double>::infinity();
    for (const auto& t : scn.targets)
        r0 = std::min(r0, closest_range(geo, t));
    const double prf = 1.0 / (num.symbol_s() * symbols_per_pulse);
    // eq. (P-36): D <= PRF / (2 V) sqrt(lambda R0 / 2), from QPE 2 pi V^2 D^2 /
    // (lambda R0 PRF^2) <= pi / 4 (eq. P-35).
    return static_cast<unsigned>(
        std::floor(prf / (2.0 * geo.velocity_mps) * std::sqrt(geo.wavelength_m() * r0 / 2.0)));
}

cheby_presum::cheby_presum(const numerology& num,
                           const geometry& geo,
                           const scene& scn,
                           unsigned num_bins,
                           double first_range_m,
                           double range_bin_m,
                           const presum_config& cfg,
                           const trajectory& nav)
    : d_num(num), d_geo(geo), d_cfg(cfg), d_k(num_bins), d_first_m(first_range_m),
      d_bin_m(range_bin_m), d_los(geo, nav, scene_centre_y(geo, scn))
{
    num.validate();
    geo.validate();
    scn.validate();
    check_at_least("decim", cfg.decim, 1u);
    check_at_least("num_bins", num_bins, 1u);
    check_at_least("symbols_per_pulse", cfg.symbols_per_pulse, 1u);
    if (static_cast<int>(cfg.method) < 0 || static_cast<int>(cfg.method) > 4)
        throw_param("method", static_cast<int>(cfg.method), "must be CHEBY, DROP, BOXCAR, FILTER_DROP or LMS");
    if (cfg.domain == presum_domain::RANGE) {
        check_finite("first_range_m", first_range_m);
        check_at_least("first_range_m", first_range_m, 0.0);
        check_finite_positive("range_bin_m", range_bin_m);
    } else if (cfg.domain == presum_domain::TF) {
        if (num_bins != num.num_subcarriers)
            throw_param("num_bins",
                        num_bins,
                        "must equal num_subcarriers = " + std::to_string(num.num_subcarriers) +
                            " in the TF domain");
    } else {
        throw_param("domain", static_cast<int>(cfg.domain), "must be RANGE or TF");
    }
    check_finite("stopband_weight", cfg.stopband_weight);
    check_finite_positive("stopband_weight", cfg.stopband_weight);
    check_finite("passband_hz", cfg.passband_hz);
    check_finite("stopband_hz", cfg.stopband_hz);
    const bool filtered =
        cfg.method == presum_method::CHEBY || cfg.method == presum_method::FILTER_DROP;
    if (filtered && cfg.num_taps == 1)
        throw_param("num_taps", cfg.num_taps, "must be 0 (4 D) or at least 2");

    d_t_in = num.symbol_s() * cfg.symbols_per_pulse;
    const double prf = 1.0 / d_t_in;
    const unsigned dmax = max_decim(num, geo, scn, cfg.symbols_per_pulse);
    // the bound of a coherent sum; DROP sums nothing and LMS adapts to the phase
    const bool sums = cfg.method != presum_method::DROP && cfg.method != presum_method::LMS;
    if (cfg.enforce_qpe_bound && sums && cfg.decim > dmax) {
        std::ostringstream lim;
        lim << "exceeds the quadratic-phase-error bound of eq. (P-36), D_max = " << dmax
            << " (PRF " << prf << " Hz, v " << geo.velocity_mps << " m/s, lambda "
            << geo.wavelength_m() << " m, nearest R0 of the scene)";
        throw_param("decim", cfg.decim, lim.str());
    }

    // Scene centre: along-track middle of the targets, middle of their closest ranges.
    los_reference::scene_centre(geo, scn, d_yc, d_rc0);
    const scene_extent ext = compute_extent(geo, scn);
    d_fdc = 0.5 * (ext.min_doppler_hz + ext.max_doppler_hz);
    const double margin = 0.1 * ext.doppler_bandwidth_hz() + 2.0 / geo.aperture_s;

    if (prf / cfg.decim < ext.doppler_bandwidth_hz()) {
        std::ostringstream w;
        w << "output PRF " << prf / cfg.decim << " Hz (D = " << cfg.decim
          << ") is below the scene's Doppler bandwidth " << ext.doppler_bandwidth_hz()
          << " Hz: the focused image aliases in azimuth";
        d_warnings.push_back(w.str());
    }

    // Window of output g: pulses gD - a .. gD + b.
    switch (cfg.method) {
    case presum_method::DROP:
        d_l = 1;
        d_a = d_b = 0;
        d_taps.assign(1, gr_complex(1.0f, 0.0f));
        break;
    case presum_method::LMS:
        // [P-3.1] baseline: its own kernel; output g estimates pulse g D from the L before it
        d_l = cfg.num_taps ? cfg.num_taps : 4 * cfg.decim;
        d_a = d_b = 0;
        d_lms = std::make_unique<lms_presum>(num_bins, cfg.decim, d_l, cfg.lms_step);
        break;
    case presum_method::BOXCAR:
        d_l = cfg.decim;
        d_a = 0;
        d_b = d_l - 1;
        d_taps.assign(d_l, gr_complex(1.0f, 0.0f));
        break;
    default: {
        d_l = cfg.num_taps ? cfg.num_taps : 4 * cfg.decim;
        if (d_l < 2)
            d_l = 2; // D = 1 with the default length: 4 taps; never below 2
        d_a = (d_l - 1) / 2;
        d_b = d_l - 1 - d_a;
        // Passband half-width: CHEBY sees the band left after the reference phase
        // history is removed (the Doppler differences between the scene's targets and
        // the reference at their range); FILTER_DROP sees the whole band around the
        // centroid.
        double half = 0.0;
        if (cfg.method == presum_method::CHEBY) {
            const double lam = geo.wavelength_m();
            for (const auto& t : scn.targets) {
                const double r0 = closest_range(geo, t);
                const double rref = cfg.domain == presum_domain::RANGE ? r0 : d_rc0;
                for (int i = 0; i <= 16; ++i) {
                    const double yp = geo.track_start_m +
                                      geo.velocity_mps * geo.aperture_s * i / 16.0;
                    const double ft = 2.0 * geo.velocity_mps * (t.y_m - yp) /
                                      (lam * std::hypot(r0, t.y_m - yp));
                    const double fr = 2.0 * geo.velocity_mps * (d_yc - yp) /
                                      (lam * std::hypot(rref, d_yc - yp));
                    half = std::max(half, std::abs(ft - fr));
                }
            }
        } else {
            half = 0.5 * ext.doppler_bandwidth_hz();
        }
        d_fs = cfg.stopband_hz > 0.0 ? cfg.stopband_hz : prf / (2.0 * cfg.decim);
        if (d_fs >= prf / 2.0)
            throw_param("stopband_hz", d_fs, "must be below PRF / 2 = " + std::to_string(prf / 2.0));
        if (cfg.passband_hz > 0.0) {
            d_fp = cfg.passband_hz;
            if (d_fp >= d_fs)
                throw_param("passband_hz",
                            d_fp,
                            "must be below the stopband edge " + std::to_string(d_fs) + " Hz");
        } else {
            d_fp = half + margin;
            if (d_fp > 0.8 * d_fs) {
                std::ostringstream w;
                w << "the scene's band needs a passband of " << d_fp
                  << " Hz, more than 80 % of the stopband edge " << d_fs
                  << " Hz: passband clipped to " << 0.8 * d_fs
                  << " Hz (signal attenuated; lower D)";
                d_warnings.push_back(w.str());
                d_fp = 0.8 * d_fs;
            }
        }
        design();
        const double f0 = cfg.method == presum_method::FILTER_DROP ? d_fdc : 0.0;
        const double c = 0.5 * (d_l - 1);
        d_taps.resize(d_l);
        for (unsigned j = 0; j < d_l; ++j) {
            // Passes the tone exp(+j 2 pi f0 t): weight h_j exp(-j 2 pi f0 (j - c) T).
            const double ph = -two_pi * f0 * (j - c) * d_t_in;
            d_taps[j] = gr_complex(d_proto[j] * std::cos(ph), d_proto[j] * std::sin(ph));
        }
        break;
    }
    }
    d_centre = 0.5 * (d_a + d_b) - d_a;
    if (cfg.first_output != 0 && d_lms)
        throw_param("first_output", cfg.first_output,
                    "must be 0 for LMS: its filter adapts from the stream's first pulse");
    // a strip's task: the window of output g0 from its first pulse (class doc)
    const std::uint64_t g0 = cfg.first_output * cfg.decim;
    d_first_pulse = g0 > d_a ? g0 - d_a : 0;
    d_pushed = d_first_pulse;
    d_out = cfg.first_output;
    d_ring.assign(d_lms ? 0 : static_cast<std::size_t>(d_l) * d_k, gr_complex(0.0f, 0.0f));
    d_ring_t.assign(d_l, 0.0);
    for (unsigned s = 0; s < d_l; ++s) // slots of the pulses before the stream start
        d_ring_t[s] = (static_cast<double>(s) - d_l) * d_t_in;
    d_row.assign(d_k, gr_complex(0.0f, 0.0f));
    d_z.assign(d_k, gr_complex(0.0f, 0.0f));
    d_w.assign(d_k, gr_complex(0.0f, 0.0f));
    if (!d_los.ideal())
        for (auto* r : { &d_ra, &d_rb, &d_rm, &d_rrow })
            r->assign(d_k, 0.0);
    set_range_axis(first_range_m, range_bin_m);
}

void cheby_presum::design()
{
    const double nyq = 0.5 / d_t_in;
    // Parks-McClellan (gr::filter::pm_remez, band edges in units of Nyquist): the
    // equiripple ("Chebyshev") low-pass of [P-2.2.1], L = 4 D taps by default.
    const std::vector<double> ampl = { 1.0, 1.0, 0.0, 0.0 };
    const std::vector<double> weight = { 1.0, d_cfg.stopband_weight };
    // gr::filter::pm_remez (3.10.5) corrupts the heap (abort / segfault) when the
    // passband is below about 0.02 / (L T), and fails cleanly up to about 0.05 / (L T):
    // never ask for less than 0.1 / (L T) (the filter's main lobe is 1 / (L T) anyway).
    const double fp_min = std::min(0.1 / (d_l * d_t_in), 0.8 * d_fs);
    if (d_fp < fp_min) // silently: the passband is a lower bound of the band to keep
        d_fp = fp_min;
    // pm_remez (3.10.5) overruns its extremal arrays on some inputs (heap corruption,
    // later abort / segfault), which a caught exception does not undo: it is only
    // called where a sweep in a fresh process found it reliable (even L in [4, 128],
    // fs >= 1 / (L T), fp <= fs / 2); elsewhere a Kaiser-windowed sinc is used.
    const double x_fp = d_fp * d_l * d_t_in, x_fs = d_fs * d_l * d_t_in;
    const bool safe = d_l % 2 == 0 && d_l >= 4 && d_l <= 128 && x_fs >= 1.0 && x_fp <= 0.5 * x_fs;
    try {
        if (!safe)
            throw std::runtime_error("outside the range where pm_remez is reliable");
        const std::vector<double> bands = { 0.0, d_fp / nyq, d_fs / nyq, 1.0 };
        d_proto = gr::filter::pm_remez(
            static_cast<int>(d_l) - 1, bands, ampl, weight, "bandpass", 32);
        d_equiripple = true;
    } catch (const std::exception& e) {
        // Very long filters (D in the hundreds) defeat the Remez exchange: fall back to a
        // Kaiser-windowed sinc (beta 8) cut at the middle of the transition band.
        std::ostringstream w;
        w << "Parks-McClellan not used for " << d_l << " taps, fp " << d_fp << " Hz, fs "
          << d_fs << " Hz (" << e.what() << "): Kaiser-windowed sinc (beta 8) instead";
        d_warnings.push_back(w.str());
        d_proto.assign(d_l, 0.0);
        const double fc = 0.5 * (d_fp + d_fs) * d_t_in; // cycles per pulse
        const double c = 0.5 * (d_l - 1);
        const double beta = 8.0;
        auto i0 = [](double x) {
            double sum = 1.0, term = 1.0;
            for (int k = 1; k < 60; ++k) {
                term *= (x / (2.0 * k)) * (x / (2.0 * k));
                sum += term;
            }
            return sum;
        };
        for (unsigned j = 0; j < d_l; ++j) {
            const double u = j - c;
            const double sinc = u == 0.0 ? 2.0 * fc : std::sin(two_pi * fc * u) / (M_PI * u);
            const double r = c > 0.0 ? u / c : 0.0;
            d_proto[j] = sinc * i0(beta * std::sqrt(std::max(0.0, 1.0 - r * r))) / i0(beta);
        }
    }
    double sum = 0.0;
    for (double h : d_proto)
        sum += h;
    for (double& h : d_proto)
        h *= d_cfg.decim / sum; // DC gain D: the coherent sum of eq. (P-29)

    // Ripple and attenuation on a dense grid (double precision DTFT).
    const int grid = 8192;
    double pmax = 0.0, pmin = INFINITY, smax = 0.0;
    for (int i = 0; i <= grid; ++i) {
        const double f = nyq * i / grid;
        std::complex<double> acc = 0.0;
        for (unsigned j = 0; j < d_l; ++j)
            acc += d_proto[j] * std::polar(1.0, -two_pi * f * j * d_t_in);
        const double a = std::abs(acc);
        if (f <= d_fp) {
            pmax = std::max(pmax, a);
            pmin = std::min(pmin, a);
        } else if (f >= d_fs) {
            smax = std::max(smax, a);
        }
    }
    d_ripple_db = 20.0 * std::log10(pmax / pmin);
    d_atten_db = 20.0 * std::log10(d_cfg.decim / std::max(smax, 1e-300));
}

double cheby_presum::phase_frequency_hz(unsigned element) const
{
    if (d_cfg.domain == presum_domain::TF)
        return d_geo.carrier_hz + element * d_num.subcarrier_spacing_hz;
    // Range domain: the range IFFT over subcarriers 0..N-1 (eq. 29) leaves the phase
    // exp(-j 4 pi (fc + (N - 1) Delta f / 2) R / c) on the target's bin: the
    // "migration" term of eq. (P-26) for an OFDM pulse is this baseband half-band shift.
    return d_geo.carrier_hz + 0.5 * (d_num.num_subcarriers - 1) * d_num.subcarrier_spacing_hz;
}

double cheby_presum::ref_range(unsigned element, double t) const
{
    if (!d_los.ideal()) // the flown path: |p(t) - reference point|
        return d_cfg.domain == presum_domain::RANGE
                   ? d_los.range(t, d_first_m + element * d_bin_m)
                   : d_los.range(t, d_rc0);
    // eq. (P-25): R(n, t) = sqrt(R0(n)^2 + (V t)^2), V t measured from the scene centre.
    const double u = d_geo.track_start_m + d_geo.velocity_mps * t - d_yc;
    const double r0sq = d_cfg.domain == presum_domain::RANGE ? d_r0sq[element] : d_rc0 * d_rc0;
    return std::sqrt(r0sq + u * u);
}

double cheby_presum::compensation_phase(unsigned element, double t_ref_s, double offset) const
{
    // eqs. (P-26), (P-27): 4 pi f dR / c, dR = R(t_ref + M T) - R(t_ref).
    const double dr = ref_range(element, t_ref_s + offset * d_t_in) - ref_range(element, t_ref_s);
    return 2.0 * two_pi * phase_frequency_hz(element) * dr / speed_of_light;
}

void cheby_presum::phase_row(double t, bool conj, gr_complex* row) const
{
    // exp(+-j 4 pi f R_ref(n, t) / c), phases formed in double (about 1.5e5 rad).
    const double sgn = conj ? -1.0 : 1.0;
    if (d_cfg.domain == presum_domain::RANGE && !d_los.ideal()) {
        const double k = 2.0 * two_pi * phase_frequency_hz(0) / speed_of_light;
        path_ranges(t, d_rrow.data());
        for (unsigned n = 0; n < d_k; ++n) {
            const double ph = fmod_two_pi(k * d_rrow[n]) * sgn;
            row[n] = gr_complex(std::cos(ph), std::sin(ph));
        }
    } else if (d_cfg.domain == presum_domain::RANGE) {
        const double k = 2.0 * two_pi * phase_frequency_hz(0) / speed_of_light;
        for (unsigned n = 0; n < d_k; ++n) {
            const double ph = fmod_two_pi(k * ref_range(n, t)) * sgn;
            row[n] = gr_complex(std::cos(ph), std::sin(ph));
        }
    } else {
        // Same range for every subcarrier: recurrence over n in double, exact restart
        // every 256 subcarriers.
        const double r = ref_range(0, t);
        const double k0 = 2.0 * two_pi * d_geo.carrier_hz * r / speed_of_light;
        const double dk = 2.0 * two_pi * d_num.subcarrier_spacing_hz * r / speed_of_light;
        const std::complex<double> step = std::polar(1.0, sgn * fmod_two_pi(dk));
        std::complex<double> z;
        for (unsigned n = 0; n < d_k; ++n) {
            if (n % 256 == 0)
                z = std::polar(1.0, sgn * fmod_two_pi(k0 + n * dk));
            row[n] = gr_complex(z.real(), z.imag());
            z *= step;
        }
    }
}

void cheby_presum::set_range_axis(double first_range_m, double range_bin_m)
{
    if (d_cfg.domain != presum_domain::RANGE) {
        update_segment();
        return;
    }
    check_finite("first_range_m", first_range_m);
    check_finite_positive("range_bin_m", range_bin_m);
    d_first_m = first_range_m;
    d_bin_m = range_bin_m;
    d_r0sq.resize(d_k);
    for (unsigned n = 0; n < d_k; ++n) {
        const double r = first_range_m + n * range_bin_m;
        d_r0sq[n] = r * r;
    }
    update_segment();
}

void cheby_presum::set_pulse_interval(double seconds)
{
    check_finite_positive("pulse_interval", seconds);
    if (d_pushed != d_first_pulse) { // the new interval from this pulse on
        d_t0 = slow_time(d_pushed);
        d_p0 = d_pushed;
    } // before the first pulse: the flight's time base from its pulse 0
    d_t_in = seconds;
    update_segment();
}

void cheby_presum::update_segment()
{
    // Largest second derivative of the reference phase per pulse^2:
    // (4 pi f / c) v^2 T^2 / R0 (d^2 R / dt^2 = v^2 R0^2 / R^3 <= v^2 / R0).
    double r0 = d_rc0;
    if (d_cfg.domain == presum_domain::RANGE)
        // ground echoes have R0 >= H: bins nearer than H hold no scatterer
        r0 = std::max({ 1.0, d_geo.height_m, std::min(std::abs(d_first_m), std::abs(d_first_m + (d_k - 1.0) * d_bin_m)) });
    const double fmax = phase_frequency_hz(d_cfg.domain == presum_domain::TF ? d_k - 1 : 0);
    const double vt = d_geo.velocity_mps * d_t_in;
    const double curv = 2.0 * two_pi * fmax / speed_of_light * vt * vt / r0;
    const double p = std::sqrt(8.0 * 1e-4 / std::max(curv, 1e-300));
    d_seg = static_cast<unsigned>(std::clamp(std::floor(p), 1.0, 64.0));
    d_seg_left = 0;
    d_seg_origin = d_pushed == d_first_pulse ? 0 : d_pushed; // before the stream: pulse 0
    d_seg_next = d_seg_origin;
}

void cheby_presum::path_ranges(double t, double* r) const
{
    if (d_cfg.domain == presum_domain::RANGE)
        d_los.ranges(t, d_first_m, d_bin_m, d_k, r);
    else
        r[0] = d_los.range(t, d_rc0);
}

unsigned cheby_presum::path_segment(std::uint64_t pulse)
{
    // The flown range is no hyperbola: its curvature includes the platform's acceleration
    // along the line of sight. The segment P is halved from 64 until the linear phase
    // interpolation errs at most 1e-4 rad at its midpoint (the largest error of a locally
    // quadratic phase) in every element, and ends within the path's span and within its
    // block of 64 pulses from the segment origin (so segments from a block's start are the
    // same whoever starts there). Fills d_ra and d_rb (the ranges at its ends); 0: the
    // path's last pulse interval.
    const unsigned n = d_cfg.domain == presum_domain::RANGE ? d_k : 1;
    const double fmax = phase_frequency_hz(d_cfg.domain == presum_domain::TF ? d_k - 1 : 0);
    const double kmax = 2.0 * two_pi * fmax / speed_of_light;
    const double t = slow_time(pulse);
    path_ranges(t, d_ra.data());
    const double room = std::floor((d_los.path().end_s() - t) / d_t_in);
    const double block = max_segment - (pulse - d_seg_origin) % max_segment;
    unsigned p = static_cast<unsigned>(std::clamp(std::min(room, block), 0.0, double(max_segment)));
    if (p == 0)
        return 0;
    for (;; p /= 2) {
        path_ranges(t + p * d_t_in, d_rb.data());
        path_ranges(t + 0.5 * p * d_t_in, d_rm.data());
        double err = 0.0;
        for (unsigned i = 0; i < n; ++i)
            err = std::max(err, std::abs(d_rm[i] - 0.5 * (d_ra[i] + d_rb[i])));
        if (kmax * err <= max_path_phase_error_rad || p == 1)
            return p;
    }
}

void cheby_presum::start_path_segment(std::uint64_t pulse)
{
    // A stream starting inside a segment (a strip's task) finds it from its block's start
    // and steps its rows there by the same recurrence as the whole stream.
    std::uint64_t start = pulse;
    if (pulse != d_seg_next) {
        start = pulse - (pulse - d_seg_origin) % max_segment;
        for (std::uint64_t p; (p = std::max(1u, path_segment(start))) <= pulse - start;)
            start += p;
    }
    const unsigned p = path_segment(start);
    phase_row(slow_time(start), false, d_z.data());
    if (p == 0) { // the path's last pulse interval: exact row, no recurrence
        std::fill(d_w.begin(), d_w.end(), gr_complex(1.0f, 0.0f));
        d_seg = d_seg_left = 1;
        d_seg_next = start + 1;
        return;
    }
    const double k = 2.0 * two_pi / speed_of_light / p;
    for (unsigned i = 0; i < d_k; ++i) {
        const double dph = d_cfg.domain == presum_domain::RANGE
                               ? k * phase_frequency_hz(0) * (d_rb[i] - d_ra[i])
                               : k * phase_frequency_hz(i) * (d_rb[0] - d_ra[0]);
        d_w[i] = gr_complex(std::cos(dph), std::sin(dph));
    }
    d_seg = d_seg_left = p;
    d_seg_next = start + p;
    for (; start < pulse; ++start, --d_seg_left)
        volk_32fc_x2_multiply_32fc(d_z.data(), d_z.data(), d_w.data(), d_k);
}

double cheby_presum::slow_time(std::uint64_t pulse) const
{
    // a product, not a running sum: a task starting mid-flight gets the same times
    return d_t0 + static_cast<double>(pulse - d_p0) * d_t_in;
}

void cheby_presum::start_segment(std::uint64_t pulse)
{
    if (!d_los.ideal()) {
        start_path_segment(pulse);
        return;
    }
    // Segments start every d_seg pulses from d_seg_origin; a stream that starts inside one
    // (a strip's task) steps its rows there by the same recurrence as the whole stream.
    const std::uint64_t start = pulse - (pulse - d_seg_origin) % d_seg;
    const double t = slow_time(start);
    // Exact rows at t; per-pulse rotation w = exp(+j dphi / P) with dphi the exact
    // (double) phase change over the segment: the phase is interpolated linearly, error
    // at most curvature P^2 / 8 (paper preset: 6e-7 rad per pulse^2 -> 3e-4 rad).
    phase_row(t, false, d_z.data());
    const double t1 = t + d_seg * d_t_in;
    const double k = 2.0 * two_pi / speed_of_light / d_seg;
    if (d_cfg.domain == presum_domain::RANGE) {
        const double f = phase_frequency_hz(0);
        for (unsigned n = 0; n < d_k; ++n) {
            const double dph = k * f * (ref_range(n, t1) - ref_range(n, t));
            d_w[n] = gr_complex(std::cos(dph), std::sin(dph));
        }
    } else {
        const double dr = ref_range(0, t1) - ref_range(0, t);
        for (unsigned n = 0; n < d_k; ++n) {
            const double dph = k * phase_frequency_hz(n) * dr;
            d_w[n] = gr_complex(std::cos(dph), std::sin(dph));
        }
    }
    d_seg_left = d_seg;
    for (std::uint64_t p = start; p < pulse; ++p, --d_seg_left)
        volk_32fc_x2_multiply_32fc(d_z.data(), d_z.data(), d_w.data(), d_k);
}

bool cheby_presum::next_push_completes() const
{
    return d_pushed >= d_b + d_out * d_cfg.decim && (d_pushed - d_b) % d_cfg.decim == 0;
}

std::uint64_t cheby_presum::pulses_needed(std::uint64_t n) const
{
    if (n == 0)
        return 0;
    const std::uint64_t last = (d_out + n - 1) * d_cfg.decim + d_b; // pulse completing it
    return last + 1 > d_pushed ? last + 1 - d_pushed : 0;
}

bool cheby_presum::push(const gr_complex* in, gr_complex* out)
{
    if (d_lms) {
        const bool done = d_lms->push(in, out);
        ++d_pushed;
        d_out += done;
        return done;
    }
    const bool completes = next_push_completes();
    const std::size_t slot = d_pushed % d_l;
    gr_complex* dst = d_ring.data() + slot * d_k;
    d_ring_t[slot] = slow_time(d_pushed);
    if (d_cfg.method == presum_method::CHEBY) {
        // u = s exp(+j phi_ref): after this, s_j C(j) of eq. (P-28) is u_j exp(-j phi(t_c)).
        if (d_seg_left == 0)
            start_segment(d_pushed);
        volk_32fc_x2_multiply_32fc(dst, in, d_z.data(), d_k);
        volk_32fc_x2_multiply_32fc(d_z.data(), d_z.data(), d_w.data(), d_k);
        --d_seg_left;
    } else {
        std::memcpy(dst, in, sizeof(gr_complex) * d_k);
    }
    ++d_pushed;
    if (!completes)
        return false;

    // Output g = d_out: window pulses gD - a .. gD + b (the pulse just pushed is gD + b).
    const std::int64_t first = static_cast<std::int64_t>(d_pushed) - static_cast<std::int64_t>(d_l);
    std::fill(out, out + d_k, gr_complex(0.0f, 0.0f));
    for (unsigned j = 0; j < d_l; ++j) {
        const std::int64_t p = first + j;
        const std::size_t s = static_cast<std::size_t>(((p % d_l) + d_l) % d_l);
        const gr_complex* src = d_ring.data() + s * d_k;
        const gr_complex h = d_taps[j];
        if (h.imag() == 0.0f) {
            const float hr = h.real();
            for (unsigned n = 0; n < d_k; ++n)
                out[n] += hr * src[n];
        } else {
            for (unsigned n = 0; n < d_k; ++n)
                out[n] += h * src[n];
        }
    }
    if (d_cfg.method == presum_method::CHEBY) {
        // Re-modulate with the reference phase at the window centre (eq. P-29).
        const std::size_t sa = static_cast<std::size_t>(((first + d_a) % d_l + d_l) % d_l);
        const double tc = d_ring_t[sa] + (0.5 * (d_l - 1) - d_a) * d_t_in;
        phase_row(tc, true, d_row.data());
        for (unsigned n = 0; n < d_k; ++n)
            out[n] *= d_row[n];
    }
    ++d_out;
    return true;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
