#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The doors of the programs (docs/robustness.md, "Command line"): every bad or edge input a
new user might type gets exit code 2 and one line on stderr that names the flag, the value
and the limit, before any work starts (never a traceback, never a silent run); Ctrl-C stops
a run with exit code 130 and leaves no unfinished image behind.

The programs run as a user runs them: apps/<program> of this tree (or of NRSAR_APPS_DIR, e.g.
/usr/local/bin for the installed ones) with this interpreter."""

import os
import signal
import subprocess
import sys
import tempfile
import time

from gnuradio import gr_unittest

APPS = os.environ.get("NRSAR_APPS_DIR") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps")

# (program, flags, text the one-line message must contain). Each row breaks one rule of an
# otherwise valid command line; the expected text is the rule, written here, not read from
# the code.
BAD_INPUTS = [
    ("nrsar-sim", ["--decim", "0", "--presum", "cheby"], "--decim = 0 must be at least 1"),
    ("nrsar-sim", ["--decim", "-3"], "--decim = -3 must be at least 1"),
    ("nrsar-sim", ["--decim", "0"], "--decim = 0 must be at least 1"),
    ("nrsar-sim", ["--decim", "5"], "--decim = 5 needs a presummer"),
    ("nrsar-sim", ["--decim", "5000", "--presum", "cheby"], "--decim = 5000 must be at most"),
    ("nrsar-sim", ["--decim", "x"], "--decim: invalid int value"),
    ("nrsar-sim", ["--seed", "-1"], "--seed = -1 must be at least 0"),
    ("nrsar-sim", ["--seed", "2147483647"], "--seed = 2147483647 must be at most"),
    ("nrsar-sim", ["--range-margin-m", "-1"], "--range-margin-m = -1 must be at least 0"),
    ("nrsar-sim", ["--range-margin-m", "nan"], "--range-margin-m = nan must be finite"),
    ("nrsar-sim", ["--snr-db", "nan"], "--snr-db = nan must be finite"),
    ("nrsar-sim", ["--snr-db", "inf"], "--snr-db = inf must be finite"),
    ("nrsar-sim", ["--aperture-s", "0"], "--aperture-s = 0 must be above 0"),
    ("nrsar-sim", ["--aperture-s", "-2"], "--aperture-s = -2 must be above 0"),
    ("nrsar-sim", ["--aperture-s", "nan"], "--aperture-s = nan must be finite"),
    ("nrsar-sim", ["--rcmc-taps", "0"], "--rcmc-taps = 0 must be at least 2"),
    ("nrsar-sim", ["--autofocus-significance", "-1"],
     "--autofocus-significance = -1 must be at least 0"),
    ("nrsar-sim", ["--autofocus-tolerance-m", "0"], "--autofocus-tolerance-m = 0 must be above 0"),
    ("nrsar-sim", ["--autofocus-gcp-along-track-se-m", "2"],
     "--autofocus-gcp-along-track-se-m = 2 must be at most 1"),
    ("nrsar-sim", ["--autofocus-gcp-speed-se-mps", "-1"],
     "--autofocus-gcp-speed-se-mps = -1 must be at least 0"),
    ("nrsar-sim", ["--autofocus-points", "65"], "--autofocus-points = 65 must be at most 64"),
    ("nrsar-sim", ["--autofocus-iterations", "51"],
     "--autofocus-iterations = 51 must be at most 50"),
    ("nrsar-sim", ["--autofocus-gcp", "800,25"],
     "--autofocus-gcp = '800,25' needs --autofocus trajectory"),
    ("nrsar-sim", ["--autofocus", "trajectory", "--focuser", "bp", "--autofocus-gcp", "800"],
     "--autofocus-gcp = '800' must be X,Y[,Z] (2 or 3 numbers, got 1)"),
    ("nrsar-sim", ["--autofocus", "trajectory", "--focuser", "bp", "--autofocus-gcp",
                   "800,nan"], "--autofocus-gcp = '800,nan' must be finite"),
    ("nrsar-sim", ["--autofocus", "trajectory", "--focuser", "bp"] +
     ["--autofocus-gcp", "300,100"] * 17, "--autofocus-gcp given 17 times must be given at "
     "most 16 times"),
    ("nrsar-sim", ["--autofocus", "trajectory", "--focuser", "bp", "--preset", "small",
                   "--autofocus-gcp", "1e5,0"], "--autofocus-gcp = '1e5,0' lies outside the "
     "image: slant range 100005.0 m"),
    ("nrsar-sim", ["--autofocus", "trajectory", "--focuser", "bp", "--preset", "small",
                   "--autofocus-gcp", "600,1e4"], "--autofocus-gcp = '600,1e4' lies outside "
     "the image: along-track y 10000.0 m"),
    ("nrsar-sim", ["--filter-threads", "3"], "--filter-threads = 3 must be at most 2"),
    ("nrsar-sim", ["--filter", "zf"], "--filter: invalid choice: 'zf'"),
    ("nrsar-sim", ["--modulation", "qam1024"], "--modulation: invalid choice"),
    ("nrsar-sim", ["--mode", "srs40"], "--mode: invalid choice"),
    ("nrsar-sim", ["--band", "half"], "--band: invalid choice"),
    # tiny's 64 subcarriers cannot hold the SRS band's 24 RB x 12 = 288 (SPEC 2)
    ("nrsar-sim", ["--mode", "srs2"], "--mode = 'srs2' needs its SRS band's 288 subcarriers, "
     "more than the numerology's 64"),
    ("nrsar-sim", ["--presum", "sum"], "--presum: invalid choice"),
    ("nrsar-sim", ["--no-such-flag"], "unrecognized arguments: --no-such-flag"),
    ("nrsar-sim", ["--preset", "huge"], "--preset: invalid choice: 'huge'"),
    ("nrsar-sim", ["--geometry", "long"], "--geometry: invalid choice: 'long'"),
    ("nrsar-sim", ["--scene", "nosuchfile"], "--scene = 'nosuchfile' is no file that exists"),
    ("nrsar-sim", ["--scene", "no/such/scene.yaml"], "is no file that exists"),
    ("nrsar-sim", ["--scene", "300"], "--scene = '300': target 0 '300': has 1 field"),
    ("nrsar-sim", ["--target", "300,abc"], "--target = ['300,abc']: target 0 '300,abc': y_m"),
    ("nrsar-sim", ["--target", "300,nan"], "--target = ['300,nan']: target 0 y_m = nan"),
    ("nrsar-sim", ["--fft-size", "10"], "--fft-size = 10 must be at least the 64 subcarriers"),
    ("nrsar-sim", ["--fft-size", "0"], "--fft-size = 0 must be at least 1"),
    ("nrsar-sim", ["--fft-size", "big"], "--fft-size = 'big' must be 'fast', 'exact'"),
    ("nrsar-sim", ["--out", ""], "--out = '' must name a folder"),
    ("nrsar-sim", ["--preset", "nr273", "--aperture-s", "0.01"], "cyclic prefix too short"),
    ("nrsar-isac", ["--cfo-hz", "45000"], "--cfo-hz = 45000 must be below the subcarrier spacing"),
    ("nrsar-isac", ["--cfo-hz", "nan"], "--cfo-hz = nan must be finite"),
    ("nrsar-isac", ["--payload", "/nonexistent/payload.bin"], "--payload = '/nonexistent/payload.bin' is not a readable file"),
    ("nrsar-isac", ["--mode", "srs2"], "--mode = 'srs2' must be data"),
    ("nrsar-isac", ["--taps", "0,0"], "--taps = '0,0' must hold at least one finite non-zero tap"),
    ("nrsar-isac", ["--taps", "1,x"], "--taps = '1,x' must be comma-separated complex numbers"),
    ("nrsar-isac", ["--delay-samples", "-1"], "--delay-samples = -1 must be at least 0"),
    ("nrsar-isac", ["--bs-snr-db", "nan"], "--bs-snr-db = nan must be finite"),
    ("nrsar-isac", ["--dmrs", "pusch3"], "dmrs preset 'pusch3' is unknown"),
    ("nrsar-isac", ["--mcs", "28"], "--mcs = 28 must be at most 27 in --mcs-table qam256"),
    ("nrsar-isac", ["--mcs", "10"], "--mcs = 10 of --mcs-table qam256 has Qm = 4, --modulation qam256 has 8"),
    ("nrsar-isac", ["--coding", "none", "--mcs", "3"], "--mcs = 3 needs --coding nr-ldpc"),
    ("nrsar-isac", ["--n-id", "1024"], "--n-id = 1024 must be at most 1023"),
    ("nrsar-isac", ["--echo-taps", "0"], "--echo-taps = 0 must be at least 2"),
    ("nrsar-soak", ["--minutes", "-1"], "--minutes = -1 must be above 0"),
    ("nrsar-soak", ["--minutes", "0"], "--minutes = 0 must be above 0"),
    ("nrsar-soak", ["--minutes", "nan"], "--minutes = nan must be finite"),
    ("nrsar-soak", ["--interval-s", "0"], "--interval-s = 0 must be above 0"),
    ("nrsar-soak", ["--warmup", "1"], "--warmup = 1 must be below 1"),
    ("nrsar-soak", ["--images", "keep"], "--images = 'keep' must be none"),
    ("nrsar-soak", ["--max-slope-mb-per-min", "-1"], "--max-slope-mb-per-min = -1 must be at least 0"),
]

# The figure programs (nrsar-figures, and the studies run as python3 -m MODULE): each row
# one bad flag, refused before any figure runs.
BAD_FIGURE_INPUTS = [
    ("nrsar-figures", ["--seeds", "0"], "--seeds = 0 must be at least 1"),
    ("nrsar-figures", ["--only", "fig3,fig9"], "--only = 'fig3,fig9': 'fig9' is not one of"),
    ("nrsar-figures", ["--only", ","], "--only = ',' names nothing"),
    ("gnuradio.nrsar.figures.presum_compare", ["--decim", "1"], "--decim = 1 must be at least 2"),
    ("gnuradio.nrsar.figures.presum_compare", ["--only", "table8"], "'table8' is not one of"),
    ("gnuradio.nrsar.figures.presum_compare", ["--table6-decim", "1"],
     "--table6-decim = 1 must be at least 2"),
    ("gnuradio.nrsar.figures.presum_compare", ["--flights", "windy"], "'windy' must be MOTION"),
    ("gnuradio.nrsar.figures.presum_compare", ["--snr-db", "nan"], "--snr-db = nan must be finite"),
    ("gnuradio.nrsar.figures.presum_compare", ["--scene", "/no/scene.yaml"],
     "--scene = '/no/scene.yaml' is not a file"),
    ("gnuradio.nrsar.figures.presum_study", ["--preset", "huge"], "--preset: invalid choice"),
    ("gnuradio.nrsar.figures.presum_study", ["--decim", "5000"], "--decim = 5000 must be at most"),
    ("gnuradio.nrsar.figures.scrambler_ghosts", ["--slots", "2"], "--slots = 2 must be at least 4"),
    ("gnuradio.nrsar.figures.accuracy", ["--seeds", "-1"], "--seeds = -1 must be at least 1"),
    ("gnuradio.nrsar.figures.autofocus_study", ["--seeds", "0"], "--seeds = 0 must be at least 1"),
    ("gnuradio.nrsar.figures.nr_bler", ["--max-iter", "0"], "--max-iter = 0 must be at least 1"),
    ("gnuradio.nrsar.figures.nr_bler", ["--only", "qam64:99"], "'qam64:99' is not one of"),
]

# The small valid scenario each row breaks one rule of.
BASE = ["--preset", "tiny", "--aperture-s", "0.02"]


def run_app(program, flags, **kwargs):
    return subprocess.run([sys.executable, os.path.join(APPS, program)] + flags,
                          capture_output=True, text=True, timeout=300, **kwargs)


class qa_apps(gr_unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="qa_apps_")

    def assert_refused(self, program, flags, expected):
        proc = run_app(program, BASE + ["--out", os.path.join(self.dir, "out")] + flags)
        where = f"{program} {' '.join(flags)}"
        self.assertEqual(proc.returncode, 2, f"{where}: exit {proc.returncode}\n{proc.stderr}")
        self.assertNotIn("Traceback", proc.stderr, where)
        self.assertIn(expected, proc.stderr, where)
        self.assertEqual(proc.stdout, "", where)
        # the message is the last line; argparse's own errors add the usage before it
        last = proc.stderr.strip().splitlines()[-1]
        self.assertTrue(last.startswith(f"{program}: error: "), f"{where}: {last}")

    def test_001_every_bad_input_is_refused_with_its_flag(self):
        for program, flags, expected in BAD_INPUTS:
            with self.subTest(program=program, flags=flags):
                self.assert_refused(program, flags, expected)

    def test_001b_figure_programs_refuse_bad_flags(self):
        for program, flags, expected in BAD_FIGURE_INPUTS:
            with self.subTest(program=program, flags=flags):
                where = f"{program} {' '.join(flags)}"
                command = ([os.path.join(APPS, program)] if program.startswith("nrsar-")
                           else ["-m", program])
                out = [] if program.endswith(("scrambler_ghosts", "nr_bler")) else \
                    ["--out", os.path.join(self.dir, "figures")]  # they print their tables
                proc = subprocess.run([sys.executable] + command + flags + out,
                                      capture_output=True, text=True, timeout=300)
                self.assertEqual(proc.returncode, 2, f"{where}: exit {proc.returncode}\n"
                                 f"{proc.stderr}")
                self.assertNotIn("Traceback", proc.stderr, where)
                self.assertIn(expected, proc.stderr, where)
                self.assertEqual(proc.stdout, "", where)
                self.assertFalse(os.listdir(os.path.join(self.dir, "figures"))
                                 if os.path.isdir(os.path.join(self.dir, "figures")) else [],
                                 f"{where}: wrote something")

    def test_002_out_checked_before_the_run(self):
        # a file, a path under a file (refused for root too) and a place that cannot be
        # created: each refused at once, and nothing of the run is left anywhere
        plain = os.path.join(self.dir, "plain")
        with open(plain, "w") as f:
            f.write("x")
        for out, expected in ((plain, "is a file, not a folder"),
                              (os.path.join(plain, "sub"), "is not a writable folder"),
                              ("/proc/nrsar-out", "is not a writable folder")):
            with self.subTest(out=out):
                start = time.monotonic()
                proc = run_app("nrsar-sim", ["--preset", "small", "--out", out])
                self.assertEqual(proc.returncode, 2, proc.stderr)
                self.assertIn(f"--out = '{out}' {expected}", proc.stderr)
                self.assertNotIn("Traceback", proc.stderr)
                # refused before the 2 s paper aperture is simulated (that takes minutes)
                self.assertLess(time.monotonic() - start, 120)

    def test_003_ctrl_c_stops_cleanly_and_writes_no_image(self):
        out = os.path.join(self.dir, "interrupted")
        # 10 s of the small preset (240 000 symbols): tens of seconds of work
        proc = subprocess.Popen([sys.executable, os.path.join(APPS, "nrsar-sim"), "--preset",
                                 "small", "--aperture-s", "10", "--target", "300,250",
                                 "--images", "keep", "--out", out], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
        # the folder appears when the options have been checked; the run then takes minutes
        deadline = time.monotonic() + 120
        while not os.path.isdir(out) and time.monotonic() < deadline:
            time.sleep(0.2)
        time.sleep(3.0)
        proc.send_signal(signal.SIGINT)
        stdout, stderr = proc.communicate(timeout=120)
        self.assertEqual(proc.returncode, 130, stderr)
        self.assertNotIn("Traceback", stderr)
        self.assertEqual(stderr.strip().splitlines()[-1],
                         "nrsar-sim: interrupted: stopped before the end, no result written")
        self.assertEqual(stdout, "")
        self.assertEqual(os.listdir(out), [])

    def test_004_atomic_writer_leaves_complete_files_or_none(self):
        import numpy as np
        from gnuradio.nrsar import results
        path = os.path.join(self.dir, "image.npy")
        data = np.arange(1000, dtype=np.complex64)
        results.write_npy(path, data)
        np.testing.assert_array_equal(np.load(path), data)

        class Interrupt(BaseException):
            pass

        def interrupted_write(tmp):
            with open(tmp, "wb") as f:
                f.write(b"partial")
            raise Interrupt()

        # an interruption while writing keeps the old complete file and leaves no temporary
        with self.assertRaises(Interrupt):
            with results.atomic(path) as tmp:
                interrupted_write(tmp)
        np.testing.assert_array_equal(np.load(path), data)
        self.assertEqual(os.listdir(self.dir), ["image.npy"])


if __name__ == "__main__":
    gr_unittest.run(qa_apps)
