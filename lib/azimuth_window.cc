/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "azimuth_window.h"
#include "param_check.h"
#include <algorithm>
#include <cmath>

namespace gr {
namespace nrsar {

azimuth_window scene_azimuth_window(const geometry& geo,
                                    const scene& scn,
                                    double band_margin_hz,
                                    double T,
                                    double first_range,
                                    double range_bin,
                                    unsigned K)
{
    azimuth_window w;
    // Scene Doppler band with margin (SPEC 7): about [0, 160] Hz in the paper geometry.
    const scene_extent ext = compute_extent(geo, scn);
    const double bw = ext.max_doppler_hz - ext.min_doppler_hz;
    const double margin = band_margin_hz >= 0.0 ? band_margin_hz : 0.1 * bw + 2.0 / geo.aperture_s;
    w.band_lo_hz = ext.min_doppler_hz - margin;
    w.band_hi_hz = ext.max_doppler_hz + margin;

    // A target at zero-Doppler line t0 has energy on the pulses t = t0 - E(f, R0) for f in
    // the band, E = f / (Ka(R0) T) = f lambda R0 / (2 v^2 T) lines. So the pulses of one
    // aperture focus about E(band centre) lines later: the output window of aperture i is
    // shifted by s = E(f_c, R_mid) lines (in the paper geometry the scene lies ahead of the
    // track, s = 1.4 s), so that an aperture's image holds what its own pulses focus to.
    const double v = geo.velocity_mps;
    // The shift and the overlap follow the ranges where the scene's targets are (its slant
    // range extent within the window), not the whole window: an uncropped range IFFT
    // (--range-crop off) reaches km beyond the scene, and its far end would place the
    // output window past the targets and make the overlap (and the memory) grow with it.
    // Bins beyond the scene hold no target, so their own focusing window does not matter.
    double r_min = first_range;
    double r_max = first_range + (K - 1) * range_bin;
    if (ext.max_slant_range_m >= r_min && ext.min_slant_range_m <= r_max) {
        r_min = std::max(r_min, ext.min_slant_range_m);
        r_max = std::min(r_max, ext.max_slant_range_m);
    }
    auto lines = [&](double f, double r) {
        return f * geo.wavelength_m() * r / (2.0 * v * v) / T;
    };
    w.e_hi = std::max(lines(w.band_hi_hz, r_min), lines(w.band_hi_hz, r_max));
    w.e_lo = std::min(lines(w.band_lo_hz, r_min), lines(w.band_lo_hz, r_max));
    if (std::abs(w.e_hi) > 1e9 || std::abs(w.e_lo) > 1e9)
        throw_param("azimuth extent of the scene band (lines)",
                    std::max(std::abs(w.e_hi), std::abs(w.e_lo)),
                    "must be below 1e9");
    const double s = std::round(lines(0.5 * (w.band_lo_hz + w.band_hi_hz), 0.5 * (r_min + r_max)));
    w.line_shift = static_cast<long long>(std::clamp(s, std::floor(w.e_lo), std::ceil(w.e_hi)));
    return w;
}

} // namespace nrsar
} // namespace gr
