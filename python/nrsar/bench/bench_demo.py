#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""`make demo` against its goals (issue #16): the one ISAC graph of nrsar-isac at `paper`
(2 s of uplink, simulation included) within 8x real time and 512 MB peak RSS. Runs the
demo's command in a child process (the payload: GPL-3 repeated 100 times, as the Makefile
writes it) and reports ratios, not pass/fail (docs/performance.md, "make demo"):

- radar time / (8 x wall): 1 or more meets the real-time goal; ratio_cpu the same with the
  child's CPU time (user + system) in place of the wall time;
- 512 MB / peak RSS of the child (getrusage's ru_maxrss): 1 or more meets the memory goal.

--quick: a 0.25 s aperture and the payload 5 times (the same graph; the focusers' blocks
scale with the aperture, so the RSS is lower than the full run's).
"""

import json
import os
import resource
import subprocess
import sys
import tempfile
import time

from . import benchutil

GOAL_REALTIME_FACTOR = 8.0  # wall time / radar time
GOAL_RSS_MB = 512.0
LICENSE = "/usr/share/common-licenses/GPL-3"

DEMO = ["--preset", "paper", "--scene", "paper3", "--filter", "wf", "--snr-db", "-20",
        "--bs-snr-db", "50", "--cfo-hz", "9000", "--delay-samples", "1234",
        "--coding", "nr-ldpc", "--mcs-table", "qam256", "--mcs", "27", "--rx-fuse", "on",
        "--json"]
DEMO += ["--rx-threads", "2" if (os.cpu_count() or 1) > 1 else "1"]  # as the Makefile
RUN_ISAC = ("import sys; from gnuradio.nrsar import cli, isac_chain; "
            "from gnuradio.nrsar.options import IsacOptions; "
            "sys.exit(cli.main('nrsar-isac', IsacOptions, isac_chain.run, ''))")


def run_demo(folder, repeats, extra):
    """The demo in a child process: (JSON dict, wall s, CPU s, peak RSS MiB)."""
    with open(LICENSE, "rb") as f:
        text = f.read()
    payload = os.path.join(folder, "payload.bin")
    with open(payload, "wb") as f:
        f.write(text * repeats)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", RUN_ISAC] + DEMO + extra +
                         ["--payload", payload, "--out", folder],
                         capture_output=True, text=True, check=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    # ru_maxrss of the children is the largest of any child so far (KiB): the demo is the
    # biggest child this process starts
    return json.loads(out.stdout.strip().splitlines()[-1]), wall, cpu, after.ru_maxrss / 1024.0


def run(quick=False):
    extra, repeats = (["--aperture-s", "0.25"], 5) if quick else ([], 100)
    with tempfile.TemporaryDirectory(prefix="bench_demo_") as folder:
        result, wall, cpu, rss = run_demo(folder, repeats, extra)
    radar_s = result["samples"] / result["sample_rate_hz"]
    goal = 1.0 / GOAL_REALTIME_FACTOR  # radar seconds per wall second at the goal
    return [
        benchutil.row("make demo: radar time per wall second", radar_s / wall,
                      f"goal {GOAL_REALTIME_FACTOR:g}x real time", goal,
                      unit="radar s per s", ratio_cpu=(radar_s / cpu) / goal,
                      wall_s=wall, cpu_s=cpu, radar_s=radar_s,
                      flowgraph_s=result["runtime_s"],
                      payload_identical=result["payload_identical"]),
        benchutil.row("make demo: memory (goal / peak RSS)", GOAL_RSS_MB, "peak RSS of the demo",
                      rss, unit="MB", peak_rss_mb=rss),
    ]
