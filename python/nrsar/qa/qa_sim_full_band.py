#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-sim --band full behind a presummer (issue 14): the NMSE of rd_focuser's full-band
compression against SPEC 8's theory plus the band term, both computed here.

After presumming by D the focuser compresses the whole output pulse rate PRF / D: noise and
data randomness fill it, the target only its own band B_t, so NMSE = NMSE_theory +
10 log10(B_noise / B_t) with B_noise = the noise-equivalent band of what the focuser
processed. A boxcar presummer's outputs sum disjoint pulses, so its noise is white over
PRF / D (B_noise = PRF / D). The Chebyshev presummer's 4 D taps overlap: its noise is shaped
by the filter, and over one whole output period (Parseval) B_noise = PRF sum |h|^2 / |sum h|^2
(the single-pulse gain's reciprocal times PRF), numpy on its taps here. nmse_theory_band_db
carries the focuser's processed band, PRF / D. B_t: the target's Doppler 2 v (y_t - y_p) /
(lambda R) at the track's two ends (eq. (8)).

At the band's edges the range migration (eq. (40) beyond |f| lambda / (2 v) = 0.99, (41)
inside) reaches ~100 bins, more than the guard the near edge at 0 m leaves: there the RCMC
interpolator reads zeros and that Doppler's noise is lost (kept_fraction below, from the
geometry and the presummer's noise spectrum). Inside, the interpolator itself keeps a share
of the noise: range noise is white (N = FFT size), and white noise interpolated at fraction
mu by the unit-DC taps h_j(mu) keeps sum_j h_j(mu)^2 of its power (Parseval:
int |H_mu(nu)|^2 dnu, below 1 where the windowed sinc rolls off near the range Nyquist; 0 dB
at mu = 0, -0.48 dB at mu = 1/2 for 16 Kaiser-6 taps). The full band's migrations take every
fraction, so on average -0.23 dB (noise_gain below, from the kernel's definition); the
target's range spectrum, demodulated to the centre, passes with unit gain.
"""

import math
import tempfile

import numpy as np
from gnuradio import gr_unittest

from gnuradio import nrsar
from gnuradio.nrsar import chain, params
from gnuradio.nrsar.options import SimOptions
from gnuradio.nrsar.theory import nmse_theory_db

C = 299792458.0
RHO = C / (2 * 512 * 30e3)  # range bin of the small preset's 512-point IFFT
X_T, Y_T, TA, D = math.sqrt((120 * RHO) ** 2 - 1000.0 ** 2), 5.0, 1.0, 8  # on bin 120


def noise_gain(frac, taps=16, beta=6.0, phases=1024):
    """sum_j h_j(mu)^2 of the RCMC's windowed sinc (sinc times a Kaiser window over taps / 2,
    normalised to unit DC gain, tabulated at the nearest of `phases` fractions) at the
    fractions frac: the power white noise keeps through it."""
    j = np.arange(1 - taps // 2, taps // 2 + 1)
    table = []
    for q in range(phases + 1):
        x = j - q / phases
        h = np.sinc(x) * np.i0(beta * np.sqrt(np.clip(1 - (2 * x / taps) ** 2, 0, 1)))
        table.append(np.sum(h * h) / np.sum(h) ** 2)
    return np.asarray(table)[np.rint(np.asarray(frac) * phases).astype(int)]


def kept_fraction(taps, prf, band, first_m, bins, guard, lam, v):
    """Share of the presummer's output noise the RCMC keeps, mean over the image's columns:
    the noise at Doppler f of column k survives while its migration stays inside the input
    window (k + migration <= bins - 1 + guard), times the interpolator's noise gain at the
    migration's fraction. Noise spectrum: |H|^2 of the taps, aliased to the output rate
    prf / D."""
    f = np.linspace(band[0], band[1], 3001)
    u = lam * f / (2 * v)
    hyp = u * u < 0.99
    d = np.sqrt(np.where(hyp, 1 - u * u, 1.0))
    n = np.arange(len(taps))
    spec = sum(np.abs(np.exp(-2j * np.pi * np.outer(f + j * prf / D, n) / prf) @ taps) ** 2
               for j in range(-2 * D, 2 * D + 1))
    kept = []
    for k in range(bins):
        r = first_m + k * RHO
        mig = np.where(hyp, r * u * u / (d * (1 + d)), r * u * u / 2) / RHO
        gain = noise_gain(mig - np.floor(mig))
        kept.append(np.sum(spec * gain * (mig <= bins - 1 - k + guard)) / np.sum(spec))
    return float(np.mean(kept))


class qa_sim_full_band(gr_unittest.TestCase):

    def run_sim(self, presum, out):
        return chain.simulate_graph(SimOptions.parse([
            "--preset", "small", "--aperture-s", str(TA), "--target", f"{X_T!r},{Y_T}",
            "--presum", presum, "--decim", str(D), "--band", "full", "--snr-db", "10",
            "--images", "none", "--out", out]))

    def test_001_full_band_nmse_at_theory(self):
        num, geo = params.make_numerology("small"), params.make_geometry("paper")
        v, lam, h = geo.velocity_mps, C / geo.carrier_hz, geo.height_m
        prf = 1.0 / num.symbol_s()
        r0 = math.hypot(X_T, h)
        ends = (geo.track_start_m, geo.track_start_m + v * TA)
        b_t = 2 * v / lam * ((Y_T - ends[0]) / math.hypot(r0, Y_T - ends[0])
                             - (Y_T - ends[1]) / math.hypot(r0, Y_T - ends[1]))
        theory = nmse_theory_db("qam256", "wf", 10.0)
        out = tempfile.mkdtemp(prefix="qa_full_band_")
        offset = {}
        for presum in ("boxcar", "cheby"):
            r, graph = self.run_sim(presum, f"{out}/{presum}")
            taps = (np.ones(D) if presum == "boxcar"
                    else np.asarray(graph["presum"].prototype(), complex))
            b_noise = prf * np.sum(np.abs(taps) ** 2) / abs(taps.sum()) ** 2
            kept = kept_fraction(taps, prf, r["doppler_band_hz"], r["range_axis_m"][0],
                                 r["range_bins"], graph["focuser"].config().guard_bins, lam, v)
            expected = theory + 10 * math.log10(b_noise / b_t) + 10 * math.log10(kept)
            band = theory + 10 * math.log10(prf / D / b_t)
            print(f"{presum}: NMSE {r['nmse_db']:.2f} dB, expected {expected:.2f} dB "
                  f"(B_noise {b_noise:.1f} Hz, B_t {b_t:.2f} Hz, RCMC keeps "
                  f"{10 * math.log10(kept):.2f} dB with the interpolator's noise gain); "
                  f"theory with the processed "
                  f"band {r['nmse_theory_band_db']:.2f} dB, here {band:.2f} dB")
            # the JSON's band term is the focuser's whole processed band, PRF / D
            self.assertAlmostEqual(r["doppler_band_hz"][1] - r["doppler_band_hz"][0], prf / D,
                                   delta=1e-6)
            self.assertAlmostEqual(r["nmse_theory_band_db"], band, delta=0.01)
            # the target is in the image, on its bin (the crop's guard, chain.range_crop)
            self.assertLess(r["peak_error_m"], RHO / 4)
            # about K B_noise Ta >= 33 x 1000 independent pixels: 1 sigma 0.03 dB
            offset[presum] = r["nmse_db"] - expected
            self.assertLess(abs(offset[presum]), 0.12)
        # the presummers' noise bands, 10 log10(B_cheby / (PRF / D)) = -4.6 dB, and the
        # RCMC's losses of their spectra account for the runs' difference
        self.assertAlmostEqual(offset["cheby"], offset["boxcar"], delta=0.1)


if __name__ == "__main__":
    gr_unittest.run(qa_sim_full_band)
