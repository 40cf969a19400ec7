/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/filter_theory.h>
#include <cmath>
#include <complex>

namespace gr {
namespace nrsar {
namespace kernel {

filter_moments
compute_filter_moments(const std::vector<gr_complex>& points, filter_type f, double snr_in)
{
    if (points.empty())
        throw_param("constellation size", 0, "must be at least 1");
    check_finite_positive("snr_in", snr_in);
    double s_chi = 0.0, s_chi2 = 0.0, s_g2 = 0.0;
    for (const auto& p : points) {
        const std::complex<double> s(p.real(), p.imag());
        const double s2 = std::norm(s);
        if (!std::isfinite(s2) || s2 <= 0.0)
            throw_param("constellation point |s|^2", s2, "must be finite and > 0");
        // eq. (25): chi = s g and |g|^2, both real for the three filters.
        double chi = 1.0, g2 = 1.0 / s2; // RF: g = 1/s
        if (f == filter_type::MF) {      // g = conj(s)
            chi = s2;
            g2 = s2;
        } else if (f == filter_type::WF) { // g = conj(s) / (|s|^2 + 1/SNR)
            const double d = s2 + 1.0 / snr_in;
            chi = s2 / d;
            g2 = s2 / (d * d);
        }
        s_chi += chi;
        s_chi2 += chi * chi;
        s_g2 += g2;
    }
    const double n = static_cast<double>(points.size());
    filter_moments m;
    m.mean_chi = s_chi / n;
    m.var_chi = std::max(0.0, s_chi2 / n - m.mean_chi * m.mean_chi);
    m.mean_g2 = s_g2 / n;
    return m;
}

double nmse_theory(const std::vector<gr_complex>& points, filter_type f, double snr_in)
{
    const auto m = compute_filter_moments(points, f, snr_in);
    // SPEC section 8 (from eqs. (56), (58)): pedestal over squared mean PSF gain.
    return (m.var_chi + m.mean_g2 / snr_in) / (m.mean_chi * m.mean_chi);
}

double nmse_theory_db(const std::vector<gr_complex>& points, filter_type f, double snr_in_db)
{
    check_finite("snr_in_db", snr_in_db);
    return 10.0 * std::log10(nmse_theory(points, f, std::pow(10.0, snr_in_db / 10.0)));
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
