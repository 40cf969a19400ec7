#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of nrsar.extended_scene_echo (maps + speckle + points + beam) against eqs. (1), (7), (8)
evaluated in numpy float64, and of the YAML scene files (nrsar.scenes)."""

import math
import os
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest

try:
    from gnuradio import nrsar
except ImportError:
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bindings"))
    from gnuradio import nrsar

C = 299792458.0
HERE = os.path.dirname(os.path.abspath(__file__))


def tsym(num):
    return 1.0 / num.subcarrier_spacing_hz + num.cp_samples / (num.fft_size * num.subcarrier_spacing_hz)


def exact_h(num, geo, xs, ys, amps, ms, gain=None):
    """H[m, n] = sum_k a_k g_k exp(-j 4 pi (fc + n df) R_k(m) / c), float64, eqs. (7)-(8)."""
    f = geo.carrier_hz + np.arange(num.num_subcarriers) * num.subcarrier_spacing_hz
    out = np.zeros((len(ms), num.num_subcarriers), dtype=np.complex128)
    for i, m in enumerate(ms):
        yp = geo.track_start_m + geo.velocity_mps * m * tsym(num)
        R = np.sqrt(xs**2 + geo.height_m**2 + (yp - ys) ** 2)
        g = np.ones_like(R) if gain is None else gain(ys - yp, R, xs)
        cyc = np.outer(2.0 * R, f) / C
        cyc -= np.floor(cyc)
        out[i] = (amps * g) @ np.exp(-2j * np.pi * cyc)
    return out


def err_db(got, ref):
    return 10 * np.log10(np.sum(np.abs(got - ref) ** 2) / np.sum(np.abs(ref) ** 2))


def run_block(blk, num, s):
    """s: (M, N) complex64 -> (echo, reference) as (M, N) arrays."""
    tb = gr.top_block()
    N = num.num_subcarriers
    src = blocks.vector_source_c(s.ravel().tolist(), False, N)
    e = blocks.vector_sink_c(N)
    r = blocks.vector_sink_c(N)
    tb.connect(src, blk)
    tb.connect((blk, 0), e)
    tb.connect((blk, 1), r)
    tb.run()
    M = s.shape[0]
    return (np.array(e.data()).reshape(M, N), np.array(r.data()).reshape(M, N), e.tags())


class qa_extended_scene_echo(gr_unittest.TestCase):

    def setUp(self):
        self.num = nrsar.make_numerology("tiny")
        self.geo = nrsar.make_geometry("paper")
        rng = np.random.default_rng(11)
        self.vals = (rng.normal(size=(10, 12)) + 1j * rng.normal(size=(10, 12))).astype(np.complex64)
        self.vals[3, 4] = 0
        self.map = nrsar.make_map(self.vals, 0.8, 1.2, 295.0, 92.0, kind="amplitude")
        self.points = nrsar.make_scene([(250.0, 100.0, 2.0)])

    def scatterers(self):
        yy, xx = np.mgrid[0:10, 0:12]
        xs = np.concatenate([295.0 + 0.8 * xx.ravel(), [250.0]])
        ys = np.concatenate([92.0 + 1.2 * yy.ravel(), [100.0]])
        a = np.concatenate([self.vals.ravel().astype(np.complex128), [math.sqrt(2.0)]])
        return xs, ys, a

    def test_fast_matches_float64_sum(self):
        M, N = 5, self.num.num_subcarriers
        rng = np.random.default_rng(3)
        s = (rng.choice([-1, 1], (M, N)) + 1j * rng.choice([-1, 1], (M, N))).astype(np.complex64) / np.sqrt(2)
        blk = nrsar.extended_scene_echo(self.num, self.geo, self.points, [self.map])
        self.assertEqual(blk.num_scatterers(), 12 * 10 - 1 + 1)
        self.assertAlmostEqual(blk.total_power(), float(np.sum(np.abs(self.vals) ** 2)) + 2.0, places=3)
        y, h, _ = run_block(blk, self.num, s)
        ref = exact_h(self.num, self.geo, *self.scatterers(), range(M))
        self.assertLess(err_db(h, ref), -50.0)  # default kernel L = 8, O = 2
        self.assertLess(err_db(y, s * ref), -50.0)
        # a shorter kernel with less oversampling: larger error (run-time knobs)
        k = nrsar.extended_scene_kernel(self.num, self.geo, self.points, [self.map], taps=4,
                                        oversampling=1.5)
        e4 = err_db(np.array([k.reference(m) for m in range(M)]), ref)
        self.assertGreater(e4, err_db(h, ref) + 10)
        self.assertLess(e4, -30.0)

    def test_agrees_with_scene_echo(self):
        # The paper3 targets as three pixels of a sparse map (the rest zero): the same echo as
        # scene_echo's independent per-target recurrence.
        vals = np.zeros((41, 51), dtype=np.complex64)
        vals[0, 50] = vals[0, 0] = vals[40, 50] = 1.0  # (300,100), (250,100), (300,140)
        mp = nrsar.make_map(vals, 1.0, 1.0, 250.0, 100.0, kind="amplitude")
        num = nrsar.make_numerology("small")
        ext = nrsar.extended_scene_echo(num, self.geo, nrsar.scene(), [mp])
        pts = nrsar.scene_echo(num, self.geo, nrsar.make_scene("paper3"))
        self.assertEqual(ext.num_scatterers(), 3)
        s = np.ones((4, num.num_subcarriers), dtype=np.complex64)
        _, h1, _ = run_block(ext, num, s)
        _, h2, _ = run_block(pts, num, s)
        self.assertLess(err_db(h1, h2), -100.0)

    def test_paper_numerology_and_late_symbol(self):
        num = nrsar.make_numerology("paper")
        k = nrsar.extended_scene_kernel(num, self.geo, self.points, [self.map])
        for m in (0, 31000):
            ref = exact_h(num, self.geo, *self.scatterers(), [m])[0]
            self.assertLess(err_db(k.reference(m), ref), -50.0)

    def test_speckle_seeded(self):
        power = np.full((64, 64), 2.0)
        a = nrsar.make_map(power, 1.0, 1.0, 280.0, 70.0, speckle=True, seed=5)
        b = nrsar.make_map(power, 1.0, 1.0, 280.0, 70.0, speckle=True, seed=5)
        c = nrsar.make_map(power, 1.0, 1.0, 280.0, 70.0, speckle=True, seed=6)
        amp = [nrsar.extended_scene_kernel(self.num, self.geo, nrsar.scene(), [mp]).scatterers()[2]
               for mp in (a, b, c)]
        np.testing.assert_array_equal(amp[0], amp[1])
        self.assertGreater(np.mean(np.abs(amp[0] - amp[2]) ** 2), 1.0)
        p = np.abs(amp[0]) ** 2
        # E|a|^2 = RCS (4096 exponential samples: 3 % standard error); |a|^2 / RCS ~ Exp(1)
        self.assertLess(abs(np.mean(p) / 2.0 - 1.0), 0.1)
        self.assertLess(abs(np.mean(p > 2.0) - math.exp(-1.0)), 0.03)
        # the phase is uniform: the mean amplitude is near 0
        self.assertLess(abs(np.mean(amp[0])), 0.1)

    def test_azimuth_beam_nulls_of_eq1(self):
        # D_a = 1 m: nulls of the two-way sinc^2 at sin(psi) = k lambda / D_a.
        beam = nrsar.make_beam("azimuth", az_aperture_m=1.0)
        lam = self.geo.wavelength_m()
        x = 300.0
        R0 = math.hypot(x, self.geo.height_m)
        s1 = lam / 1.0
        dy1 = R0 * s1 / math.sqrt(1 - s1 * s1)  # first null at m = 0
        s2 = 2 * lam / 1.0
        dy2 = R0 * s2 / math.sqrt(1 - s2 * s2)  # second null
        ys = np.array([0.0, dy1, dy2, 0.5 * dy1])
        for y, want in zip(ys, [1.0, 0.0, 0.0, None]):
            pts = nrsar.make_scene([(x, y, 1.0)])
            k = nrsar.extended_scene_kernel(self.num, self.geo, pts, [], beam)
            h = k.reference(0)
            R = math.hypot(R0, y)
            u = 1.0 * y / (R * lam)
            g = np.sinc(u) ** 2  # numpy's sinc is sin(pi u) / (pi u)
            if want is not None:
                self.assertAlmostEqual(g, want, places=9)
            self.assertAlmostEqual(float(np.mean(np.abs(h))), g, places=4)
        # whole-block illumination keeps the null target at full amplitude
        k = nrsar.extended_scene_kernel(self.num, self.geo, nrsar.make_scene([(x, dy1, 1.0)]), [])
        self.assertAlmostEqual(float(np.mean(np.abs(k.reference(0)))), 1.0, places=4)
        # eq. (1) beam width and eq. (2) coverage at the paper's D_a = 0.1 m, theta_c = 45 deg
        pb = nrsar.make_beam("azimuth")
        th = 0.886 * lam / 0.1
        self.assertAlmostEqual(pb.azimuth_beamwidth_rad(self.geo), th, places=12)
        self.assertAlmostEqual(pb.azimuth_coverage_m(self.geo),
                               2 * 1000.0 / math.cos(math.pi / 4) * math.tan(th / 2), places=6)

    def test_azimuth_beam_over_aperture(self):
        # A target swept through the beam: the reference follows sinc^2 over the symbols.
        beam = nrsar.make_beam("azimuth", az_aperture_m=4.0, cutoff=3.0)
        geo = nrsar.make_geometry("paper", track_start_m=-60.0)
        pts = nrsar.make_scene([(300.0, 0.0, 1.0)])
        blk = nrsar.extended_scene_echo(self.num, geo, pts, [], beam)
        M = 60
        ms = np.arange(M) * 40  # every 40th symbol: feed ones, keep the reference
        s = np.ones((ms[-1] + 1, self.num.num_subcarriers), dtype=np.complex64)
        _, h, _ = run_block(blk, self.num, s)
        lam = geo.wavelength_m()
        def gain(dy, R, xs):
            u = 4.0 * dy / (R * lam)
            return np.where(np.abs(u) > 3.0, 0.0, np.sinc(u) ** 2)
        ref = exact_h(self.num, geo, np.array([300.0]), np.array([0.0]), np.array([1.0 + 0j]), ms, gain)
        self.assertLess(err_db(h[ms], ref), -50.0)

    def test_elevation_coverage_eq3(self):
        beam = nrsar.make_beam("azimuth_elevation", el_aperture_m=0.5, el_center_deg=16.7)
        lam = self.geo.wavelength_m()
        H = self.geo.height_m
        on = H * math.tan(math.radians(16.7))
        # first elevation null: sin(look - theta_c) = lambda / D_e
        null = H * math.tan(math.radians(16.7) + math.asin(lam / 0.5))
        self.assertAlmostEqual(beam.elevation_gain(self.geo, on), 1.0, places=12)
        self.assertAlmostEqual(beam.elevation_gain(self.geo, null), 0.0, places=12)
        k = nrsar.extended_scene_kernel(self.num, self.geo, nrsar.make_scene([(null, 0, 1)]), [], beam)
        self.assertLess(float(np.max(np.abs(k.reference(0)))), 1e-6)  # the null: no echo
        # beyond the cutoff (|u_el| > 2 here): the scatterer is dropped, it costs nothing
        beam.cutoff = 2.0
        far = H * math.tan(math.radians(16.7) + math.asin(2.5 * lam / 0.5))
        k = nrsar.extended_scene_kernel(self.num, self.geo, nrsar.make_scene([(far, 0, 1), (on, 0, 1)]),
                                        [], beam)
        self.assertEqual(k.num_scatterers(), 1)
        th = 0.886 * lam / 0.5
        t = math.radians(16.7)
        self.assertAlmostEqual(beam.elevation_coverage_m(self.geo),
                               H * (math.tan(t + th / 2) - math.tan(t - th / 2)), places=6)

    def test_noise_variance(self):
        blk = nrsar.extended_scene_echo(self.num, self.geo, self.points, [self.map], snr_db=10.0)
        want = (float(np.sum(np.abs(self.vals) ** 2)) + 2.0) / 10.0
        self.assertAlmostEqual(blk.noise_variance() / want, 1.0, places=5)
        s = np.zeros((200, self.num.num_subcarriers), dtype=np.complex64)
        y, _, _ = run_block(blk, self.num, s)
        self.assertLess(abs(np.mean(np.abs(y) ** 2) / want - 1.0), 0.05)

    def test_nonfinite_input(self):
        blk = nrsar.extended_scene_echo(self.num, self.geo, self.points, [self.map])
        s = np.ones((3, self.num.num_subcarriers), dtype=np.complex64)
        s[1, 5] = np.nan
        y, h, tags = run_block(blk, self.num, s)
        self.assertEqual(blk.nonfinite_count(), 1)
        self.assertEqual(y[1, 5], 0)
        self.assertTrue(any(pmt.symbol_to_string(t.key) == nrsar.tag_keys.nonfinite and t.offset == 1 for t in tags))

    def test_invalid_parameters(self):
        cases = [
            (dict(taps=7), "taps"),
            (dict(taps=40), "taps"),
            (dict(oversampling=1.0), "oversampling"),
            (dict(snr_db=float("nan")), "snr_db"),
        ]
        for kw, name in cases:
            with self.assertRaisesRegex(ValueError, name):
                nrsar.extended_scene_echo(self.num, self.geo, self.points, [self.map], **kw)
        with self.assertRaisesRegex(ValueError, "map.dx"):
            nrsar.make_map(np.ones((2, 2)), 0.0, 1.0)
        with self.assertRaisesRegex(ValueError, "power"):
            nrsar.make_map(-np.ones((2, 2)), 1.0, 1.0)
        with self.assertRaisesRegex(ValueError, "beam.az_aperture_m"):
            nrsar.make_beam("azimuth", az_aperture_m=-1.0)
        with self.assertRaisesRegex(ValueError, "mode"):
            nrsar.make_beam("sideways")
        bad = nrsar.reflectivity_map()
        bad.nx, bad.ny = 3, 3
        bad.values = np.ones(4, dtype=np.complex64)
        with self.assertRaisesRegex(ValueError, "map.values.size"):
            nrsar.extended_scene_echo(self.num, self.geo, self.points, [bad])
        # a map beyond the cyclic prefix: check_scenario refuses it
        far = nrsar.make_map(np.ones((2, 2)), 1.0, 1.0, 3000.0, 0.0)
        with self.assertRaises(ValueError):
            nrsar.extended_scene_echo(self.num, self.geo, nrsar.scene(), [far])


class qa_scene_files(gr_unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp()
        np.save(os.path.join(self.dir, "m.npy"), np.full((4, 5), 0.5, dtype=np.float32))

    def write(self, text):
        p = os.path.join(self.dir, "s.yaml")
        with open(p, "w") as f:
            f.write(text)
        return p

    def example_dir(self):
        for d in (os.path.join(HERE, "..", "..", "..", "examples", "scenes"),
                  os.path.join(HERE, "..", "..", "..", "..", "examples", "scenes")):
            if os.path.isdir(d):
                return d
        self.skipTest("examples/scenes not found")

    def test_good_file(self):
        p = self.write("geometry: {preset: paper, track_start_m: -10}\n"
                       "beam: {mode: azimuth, az_aperture_m: 0.2}\n"
                       "targets:\n  - {x: 300, y: 100, rcs: 2, phase_deg: 90}\n"
                       "maps:\n  - {file: m.npy, dx: 0.5, dy: 2, origin: [290, 95], scale: 2,"
                       " speckle: true, seed: 3}\n")
        sf = nrsar.load_scene_file(p)
        self.assertEqual(sf.geometry.track_start_m, -10.0)
        self.assertEqual(sf.beam.mode, nrsar.beam_mode.AZIMUTH)
        self.assertEqual(sf.beam.az_aperture_m, 0.2)
        t = sf.points.targets[0]
        self.assertEqual((t.x_m, t.y_m, t.rcs), (300.0, 100.0, 2.0))
        self.assertAlmostEqual(t.phase_rad, math.pi / 2)
        m = sf.maps[0]
        self.assertEqual((m.nx, m.ny, m.dx, m.dy, m.x0, m.y0), (5, 4, 0.5, 2.0, 290.0, 95.0))
        np.testing.assert_allclose(np.abs(m.values), 1.0, rtol=1e-6)  # sqrt(0.5 * 2)
        self.assertTrue(m.speckle)
        self.assertEqual(m.speckle_seed, 3)

    def test_pgm_map(self):
        with open(os.path.join(self.dir, "m.pgm"), "wb") as f:
            f.write(b"P5\n# c\n3 2\n255\n" + bytes([0, 10, 20, 30, 40, 255]))
        sf = nrsar.load_scene_file(self.write("maps:\n  - {file: m.pgm, dx: 1, dy: 1}\n"))
        np.testing.assert_allclose(np.abs(sf.maps[0].values) ** 2,
                                   [[0, 10, 20], [30, 40, 255]], rtol=1e-5)

    def test_broken_files(self):
        cases = [
            ("targets:\n  - {x: 300, y: abc}\n", ":2:", "targets[0].y"),
            ("targets:\n  - {x: 300}\n", ":2:", "targets[0].y"),
            ("targets:\n  - {x: 300, y: 1, rcs: -1}\n", ":2:", "targets[0].rcs"),
            ("targets:\n  - {x: 300, y: 1, colour: red}\n", ":2:", "targets[0].colour"),
            ("maps:\n  - file: nope.npy\n    dx: 1\n    dy: 1\n", ":2:", "maps[0].file"),
            ("maps:\n  - file: m.npy\n    dx: 1\n    dy: -1\n", ":4:", "maps[0].dy"),
            ("maps:\n  - file: m.npy\n    dx: 1\n    dy: 1\n    origin: [1]\n", ":5:", "maps[0].origin"),
            ("beam:\n  mode: sideways\n", ":2:", "beam.mode"),
            ("geometry:\n  preset: paper\n  height_m: -5\n", ":", "geometry"),
            ("geometry: {preset: nowhere}\ntargets: [{x: 1, y: 1}]\n", ":1:", "geometry"),
            ("targets: [{x: 1, y: 1}\n", ":", "YAML syntax"),
            ("wind: 3\n", ":1:", "scene.wind"),
            ("beam: {mode: azimuth}\n", ":1:", "at least one target or map"),
        ]
        for text, line, name in cases:
            with self.assertRaises(nrsar.SceneFileError, msg=text) as cm:
                nrsar.load_scene_file(self.write(text))
            self.assertIn(line, str(cm.exception), text)
            self.assertIn(name, str(cm.exception), text)

    def test_example_file(self):
        d = self.example_dir()
        sf = nrsar.load_scene_file(os.path.join(d, "ship_and_sea.yaml"))
        self.assertGreater(len(sf.maps), 0)
        num = nrsar.make_numerology("small")
        geo = sf.geometry or nrsar.make_geometry("paper")
        blk = nrsar.extended_scene_echo(num, geo, sf.points, sf.maps, sf.beam or nrsar.antenna_beam())
        self.assertGreater(blk.num_scatterers(), 1000)

    def test_sim_accepts_scene_file(self):
        from gnuradio.nrsar import chain
        from gnuradio.nrsar.options import SimOptions
        d = self.example_dir()
        args = SimOptions.parse(
            ["--scene", os.path.join(d, "ship_and_sea.yaml"), "--preset", "small",
             "--aperture-s", "0.25", "--snr-db", "30", "--out", self.dir])
        res = chain.simulate(args)
        img = np.load(res["image_npy"])
        self.assertTrue(np.all(np.isfinite(img)))
        # the map and the reference target are in the image: energy well above the empty rim
        p = np.abs(img) ** 2
        self.assertGreater(p.max(), 1e3 * np.median(p))
        self.assertEqual(res["nonfinite"], 0)


if __name__ == "__main__":
    gr_unittest.run(qa_extended_scene_echo)  # runs every TestCase of the module
