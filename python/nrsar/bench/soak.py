#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-soak: the imaging chain on an endless stream, and whether its memory stays flat.

Runs the nrsar-sim chain (transmitter, echo, TF filter, range IFFT, presummer, focuser, probe
and the reference branch; images to null sinks) over many consecutive apertures of the
geometry's length (2 s by default) for --minutes of radar time, samples the process's
resident set size (VmRSS) every --interval-s of wall time, fits a straight line to RSS
against radar time after the warm-up, and fails (exit 1) when the slope exceeds
--max-slope-mb-per-min. Writes soak.csv (wall s, radar s, RSS MB), soak.png and soak.json
into --out. `make soak` runs the full 10 minutes at paper scale; ctest runs a short one.
"""

import os
import threading
import time

import numpy as np

from gnuradio import gr

from .. import chain, results, runtime, scenario
from ..options import check_out_dir


def fit_slope(radar_s, rss, start_s):
    """Least-squares slope [MiB per radar minute] and intercept of RSS over radar time
    from start_s on; (nan, nan) with fewer than 3 samples."""
    t = np.asarray(radar_s, float)
    r = np.asarray(rss, float)
    keep = t >= start_s
    if keep.sum() < 3:
        return float("nan"), float("nan")
    slope, intercept = np.polyfit(t[keep] / 60.0, r[keep], 1)
    return float(slope), float(intercept)


def run(opts):
    """The soak of validated SoakOptions; returns its JSON dict and writes soak.csv,
    soak.json and soak.png into opts.out."""
    sc = scenario.of(opts.validate())
    check_out_dir(opts.out)
    num = sc.num
    aperture_symbols = sc.symbols
    total_symbols = int(round(opts.minutes * 60.0 / num.symbol_s()))
    total_symbols = max(aperture_symbols, total_symbols - total_symbols % aperture_symbols)

    tb = gr.top_block("nrsar-soak")
    head = chain.build(tb, opts, sc)["head"]
    head.set_length(total_symbols)  # many apertures through the same chain
    tsym = num.symbol_s()

    samples = []  # (wall s, radar s, RSS MiB)
    done = threading.Event()
    start = time.perf_counter()
    cpu0 = time.process_time()
    tb.start()
    waiter = threading.Thread(target=lambda: (tb.wait(), done.set()), daemon=True)
    waiter.start()
    try:
        while True:
            # Only while the stream runs (RSS read first, then the count): once head has sent
            # it all, the graph may be stopping, and stopped focusers have given their blocks
            # back (-14 MiB at small, which read as a spread of RSS, not a leak).
            now, rss = time.perf_counter() - start, runtime.rss_mb()
            sent = head.nitems_written(0)
            if sent < total_symbols:
                samples.append((now, sent * tsym, rss))
            if done.wait(opts.interval_s):
                break
    except KeyboardInterrupt:
        tb.stop()
        done.wait()
        raise runtime.Interrupted("interrupted before the end of the soak") from None
    wall = time.perf_counter() - start
    cpu = time.process_time() - cpu0

    radar_s = head.nitems_written(0) * tsym  # what streamed (all of it unless interrupted)
    warm_s = max(opts.warmup * radar_s, 2 * aperture_symbols * tsym)
    wall_s, radar, rss = zip(*samples)
    slope, intercept = fit_slope(radar, rss, warm_s)
    after = [r for t, r in zip(radar, rss) if t >= warm_s]
    result = {
        "preset": opts.preset,
        "filter": opts.filter,
        "presum": opts.presum,
        "decim": opts.presum_factor(),
        "radar_s": radar_s,
        "apertures": total_symbols // aperture_symbols,
        "wall_s": wall,
        "cpu_s": cpu,
        "realtime_factor": radar_s / wall,
        "samples": len(samples),
        "warmup_radar_s": warm_s,
        "rss_peak_mb": max(rss),
        "rss_after_warmup_min_mb": min(after) if after else None,
        "rss_after_warmup_max_mb": max(after) if after else None,
        "slope_mb_per_min": slope,
        "max_slope_mb_per_min": opts.max_slope_mb_per_min,
        "passed": bool(np.isfinite(slope) and slope <= opts.max_slope_mb_per_min),
    }
    write_outputs(opts.out, samples, result, intercept)
    return result


def write_outputs(out, samples, result, intercept):
    results.write_text(os.path.join(out, "soak.csv"), "wall_s,radar_s,rss_mb\n" + "".join(
        f"{w:.3f},{t:.4f},{r:.2f}\n" for w, t, r in samples))
    results.write_json(os.path.join(out, "soak.json"), result)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, t, r = zip(*samples)
    t = np.asarray(t) / 60.0
    fig, ax = plt.subplots(figsize=(7, 3.8))
    ax.plot(t, r, ".-", lw=0.8, ms=3, label="RSS (VmRSS)")
    if np.isfinite(result["slope_mb_per_min"]):
        tf = np.array([result["warmup_radar_s"] / 60.0, t[-1]])
        ax.plot(tf, intercept + result["slope_mb_per_min"] * tf, "r--", lw=1,
                label=f"fit after warm-up: {result['slope_mb_per_min']:+.3f} MiB/min")
    ax.axvline(result["warmup_radar_s"] / 60.0, color="gray", lw=0.6, ls=":")
    ax.set_xlabel("radar time [min]")
    ax.set_ylabel("resident set size [MiB]")
    ax.set_title(f"nrsar-soak: {result['preset']}, {result['apertures']} apertures, "
                 f"presum {result['presum']} D{result['decim']}", fontsize=9)
    ax.set_ylim(0, max(r) * 1.15)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    results.save_figure(fig, os.path.join(out, "soak.png"), dpi=110)
    plt.close(fig)


def verdict(result):
    """nrsar-soak's exit code: 1 when the RSS grew faster than the bound."""
    return 0 if result["passed"] else 1
