#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-sim end to end on a small scenario: files, axes and where the target lands."""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

from gnuradio import gr_unittest
from gnuradio.nrsar import sim

APP = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps",
                   "nrsar-sim")


def parse(argv):
    return sim.add_arguments(argparse.ArgumentParser()).parse_args(argv)


class qa_sim(gr_unittest.TestCase):

    def setUp(self):
        self.out = tempfile.mkdtemp(prefix="qa_sim_")

    def test_single_target_lands_at_its_slant_range(self):
        args = parse(["--preset", "small", "--aperture-s", "0.05", "--target", "300,100",
                      "--snr-db", "10", "--filter", "wf", "--out", self.out])
        result = sim.run(args)
        image = np.load(result["image_npy"])
        self.assertEqual(image.dtype, np.complex64)
        self.assertEqual(image.shape, (result["symbols"], result["range_bins"]))
        self.assertEqual(result["symbols"], round(0.05 / (1 / 30e3 + 128 / (512 * 30e3))))
        # Range axis: bins of c / (2 Nfft Delta f) (SPEC 5).
        first, step = result["range_axis_m"]
        self.assertAlmostEqual(step, 299792458.0 / (2 * result["range_fft_size"] * 30e3), 9)
        # Slant range of the target during the aperture, eq. (8), y_p from 0 to 2.5 m.
        r_mid = math.sqrt(300.0**2 + 1000.0**2 + (100.0 - 1.25)**2)
        self.assertLess(abs(result["brightest_range_m"] - r_mid), 0.5 * step + 1e-9)
        self.assertTrue(os.path.getsize(result["image_png"]) > 1000)
        self.assertEqual(result["nonfinite"], 0)

    def test_cli_prints_json_with_the_contract_keys(self):
        proc = subprocess.run(
            [sys.executable, APP, "--preset", "tiny", "--aperture-s", "0.01", "--scene", "paper3",
             "--snr-db", "0", "--json", "--out", self.out],
            capture_output=True, text=True, check=True)
        result = json.loads(proc.stdout.strip().splitlines()[-1])
        for key in ("runtime_s", "symbols", "subcarriers", "image_npy", "image_png",
                    "range_axis_m", "azimuth_axis_m"):
            self.assertIn(key, result)
        self.assertEqual(result["subcarriers"], 64)
        self.assertEqual(len(result["azimuth_axis_m"]), 2)

    def test_cli_reports_a_geometry_the_cp_cannot_hold(self):
        proc = subprocess.run(
            [sys.executable, APP, "--preset", "nr273", "--aperture-s", "0.01", "--out", self.out],
            capture_output=True, text=True)
        self.assertEqual(proc.returncode, 2)
        self.assertIn("cyclic prefix too short", proc.stderr)


if __name__ == '__main__':
    gr_unittest.run(qa_sim)
