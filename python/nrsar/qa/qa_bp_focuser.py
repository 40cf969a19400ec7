#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of bp_focuser: back-projection of synthetic range-compressed point targets.

The input is the exact range-compressed echo of eqs. (8), (29) in numpy float64, on the
ideal line and on a swaying flight (trajectory.motion 'gusty'); the references are a slow
float64 numpy back-projection of the same grid (theory.numpy_bp), the target's true
position and the peak sqrt(N M) of a target seen by all M pulses, and rd_focuser's grid.
"""

import math
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest

try:
    from gnuradio import nrsar
except ImportError:
    import os
    import sys
    dirname, filename = os.path.split(os.path.abspath(__file__))
    sys.path.append(os.path.join(dirname, "..", "bindings"))
    from gnuradio import nrsar

from gnuradio.nrsar.focus_scenario import (LAM, V, H, N_SUB, NFFT, RHO, K, R_FIRST, NUM, T,
                                          SPP, geometry, echo_along)
from gnuradio.nrsar import chain
from gnuradio.nrsar.options import OptionError, ProcessOptions, SimOptions
from gnuradio.nrsar.theory import nmse_theory_db, numpy_bp

M = 200                        # pulses per aperture (0.5 s, 25 m of track)
FC_R = (N_SUB - 1) / (2 * NFFT)  # range spectrum centre [cycles/bin]
X_T, Y_T = 800.0, 12.53        # closest approach 1000 m = bin 30; between two lines


def ideal_antenna(n):
    t = np.arange(n) * T
    return np.stack([np.zeros(n), V * t, np.full(n, H)], axis=1)


def focus(data, cfg=None, nav=None, scn=None):
    """The block on data (pulses x K): image lines and the tags of the output."""
    geo = geometry(M * T)
    scn = scn or nrsar.make_scene([(X_T, Y_T)])
    cfg = cfg or nrsar.bp_config(symbols_per_pulse=SPP, lines_per_aperture=M)
    args = (NUM, geo, scn, K, R_FIRST, RHO, cfg) + ((nav,) if nav is not None else ())
    blk = nrsar.bp_focuser(*args)
    tb = gr.top_block()
    src = blocks.vector_source_c(data.astype(np.complex64).ravel().tolist(), False, K)
    snk = blocks.vector_sink_c(K)
    tb.connect(src, blk, snk)
    tb.run()
    return np.array(snk.data()).reshape(-1, K), snk.tags(), blk


def nmse_db(got, ref):
    return 10 * math.log10(np.sum(np.abs(got - ref) ** 2) / np.sum(np.abs(ref) ** 2))


def peak_position(img, carrier=0.0, factor=32):
    """(line, bin) of the peak, each refined by FFT upsampling of the cut through it (the
    range cut demodulated by its carrier, cycles per bin)."""
    j, k = np.unravel_index(np.argmax(np.abs(img)), img.shape)

    def refine(cut, c):
        n = len(cut)
        spec = np.fft.fft(cut * np.exp(-2j * np.pi * c * np.arange(n)))
        pos, neg = (n + 1) // 2, n // 2
        z = np.zeros(n * factor, complex)
        z[:pos] = spec[:pos]
        z[len(z) - neg:] = spec[n - neg:]
        return np.argmax(np.abs(np.fft.ifft(z))) / factor

    return refine(img[:, k], 0.0), refine(img[j, :], carrier)


class qa_bp_focuser(gr_unittest.TestCase):

    def test_001_matches_numpy_and_focuses_at_the_target(self):
        ant = ideal_antenna(M)
        data = echo_along(ant, [(X_T, Y_T, 1.0)]).astype(np.complex64)
        img, tags, blk = focus(data)
        self.assertEqual(img.shape, (M, K))
        dy = V * T
        y0 = blk.line_shift() * dy  # track_start 0
        ref = numpy_bp(data, ant, R_FIRST, RHO, LAM, FC_R, 8, y0 + dy * np.arange(M), H)
        err = nmse_db(img, ref)
        # float32 samples, phases and sums against float64: about -120 dB; -60 dB is the
        # issue's bound for "the same image".
        self.assertLess(err, -60.0)
        # The peak at the target's (y, r0), within a quarter of a line and of a bin.
        line, rbin = peak_position(img, FC_R)
        self.assertAlmostEqual(line, (Y_T - y0) / dy, delta=0.25)
        self.assertAlmostEqual(rbin, (math.hypot(X_T, H) - R_FIRST) / RHO, delta=0.25)
        # Peak sqrt(N) M / sqrt(M); linear interpolation at U = 8 loses at most
        # (pi b / U)^2 / 8 = 0.5 % of amplitude (b = N / NFFT), and the target sits between
        # two lines (the peak sample is off the azimuth peak by up to half a line).
        peak = np.max(np.abs(img))
        self.assertLess(peak, math.sqrt(N_SUB * M) * 1.0001)
        self.assertGreater(peak, 0.9 * math.sqrt(N_SUB * M))
        # Tags on the first line; rd_focuser's grid (same shift s) for the same scene.
        by_key = {str(t.key): t for t in tags}
        self.assertIn("aperture", by_key)
        az = by_key["azimuth_axis"]
        self.assertEqual(az.offset, 0)
        self.assertAlmostEqual(pmt.to_double(pmt.tuple_ref(az.value, 0)), y0, places=9)
        self.assertAlmostEqual(pmt.to_double(pmt.tuple_ref(az.value, 1)), dy, places=12)
        rd = nrsar.rd_focuser(NUM, geometry(M * T), nrsar.make_scene([(X_T, Y_T)]), K, R_FIRST,
                              RHO, nrsar.focuser_config(symbols_per_pulse=SPP,
                                                        lines_per_aperture=M))
        self.assertEqual(rd.line_shift(), blk.line_shift())
        print(f"bp vs numpy float64: NMSE {err:.1f} dB; peak at line {line:.3f} "
              f"(true {(Y_T - y0) / dy:.3f}), bin {rbin:.3f} (true 30.000)")

    def test_002_swaying_flight_focused_from_navigation(self):
        # Truth = navigation: a gusty flight (decimetres of sway). Projected along it the
        # target focuses as on the ideal line; projected along the ideal line it does not.
        geo = geometry(M * T)
        nav = nrsar.trajectory.motion(geo, nrsar.motion_model.GUSTY, 5, M * T + 0.1)
        ant = np.array(nav.positions(list(np.arange(M) * T)))
        sway = np.abs(ant - ideal_antenna(M))[:, [0, 2]].max()
        self.assertGreater(sway, 0.05)  # centimetres of unknown path: radians of phase
        data = echo_along(ant, [(X_T, Y_T, 1.0)]).astype(np.complex64)
        img, _, blk = focus(data, nav=nav)
        dy = V * T
        y0 = blk.line_shift() * dy
        ref = numpy_bp(data, ant, R_FIRST, RHO, LAM, FC_R, 8, y0 + dy * np.arange(M), H)
        self.assertLess(nmse_db(img, ref), -60.0)
        line, rbin = peak_position(img, FC_R)
        self.assertAlmostEqual(line, (Y_T - y0) / dy, delta=0.25)
        self.assertAlmostEqual(rbin, 30.0, delta=0.25)
        peak = np.max(np.abs(img))
        self.assertGreater(peak, 0.9 * math.sqrt(N_SUB * M))
        # Projected along the ideal line, the target's pixel loses what the unknown path
        # lengths cost: |mean_p exp(j Delta_p)|, Delta_p = 4 pi (R_ideal,p - R_true,p) /
        # lambda at the target (the range offsets, centimetres against 1.5 m bins, barely
        # move the profile's amplitude; the pixel is a quarter line from the target: 1 dB).
        ideal, _, _ = focus(data)
        j, k = int(round((Y_T - y0) / dy)), 30
        loss_db = 20 * math.log10(abs(img[j, k]) / abs(ideal[j, k]))
        ideal_ant = ideal_antenna(M)
        r_true = np.sqrt((X_T - ant[:, 0]) ** 2 + (Y_T - ant[:, 1]) ** 2 + ant[:, 2] ** 2)
        r_ideal = np.sqrt(X_T ** 2 + (Y_T - ideal_ant[:, 1]) ** 2 + ideal_ant[:, 2] ** 2)
        want_db = -20 * math.log10(abs(np.mean(np.exp(4j * np.pi * (r_ideal - r_true) / LAM))))
        self.assertGreater(want_db, 1.0)  # the sway matters
        self.assertAlmostEqual(loss_db, want_db, delta=1.0)
        print(f"gusty flight: largest sway {sway:.3f} m; ideal-line BP loses {loss_db:.1f} dB "
              f"at the target (predicted {want_db:.1f} dB)")

    def test_003_stream_of_apertures_and_flush(self):
        # Two and a half apertures: three images, the last from the pulses received; the
        # azimuth axis advances by M v T; each aperture's image is its pulses' alone.
        n = 2 * M + M // 2
        ant = ideal_antenna(n)
        data = echo_along(ant, [(X_T, Y_T + 25.0, 1.0)]).astype(np.complex64)
        img, tags, blk = focus(data)
        self.assertEqual(img.shape, (3 * M, K))
        self.assertEqual(blk.apertures(), 3)
        starts = sorted((t.offset, pmt.to_double(pmt.tuple_ref(t.value, 0)))
                        for t in tags if str(t.key) == "azimuth_axis")
        dy = V * T
        self.assertEqual([o for o, _ in starts], [0, M, 2 * M])
        for i, (_, y) in enumerate(starts):
            self.assertAlmostEqual(y, (blk.line_shift() + i * M) * dy, places=9)
        y_lines = blk.line_shift() * dy + dy * np.arange(M, 2 * M)
        ref = numpy_bp(data[M:2 * M], ant[M:2 * M], R_FIRST, RHO, LAM, FC_R, 8, y_lines, H)
        self.assertLess(nmse_db(img[M:2 * M], ref), -60.0)

    def test_003b_first_aperture_equals_the_whole_streams(self):
        # a strip's task: first_aperture = a, apertures = 1, fed the stream from pulse a M
        # (stream_first_line) makes aperture a of the whole stream bit for bit, its tags
        # the whole stream's, and stops there
        n = 3 * M
        ant = ideal_antenna(n)
        data = echo_along(ant, [(X_T, Y_T + 25.0, 1.0)]).astype(np.complex64)
        whole, whole_tags, _ = focus(data)
        for a in range(3):
            cfg = nrsar.bp_config(symbols_per_pulse=SPP, lines_per_aperture=M,
                                  first_aperture=a, apertures=1)
            img, tags, blk = focus(data[a * M:], cfg)
            self.assertEqual(blk.stream_first_line(), a * M)
            self.assertEqual(blk.apertures(), 1)
            np.testing.assert_array_equal(img, whole[a * M:(a + 1) * M])
            got = [(str(t.key), pmt.write_string(t.value)) for t in tags]
            ref = [(str(t.key), pmt.write_string(t.value)) for t in whole_tags
                   if t.offset == a * M]
            self.assertEqual(sorted(got), sorted(ref))

    def test_003c_line_step_keeps_every_lth_line(self):
        # line_step L: M / L lines per aperture at pulse positions 0, L, 2 L, ... (L v T
        # apart): against the numpy float64 BP of that coarse grid, the L = 1 image's every
        # L-th line to float rounding (the AVX2 kernel takes a line's distances from the
        # previous line's, exact to 2 ulp: each pulse's phase at most one float ulp, 6e-8
        # cycle, apart, 2 pi 6e-8 of the peak in all), the tags' axis and count on the coarse
        # grid, across apertures and the partial one at the end.
        n = 2 * M + M // 2
        ant = ideal_antenna(n)
        data = echo_along(ant, [(X_T, Y_T + 25.0, 1.0)]).astype(np.complex64)
        full, full_tags, _ = focus(data)
        step, dy = 8, V * T
        cfg = nrsar.bp_config(symbols_per_pulse=SPP, lines_per_aperture=M, line_step=step)
        img, tags, blk = focus(data, cfg)
        j = M // step
        self.assertEqual((blk.lines_per_aperture(), blk.image_lines_per_aperture()), (M, j))
        self.assertEqual(img.shape, (3 * j, K))
        self.assertLessEqual(np.abs(img - full[::step]).max(),
                             2 * np.pi * 6e-8 * np.abs(full).max())
        axes = sorted((t.offset, [pmt.to_double(pmt.tuple_ref(t.value, i)) for i in (0, 1)],
                       pmt.to_uint64(pmt.tuple_ref(t.value, 2)))
                      for t in tags if str(t.key) == "azimuth_axis")
        full_axes = sorted((t.offset, pmt.to_double(pmt.tuple_ref(t.value, 0)))
                           for t in full_tags if str(t.key) == "azimuth_axis")
        self.assertEqual([a[0] for a in axes], [0, j, 2 * j])
        for (_, (y, d), count), (_, y_full) in zip(axes, full_axes):
            self.assertEqual(y, y_full)
            self.assertAlmostEqual(d, step * dy, places=12)
            self.assertEqual(count, j)
        y_lines = blk.line_shift() * dy + dy * np.arange(M, 2 * M, step)
        ref = numpy_bp(data[M:2 * M], ant[M:2 * M], R_FIRST, RHO, LAM, FC_R, 8, y_lines, H)
        self.assertEqual(ref.shape, (j, K))
        self.assertLess(nmse_db(img[j:2 * j], ref), -60.0)
        with self.assertRaisesRegex(ValueError, r"line_step = 3 .*must divide .*M = 200"):
            focus(data[:4], nrsar.bp_config(symbols_per_pulse=SPP, lines_per_aperture=M,
                                            line_step=3))
        with self.assertRaisesRegex(ValueError, "line_step = 0"):
            nrsar.bp_config(line_step=0).validate()
        with self.assertRaisesRegex(ValueError, "line_step = 2 .*trajectory_autofocus"):
            nrsar.bp_config(line_step=2, trajectory_autofocus=True).validate()

    def test_004_parameters_validated(self):
        with self.assertRaisesRegex(ValueError, "upsample = 0"):
            nrsar.bp_config(upsample=0).validate()
        with self.assertRaisesRegex(ValueError, "num_threads = 3"):
            focus(np.zeros((4, K)), cfg=nrsar.bp_config(num_threads=3))
        short = nrsar.trajectory.motion(geometry(M * T), nrsar.motion_model.CALM, 1, 0.2)
        with self.assertRaisesRegex(ValueError, "too short"):
            focus(np.zeros((4, K)), nav=short)

    def test_005_ground_grid(self):
        ant = ideal_antenna(M)
        data = echo_along(ant, [(X_T, Y_T, 1.0)]).astype(np.complex64)
        cfg = nrsar.bp_config(symbols_per_pulse=SPP, lines_per_aperture=M,
                              grid=nrsar.image_grid.GROUND)
        img, tags, blk = focus(data, cfg=cfg)
        # Column 0 at the first bin's ground range, the bin projected at mid range.
        x0 = math.sqrt(R_FIRST ** 2 - H ** 2)
        r_mid = R_FIRST + (K - 1) / 2 * RHO
        dx = RHO * r_mid / math.sqrt(r_mid ** 2 - H ** 2)
        self.assertAlmostEqual(blk.ground_first_x_m(), x0, places=9)
        self.assertAlmostEqual(blk.ground_spacing_m(), dx, places=9)
        dy = V * T
        y0 = blk.line_shift() * dy
        ref = numpy_bp(data, ant, R_FIRST, RHO, LAM, FC_R, 8, y0 + dy * np.arange(M), H,
                       ground=(x0 + dx * np.arange(K), 0.0))
        self.assertLess(nmse_db(img, ref), -60.0)
        # The target's (y, x); along x the range carrier FC_R per bin becomes FC_R dx / RHO
        # times dr/dx = x / r at the target.
        line, col = peak_position(img, FC_R * dx / RHO * X_T / math.hypot(X_T, H))
        self.assertAlmostEqual(line, (Y_T - y0) / dy, delta=0.25)
        self.assertAlmostEqual(col, (X_T - x0) / dx, delta=0.25)
        keys = [str(t.key) for t in tags]
        self.assertIn("ground_range_axis", keys)
        self.assertNotIn("range_axis", keys)
        with self.assertRaisesRegex(ValueError, "ground_height_m = 2000"):
            focus(data[:4], cfg=nrsar.bp_config(grid=nrsar.image_grid.GROUND,
                                                ground_height_m=2000.0))

    def test_006_ffbp_against_back_projection(self):
        # A swaying flight; FFBP's error against the exact BP of the same block is the
        # linear interpolation between beams, pi^4 / (600 os^4) of the image power at most
        # (-44 dB at os = 8; kernel test), measured away from the window's ends.
        nav = nrsar.trajectory.motion(geometry(M * T), nrsar.motion_model.GUSTY, 3, M * T + 0.1)
        ant = np.array(nav.positions(list(np.arange(M) * T)))
        data = echo_along(ant, [(X_T, Y_T, 1.0)]).astype(np.complex64)
        exact, _, _ = focus(data, nav=nav)
        for os_, sub in ((8.0, 25), (4.0, 40)):
            cfg = nrsar.bp_config(symbols_per_pulse=SPP, lines_per_aperture=M,
                                  ffbp_subaperture=sub, ffbp_beam_oversample=os_)
            img, _, _ = focus(data, cfg=cfg, nav=nav)
            bound = 10 * math.log10((math.pi / os_) ** 4 / 600)
            self.assertLess(nmse_db(img[:, 8:-8], exact[:, 8:-8]), bound + 1.0)
            for a, b in zip(peak_position(img, FC_R), peak_position(exact, FC_R)):
                self.assertAlmostEqual(a, b, delta=0.25)
        with self.assertRaisesRegex(ValueError, "ffbp_beam_oversample = 0.5"):
            nrsar.bp_config(ffbp_beam_oversample=0.5).validate()

    def test_006b_recursive_ffbp_against_numpy_bp(self):
        # Recursive FFBP (subapertures of 8 pulses merged 2 at a time, n = 1..3 levels)
        # through the block against theory.numpy_bp (float64, U = 8) on a gusty flight. Each
        # level adds one interpolation between beams (pi^4 / (600 os^4), adding in amplitude:
        # n^2 of it at most) and one in range (pi^4 (b / U)^4 / 600, b = N / NFFT of a bin):
        # the kernel test's bound, measured away from the window's ends.
        geo = geometry(M * T)
        nav = nrsar.trajectory.motion(geo, nrsar.motion_model.GUSTY, 3, M * T + 0.1)
        ant = np.array(nav.positions(list(np.arange(M) * T)))
        data = echo_along(ant, [(X_T, Y_T, 1.0)]).astype(np.complex64)
        dy = V * T
        os_ = 8.0
        for n in (1, 2, 3):
            cfg = nrsar.bp_config(symbols_per_pulse=SPP, lines_per_aperture=M,
                                  ffbp_subaperture=8, ffbp_beam_oversample=os_,
                                  ffbp_levels=n, ffbp_merge_factor=2)
            img, _, blk = focus(data, cfg=cfg, nav=nav)
            if n == 1:
                y0 = blk.line_shift() * dy
                ref = numpy_bp(data, ant, R_FIRST, RHO, LAM, FC_R, 8, y0 + dy * np.arange(M), H)
            bound = 10 * math.log10(n * n * (math.pi / os_) ** 4 / 600
                                    + n * (math.pi * N_SUB / (NFFT * 8)) ** 4 / 600)
            err = nmse_db(img[:, 8:-8], ref[:, 8:-8])
            print(f"ffbp levels {n} (8 pulses, merged 2 at a time, os 8): NMSE against numpy_bp "
                  f"{err:.1f} dB inner (bound {bound:.1f} dB)")
            self.assertLess(err, bound + 1.0)
            for a, b in zip(peak_position(img, FC_R), peak_position(ref, FC_R)):
                self.assertAlmostEqual(a, b, delta=0.25)
        with self.assertRaisesRegex(ValueError, "ffbp_levels = 2.*ffbp_subaperture < 2"):
            nrsar.bp_config(ffbp_levels=2).validate()
        with self.assertRaisesRegex(ValueError, "ffbp_merge_factor = 1"):
            nrsar.bp_config(ffbp_subaperture=8, ffbp_levels=2, ffbp_merge_factor=1).validate()
        with self.assertRaisesRegex(OptionError, "--ffbp-levels = 2 needs --focuser ffbp"):
            SimOptions(focuser="bp", ffbp_levels=2).validate()

    def test_007_chain_nmse_sits_at_spec8_theory(self):
        # SPEC 8 in nrsar-sim (docs/blocks/bp_focuser.md, "NMSE"): every BP pixel correlates
        # all N M samples of the aperture along its own range history, so its error power is
        # the per-RE error (Var(chi) + E|g|^2 / SNR_in) |alpha|^2 / E{chi}^2 and a target on
        # a pixel peaks at sqrt(N M) |alpha|: NMSE = the theory (theory.nmse_theory_db, numpy
        # float64 over the 256-QAM points). Off the grid by a fraction d of a range bin the
        # peak is the Dirichlet kernel's D_N(d) = sin(pi d) / (N sin(pi d / N)) (Nfft = N
        # here): NMSE = theory - 20 log10 D_N(d). rd_focuser's phase-only compression over
        # its processed band B_p sits 10 log10(B_p / B_t) above, B_t the target's own Doppler
        # band over the aperture (eq. (8) at the aperture's ends). 1 s aperture, so that the
        # estimate holds about 49 range bins x B_t Ta = 47 independent pixels per bin (a
        # 0.1 dB scatter); the presummer's passband (75 Hz) holds every pixel's history
        # (|f| < 47 Hz), and every pixel of the crop lies above the height. A pixel whose
        # range history leaves the crop reads zeros there (the data ends): its error power
        # is that fraction of the aperture's, so the expectation carries 10 log10 of the
        # mean fraction over the pixels, here the last bin's (R > r0 off closest approach):
        # 10 log10(48 / 49) = -0.09 dB.
        n_sub, v, height, ta, fc = 512, 50.0, 1000.0, 1.0, 3.5e9
        lam, rho = 299792458.0 / fc, 299792458.0 / (2 * n_sub * 30e3)

        def covered_db(r):
            first, step = r["range_axis_m"]
            y_first, dy = r["azimuth_axis_m"]
            r0 = first + step * np.arange(r["range_bins"])
            lines = y_first + dy * np.arange(0, r["azimuth_lines"], 10)
            track = np.linspace(0.0, v * ta, 1000)
            rng = np.sqrt(r0[None, :, None] ** 2 + (lines[:, None, None] - track) ** 2)
            return 10 * math.log10(np.mean(rng <= r0[-1]))

        def run(focuser, filt, snr_db, bins, out, *extra):
            x = math.sqrt((bins * rho) ** 2 - height ** 2)
            return chain.simulate(SimOptions.parse([
                "--preset", "small", "--aperture-s", str(ta), "--target", f"{x!r},25",
                "--presum", "cheby", "--decim", "8", "--range-margin-m", "235",
                "--focuser", focuser, "--filter", filt, "--snr-db", str(snr_db),
                "--images", "none", "--out", out] + list(extra)))

        out = tempfile.mkdtemp(prefix="qa_bp_nmse_")
        runs = {}
        for filt, snr_db, bins in (("wf", 10.0, 127), ("wf", -10.0, 127), ("rf", 20.0, 127.5)):
            r = run("bp", filt, snr_db, bins, f"{out}/{filt}{snr_db}")
            d = bins - math.floor(bins)
            peak = math.sin(math.pi * d) / (n_sub * math.sin(math.pi * d / n_sub)) if d else 1.0
            expected = (nmse_theory_db("qam256", filt, snr_db) - 20 * math.log10(peak)
                        + covered_db(r))
            print(f"bp {filt} {snr_db:g} dB, target at bin {bins}: NMSE {r['nmse_db']:.2f} dB, "
                  f"expected {expected:.2f} dB")
            self.assertAlmostEqual(r["nmse_db"], expected, delta=0.3)
            self.assertAlmostEqual(r["nmse_theory_band_db"], r["nmse_theory_db"], places=9)
            runs[filt, snr_db] = r
        # --bp-line-step 4: every 4th line (5.7 cm; the azimuth resolution lambda r0 / (2 v Ta)
        # is 1.06 m) holds the same pixels, so the same NMSE to the estimate's scatter (a
        # quarter of the pixels); the target up to 2.9 cm off a line loses at most
        # (pi 0.029 / 1.06)^2 / 6 of its peak amplitude (0.01 dB).
        r = run("bp", "wf", 10.0, 127, f"{out}/step4", "--bp-line-step", "4")
        full = runs["wf", 10.0]
        self.assertEqual(r["azimuth_lines"], full["azimuth_lines"] // 4)
        self.assertAlmostEqual(r["azimuth_axis_m"][1], 4 * full["azimuth_axis_m"][1], places=12)
        expected = nmse_theory_db("qam256", "wf", 10.0) + covered_db(r)
        print(f"bp wf 10 dB, --bp-line-step 4: NMSE {r['nmse_db']:.2f} dB, expected "
              f"{expected:.2f} dB")
        self.assertAlmostEqual(r["nmse_db"], expected, delta=0.3)
        # Recursive FFBP (--ffbp-levels 3: 16 pulses merged 4 at a time, os 8): its error
        # against BP, at most 9 pi^4 / (600 os^4) + 3 pi^4 (b / U)^4 / 600 of the image
        # power (test_006b; below -30 dB), leaves the NMSE at the theory.
        r = run("ffbp", "wf", 10.0, 127, f"{out}/ffbp3", "--ffbp-subaperture", "16",
                "--ffbp-levels", "3", "--ffbp-merge-factor", "4")
        expected = nmse_theory_db("qam256", "wf", 10.0) + covered_db(r)
        print(f"ffbp wf 10 dB, --ffbp-levels 3: NMSE {r['nmse_db']:.2f} dB, expected "
              f"{expected:.2f} dB (bp {full['nmse_db']:.2f} dB)")
        self.assertAlmostEqual(r["nmse_db"], expected, delta=0.3)
        with self.assertRaisesRegex(OptionError, "--bp-line-step = 2 needs --focuser bp"):
            SimOptions(bp_line_step=2).validate()
        with self.assertRaisesRegex(OptionError, "--bp-line-step = 2 with --autofocus traj"):
            SimOptions(bp_line_step=2, focuser="bp", autofocus="trajectory").validate()
        self.assertNotEqual(full["azimuth_lines"] % 7, 0)
        with self.assertRaisesRegex(OptionError, "--bp-line-step = 7 must divide the pulses "
                                    f"per aperture at the focuser, {full['azimuth_lines']}"):
            run("bp", "wf", 10.0, 127, f"{out}/step7", "--bp-line-step", "7")
        with self.assertRaisesRegex(OptionError, "--bp-line-step = 2 with --strip-aperture"):
            ProcessOptions(recording="f.sigmf-meta", focuser="bp", bp_line_step=2,
                           strip_aperture_s=1.0).validate()
        rd = run("rd", "wf", 10.0, 127, f"{out}/rd")
        r0 = 127 * rho
        y0, y1 = 0.0, v * ta  # the track over the aperture; the target at y = 25 m
        b_t = 2 * v / lam * ((25 - y0) / math.hypot(r0, 25 - y0)
                             - (25 - y1) / math.hypot(r0, 25 - y1))
        b_p = rd["doppler_band_hz"][1] - rd["doppler_band_hz"][0]
        bp = runs["wf", 10.0]
        gap = rd["nmse_db"] - (bp["nmse_db"] - covered_db(bp))  # rd has guard bins
        print(f"rd - bp (full pixels): {gap:.2f} dB, 10 log10(B_p / B_t) = 10 log10({b_p:.1f} / {b_t:.1f}) = "
              f"{10 * math.log10(b_p / b_t):.2f} dB")
        self.assertAlmostEqual(gap, 10 * math.log10(b_p / b_t), delta=0.3)


if __name__ == "__main__":
    gr_unittest.run(qa_bp_focuser)
