#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-bench --sweep: run time against image error, one processing knob at a time.

Each case is one `nrsar-sim --json` run in its own process (so `peak_rss_mb` is that run's):
a baseline (the defaults) and one knob changed per case: RCMC taps, presummer type and D,
presum before / after the range IFFT, azimuth band scene / full, range crop on / off, range
FFT size exact / fast. Writes sweep.csv and sweep.png (Pareto plot: receive-chain CPU time
against NMSE, one labelled point per case) into the output folder and prints a table.
"""

import argparse
import csv
import io
import multiprocessing
import os
import sys

from .. import chain, progress, results, runtime
from ..options import SimOptions, check_out_dir

# (label, extra nrsar-sim flags); the baseline is nrsar-sim's defaults
CASES = [
    ("baseline", []),
    ("rcmc 4 taps", ["--rcmc-taps", "4"]),
    ("rcmc 8 taps", ["--rcmc-taps", "8"]),
    ("rcmc 32 taps", ["--rcmc-taps", "32"]),
    ("presum drop D10", ["--presum", "drop", "--decim", "10"]),
    ("presum boxcar D10", ["--presum", "boxcar", "--decim", "10"]),
    ("presum filter_drop D10", ["--presum", "filter_drop", "--decim", "10"]),
    ("presum cheby D4", ["--presum", "cheby", "--decim", "4"]),
    ("presum cheby D10", ["--presum", "cheby", "--decim", "10"]),
    ("presum cheby D12", ["--presum", "cheby", "--decim", "12"]),
    ("presum cheby D10 before IFFT", ["--presum", "cheby", "--decim", "10",
                                      "--presum-domain", "tf"]),
    ("band full", ["--band", "full"]),
    ("range crop off", ["--range-crop", "off"]),
    ("range FFT exact", ["--fft-size", "exact"]),
    # perf: constant-modulus data (shortcut on by default, then off) and the 2-thread filter
    ("qpsk", ["--modulation", "qpsk"]),
    ("qpsk, cm shortcut off", ["--modulation", "qpsk", "--cm-path", "off"]),
    ("filter 2 threads", ["--filter-threads", "2"]),
]

KEYS = ["runtime_s", "rx_runtime_s", "peak_rss_mb", "nmse_db", "nmse_theory_db", "snr_out_db",
        "pslr_db", "islr_db", "irw_range_m", "irw_azimuth_m", "peak_error_m", "range_bins",
        "range_fft_size", "azimuth_lines"]


def base_args(quick):
    """The moderate case: paper numerology (3333 subcarriers, 24 kHz PRF), one target,
    WF at SNR_in -20 dB, 0.5 s of aperture (12 000 symbols; quick: 0.1 s)."""
    return ["--preset", "paper", "--aperture-s", "0.1" if quick else "0.5",
            "--target", "300,12" if not quick else "300,2.5", "--filter", "wf",
            "--snr-db", "-20"]


def _simulate_in_child(opts, conn):
    try:
        conn.send((None, chain.simulate(opts)))
    except Exception as err:  # reported by the parent with the case's flags
        conn.send((f"{type(err).__name__}: {err}", None))


def run_case(flags, out_dir):
    """nrsar-sim's run of flags in a fresh process (so its peak_rss_mb is that run's)."""
    parser = SimOptions.add_arguments(argparse.ArgumentParser(prog="nrsar-sim"))
    opts = SimOptions.from_args(parser.parse_args(flags + ["--json", "--out", out_dir]))
    check_out_dir(opts.out)
    ctx = multiprocessing.get_context("spawn")
    receive, send = ctx.Pipe(duplex=False)
    child = ctx.Process(target=_simulate_in_child, args=(opts, send))
    child.start()
    send.close()
    try:
        error, result = receive.recv()
    except EOFError:
        error, result = f"the process ended with exit code {child.exitcode}", None
    child.join()
    if error is not None:
        raise RuntimeError(f"nrsar-sim {' '.join(flags)}: {error}")
    return result


def run(out, quick=False, cases=None):
    rows = []
    for label, extra in cases or CASES:
        print(f"sweep: {label} ...", file=sys.stderr, flush=True)
        progress.step(len(rows) + 1, len(cases or CASES), "sweep case")
        flags = base_args(quick) + extra
        r = run_case(flags, os.path.join(out, "runs", label.replace(" ", "_")))
        row = {"case": label, "flags": " ".join(extra)}
        row.update({k: r.get(k) for k in KEYS})
        rows.append(row)
    return rows


def write_csv(path, rows):
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=["case", "flags"] + KEYS)
    writer.writeheader()
    writer.writerows(rows)
    results.write_text(path, text.getvalue())


def pareto(rows, x="rx_runtime_s", y="nmse_db"):
    """Cases no other case beats in both run time and NMSE."""
    return [r for r in rows
            if not any(o[x] <= r[x] and o[y] <= r[y] and (o[x] < r[x] or o[y] < r[y])
                       for o in rows)]


def write_png(path, rows, cpu):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    front = {r["case"] for r in pareto(rows)}
    fig, ax = plt.subplots(figsize=(10, 5.5))
    for i, r in enumerate(rows, 1):
        on = r["case"] in front
        ax.plot(r["rx_runtime_s"], r["nmse_db"], "o", color="tab:red" if on else "tab:blue")
        # numbers at the points (clustered cases would overprint names), names in the key
        ax.annotate(str(i), (r["rx_runtime_s"], r["nmse_db"]), fontsize=7,
                    xytext=(3 + 9 * (i % 3), 3 + 7 * (i % 4)), textcoords="offset points",
                    arrowprops=dict(arrowstyle="-", lw=0.3))
    key = "\n".join(f"{i}: {r['case']}" for i, r in enumerate(rows, 1))
    ax.text(1.02, 1.0, key, transform=ax.transAxes, fontsize=7, va="top")
    pts = sorted((r["rx_runtime_s"], r["nmse_db"]) for r in rows if r["case"] in front)
    ax.plot([p[0] for p in pts], [p[1] for p in pts], "--", color="tab:red", lw=0.8,
            label="Pareto front")
    ax.set_xscale("log")
    ax.set_xlabel("receive chain CPU time in work() [s] (filter, range IFFT, presum, "
                  "focuser, probe)")
    ax.set_ylabel("NMSE [dB] (calibrated, SPEC 8)")
    ax.set_title(f"run time vs error, one knob per point ({cpu})", fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    results.save_figure(fig, path, dpi=110)
    plt.close(fig)


def read_csv(path):
    """Rows of a sweep.csv, numbers as numbers (to re-plot without re-running)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in KEYS:
            r[k] = float(r[k]) if k not in ("range_bins", "range_fft_size", "azimuth_lines") \
                else int(r[k])
    return rows


def format_table(rows):
    lines = [f"{'case':30s} {'wall s':>7s} {'rx s':>7s} {'RSS MB':>7s} {'NMSE':>7s} "
             f"{'theory':>7s} {'SNRout':>7s} {'PSLR':>7s} {'err m':>6s} {'K':>5s}"]
    for r in rows:
        lines.append(f"{r['case']:30s} {r['runtime_s']:7.3f} {r['rx_runtime_s']:7.3f} "
                     f"{r['peak_rss_mb']:7.0f} {r['nmse_db']:7.2f} {r['nmse_theory_db']:7.2f} "
                     f"{r['snr_out_db']:7.2f} {r['pslr_db']:7.2f} {r['peak_error_m']:6.3f} "
                     f"{r['range_bins']:5d}")
    return "\n".join(lines)


def main(out, quick=False):
    os.makedirs(out, exist_ok=True)
    rows = run(out, quick)
    write_csv(os.path.join(out, "sweep.csv"), rows)
    cpu = f"{runtime.cpu_model()}, {os.cpu_count()} cores"
    write_png(os.path.join(out, "sweep.png"), rows, cpu)
    print(f"CPU: {cpu}")
    print(format_table(rows))
    print("Pareto front (rx time vs NMSE): " + ", ".join(r["case"] for r in pareto(rows)))
    return 0
