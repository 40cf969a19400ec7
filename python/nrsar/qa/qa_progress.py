#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Progress output of the apps: stderr only, on with --progress or a terminal, off with --quiet;
stdout keeps one clean JSON object."""

import io
import json
import os
import subprocess
import sys
import tempfile

from gnuradio import gr_unittest
from gnuradio.nrsar import progress

APP = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps",
                   "nrsar-sim")


class _Tty(io.StringIO):
    def isatty(self):
        return True


class _Args:
    def __init__(self, progress=False, quiet=False):
        self.progress, self.quiet = progress, quiet


class qa_progress(gr_unittest.TestCase):

    def tearDown(self):
        progress.configure(False)

    def sim(self, *flags):
        out = tempfile.mkdtemp(prefix="qa_progress_")
        return subprocess.run(
            [sys.executable, APP, "--preset", "tiny", "--aperture-s", "0.01", "--target",
             "300,0", "--snr-db", "0", "--json", "--out", out] + list(flags),
            capture_output=True, text=True, check=True)

    def test_progress_goes_to_stderr_and_json_stays_clean(self):
        proc = self.sim("--progress")
        result = json.loads(proc.stdout)  # the whole of stdout is the one JSON object
        self.assertEqual(result["symbols"], 240)  # 0.01 s / 41.67 us
        self.assertIn("symbols [", proc.stderr)
        self.assertIn("100.0 %", proc.stderr)  # the filter's item counter reached M
        self.assertNotIn("%", proc.stdout)

    def test_quiet_wins(self):
        proc = self.sim("--progress", "--quiet")
        json.loads(proc.stdout)
        self.assertNotIn("%", proc.stderr)

    def test_enabled_only_on_a_terminal_unless_asked(self):
        self.assertTrue(progress.from_args(_Args(), stream=_Tty()))
        self.assertFalse(progress.from_args(_Args(), stream=io.StringIO()))
        self.assertTrue(progress.from_args(_Args(progress=True), stream=io.StringIO()))
        self.assertFalse(progress.from_args(_Args(progress=True, quiet=True), stream=_Tty()))

    def test_steps_and_polled_counter_on_a_terminal(self):
        tty = _Tty()
        progress.configure(True, stream=tty)
        progress.step(2, 4, "figure fig4")
        progress.step(3, 10, "runs", level=1)
        count = [0]
        with progress.polling("symbols", 200, lambda: count[0], interval_s=0.01):
            count[0] = 200
        progress.finish()
        text = tty.getvalue()
        self.assertIn("figure fig4 2/4", text)
        self.assertIn("figure fig4 2/4 | runs 3/10 | symbols [", text)
        self.assertIn("100.0 %", text)
        self.assertTrue(text.endswith("\n"))
        self.assertNotIn("\n", text[:-1])  # redrawn in place with \r, one final newline

    def test_disabled_writes_nothing(self):
        stream = io.StringIO()
        progress.configure(False, stream=stream)
        progress.step(1, 2, "x")
        with progress.polling("symbols", 10, lambda: 10):
            pass
        progress.finish()
        self.assertEqual(stream.getvalue(), "")

    def test_a_failing_counter_does_not_break_the_run(self):
        stream = io.StringIO()
        progress.configure(True, stream=stream)

        def broken():
            raise RuntimeError("block gone")
        with progress.polling("symbols", 10, broken, interval_s=0.01):
            pass
        self.assertIn("0.0 %", stream.getvalue())


if __name__ == "__main__":
    gr_unittest.run(qa_progress)
