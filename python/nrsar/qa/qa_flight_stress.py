#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Numerical stress of a flown path (issue #14, "long strips, large phases and slow drifts
without degradation"; docs/stress.md): a 2000 s flight (100 km of track) from a 10 Hz CSV
and a 5.6 h line against the analytic path in float64; bp_focuser late in a 1250 s strip
(first_aperture 2400, 60 km on) along a gusty path against theory.numpy_bp in float64, as
at the strip's start; a GNSS navigation error along that strip: the image's loss at the
target as the drift's own geometry predicts (float64), at every aperture; cheby_presum along
a swaying navigation 1205 s in against eqs. (P-25..P-29) in float64, as 5 s in; rd_focuser's
motion compensation (first, second order, resampled) for a strip's aperture 1205 s in
against the same aperture of the same flight moved to the start.

The echo at the end of the 2000 s flight is the GTest
SceneEcho.LongFlightLateEchoMatchesDirectFloat64Below80dB (tests/test_scene_echo.cc). Every
assertion is an error figure against an independent reference; no timing."""

import math
import os
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest

from gnuradio import nrsar
from gnuradio.nrsar import params, runtime
from gnuradio.nrsar.focus_scenario import (C, FC, LAM, V, H, N_SUB, NFFT, RHO, K, R_FIRST,
                                          NUM, T, SPP, geometry, echo_along)
from gnuradio.nrsar.theory import numpy_bp

# The long flight: the ideal line plus slow sway, sampled at 10 Hz (a GNSS/INS record's rate)
H_S = 0.1
FLIGHT_S = 2000.0
W = 2 * math.pi * np.array([0.05, 0.02, 0.1])  # x, y, z sway [rad/s]
A = np.array([1.0, 4.0, 0.5])                  # [m]; y: 0.5 m/s of speed variation

# bp_focuser's strip: focus_scenario's numerology, 0.5 s apertures of M pulses
M = 200
DY = V * T
FC_R = (N_SUB - 1) / (2 * NFFT)
CS = 2.0 / LAM + FC_R / RHO    # cycles per metre of range at the pixel
X_T = 800.0                    # slant range 1000 m: bin 30
J_T = 100                      # the target on grid line J_T (before the line shift)
STRIP_S = 1250.0
APERTURES = (0, 800, 1600, 2400)  # 0, 400, 800, 1200 s on
BP_FLOOR_DB = -115.0  # float32 samples, phases and sums: -125 ... -132 dB measured

# cheby_presum and rd_focuser's MoCo late in a flight: aperture A_E (5 s in) of a swaying
# flight and the same flight DA apertures (1200 s, 60 km) later
A_E = 10
DA = 2400
DECIM = 4
F_PHASE = FC + 0.5 * (N_SUB - 1) * NUM.subcarrier_spacing_hz  # a compressed bin's phase


def sway_path(t, t_off=0.0, height=1000.0):
    """The paper geometry's line (y = V t) plus slow sway whose phase counts from t_off, and
    its velocity."""
    s = np.asarray(t) - t_off
    p = np.sin(np.outer(s, W)) * A
    p[:, 1] += V * np.asarray(t)
    p[:, 2] = height + A[2] * np.cos(W[2] * s)
    v = np.cos(np.outer(s, W)) * A * W
    v[:, 1] += V
    v[:, 2] = -A[2] * W[2] * np.sin(W[2] * s)
    return p, v


def shifted_sway(t_off, t0, t1):
    """sway_path at focus_scenario's height with its phase from t_off, sampled at 10 Hz on
    t_off + [t0, t1]: the same knots relative to the sway whatever t_off, so the flight at
    t_off is the one at 0 moved V t_off along track."""
    ts = t_off + np.arange(math.floor(t0 / H_S), math.ceil(t1 / H_S) + 1) * H_S
    p, _ = sway_path(ts, t_off, H)
    return nrsar.trajectory.from_samples(list(ts), [tuple(x) for x in p])


def ulp(x):
    return float(np.spacing(np.abs(x).max()))


def nmse_db(got, ref):
    err = np.sum(np.abs(got - ref) ** 2)
    return 10 * math.log10(err / np.sum(np.abs(ref) ** 2)) if err > 0 else -math.inf


def antenna(path, a):
    """Antenna of pulses a M .. a M + M - 1 at t = n T, float64 products."""
    n = a * M + np.arange(M)
    return np.array(path.positions(list(n.astype(float) * T)))


def run(blk, data):
    """data (pulses x K) through blk: the vector sink (K-vectors)."""
    tb = gr.top_block()
    src = blocks.vector_source_c(data.astype(np.complex64).ravel().tolist(), False, K)
    snk = blocks.vector_sink_c(K)
    tb.connect(src, blk, snk)
    tb.run()
    return snk


def bp_image(data, nav, a, spp=SPP):
    """bp_focuser's image of aperture a (a strip's task: first_aperture a) along nav, and the
    first line's y of its azimuth_axis tag."""
    cfg = nrsar.bp_config(symbols_per_pulse=spp, lines_per_aperture=M, first_aperture=a,
                          apertures=1)
    t = NUM.symbol_s() * spp
    blk = nrsar.bp_focuser(NUM, geometry(M * t), nrsar.make_scene([(X_T, J_T * V * t)]), K,
                           R_FIRST, RHO, cfg, nav)
    snk = run(blk, data)
    y0 = [pmt.to_double(pmt.tuple_ref(t.value, 0)) for t in snk.tags()
          if str(t.key) == "azimuth_axis"]
    return np.array(snk.data()).reshape(-1, K), y0[0], blk.line_shift()


def late_case(a):
    """Aperture a's geometry, scene, navigation, targets (x, y, amplitude) and their middle
    y_c: three targets about the aperture's middle (5 m either side along track at X_T, one
    30 m further in ground range), the track 0 .. 2 y_c (the scene's Doppler extent from it
    symmetric: band centre 0, line shift 0, early as late) and the sway from (a - A_E) M T,
    covering the aperture's block (+-12 s)."""
    t_off = (a - A_E) * M * T
    y_c = V * (a * M + M / 2) * T
    targets = [(X_T, y_c - 5.0, 1.0), (X_T, y_c + 5.0, 1.0), (X_T + 30.0, y_c, 1.0)]
    scn = nrsar.make_scene([(x, y) for x, y, _ in targets])
    nav = shifted_sway(t_off, (A_E * M + M / 2) * T - 12.0, (A_E * M + M / 2) * T + 12.0)
    return geometry(2.0 * y_c / V), scn, nav, targets, y_c


def presum_reference(blk, data, nav, p0, y_c):
    """cheby_presum's outputs from the pulses p0 + i (data[i]) in float64, eqs. (P-25..P-29)
    on the flown path: out(k, g) = exp(-j kf R_k(t_c)) sum_j h_j s(k, g D - a + j)
    exp(+j kf R_k(t_j)), R_k(t) = |nav(t) - (sqrt(R0_k^2 - H^2), y_c, 0)| the range to the
    bin's reference scatterer, kf = 4 pi (fc + (N - 1) Delta f / 2) / c, t_j = p T, t_c the
    window's centre; h the block's prototype (its design is qa_cheby_presum's)."""
    d, a, taps = blk.decim(), blk.history(), np.array(blk.prototype())
    r0 = R_FIRST + RHO * np.arange(K)
    gx = np.sqrt(r0 * r0 - H * H)
    kf = 4 * math.pi * F_PHASE / C

    def ranges(times):
        p = np.array(nav.positions(list(times)))
        return np.sqrt((p[:, :1] - gx) ** 2 + (p[:, 1:2] - y_c) ** 2 + p[:, 2:] ** 2)

    u = data * np.exp(1j * kf * ranges((p0 + np.arange(len(data))).astype(float) * T))
    g = np.arange((p0 + a) // d, (p0 + len(data) - blk.lookahead() - 1) // d + 1)
    first = g * d - a - p0
    acc = np.array([taps @ u[f:f + len(taps)] for f in first])
    return acc * np.exp(-1j * kf * ranges((g * d + blk.centre_offset()) * T))


def rd_block(geo, scn, nav, a, moco, resample):
    """rd_focuser for aperture a (a strip's task: first_aperture a) along nav, full band,
    overlap-save with 150 lines either side (automatic: from the scene's extent seen from the
    track's start, which differs early and late)."""
    cfg = nrsar.focuser_config(symbols_per_pulse=SPP, lines_per_aperture=M, overlap_lines=150,
                               band=nrsar.doppler_band.FULL, moco=moco, moco_resample=resample,
                               first_aperture=a, apertures=1)
    return nrsar.rd_focuser(NUM, geo, scn, K, R_FIRST, RHO, cfg, nav)


class qa_flight_stress(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        runtime.quiet_gnuradio_logs()
        geo = geometry(M * T)
        cls.truth = nrsar.trajectory.motion(geo, nrsar.motion_model.GUSTY, 5, STRIP_S)
        cls.nav = nrsar.trajectory.navigation(cls.truth, nrsar.nav_error_model.GNSS, 7, STRIP_S)
        cls.strip = {}  # aperture -> (truth antenna, data, truth image, numpy_bp of it)

    def aperture(self, a):
        """Aperture a of the strip along the true (gusty) path: echo, image, reference."""
        if a not in self.strip:
            ant = antenna(self.truth, a)
            data = echo_along(ant, [(X_T, (J_T + a * M) * DY, 1.0)]).astype(np.complex64)
            img, y0, shift = bp_image(data, self.truth, a)
            y_lines = (shift + a * M + np.arange(M)) * DY
            self.assertAlmostEqual(y0, y_lines[0], delta=1e-6)
            ref = numpy_bp(data, ant, R_FIRST, RHO, LAM, FC_R, 8, y_lines, H)
            self.strip[a] = (ant, data, img, ref, y_lines, shift)
        return self.strip[a]

    def test_long_flight_path_keeps_double_precision(self):
        """A 2000 s flight (platform 100 km on) in a 10 Hz CSV (make_trajectory, the user's
        path): positions and velocities 1990 s in against the analytic path in float64 equal
        the start's, within the spline's bound (trajectory.h: h^4 max|p''''| / 384 +
        h^5 max|p'''''| / 20; velocity sqrt(3) / 216 h^3 max|p''''| + h^4 max|p'''''| / 30,
        the cubic Hermite's derivative plus its 5-point slopes' error) and the rounding of
        |p| (8 ulp, 8 ulp / h). And a 5.6 h line (1000 km, 200 001 samples), interpolated
        exactly by the spline: only that rounding is left."""
        t = np.arange(int(FLIGHT_S / H_S) + 1) * H_S
        p, _ = sway_path(t)
        fd, csv = tempfile.mkstemp(suffix=".csv")
        try:
            with os.fdopen(fd, "w") as f:
                f.write("t_s,x_m,y_m,z_m\n")
                f.writelines(f"{ti!r},{x!r},{y!r},{z!r}\n" for ti, (x, y, z) in zip(t, p))
            path = params.make_trajectory(csv, params.make_geometry("paper"), FLIGHT_S)
        finally:
            os.unlink(csv)
        d4, d5 = A * W ** 4, A * W ** 5
        pos_bound = H_S ** 4 * d4.max() / 384 + H_S ** 5 * d5.max() / 20
        vel_bound = math.sqrt(3) / 216 * H_S ** 3 * d4.max() + H_S ** 4 * d5.max() / 30
        errs = {}
        for t0 in (1.0, 1990.0):
            ts = t0 + np.arange(0.0, 5.0, 0.0137)  # off the knots, interior segments
            want_p, want_v = sway_path(ts)
            got_p = np.array(path.positions(list(ts)))
            got_v = np.array([path.velocity(x) for x in ts])
            errs[t0] = (np.abs(got_p - want_p).max(), np.abs(got_v - want_v).max())
            self.assertLess(errs[t0][0], pos_bound + 8 * ulp(want_p), t0)
            self.assertLess(errs[t0][1], vel_bound + 8 * ulp(want_p) / H_S, t0)
        line_t = np.arange(200001) * H_S
        line = nrsar.trajectory.from_samples(list(line_t), [(0.0, V * x, H) for x in line_t])
        ts = 19990.0 + np.arange(0.0, 5.0, 0.0137)
        line_p = np.abs(np.array(line.positions(list(ts)))[:, 1] - V * ts).max()
        line_v = np.abs(np.array([line.velocity(x)[1] for x in ts]) - V).max()
        self.assertLess(line_p, 8 * ulp(V * ts))
        self.assertLess(line_v, 8 * ulp(V * ts) / H_S)
        print(f"\n2000 s flight, 10 Hz CSV: position error {errs[1.0][0] * 1e6:.4f} um at 1 s, "
              f"{errs[1990.0][0] * 1e6:.4f} um at 1990 s (bound {pos_bound * 1e6:.4f} um); "
              f"velocity {errs[1.0][1]:.2e} / {errs[1990.0][1]:.2e} m/s (bound "
              f"{vel_bound:.2e}); 5.6 h line at 1000 km: {line_p * 1e6:.6f} um, "
              f"{line_v:.1e} m/s ({line_p / ulp(V * ts):.1f} ulp, "
              f"{line_v * H_S / ulp(V * ts):.1f} ulp / h)")

    def test_bp_late_in_a_long_strip_as_at_its_start(self):
        """bp_focuser's aperture 2400 of a strip (first_aperture: 1200 s, 60 km on) along a
        gusty path against theory.numpy_bp in float64 (antenna at n T): the NMSE as at
        aperture 0 (float32 samples, phases and sums: -131 dB), the target on its pixel at
        sqrt(N M)."""
        got = {}
        for a in (0, APERTURES[-1]):
            _, _, img, ref, _, shift = self.aperture(a)
            got[a] = nmse_db(img, ref)
            self.assertLess(got[a], BP_FLOOR_DB, a)
            # the peak sqrt(N M), less the linear interpolation's 0.5 % at most
            peak = abs(img[J_T - shift, 30]) / math.sqrt(N_SUB * M)
            self.assertLess(peak, 1.0 + 1e-5)
            self.assertGreater(peak, 0.995)
        self.assertLess(got[APERTURES[-1]], got[0] + 3.0)
        print(f"\nBP against numpy float64 along a gusty path: {got[0]:.1f} dB at aperture 0, "
              f"{got[APERTURES[-1]]:.1f} dB at aperture {APERTURES[-1]} "
              f"({APERTURES[-1] * M * T:.0f} s, y {APERTURES[-1] * M * DY / 1e3:.1f} km)")

    def test_bp_after_7_h_of_40_khz_pulses(self):
        """A strip's aperture 5.12e6 at a PRF of 40 kHz (39 symbols per pulse, M = 200):
        pulse 1.024e9, 7.1 h and 1279 km on, along a swaying navigation (0.25 m at 0.3 Hz
        across: 0.47 m/s) sampled at 16 Hz, against theory.numpy_bp in float64 with the
        antenna at n T. The block summed T per pulse: 0.19 ms off n T there, 0.09 mm of
        sway, 0.0106 rad on the line of sight, -39.5 dB (and M v T per aperture: the first
        line 58 um off); both are products now (docs/stress.md)."""
        spp = 39
        t_p = NUM.symbol_s() * spp
        a = 5120000
        span = (a + 2) * M * t_p
        ts = np.arange(int(span * 16) + 2) / 16.0  # 16 Hz: binary fractions, exact
        w = 2 * math.pi * 0.3
        path = nrsar.trajectory.from_samples(
            list(ts), list(zip(0.25 * np.sin(w * ts), V * ts, np.full(len(ts), H))))
        got = {}
        for ap in (0, a):
            n = ap * M + np.arange(M)
            ant = np.array(path.positions(list(n.astype(float) * t_p)))
            data = echo_along(ant, [(X_T, (J_T + ap * M) * V * t_p, 1.0)]).astype(np.complex64)
            img, y0, shift = bp_image(data, path, ap, spp)
            y_lines = (shift + ap * M + np.arange(M)) * V * t_p
            self.assertAlmostEqual(y0, y_lines[0], delta=1e-6)
            got[ap] = nmse_db(img, numpy_bp(data, ant, R_FIRST, RHO, LAM, FC_R, 8, y_lines, H))
            self.assertLess(got[ap], BP_FLOOR_DB, ap)
        print(f"\nBP at 40 kHz along a sway: {got[0]:.1f} dB at aperture 0, {got[a]:.1f} dB at "
              f"aperture {a} ({a * M * t_p / 3600:.2f} h, y {a * M * V * t_p / 1e3:.0f} km)")

    def test_gnss_drift_costs_what_its_geometry_predicts(self):
        """The strip's data (true gusty path) focused along a GNSS navigation (decimetres of
        slow error, 0.002-0.1 Hz) at apertures 0 ... 2400: the image against numpy_bp of the
        same navigation at the float64 floor (no numerical loss late in the strip), and the
        target's pixel against the truth-navigated one, g = mean_p D(dq_p) / N
        exp(j 2 pi cs dR_p), dR_p = |nav_p - P| - |truth_p - P| the drift's range at the
        target P, dq_p = dR_p / rho, D the Dirichlet kernel of the N subcarriers, cs = 2 /
        lambda + fc_r / rho (float64): within the 8x upsampling's linear interpolation,
        (pi b / U)^2 / 8 = 0.5 % for b = N / NFFT (qa_bp_focuser)."""
        rows = []
        for a in APERTURES:
            ant, data, img_truth, _, y_lines, shift = self.aperture(a)
            img, _, _ = bp_image(data, self.nav, a)
            nav_ant = antenna(self.nav, a)
            err = nmse_db(img, numpy_bp(data, nav_ant, R_FIRST, RHO, LAM, FC_R, 8, y_lines, H))
            self.assertLess(err, BP_FLOOR_DB, a)
            target = np.array([X_T, (J_T + a * M) * DY, 0.0])
            dr = (np.linalg.norm(nav_ant - target, axis=1) -
                  np.linalg.norm(ant - target, axis=1))
            dq = dr / RHO
            with np.errstate(invalid="ignore", divide="ignore"):
                dirichlet = np.where(np.abs(dq) < 1e-12, N_SUB,
                                     np.sin(np.pi * N_SUB * dq / NFFT) / np.sin(np.pi * dq / NFFT))
            g_pred = np.mean(dirichlet / N_SUB * np.exp(2j * np.pi * CS * dr))
            j = J_T - shift
            g = img[j, 30] / img_truth[j, 30]
            self.assertLess(abs(g - g_pred), 0.005 * abs(g_pred) + 1e-4, a)
            rows.append((a, np.mean(dr), np.ptp(dr), 20 * math.log10(abs(g_pred)),
                         20 * math.log10(abs(g)), abs(g - g_pred) / abs(g_pred), err))
        print("\nGNSS drift along the strip: aperture (t), mean / span of the drift's range at "
              "the target, pixel loss predicted / measured, |g - g_pred| / |g_pred|, NMSE vs "
              "numpy:\n" + "\n".join(
                  f"  {a} ({a * M * T:.0f} s): {mean * 1e3:.1f} / {span * 1e3:.1f} mm, "
                  f"{lp:.2f} / {lm:.2f} dB, {rel:.1e}, {e:.1f} dB"
                  for a, mean, span, lp, lm, rel, e in rows))

    def test_presum_late_in_a_flight_as_at_its_start(self):
        """cheby_presum (D = 4, 16 taps) along a swaying navigation, a strip's task
        (first_output) for aperture 10 (5 s in) and the same flight's aperture 2410 (1205 s,
        60 km on: the same relative geometry and data): every output against eqs.
        (P-25..P-29) on the flown path in float64 (presum_reference), the same NMSE late as
        early. Float32 samples and rotors: -141.5 dB measured, bound -120 dB (the block's
        1e-4 rad linear-interpolation bound, -80 dB, is for the worst segment; this path's
        curvature is far below it). A slow time rounded to float (7e-5 s at 1205 s) gives
        -54.6 dB late."""
        got, outs = {}, {}
        for a in (A_E, A_E + DA):
            geo, scn, nav, targets, y_c = late_case(a)
            cfg = nrsar.presum_config(decim=DECIM, symbols_per_pulse=SPP, passband_hz=20.0,
                                      first_output=a * M // DECIM)
            blk = nrsar.cheby_presum(NUM, geo, scn, K, R_FIRST, RHO, cfg, nav)
            self.assertTrue(blk.follows_path())
            p0 = blk.first_pulse()
            if a == A_E:
                n = M + blk.num_taps()
                ant = np.array(nav.positions(list((p0 + np.arange(n)).astype(float) * T)))
                data = echo_along(ant, targets)
            self.assertEqual(p0, A_E * M - blk.history() + (a - A_E) * M)
            out = np.array(run(blk, data).data()).reshape(-1, K)
            ref = presum_reference(blk, data, nav, p0, y_c)
            self.assertEqual(out.shape, ref.shape)
            got[a], outs[a] = nmse_db(out, ref), out
            self.assertLess(got[a], -120.0, a)
        late = A_E + DA
        self.assertLess(got[late], got[A_E] + 3.0)
        same = np.array_equal(outs[late], outs[A_E])
        print(f"\ncheby_presum along a sway against float64: {got[A_E]:.1f} dB at pulse "
              f"{A_E * M}, {got[late]:.1f} dB at pulse {late * M} ({late * M * T:.0f} s, "
              f"y {late * M * T * V / 1e3:.1f} km); late output "
              + ("bit-identical to early" if same else
                 f"against early {nmse_db(outs[late], outs[A_E]):.1f} dB"))

    def test_rd_moco_late_in_a_strip_as_at_its_start(self):
        """rd_focuser with motion compensation (first order, second order, second order
        after along-track resampling) along a swaying navigation, full band with overlap-save:
        a strip's task for aperture 2410 (1205 s, 60 km on) against the same task at
        aperture 10 of the same flight moved to the start (same data, same geometry relative
        to the aperture; only the flight's times and positions differ): within -100 dB
        (measured: bit-identical, -154.7 dB for the second order's per-bin phases; a block
        start time rounded to float, 7e-5 s late, gives -56.7 dB), the targets on their
        pixels, and the compensation at work (the image moved from moco off's)."""
        late = A_E + DA
        rows = []
        for name, moco, resample in (("off", nrsar.moco_order.OFF, False),
                                     ("first", nrsar.moco_order.FIRST, False),
                                     ("second", nrsar.moco_order.SECOND, False),
                                     ("resample", nrsar.moco_order.SECOND, True)):
            img = {}
            for a in (A_E, late):
                geo, scn, nav, targets, _ = late_case(a)
                blk = rd_block(geo, scn, nav, a, moco, resample)
                if a == A_E:
                    line0 = blk.stream_first_line()
                    n = blk.overlap_before() + M + blk.overlap_after()
                    ant = np.array(nav.positions(list((line0 + np.arange(n)).astype(float) * T)))
                    data = echo_along(ant, targets)
                img[a] = np.array(run(blk, data).data()).reshape(-1, K)
                self.assertEqual(blk.stream_first_line(), line0 + (a - A_E) * M)
                self.assertEqual(blk.line_shift(), 0)
                self.assertEqual(img[a].shape, (M, K))
                if name != "off":  # compensated, the targets 5 m (40 lines) either side of
                    # the middle at 1000 m (bin 30) peak
                    peak = np.unravel_index(np.argmax(np.abs(img[a][:, :40])), (M, 40))
                    self.assertIn(peak, ((M // 2 - 40, 30), (M // 2 + 40, 30)), (name, a))
            err = nmse_db(img[late], img[A_E])
            self.assertLess(err, -100.0, name)
            if name == "off":
                off = img[A_E]
            else:  # the compensation is at work: 1 m of sway across
                self.assertGreater(nmse_db(img[A_E], off), -30.0, name)
            rows.append(f"{name} " + ("bit-identical" if err == -math.inf else f"{err:.1f} dB")
                        + (f" (against off {nmse_db(img[A_E], off):+.1f} dB)"
                           if name != "off" else ""))
        print(f"\nrd_focuser MoCo, aperture {late} ({late * M * T:.0f} s) against aperture "
              f"{A_E} of the same flight moved to the start: " + ", ".join(rows))


if __name__ == "__main__":
    gr_unittest.run(qa_flight_stress)
