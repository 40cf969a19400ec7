#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of the processing from navigation (issue #14): cheby_presum's inter-pulse compensation
along the flown path and rd_focuser's motion compensation.

The echo is the exact range-compressed echo of a point target (eqs. 8, 29) seen from a
`gusty` path, evaluated here in numpy float64 from the path's positions; the references are
written here in float64 too: the presummer's coherent sum with the path's line of sight (and
the ideal line's, for what it loses), and a matched filter along the flown path for the
impulse-response width the path can give. Geometry: focus_scenario (PRF 400 Hz, 1.5 m range
bins, H = 600 m, the target at 1000 m slant range).
"""

import math

import numpy as np
from gnuradio import blocks, gr, gr_unittest

try:
    from gnuradio import nrsar
except ImportError:
    import os
    import sys
    dirname, filename = os.path.split(os.path.abspath(__file__))
    sys.path.append(os.path.join(dirname, "..", "bindings"))
    from gnuradio import nrsar

from gnuradio.nrsar.focus_scenario import (C, FC, V, H, N_SUB, NFFT, RHO, K, R_FIRST, SPP, NUM,
                                          T, geometry)
from qa_rd_focuser import cut_metrics  # peak, IRW [samples], PSLR, ISLR of a cut

F_PHASE = FC + 0.5 * (N_SUB - 1) * NUM.subcarrier_spacing_hz  # phase of a compressed bin
X_T, Y_T = 800.0, 25.0          # target: ground range, along track
R0_T = math.hypot(X_T, H)       # 1000 m: range bin 30
K_T = int(round((R0_T - R_FIRST) / RHO))
SEED = 5


def path_echo(pos, targets=((X_T, Y_T, 1.0),), illum=None):
    """Range-compressed echo (pulses x K) from antenna positions pos (pulses x 3): line m,
    bin k: a w_m sum_{n<N} exp(j 2 pi n (k - k_m) / NFFT) / sqrt(N) exp(-j 4 pi fc R_m / c),
    R_m = |pos_m - (x, y, 0)|, k_m = (R_m - R_FIRST) / RHO; w_m = 1, or with illum a
    smooth beam cos^2(pi (y_m - y) / (2 illum)) over |y_m - y| < illum."""
    k = np.arange(K)
    n = np.arange(N_SUB)
    out = np.zeros((len(pos), K), complex)
    for x, y, a in targets:
        r = np.sqrt((pos[:, 0] - x) ** 2 + (pos[:, 1] - y) ** 2 + pos[:, 2] ** 2)
        kq = (r - R_FIRST) / RHO
        prof = np.exp(2j * np.pi * (k[None, :, None] - kq[:, None, None]) * n[None, None, :]
                      / NFFT).sum(-1) / np.sqrt(N_SUB)
        u = (pos[:, 1] - y) / illum if illum else np.zeros(len(pos))
        w = np.where(np.abs(u) < 1.0, np.cos(0.5 * np.pi * u) ** 2, 0.0)
        out += a * (w * np.exp(-4j * np.pi * np.mod(r * FC / C, 1.0)))[:, None] * prof
    return out


def flight(n_pulses, motion=True, targets=((X_T, Y_T, 1.0),), seed=SEED):
    """(geometry, scene, true path, positions of the pulses): aperture n_pulses T."""
    geo = geometry(n_pulses * T)
    scn = nrsar.make_scene([(x, y) for x, y, _ in targets])
    if motion:
        path = nrsar.trajectory.motion(geo, nrsar.motion_model.GUSTY, seed, n_pulses * T + 0.5)
    else:
        path = nrsar.trajectory.ideal(geo)
    pos = np.array(path.positions(list(np.arange(n_pulses) * T)))
    return geo, scn, path, pos


def run(block, data, vlen_out):
    src = blocks.vector_source_c(np.asarray(data, np.complex64).ravel().tolist(), False, K)
    snk = blocks.vector_sink_c(vlen_out)
    tb = gr.top_block()
    tb.connect(src, block, snk)
    tb.run()
    return np.array(snk.data(), complex).reshape(-1, vlen_out)


class qa_motion_compensation(gr_unittest.TestCase):

    # ---- cheby_presum ------------------------------------------------------------------

    def presum_case(self, decim=8):
        n = 480
        geo, scn, path, pos = flight(n)
        data = path_echo(pos)
        cfg = nrsar.presum_config(decim=decim, symbols_per_pulse=SPP)
        return geo, scn, path, pos, data, cfg

    def expected_presum(self, blk, data, path, ideal_geo=None):
        """Output of eqs. (P-25..P-29) in float64: out(k, g) = sum_j h_j s(k, p_j) C(k, j),
        C = exp(+j 4 pi f (R(t_j) - R(t_c)) / c), R the range of the reference scatterer
        (the scene centre, ground range sqrt(R0(k)^2 - H^2)) from the path (ideal_geo None)
        or from the ideal line of ideal_geo."""
        d, taps = blk.decim(), np.array(blk.taps())
        a = (blk.num_taps() - 1) // 2  # window of output g: pulses g D - a .. g D + b
        r0 = R_FIRST + RHO * np.arange(K)
        gx = np.sqrt(np.maximum(r0 * r0 - H * H, 0.0))

        def ranges(t):
            if ideal_geo is not None:
                u = ideal_geo.track_start_m + ideal_geo.velocity_mps * t - Y_T
                return np.sqrt(r0 * r0 + u * u)
            p = np.array(path.position(float(t)))
            return np.sqrt((p[0] - gx) ** 2 + (p[1] - Y_T) ** 2 + p[2] ** 2)

        outs = []
        g = 0
        while g * d + blk.lookahead() < len(data):
            first = g * d - a
            if first >= 0:  # full windows only
                tc = (first + 0.5 * (blk.num_taps() - 1)) * T
                rc = ranges(tc)
                acc = np.zeros(K, complex)
                for j in range(blk.num_taps()):
                    c = np.exp(4j * np.pi * F_PHASE * (ranges((first + j) * T) - rc) / C)
                    acc += taps[j] * data[first + j] * c
                outs.append((g, acc))
            g += 1
        return outs

    def test_001_presum_follows_the_navigation(self):
        # gusty path, perfect navigation: the block's output equals the float64 coherent
        # sum along the path's line of sight, and the target keeps the full coherent gain
        # D^2 (what eq. P-29 promises); the ideal-line compensation loses what the float64
        # sum with the ideal line predicts.
        geo, scn, path, pos, data, cfg = self.presum_case()
        d = cfg.decim
        nav = nrsar.cheby_presum(NUM, geo, scn, K, R_FIRST, RHO, cfg, path)
        ideal = nrsar.cheby_presum(NUM, geo, scn, K, R_FIRST, RHO, cfg)
        self.assertTrue(nav.follows_path())
        self.assertFalse(ideal.follows_path())
        out_nav = run(nav, data, K)
        out_ideal = run(ideal, data, K)
        pulse_power = np.mean(np.abs(data[:, K_T]) ** 2)
        gain, expected = {}, {}
        for name, blk, out, geo_ref in (("nav", nav, out_nav, None),
                                        ("ideal", ideal, out_ideal, geo)):
            exp = self.expected_presum(blk, data, path, geo_ref)
            got = np.array([out[g] for g, _ in exp])
            ref = np.array([e for _, e in exp])
            nmse = np.sum(np.abs(got - ref) ** 2) / np.sum(np.abs(ref) ** 2)
            self.assertLess(10 * np.log10(nmse), -50.0)
            gain[name] = 10 * np.log10(np.mean(np.abs(got[:, K_T]) ** 2) / (d * d * pulse_power))
            expected[name] = 10 * np.log10(np.mean(np.abs(ref[:, K_T]) ** 2)
                                           / (d * d * pulse_power))
            self.assertAlmostEqual(gain[name], expected[name], delta=0.02)
        # the coherent sum along the flown line of sight: D^2 x the pulse power (the
        # envelope moves by at most 0.02 bins over a window)
        self.assertAlmostEqual(gain["nav"], 0.0, delta=0.05)
        # the ideal line leaves the sway's Doppler (8 Hz rms) in the filter's transition band
        self.assertLess(gain["ideal"], -1.0)
        print(f"\nD = {d}: coherent gain re D^2, navigation {gain['nav']:+.3f} dB, ideal line "
              f"{gain['ideal']:+.3f} dB (float64 expectation {expected['ideal']:+.3f} dB); "
              f"phase segment {nav.phase_segment()} pulses")

    def test_002_ideal_navigation_is_the_ideal_line_bit_for_bit(self):
        n = 160
        geo, scn, path, pos = flight(n, motion=False)
        data = path_echo(pos)
        cfg = nrsar.presum_config(decim=4, symbols_per_pulse=SPP)
        a = run(nrsar.cheby_presum(NUM, geo, scn, K, R_FIRST, RHO, cfg), data, K)
        b = run(nrsar.cheby_presum(NUM, geo, scn, K, R_FIRST, RHO, cfg, path), data, K)
        self.assertEqual(a.shape, b.shape)
        self.assertTrue(np.array_equal(a, b))

    # ---- rd_focuser ----------------------------------------------------------------------

    def focus(self, data, geo, scn, nav=None, moco=nrsar.moco_order.SECOND, resample=False):
        cfg = nrsar.focuser_config(symbols_per_pulse=SPP, lines_per_aperture=len(data),
                                   overlap_lines=0, moco=moco, moco_resample=resample)
        blk = nrsar.rd_focuser(NUM, geo, scn, K, R_FIRST, RHO, cfg,
                               nav if nav is not None else nrsar.trajectory())
        return run(blk, data, K)

    def matched_filter_irw(self, data, pos, x, bin_, y_t=Y_T):
        """Azimuth IRW [m] the flown pulses give the target at ground range x: the float64
        matched filter of its range bin along the path,
        I(y) = sum_m s_m exp(+j 4 pi f |pos_m - (x, y, 0)| / c), on a 1 cm grid around it."""
        y = y_t + np.arange(-300, 301) * 0.01
        r = np.sqrt((pos[:, 0, None] - x) ** 2 + (pos[:, 1, None] - y[None, :]) ** 2
                    + pos[:, 2, None] ** 2)
        img = (data[:, bin_, None] * np.exp(4j * np.pi * F_PHASE * r / C)).sum(0)
        return cut_metrics(img)[1] * 0.01

    def test_003_rd_motion_compensation_refocuses_gusty_flight(self):
        # Two targets 21 m either side of the scene's reference range (bins 30 and 58): the
        # first order removes the line-of-sight displacement at the reference range, the
        # second order the rest per range bin.
        n = 400
        x2 = math.sqrt((R0_T + 42 * RHO / 1.5) ** 2 - H * H)
        targets = ((X_T, Y_T, 1.0), (x2, Y_T, 1.0))
        bins = (K_T, K_T + 28)
        geo, scn, path, pos = flight(n, targets=targets)
        _, _, _, pos_ideal = flight(n, motion=False, targets=targets)
        rng = np.random.default_rng(7)
        noise = (rng.standard_normal((n, K)) + 1j * rng.standard_normal((n, K))) * 0.05
        ideal, flown = path_echo(pos_ideal, targets), path_echo(pos, targets)
        ref_ideal = self.focus(ideal, geo, scn)
        img = {"ideal": (ref_ideal, self.focus(ideal + noise, geo, scn))}
        for name in ("off", "first", "second"):
            moco = getattr(nrsar.moco_order, name.upper())
            img[name] = (self.focus(flown, geo, scn, path, moco),
                         self.focus(flown + noise, geo, scn, path, moco))
        dy = V * T
        res = {}
        for name, (ref, noisy) in img.items():
            # SPEC 8 against the case's own noise-free image: c, NMSE (N M mean / max^2)
            c = np.vdot(ref, noisy) / np.vdot(ref, ref)
            nmse = N_SUB * n * np.mean(np.abs(noisy / c - ref) ** 2) / np.abs(ref).max() ** 2
            # PEL against the ideal flight's noise-free image (focus and position)
            pel = -20 * np.log10(abs(np.vdot(ref_ideal, ref) / np.vdot(ref_ideal, ref_ideal)))
            res[name] = dict(
                nmse_db=10 * np.log10(nmse), pel_db=pel,
                peak_db=[20 * np.log10(np.abs(ref[:, b]).max() / np.abs(ref_ideal[:, b]).max())
                         for b in bins],
                irw_m=[cut_metrics(ref[:, b])[1] * dy for b in bins],
                line=[int(np.argmax(np.abs(ref[:, b]))) for b in bins])
        model = [self.matched_filter_irw(flown, pos, t[0], b) for t, b in zip(targets, bins)]
        print()
        for name, r in res.items():
            print(f"{name:>6}: NMSE {r['nmse_db']:6.2f} dB, PEL {r['pel_db']:6.2f} dB, peaks "
                  f"{r['peak_db'][0]:+6.2f} / {r['peak_db'][1]:+6.2f} dB, az IRW "
                  f"{r['irw_m'][0]:.3f} / {r['irw_m'][1]:.3f} m, lines {r['line']}")
        print(f"matched filter along the path: IRW {model[0]:.3f} / {model[1]:.3f} m")
        # without MoCo the gusty flight defocuses (and shifts)
        self.assertGreater(res["off"]["pel_db"], 3.0)
        self.assertGreater(res["off"]["nmse_db"], res["ideal"]["nmse_db"] + 3.0)
        # with it: within 0.5 dB NMSE of the ideal flight, IRW within 5 % of the flown
        # path's matched filter, both targets at the ideal flight's lines
        r = res["second"]
        self.assertLess(abs(r["nmse_db"] - res["ideal"]["nmse_db"]), 0.5)
        self.assertLess(r["pel_db"], 0.5)
        self.assertEqual(r["line"], res["ideal"]["line"])
        for i in range(2):
            self.assertAlmostEqual(r["irw_m"][i] / model[i], 1.0, delta=0.05)
            self.assertGreater(r["peak_db"][i], -0.5)
        # the first order alone leaves the targets off the reference range a residual
        self.assertGreater(res["first"]["pel_db"], r["pel_db"])

    def test_007_along_track_resampling(self):
        # gusty seed 0: the along-track position lags the ideal line by up to 0.83 m over the
        # 1.2 s (speed -2.3 % at the start, a shift of 6.6 lines at the end). Three targets
        # 12 m apart along track at the reference range, each lit by a smooth 30 m beam
        # inside the block. Expectation, float64: the exact echo at the resampled positions
        # p(tau_m), tau_m solved here by Newton (y(tau_m) = v t_m), focused with the second
        # order along those positions: what the block must give up to its interpolation.
        n, illum = 480, 15.0
        targets = ((X_T, 18.0, 1.0), (X_T, 30.0, 1.0), (X_T, 42.0, 1.0))
        geo, scn, path, pos = flight(n, targets=targets, seed=0)
        _, _, _, pos_ideal = flight(n, motion=False, targets=targets)
        t = np.arange(n) * T
        tau = t.copy()
        for _ in range(6):
            y = np.array([path.position(float(s))[1] for s in tau])
            vy = np.array([path.velocity(float(s))[1] for s in tau])
            tau -= (y - V * t) / vy
        pos_hat = np.array(path.positions(list(tau)))
        self.assertLess(np.abs(pos_hat[:, 1] - V * t).max(), 1e-9)
        nav_hat = nrsar.trajectory.from_samples(list(t), [tuple(p) for p in pos_hat])
        flown = path_echo(pos, targets, illum)
        expected = self.focus(path_echo(pos_hat, targets, illum), geo, scn, nav_hat)
        got = self.focus(flown, geo, scn, path, resample=True)
        err_db = 10 * np.log10(np.sum(np.abs(got - expected) ** 2)
                               / np.sum(np.abs(expected) ** 2))
        # bound: the windowed sinc's worst error (power) over the envelope's band |nu| <= 0.2
        # cycles per line and fractions mu, from the kernel's definition (16 Kaiser-6 taps,
        # the RCMC kernel, tabulated at the nearest of 1024 phases), in float64 here
        j = np.arange(-7, 9)
        worst = 0.0
        for mu in np.linspace(0.0, 1.0, 97):
            x = j - round(mu * 1024) / 1024
            h = np.sinc(x) * np.i0(6.0 * np.sqrt(np.clip(1 - (x / 8) ** 2, 0, 1))) / np.i0(6.0)
            h /= h.sum()
            for nu in np.linspace(-0.2, 0.2, 81):
                got_nu = np.sum(h * np.exp(2j * np.pi * nu * (j - mu)))
                worst = max(worst, abs(got_nu - 1.0) ** 2)
        bound_db = 10 * np.log10(worst)
        print(f"\nresampled block against the float64 resampled flight: {err_db:.1f} dB "
              f"(interpolator bound over |nu| <= 0.2: {bound_db:.1f} dB)")
        self.assertLess(err_db, bound_db)

        # what it gains, against the ideal flight and against BP along the same navigation
        rng = np.random.default_rng(3)
        noise = (rng.standard_normal((n, K)) + 1j * rng.standard_normal((n, K))) * 0.05
        ideal = path_echo(pos_ideal, targets, illum)
        img = {"ideal": (self.focus(ideal, geo, scn), self.focus(ideal + noise, geo, scn)),
               "second": (self.focus(flown, geo, scn, path),
                          self.focus(flown + noise, geo, scn, path)),
               "resample": (got, self.focus(flown + noise, geo, scn, path, resample=True))}
        bp_cfg = nrsar.bp_config(symbols_per_pulse=SPP, lines_per_aperture=n)

        def bp(data, nav):
            return run(nrsar.bp_focuser(NUM, geo, scn, K, R_FIRST, RHO, bp_cfg, nav), data, K)
        ideal_path = nrsar.trajectory.ideal(geo)
        img_bp = {"bp ideal": (bp(ideal, ideal_path), bp(ideal + noise, ideal_path)),
                  "bp": (bp(flown, path), bp(flown + noise, path))}
        res = {}
        for name, (ref, noisy) in list(img.items()) + list(img_bp.items()):
            ref_ideal = (img_bp["bp ideal"] if name.startswith("bp") else img["ideal"])[0]
            c = np.vdot(ref, noisy) / np.vdot(ref, ref)
            nmse = N_SUB * n * np.mean(np.abs(noisy / c - ref) ** 2) / np.abs(ref).max() ** 2
            pel = -20 * np.log10(abs(np.vdot(ref_ideal, ref) / np.vdot(ref_ideal, ref_ideal)))
            peaks, irw, lines = [], [], []
            col = np.abs(ref_ideal[:, K_T])  # the ideal image's three peaks, in order
            tops = sorted(np.argsort(col)[::-1][:1])
            while len(tops) < 3:
                far = [j for j in np.argsort(col)[::-1] if min(abs(j - t) for t in tops) > 40]
                tops = sorted(tops + far[:1])
            for top in tops:  # each target's own stretch of lines
                lo = int(top) - 40
                cut = ref[lo:lo + 80, K_T]
                cut_i = ref_ideal[lo:lo + 80, K_T]
                peaks.append(20 * np.log10(np.abs(cut).max() / np.abs(cut_i).max()))
                irw.append(cut_metrics(cut)[1] * V * T)
                lines.append(lo + int(np.argmax(np.abs(cut))))
            res[name] = dict(nmse_db=10 * np.log10(nmse), pel_db=pel, peak_db=peaks,
                             irw_m=irw, line=lines)
        model = [self.matched_filter_irw(flown, pos, tg[0], K_T, tg[1]) for tg in targets]
        for name, r in res.items():
            print(f"{name:>8}: NMSE {r['nmse_db']:6.2f} dB, PEL {r['pel_db']:6.2f} dB, peaks "
                  + " / ".join(f"{p:+.2f}" for p in r["peak_db"]) + " dB, az IRW "
                  + " / ".join(f"{w:.3f}" for w in r["irw_m"]) + f" m, lines {r['line']}")
        print("matched filter along the path: IRW " + " / ".join(f"{w:.3f}" for w in model))
        r, s2 = res["resample"], res["second"]
        self.assertLess(res["bp"]["pel_db"], 0.5)
        self.assertLess(abs(r["nmse_db"] - res["ideal"]["nmse_db"]), 0.5)
        self.assertLess(r["pel_db"], 0.5 * s2["pel_db"])
        self.assertEqual(r["line"], res["ideal"]["line"])
        for i in range(3):
            self.assertAlmostEqual(r["irw_m"][i] / model[i], 1.0, delta=0.05)

    def test_008_resampling_widens_the_overlap_by_the_path_lag(self):
        # overlap-save: a resampled line reads the pulses up to the path's along-track lag
        # |y_nav - y| / (v T) plus half the interpolator away, so the block grows that much
        # on both sides (the lag from the path's positions on a 10 ms grid, here)
        n = 480
        geo, scn, path, _ = flight(n, seed=0)

        def overlap(resample):
            cfg = nrsar.focuser_config(symbols_per_pulse=SPP, moco_resample=resample)
            blk = nrsar.rd_focuser(NUM, geo, scn, K, R_FIRST, RHO, cfg, path)
            return blk.overlap_before(), blk.overlap_after()
        t = np.arange(0.0, n * T + 0.5 + 1e-9, 0.01)
        t = t[t <= path.end_s()]
        lag = np.abs(np.array(path.positions(list(t)))[:, 1] - V * t).max()
        extra = math.ceil(lag / (V * T) + 8)
        (b0, a0), (b1, a1) = overlap(False), overlap(True)
        self.assertEqual((b1 - b0, a1 - a0), (extra, extra))

    def test_004_moco_on_the_ideal_line_changes_nothing(self):
        n = 200
        geo, scn, path, pos = flight(n, motion=False)
        data = path_echo(pos)
        off = self.focus(data, geo, scn, None, nrsar.moco_order.OFF)
        for nav in (None, path):
            for resample in (False, True):
                on = self.focus(data, geo, scn, nav, nrsar.moco_order.SECOND, resample)
                self.assertTrue(np.array_equal(on, off))

    def test_005_bad_moco_value(self):
        with self.assertRaises(ValueError):
            nrsar.make_moco_order("third")
        with self.assertRaises(nrsar.OptionError):
            nrsar.SimOptions(preset="tiny", moco="maybe").validate()

    def test_006_sim_moco_option_sets_the_focuser(self):
        from gnuradio.nrsar import chain, scenario
        for flag, order, resample in (("on", nrsar.moco_order.SECOND, False),
                                      ("off", nrsar.moco_order.OFF, False),
                                      ("resample", nrsar.moco_order.SECOND, True)):
            opts = nrsar.SimOptions(preset="tiny", moco=flag).validate()
            cfg = chain.focuser_config_of(opts, scenario.of(opts), 0)
            self.assertEqual(cfg.moco, order)
            self.assertEqual(cfg.moco_resample, resample)


if __name__ == "__main__":
    gr_unittest.run(qa_motion_compensation)
