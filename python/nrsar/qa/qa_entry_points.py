#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Every door a user opens (docs/robustness.md, "Command line"): the programs (apps/nrsar-*)
and every module run as `python3 -m gnuradio.nrsar.<...>` (the figure studies, the bench
modules), found in the tree so that a new one is covered without editing this file.

    --help            exit 0, a usage that names the program, no traceback
    a bad flag        exit 2, one last line '<program>: error: ...' naming the flag, its
                      value and the limit, nothing on stdout, no traceback
    documented -m     every `-m gnuradio.nrsar.<module>` shown by the docs and by the
                      modules' own help names a module found here
    recorded ISAC run the smallest documented `nrsar-isac --record` and `nrsar-process` of
                      its recording (docs/recording.md) exit 0

--help and the bad flags run in one child interpreter (imports paid once, a hung entry point
cut by the timeout); the recorded run is two real processes. qa_apps holds the many bad
inputs of each program; this file holds one or two of each program."""

import contextlib
import glob
import io
import json
import os
import re
import runpy
import subprocess
import sys
import tempfile
import traceback

from gnuradio import gr_unittest

SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
APPS = os.environ.get("NRSAR_APPS_DIR") or os.path.join(SOURCE, "apps")
# theory.py's __main__ prints SPEC 8's table (a check of the theory, no options);
# bindings/ are build tools, not installed programs.
NOT_PROGRAMS = {"gnuradio.nrsar.theory"}

# (entry point, flags, text the one-line message must contain): one or two per program, the
# rule written here, not read from the code. nrsar-process checks its flags before the file.
BAD_FLAGS = [
    ("nrsar-sim", ["--decim", "0"], "--decim = 0 must be at least 1"),
    ("nrsar-isac", ["--mcs", "28"], "--mcs = 28 must be at most 27"),
    ("nrsar-soak", ["--minutes", "0"], "--minutes = 0 must be above 0"),
    ("nrsar-figures", ["--seeds", "0"], "--seeds = 0 must be at least 1"),
    ("nrsar-process", ["no.sigmf-meta", "--strip-aperture-s", "-1"],
     "--strip-aperture-s = -1 must be above 0"),
    ("nrsar-process", ["--dask-make-certs", "/proc/nrsar-certs"],
     "--dask-make-certs = '/proc/nrsar-certs' is not a writable folder"),
    ("nrsar-bench", ["--only", "nosuch"], "--only = nosuch is not one of"),
    ("gnuradio.nrsar.bench.bench_td_echo", ["--quick", "--no-such-flag"],
     "unrecognized arguments: --no-such-flag"),
    ("gnuradio.nrsar.bench.bench_rx_realtime", ["--flight-s", "0.1"],
     "--flight-s = 0.1 must be >= 3"),
    ("gnuradio.nrsar.figures.double_reference", ["--guard-m", "-1"],
     "--guard-m = -1 must be at least 0"),
    ("gnuradio.nrsar.bench.base_station_realtime", ["--slots", "0"],
     "--slots = 0 must be at least 1"),
]
# those of BAD_FLAGS that are given an --out (so that a wrongly accepted flag writes nothing
# into the working folder)
TAKE_OUT = {"nrsar-sim", "nrsar-isac", "nrsar-soak", "nrsar-figures", "nrsar-bench",
            "gnuradio.nrsar.figures.double_reference"}


def programs():
    """[(entry point, how to run it)]: ('nrsar-sim', path of the app) and
    ('gnuradio.nrsar.figures.nr_bler', None) for every module with a __main__ block."""
    import gnuradio.nrsar
    found = [(name, os.path.join(APPS, name)) for name in sorted(os.listdir(APPS))
             if name.startswith("nrsar-")]
    root = os.path.dirname(gnuradio.nrsar.__file__)
    for folder, subs, files in os.walk(root):
        subs[:] = sorted(s for s in subs if s not in ("bindings", "qa", "__pycache__"))
        for f in sorted(files):
            path = os.path.join(folder, f)
            if not f.endswith(".py") or f == "__init__.py":
                continue
            with open(path) as text:
                if 'if __name__ == "__main__":' not in text.read():
                    continue
            rel = os.path.relpath(path, root)[:-3].replace(os.sep, ".")
            if f"gnuradio.nrsar.{rel}" not in NOT_PROGRAMS:
                found.append((f"gnuradio.nrsar.{rel}", None))
    return found


def run_in_process(name, path, args):
    """(exit code, stdout, stderr) of one entry point run in this interpreter as a user's
    command would run it; an escaping exception is the traceback a user would see, exit 1."""
    out, err, saved = io.StringIO(), io.StringIO(), sys.argv
    sys.argv = [path or name] + args
    code = 0
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            if path:
                runpy.run_path(path, run_name="__main__")
            else:
                runpy.run_module(name, run_name="__main__", alter_sys=True)
    except SystemExit as e:
        code = 0 if e.code is None else e.code if isinstance(e.code, int) else 1
    except BaseException:
        err.write(traceback.format_exc())
        code = 1
    finally:
        sys.argv = saved
    return code, out.getvalue(), err.getvalue()


def child(cases, result_path):
    """Runs [(name, path, args)] in this process; writes [(code, stdout, stderr)]."""
    import warnings
    # runpy's note that a module ran after its package imported it is no user's concern
    warnings.filterwarnings("ignore", category=RuntimeWarning, module="runpy")
    with open(result_path, "w") as f:
        json.dump([run_in_process(*case) for case in cases], f)


class qa_entry_points(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="qa_entry_points_")
        cls.programs = programs()
        where = dict(cls.programs)
        out = ["--out", os.path.join(cls.dir, "out")]
        cls.help_cases = [(name, path, ["--help"]) for name, path in cls.programs]
        cls.bad_cases = [(name, where[name], flags + (out if name in TAKE_OUT else []))
                         for name, flags, _ in BAD_FLAGS]
        results = os.path.join(cls.dir, "results.json")
        subprocess.run([sys.executable, os.path.abspath(__file__), "--child", results],
                       input=json.dumps(cls.help_cases + cls.bad_cases), text=True,
                       timeout=300, check=True, stdout=subprocess.DEVNULL)
        with open(results) as f:
            got = json.load(f)
        cls.help_results = got[:len(cls.help_cases)]
        cls.bad_results = got[len(cls.help_cases):]

    def test_001_every_program_is_found(self):
        names = [name for name, _ in self.programs]
        for name in ("nrsar-sim", "nrsar-isac", "nrsar-process", "nrsar-bench",
                     "nrsar-figures", "nrsar-soak", "gnuradio.nrsar.figures.nr_bler",
                     "gnuradio.nrsar.figures.double_reference",
                     "gnuradio.nrsar.bench.bench_bp_focuser",
                     "gnuradio.nrsar.bench.bench_rx_realtime"):
            self.assertIn(name, names)

    def test_002_help(self):
        for (name, _, _), (code, stdout, stderr) in zip(self.help_cases, self.help_results):
            with self.subTest(program=name):
                self.assertNotIn("Traceback", stderr, name)
                self.assertEqual(code, 0, f"{name} --help: exit {code}\n{stderr[-3000:]}")
                usage = stdout.split("\n", 1)[0]
                self.assertTrue(usage.startswith("usage: "), f"{name}: {usage}")
                # the program: nrsar-sim, nr_bler.py, nrsar-double-reference
                short = name.rsplit(".", 1)[-1]
                self.assertTrue(short in usage or short.replace("_", "-") in usage,
                                f"{name}: {usage}")

    def test_003_one_bad_flag_each(self):
        for (name, flags, expected), (code, stdout, stderr) in zip(BAD_FLAGS, self.bad_results):
            where = f"{name} {' '.join(flags)}"
            with self.subTest(program=name):
                self.assertNotIn("Traceback", stderr, where)
                self.assertEqual(code, 2, f"{where}: exit {code}\n{stderr[-3000:]}")
                self.assertEqual(stdout, "", where)
                last = stderr.strip().splitlines()[-1]
                self.assertIn(": error: ", last, where)
                self.assertIn(expected, last, where)

    def test_003b_documented_modules_exist(self):
        names = {name for name, _ in self.programs}
        sources = ([os.path.join(SOURCE, "README.md")] +
                   glob.glob(os.path.join(SOURCE, "docs", "**", "*.md"), recursive=True) +
                   glob.glob(os.path.join(SOURCE, "python", "nrsar", "**", "*.py"),
                             recursive=True))
        for path in sources:
            with open(path) as f:
                text = f.read()
            # 'bench_<block>' is a pattern, not a name
            for module in re.findall(r"-m (gnuradio\.nrsar(?:\.\w+)+)(?![\w.<])", text):
                where = f"{os.path.relpath(path, SOURCE)}: -m {module}"
                self.assertTrue(module in names, f"{where} is no module with a __main__")

    def test_004_recorded_isac_run_and_its_processing(self):
        # docs/recording.md's nrsar-isac --record ... && nrsar-process rec/flight.sigmf-meta,
        # at the tiny preset without coding (seconds)
        payload = os.path.join(self.dir, "payload.bin")
        with open(payload, "wb") as f:
            f.write(bytes(range(200)))
        rec = os.path.join(self.dir, "rec")
        for program, flags in (
                ("nrsar-isac", ["--preset", "tiny", "--aperture-s", "0.01", "--coding", "none",
                                "--images", "none", "--payload", payload, "--record", rec,
                                "--out", os.path.join(self.dir, "isac")]),
                ("nrsar-process", [os.path.join(rec, "flight.sigmf-meta"), "--out",
                                   os.path.join(self.dir, "proc")])):
            proc = subprocess.run([sys.executable, os.path.join(APPS, program)] + flags,
                                  capture_output=True, text=True, timeout=300)
            self.assertNotIn("Traceback", proc.stderr, program)
            self.assertEqual(proc.returncode, 0, f"{program}: {proc.stderr[-3000:]}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        child(json.load(sys.stdin), sys.argv[2])
    else:
        gr_unittest.run(qa_entry_points)
