#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of the flight contracts of the programs (issue #14): --trajectory / --motion /
--motion-seed / --nav / --nav-error checked before any work (OptionError naming the flag, the
value and the limit; the app exits 2 with one line), Scenario.trajectory (the truth, flown by
the echo) and Scenario.navigation (what the processing uses), the JSON keys
trajectory_rms_dev_m and nav_rms_err_m, and the end-to-end check of docs/flight.md: a gusty
flight imaged by back-projection along the (perfect) navigation focuses, rd_focuser without
motion compensation defocuses."""

import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
from gnuradio import gr_unittest

from gnuradio.nrsar import chain, isac_chain, scenario
from gnuradio.nrsar.options import IsacOptions, OptionError, SimOptions

APPS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps")


def parse(argv):
    return SimOptions.parse(argv)


def write_path_csv(path, x_offset=0.0, span_s=0.3, height=1000.0):
    """A straight 50 m/s line at 50 Hz over [0, span_s], x_offset across track."""
    with open(path, "w") as f:
        f.write("t_s,x_m,y_m,z_m\n")
        for i in range(int(round(span_s * 50)) + 1):
            t = i / 50.0
            f.write(f"{t!r},{x_offset!r},{50.0 * t!r},{height!r}\n")


def write_sway_csv(path, height=1000.0):
    """A 50 m/s line swaying 1.6 m across track and 0.6 m vertically within its first second
    (a period of 1 s), at 1 kHz over [0, 1.2] s. Returns (t, dx, dz)."""
    t = np.arange(1201) / 1000.0
    dx, dz = -0.8 + 0.8 * np.sin(2 * np.pi * t), 0.3 * np.sin(2 * np.pi * t)
    with open(path, "w") as f:
        f.write("t_s,x_m,y_m,z_m\n")
        for row in zip(t, dx, 50.0 * t, height + dz):
            f.write(",".join(repr(float(v)) for v in row) + "\n")
    return t, dx, dz


class qa_flight(gr_unittest.TestCase):

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.out = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def csv(self, name, **kwargs):
        path = os.path.join(self.out, name)
        write_path_csv(path, **kwargs)
        return path

    def test_flags_are_checked_before_work(self):
        cases = [
            (dict(motion="wild"), "--motion = 'wild' must be one of none, calm, gusty"),
            (dict(nav_error="dgps"), "--nav-error = 'dgps' must be one of none, rtk, gnss"),
            (dict(motion_seed=-1), "--motion-seed = -1 must be at least 0"),
            (dict(trajectory=os.path.join(self.out, "missing.csv")), "is not a readable file"),
            (dict(trajectory=self.csv("a.csv"), motion="gusty"), "both name the path"),
            (dict(nav=self.csv("b.csv"), nav_error="rtk"), "both name the path"),
        ]
        for fields, text in cases:
            with self.assertRaises(OptionError) as ctx:
                SimOptions(**fields).validate()
            self.assertIn(text, str(ctx.exception), fields)

    def test_path_contents_are_checked_with_the_flag(self):
        base = ["--preset", "tiny", "--aperture-s", "0.2", "--out", self.out]
        # too short for the aperture (0.1 s of samples)
        opts = parse(base + ["--trajectory", self.csv("ok.csv")])
        self.assertFalse(scenario.of(opts).trajectory.is_ideal())
        short = self.csv("short2.csv", span_s=0.1)
        with self.assertRaisesRegex(OptionError, r"^--trajectory = .*short2.csv.*too short"):
            scenario.of(opts.replace(trajectory=short))
        # 260 m across track: T2 of paper3 (x = 250 m) is behind the antenna
        side = self.csv("side.csv", x_offset=260.0)
        with self.assertRaisesRegex(OptionError, r"^--trajectory = .*target 1 .*behind"):
            scenario.of(opts.replace(trajectory=side))
        with self.assertRaisesRegex(OptionError, r"^--nav = .*too short"):
            scenario.of(opts.replace(trajectory=None, nav=short))
        # the app: exit 2, one line, no traceback
        proc = subprocess.run([sys.executable, os.path.join(APPS, "nrsar-sim")] + base +
                              ["--trajectory", side], capture_output=True, text=True,
                              timeout=120)
        self.assertEqual(proc.returncode, 2, proc.stderr)
        self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
        self.assertIn("--trajectory", proc.stderr)
        self.assertNotIn("Traceback", proc.stderr)

    def test_scenario_names_the_truth_and_the_navigation(self):
        base = ["--preset", "tiny", "--aperture-s", "0.2"]
        sc = scenario.of(parse(base))
        self.assertTrue(sc.trajectory.is_ideal() and sc.navigation.is_ideal())
        sc = scenario.of(parse(base + ["--motion", "gusty", "--motion-seed", "5"]))
        self.assertFalse(sc.trajectory.is_ideal())
        p0 = np.array(sc.trajectory.position(0.1))
        self.assertEqual(list(sc.navigation.position(0.1)), list(p0))  # perfect navigation
        again = scenario.of(parse(base + ["--motion", "gusty", "--motion-seed", "5"]))
        self.assertEqual(list(again.trajectory.position(0.1)), list(p0))  # seeded
        other = scenario.of(parse(base + ["--motion", "gusty", "--motion-seed", "6"]))
        self.assertNotEqual(list(other.trajectory.position(0.1)), list(p0))
        sc = scenario.of(parse(base + ["--motion", "gusty", "--nav-error", "gnss"]))
        d = np.array(sc.navigation.position(0.1)) - np.array(sc.trajectory.position(0.1))
        self.assertGreater(np.linalg.norm(d), 1e-3)
        # a CSV file is the truth, a second one the navigation
        sc = scenario.of(parse(base + ["--trajectory", self.csv("t.csv", x_offset=0.2),
                                       "--nav", self.csv("n.csv", x_offset=0.1)]))
        self.assertAlmostEqual(sc.trajectory.position(0.05)[0], 0.2, places=12)
        self.assertAlmostEqual(sc.navigation.position(0.05)[0], 0.1, places=12)

    def test_gusty_flight_bp_and_rd_with_moco_focus_rd_without_defocuses(self):
        # docs/flight.md and the evidence: a gusty flight, presummed, perfect
        # navigation. BP along the navigation and rd_focuser with its motion compensation
        # (--moco on, the default) focus the target within a quarter range bin and come back
        # to within 0.5 dB NMSE of the ideal flight; rd_focuser without it (--moco off)
        # defocuses. The chain's reference branch images the same flight along the truth, so
        # every image is also held against the ideal flight's reference image: PEL_ideal =
        # -20 log10 |<ref_ideal, img> / <ref_ideal, ref_ideal>| (SPEC 8's calibration factor
        # against the ideal flight).
        common = ["--preset", "small", "--aperture-s", "0.2", "--target", "600,5",
                  "--snr-db", "10", "--presum", "cheby", "--decim", "4"]
        cases = {"bp": ["--focuser", "bp"], "rd": ["--focuser", "rd"],
                 "rd-nomoco": ["--focuser", "rd", "--moco", "off"]}
        runs = {}
        for name, flags in cases.items():
            for motion in ("none", "gusty"):
                opts = parse(common + flags + ["--motion", motion, "--out",
                                               os.path.join(self.out, name + motion)])
                r, g = chain.simulate_graph(opts, keep_reference=True)
                ref = np.array(g["reference_sink"].data()).reshape(-1, r["range_bins"])
                runs[name, motion] = (r, np.load(r["image_npy"]), ref)
        sc = scenario.of(parse(common + ["--motion", "gusty"]))
        for name in cases:
            ideal, img_i, ref_i = runs[name, "none"]
            gusty, img_g, _ = runs[name, "gusty"]
            self.assertEqual(ideal["trajectory_rms_dev_m"], 0.0)
            self.assertEqual(ideal["nav_rms_err_m"], 0.0)
            self.assertAlmostEqual(gusty["trajectory_rms_dev_m"],
                                   sc.trajectory.rms_deviation_m(0.0, 0.2), places=12)
            self.assertEqual(gusty["nav_rms_err_m"], 0.0)
            pel = {m: -20 * math.log10(abs(np.vdot(ref_i, img) / np.vdot(ref_i, ref_i)))
                   for m, img in (("none", img_i), ("gusty", img_g))}
            print(f"{name}: rms deviation {gusty['trajectory_rms_dev_m'] * 100:.2f} cm; ideal "
                  f"flight PEL {ideal['pel_db']:.2f} dB NMSE {ideal['nmse_db']:.2f} dB peak error "
                  f"{ideal['peak_error_m']:.3f} m IRW az {ideal['irw_azimuth_m']}; gusty PEL "
                  f"{gusty['pel_db']:.2f} dB NMSE {gusty['nmse_db']:.2f} dB peak error "
                  f"{gusty['peak_error_m']:.3f} m IRW az {gusty['irw_azimuth_m']}; against the "
                  f"ideal flight's reference: PEL {pel['none']:.2f} -> {pel['gusty']:.2f} dB")
            runs[name] = (ideal, gusty, pel)
        for name in ("bp", "rd"):
            ideal, gusty, pel = runs[name]
            self.assertEqual(gusty["moco"], "on")
            self.assertLess(gusty["peak_error_m"], 0.25 * gusty["range_axis_m"][1])
            self.assertLess(abs(gusty["nmse_db"] - ideal["nmse_db"]), 0.5)
            self.assertLess(abs(pel["gusty"] - pel["none"]), 0.5)
        ideal, gusty, pel = runs["rd-nomoco"]
        self.assertGreater(pel["gusty"], pel["none"] + 3.0)  # defocused: the peak energy goes

    def test_large_sway_spreads_the_range_spectrum_beyond_a_critical_grid(self):
        # docs/flight.md (ALFA): a sway that turns the line of sight changes each pulse's
        # range wavenumber on the ideal line's slant grid, s(t) = fc (dr/dR0 - dr_ideal/dR0)
        # at the target, so the image's range spectrum is the band B spread by s's range.
        # Beyond a critically sampled grid's headroom (--fft-size = subcarriers) the range cut
        # aliases and its peak and IRW err by metres; on a 2x grid rd_focuser with MoCo puts
        # the peak at the target and the range IRW at the float64 expectation of the spread
        # band, |D(d) mean_t exp(j 4 pi s(t) d / c)| (D: the band's Dirichlet kernel).
        c, fc, h, df, n_sub, x_t, y_t = 299792458.0, 3.5e9, 1000.0, 30e3, 512, 600.0, 25.0
        path = os.path.join(self.out, "sway.csv")
        t, dx, dz = write_sway_csv(path, h)  # 1.6 m cross-track, 0.6 m vertical in 1 s
        ts = t[:1001:10]  # the aperture, 10 ms steps
        x, y, z = dx[:1001:10], 50.0 * ts, h + dz[:1001:10]
        r0 = math.hypot(x_t, h)
        r = np.sqrt((x - x_t) ** 2 + (y - y_t) ** 2 + z * z)
        r_ideal = np.sqrt(x_t * x_t + (y - y_t) ** 2 + h * h)
        s = fc * ((x_t - x) / r - x_t / r_ideal) * r0 / x_t  # d r / d R0 = (g - x) / r dg/dR0
        spread = (s.max() - s.min()) / (n_sub * df)
        d = np.arange(-1200, 1201) * 0.005  # slant offset [m]
        u = 2 * np.pi * df * 2 * d / c
        dirichlet = np.sin(n_sub * u / 2) / np.where(u == 0, 1.0, np.sin(u / 2))
        dirichlet[u == 0] = n_sub
        cut = np.abs(dirichlet * np.exp(4j * np.pi * np.outer(d, s) / c).mean(1)) ** 2
        above = d[cut >= 0.5 * cut.max()]
        irw = above.max() - above.min()
        common = ["--preset", "small", "--aperture-s", "1", "--target", f"{x_t:g},{y_t:g}",
                  "--snr-db", "10", "--presum", "cheby", "--decim", "4", "--focuser", "rd"]
        runs = {}
        for fft in ("512", "1024"):
            for name, flags in (("ideal", ["--motion", "none"]), ("sway", ["--trajectory", path])):
                opts = parse(common + flags + ["--fft-size", fft,
                                               "--out", os.path.join(self.out, name + fft)])
                runs[name, fft] = chain.simulate_graph(opts)[0]
        print(f"spread {spread:.3f} B, expected range IRW {irw:.3f} m; " + "; ".join(
            f"{n} {f}: peak error {r['peak_error_m']:.3f} m IRW {r['irw_range_m']:.3f} m"
            for (n, f), r in runs.items()))
        self.assertGreater(spread, 0.25)  # the ALFA window's 0.37 B regime ...
        self.assertLess(spread, 1.0)  # ... within a 2x grid's headroom
        self.assertEqual(runs["sway", "1024"]["moco"], "on")
        self.assertLess(runs["sway", "1024"]["peak_error_m"], 0.1)  # 1 % of the resolution
        self.assertAlmostEqual(runs["sway", "1024"]["irw_range_m"] / irw, 1.0, delta=0.01)
        # the critical grid: the ideal flight's peak is right, the sway's aliases
        self.assertLess(runs["ideal", "512"]["peak_error_m"], 0.1)
        self.assertGreater(runs["sway", "512"]["peak_error_m"],
                           0.25 * runs["sway", "512"]["range_axis_m"][1])

    def test_range_grid_headroom_check_warns_before_the_run(self):
        # scenario.of warns (the JSON's warnings) when the navigation's sway spreads the range
        # spectrum beyond the range grid's headroom (fft_size - N) Delta f; built without a
        # graph. The test's own float64 s(t): dr/dR0 by a central difference in R0 (the
        # target moved along the ground), on the CSV's analytic path, the aperture's 1 ms grid.
        mhz, fc, h, df, n_sub = 1e6, 3.5e9, 1000.0, 30e3, 512
        path = os.path.join(self.out, "sway.csv")
        t, dx, dz = write_sway_csv(path, h)  # the large-sway test's path
        x, y, z = dx[:1001], 50.0 * t[:1001], h + dz[:1001]

        def r_of(r0, y_t, x0, z0):  # the range to the ground point of range r0 off the line
            return np.sqrt((x0 - math.sqrt(r0 * r0 - h * h)) ** 2 + (y - y_t) ** 2 + z0 * z0)
        spreads, e = {}, 1e-3
        for g, y_t in ((700.0, 25.0), (600.0, 25.0)):
            r0 = math.hypot(g, h)
            s = fc * ((r_of(r0 + e, y_t, x, z) - r_of(r0 - e, y_t, x, z))
                      - (r_of(r0 + e, y_t, 0.0, h) - r_of(r0 - e, y_t, 0.0, h))) / (2 * e)
            spreads[g] = s.max() - s.min()
        spread = max(spreads.values())

        def smooth(n):  # 2^a 3^b 5^c 7^d: the sizes --fft-size fast picks
            for p in (2, 3, 5, 7):
                while n % p == 0:
                    n //= p
            return n == 1
        fast = next(n for n in range(n_sub + math.ceil(spread / df), 4 * n_sub) if smooth(n))
        base = ["--preset", "small", "--aperture-s", "1", "--target", "700,25", "--target",
                "600,25"]
        warned = {}
        for fft in ("512", "1024"):
            for name, flags in (("ideal", ["--motion", "none"]), ("sway", ["--trajectory", path])):
                sc = scenario.of(parse(base + flags + ["--fft-size", fft]))
                warned[name, fft] = [w for w in sc.warnings if "range grid" in w]
        # gusty seed 0 at 600 m: 0.063 B of spread past the critical grid's zero headroom,
        # inside the 0.1 B tolerance (its peak moved 0.09 m): no warning
        sc = scenario.of(parse(["--preset", "small", "--aperture-s", "1", "--target", "600,25",
                                "--motion", "gusty", "--fft-size", "512"]))
        gusty = scenario.sway_spread_hz(sc)[0] / (n_sub * df)
        self.assertTrue(0.0 < gusty < scenario.RANGE_SPREAD_TOLERANCE_B, gusty)
        self.assertEqual([w for w in sc.warnings if "range grid" in w], [])
        print(f"spread {spread / mhz:.4f} MHz ({spread / (n_sub * df):.4f} B) at x = "
              f"{max(spreads, key=spreads.get):g} m; --fft-size {fast}; {warned['sway', '512']}")
        self.assertEqual(warned["ideal", "512"], [])
        self.assertEqual(warned["ideal", "1024"], [])
        self.assertEqual(warned["sway", "1024"], [])  # 15.36 MHz of headroom
        self.assertEqual(len(warned["sway", "512"]), 1)
        text = warned["sway", "512"][0]
        m = re.search(r"by ([\d.]+) MHz \(([\d.]+) B, B = ([\d.]+) MHz\).*x = (\d+) m.*"
                      r"headroom of ([\d.]+) MHz.*--fft-size (\d+) holds", text)
        self.assertIsNotNone(m, text)
        self.assertAlmostEqual(float(m[1]), spread / mhz, delta=6e-4)  # printed to 1 kHz
        self.assertAlmostEqual(float(m[2]), spread / (n_sub * df), delta=6e-4)
        self.assertEqual((float(m[3]), int(m[4]), float(m[5])), (15.36, 600, 0.0))
        self.assertEqual(int(m[6]), fast)
        self.assertGreater(spread, 0.5 * n_sub * df)  # qa's 0.55 B

    def test_isac_flies_the_path_through_the_time_domain(self):
        # nrsar-isac: td_echo flies the truth, the processing uses the navigation (rtk)
        payload = os.path.join(self.out, "payload.bin")
        with open(payload, "wb") as f:
            f.write(bytes(range(200)))
        r = isac_chain.run(IsacOptions.parse(
            ["--preset", "sdr20", "--aperture-s", "0.05", "--target", "300,1", "--payload",
             payload, "--motion", "gusty", "--nav-error", "rtk", "--focuser", "bp",
             "--out", os.path.join(self.out, "isac")]))
        sc = scenario.of(SimOptions.parse(["--preset", "sdr20", "--aperture-s", "0.05",
                                           "--motion", "gusty", "--nav-error", "rtk"]))
        t = np.linspace(0.0, 0.05, 1000)
        d = np.array(sc.navigation.positions(list(t))) - np.array(sc.trajectory.positions(list(t)))
        self.assertAlmostEqual(r["nav_rms_err_m"], float(np.sqrt(np.mean(np.sum(d * d, 1)))),
                               places=12)
        self.assertGreater(r["nav_rms_err_m"], 1e-3)  # centimetres (docs/flight.md)
        self.assertLess(r["nav_rms_err_m"], 0.2)
        self.assertGreater(r["trajectory_rms_dev_m"], 0.0)
        self.assertTrue(r["payload_identical"])


if __name__ == "__main__":
    gr_unittest.run(qa_flight)
