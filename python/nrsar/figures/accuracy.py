#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Accuracy table of docs/accuracy.md: measured vs theory NMSE (SPEC 8) of the whole chain
(nrsar-sim: nr_isac_tx -> scene_echo -> tf_filter -> range_ifft -> rd_focuser -> nmse_probe
with the reference branch) for RF / MF / WF, SNR_in -20..30 dB, 256-QAM, 16-QAM and QPSK.

    /usr/bin/python3 -m gnuradio.nrsar.figures.accuracy --out DIR [--quick] [--seeds N]

writes accuracy.csv (every run) and accuracy.md (the table: mean over seeds of
measured - theory, and the headline spread of that difference over all cells).
"""

import dataclasses
import os
import sys
import tempfile

import numpy as np

from .. import cli, results
from ..options import Options, option
from .. import figures

MODULATIONS = ("qam256", "qam16", "qpsk")


def run(out, quick=False, seeds=2):
    snrs = (-20, 10, 30) if quick else tuple(range(-20, 31, 5))
    cases = [(m, f) for m in MODULATIONS for f in figures.FILTERS]
    os.makedirs(out, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="nrsar-accuracy-") as work:
        rows = figures.nmse_sweep(work, cases, snrs, range(1, seeds + 1), quick, "accuracy")
    figures.write_csv(os.path.join(out, "accuracy.csv"),
                      ("modulation", "filter", "snr_db", "seed", "nmse_db", "nmse_theory_db",
                       "theory_py_db", "nmse_theory_band_db"), rows)
    summ = figures.summarise(rows)
    diffs = {k: v[0] - v[4] for k, v in summ.items()}  # against the floor with the band term
    spread = max(diffs.values()) - min(diffs.values())
    cfg = figures.sweep_config(quick)
    lines = [f"Preset `{cfg['preset']}`, aperture {cfg['aperture_s']} s, target 1 alone, "
             f"{seeds} seeds per cell; each cell: measured / theory NMSE [dB] with the "
             f"band-occupancy term (nmse_theory_band_db; measured = mean of the seeds' dB "
             f"values), then measured - that theory.", ""]
    for mod in MODULATIONS:
        lines.append(f"**{mod}**")
        lines.append("")
        lines.append("| SNR_in [dB] | " + " | ".join(f.upper() for f in figures.FILTERS) + " |")
        lines.append("|---|" + "---|" * len(figures.FILTERS))
        for snr in snrs:
            cells = []
            for f in figures.FILTERS:
                mean, _lo, _hi, _th, band = summ[(mod, f, float(snr))]
                cells.append(f"{mean:.2f} / {band:.2f} ({mean - band:+.2f})")
            lines.append(f"| {snr} | " + " | ".join(cells) + " |")
        lines.append("")
    seed_spread = max(v[2] - v[1] for v in summ.values())
    lines.append(f"Offset measured - theory with the band term over all {len(diffs)} cells: min "
                 f"{min(diffs.values()):+.2f} dB, max {max(diffs.values()):+.2f} dB, "
                 f"mean {np.mean(list(diffs.values())):+.2f} dB; **spread "
                 f"{spread:.2f} dB**; largest seed-to-seed range in one cell "
                 f"{seed_spread:.2f} dB.")
    text = "\n".join(lines) + "\n"
    results.write_text(os.path.join(out, "accuracy.md"), text)
    return {"spread_db": spread, "min_db": min(diffs.values()), "max_db": max(diffs.values()),
            "summary": summ, "markdown": text}


@dataclasses.dataclass
class AccuracyOptions(Options):
    out: str = option("nrsar-accuracy", "output folder")
    quick: bool = option(False, "small sizes (the smoke test)")
    seeds: int = option(2, "seeds per cell", at_least=1, at_most=100)


def main(argv=None):
    args = cli.parse("nrsar-accuracy", AccuracyOptions, __doc__, argv)
    if args is None:
        return cli.EXIT_USAGE
    res = run(args.out, args.quick, args.seeds)
    print(res["markdown"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
