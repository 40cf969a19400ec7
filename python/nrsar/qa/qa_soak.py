#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-soak, short: 30 s of radar time (15 apertures of 2 s) on the `small` preset through
the whole chain; the resident set size must stay flat after the warm-up. (`make soak` runs
10 minutes at paper scale.)"""

import json
import os
import tempfile

import numpy as np
from gnuradio import gr_unittest

from gnuradio.nrsar import cli
from gnuradio.nrsar.bench import soak
from gnuradio.nrsar.options import SoakOptions


class qa_soak(gr_unittest.TestCase):

    def test_001_slope_fit_detects_a_leak(self):
        # synthetic RSS: 100 MiB + 3 MiB per radar minute + 0.2 MiB jitter, and a warm-up
        # ramp before 10 s that the fit must ignore
        rng = np.random.default_rng(3)
        t = np.linspace(0.0, 60.0, 61)
        rss = 100.0 + 3.0 * t / 60.0 + 0.2 * rng.standard_normal(t.size)
        rss[t < 10.0] -= 40.0
        slope, _ = soak.fit_slope(t, rss, 10.0)
        self.assertAlmostEqual(slope, 3.0, delta=0.3)
        flat, _ = soak.fit_slope(t, 100.0 + 0.0 * t, 10.0)
        self.assertAlmostEqual(flat, 0.0, delta=1e-9)
        self.assertTrue(np.isnan(soak.fit_slope(t[:2], rss[:2], 0.0)[0]))

    def test_002_short_soak_small_preset_is_flat(self):
        out = tempfile.mkdtemp(prefix="qa_soak_")
        code = cli.main("nrsar-soak", SoakOptions, soak.run, soak.__doc__,
                        ["--preset", "small", "--minutes", "0.5", "--interval-s", "0.5",
                         "--max-slope-mb-per-min", "6", "--json", "--out", out], soak.verdict)
        with open(os.path.join(out, "soak.json")) as f:
            r = json.load(f)
        self.assertEqual(r["apertures"], 15)
        self.assertAlmostEqual(r["radar_s"], 30.0, delta=1e-6)
        self.assertGreaterEqual(r["samples"], 5)
        # flat: bounded slope after the warm-up, and a small spread of the samples
        self.assertLessEqual(r["slope_mb_per_min"], 6.0)
        self.assertLess(r["rss_after_warmup_max_mb"] - r["rss_after_warmup_min_mb"], 8.0)
        self.assertEqual(code, 0)
        for name in ("soak.csv", "soak.png"):
            self.assertTrue(os.path.getsize(os.path.join(out, name)) > 0)
        data = np.loadtxt(os.path.join(out, "soak.csv"), delimiter=",", skiprows=1)
        self.assertTrue(np.all(np.diff(data[:, 1]) >= 0))  # radar time only advances
        self.assertAlmostEqual(data[-1, 1], 30.0, delta=1e-3)


if __name__ == "__main__":
    gr_unittest.run(qa_soak)
