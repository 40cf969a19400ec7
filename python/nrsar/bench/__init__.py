#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-bench: block throughput against peers measured in the same run.

Runs every `bench_<block>` module of the package (each compares one of our blocks with a
stock GNU Radio chain, gr-radar or numpy doing the same work), prints a table and writes
bench.csv and bench.png (ratios ours / peer) into the output folder.
"""

import argparse
import csv
import importlib
import io
import os
import pkgutil
import sys

from . import __path__ as package_path
from .. import progress, results, runtime
from ..options import check_out_dir

COLUMNS = ["benchmark", "unit", "ours", "peer", "peer_rate", "ratio"]


def bench_modules(selected=None):
    names = sorted(m.name for m in pkgutil.iter_modules(package_path)
                   if m.name.startswith("bench_"))
    if selected:
        unknown = set(selected) - {n[len("bench_"):] for n in names}
        if unknown:
            raise ValueError(f"--only = {', '.join(sorted(unknown))} is not one of "
                             f"{', '.join(n[len('bench_'):] for n in names)}")
        names = [n for n in names if n[len("bench_"):] in selected]
    return [importlib.import_module(f".{n}", __package__) for n in names]


def format_table(rows):
    lines = [f"{'benchmark':44s} {'ours':>12s} {'peer':>12s} {'ratio':>7s}  peer"]
    for r in rows:
        ratio = "" if r.get("ratio") is None else f"{r['ratio']:.2f}"
        lines.append(f"{r['benchmark']:44s} {r['ours']:12.4g} {r['peer_rate'] or 0:12.4g} "
                     f"{ratio:>7s}  {r['peer']} [{r['unit']}]")
    return "\n".join(lines)


def write_csv(path, rows):
    extra = sorted({k for r in rows for k in r} - set(COLUMNS))
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=COLUMNS + extra)
    writer.writeheader()
    writer.writerows(rows)
    results.write_text(path, text.getvalue())


def write_png(path, rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rated = [r for r in rows if r.get("ratio")]
    if not rated:
        return
    fig, ax = plt.subplots(figsize=(8, 0.45 * len(rated) + 1.2))
    ax.barh([r["benchmark"] for r in rated], [r["ratio"] for r in rated], color="tab:blue")
    ax.axvline(1.0, color="k", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("throughput ratio, ours / peer (same run)")
    ax.set_title(f"gr-nrsar block throughput on {runtime.cpu_model()}", fontsize=9)
    ax.invert_yaxis()
    fig.tight_layout()
    results.save_figure(fig, path, dpi=110)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="nrsar-bench", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="nrsar-bench-out", help="folder for bench.csv/png")
    parser.add_argument("--only", action="append", metavar="BLOCK",
                        help="run only this block's comparisons (repeatable)")
    parser.add_argument("--quick", action="store_true",
                        help="short runs (smoke test; ratios are noisier)")
    parser.add_argument("--sweep", action="store_true",
                        help="instead: run time vs NMSE / SNR_out / PSLR of nrsar-sim, one "
                             "processing knob at a time (sweep.csv, sweep.png)")
    progress.add_arguments(parser)
    args = parser.parse_args(argv)
    progress.configure(progress.from_args(args))

    runtime.quiet_gnuradio_logs()
    if os.environ.get("VOLK_GENERIC"):
        print("nrsar-bench: VOLK_GENERIC is set: VOLK's generic kernels would be measured",
              file=sys.stderr)
    if args.sweep:  # stress
        from . import sweep
        return sweep.main(args.out, args.quick)
    try:
        modules = bench_modules(args.only)
        check_out_dir(args.out)  # before minutes of benchmarks, not after them
    except ValueError as err:
        print(f"nrsar-bench: error: {err}", file=sys.stderr)
        return 2
    rows = []
    for module in modules:
        progress.step(modules.index(module) + 1, len(modules), "benchmark")
        print(f"running {module.__name__.rsplit('.', 1)[-1]} ...", file=sys.stderr, flush=True)
        rows.extend(module.run(quick=args.quick))
    progress.finish()
    write_csv(os.path.join(args.out, "bench.csv"), rows)
    write_png(os.path.join(args.out, "bench.png"), rows)
    print(f"CPU: {runtime.cpu_model()}, {os.cpu_count()} cores")
    print(format_table(rows))
    return 0
