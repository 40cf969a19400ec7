#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-process --dask on 1, 2 and 4 local workers against the same strip in one process
(distributed_process.py), and Dask's own cost per task against a task's compute time.

A recording of sdr20, two targets near the middle of the track, 0.2 s (quick: 0.1 s) cut
into apertures of 0.05 s (1200 symbols each), against one graph focusing the whole
recording (each task reads its aperture and the focuser's overlap: read_factor lines per
line kept), with the automatic overlap (the scene band's extent: the whole flight for these
beamless targets) and with --strip-overlap-s 0.0125 (300 lines each side). Rates are
apertures per second of wall time, the cluster already started (its start-up is a column of
its own); TLS on, as nrsar-process runs it. Each rate, the one graph's and each cluster's,
is the median of 3 runs of the whole strip. Per-task overhead: the wall time of 200 empty
tasks through the same cluster, divided by 200 (a mean over 200 already). A row of its own: a task without the
reference branch against one with it (median of 5 alternating runs). The bounded overlap
again with --estimate-snr: the strip's rate includes its pre-pass (the SNR estimator's sums,
streamed to the tasks as nrsar-process does; prepass_s: the median of 3 on its own),
read_factor counts the pre-pass's symbols too.
docs/scale.md turns these into a projection for 100 workers.
"""

import os
import shutil
import statistics
import tempfile
import time

from gnuradio.nrsar import chain, distributed_process as dp, recording
from gnuradio.nrsar.bench import benchutil
from gnuradio.nrsar.options import ProcessOptions, SimOptions


def _noop(x):
    return x


def _reference_row(opts, meta, sl):
    """A task's compute time without the reference branch against with it."""
    times = {True: [], False: []}
    for _ in range(5):
        for reference in (True, False):
            times[reference].append(dp.focus_slice(opts, meta, sl, reference)["compute_s"])
    without, with_ = statistics.median(times[False]), statistics.median(times[True])
    return benchutil.row(f"strip task {sl.index} without the reference branch", 1 / without,
                         "with it", 1 / with_, unit="tasks/s", task_compute_s=without,
                         read_factor=None, workers=1)


def _median_rate(apertures, strip, runs=3):
    """Apertures per second of wall time: the median of `runs` calls of strip()."""
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        strip()
        times.append(time.perf_counter() - start)
    return apertures / statistics.median(times)


def run(quick=False):
    folder = tempfile.mkdtemp(prefix="nrsar_bench_dask_")
    try:
        chain.simulate(SimOptions(preset="sdr20", aperture_s=0.1 if quick else 0.2,
                                  target=["300,5", "290,4"], snr_db=5.0, images="none",
                                  record=os.path.join(folder, "rec"),
                                  out=os.path.join(folder, "sim")))
        meta = os.path.join(folder, "rec", "flight.sigmf-meta")
        rec = recording.read(meta)
        rows = []
        for overlap, estimate in ((None, False), (0.0125, False), (0.0125, True)):
            opts = ProcessOptions(recording=meta, strip_aperture_s=0.05, strip_overlap_s=overlap,
                                  estimate_snr=estimate,
                                  out=os.path.join(folder, "out")).validate()
            lay = dp.layout(opts, rec)
            slices = lay.slices
            kept = len(slices) * lay.lines * lay.step
            read_factor = lay.read_factor() + dp.prepass_symbols(opts, rec, lay) / kept
            warm = slices[len(slices) // 2]  # one that reads symbols (the first may not)
            dp.focus_slice(opts, meta, warm)  # FFT plans, imports: not part of the rate
            with_history, _ = dp.prepass(opts, rec, lay)
            compute = statistics.median(r["compute_s"] for r in
                                        dp.run_slices(opts, meta, with_history).values())
            # the peer: one graph focusing the whole recording (it reads every line once)
            serial_rate = _median_rate(len(slices), lambda: dp.focus_slice(
                opts, meta, dp.whole(opts, rec, lay)))
            name = "automatic overlap" if overlap is None else f"overlap {overlap:g} s"
            name += ", --estimate-snr" if estimate else ""
            for workers in (1, 2, 4):
                start = time.perf_counter()
                with dp.connect(opts.replace(dask=f"local:{workers}")) as client:
                    startup = time.perf_counter() - start
                    client.run(dp.focus_slice, opts, meta, warm)  # on every worker
                    rate = _median_rate(len(slices), lambda: dp.run_slices(
                        opts, meta, dp.histories(opts, rec, lay, client), client))
                    prepass = statistics.median(
                        dp.prepass(opts, rec, lay, client)[1] for _ in range(3))
                    n = 200
                    start = time.perf_counter()
                    client.gather(client.map(_noop, range(n), pure=False))
                    overhead = (time.perf_counter() - start) / n
                rows.append(benchutil.row(
                    f"strip of {len(slices)} apertures, {name}, dask local:{workers} (TLS)",
                    rate, "one process", serial_rate, unit="apertures/s", workers=workers,
                    cluster_start_s=startup, task_overhead_s=overhead, task_compute_s=compute,
                    read_factor=read_factor, prepass_s=prepass))
            if overlap is not None and not estimate:
                rows.append(_reference_row(opts, meta, slices[len(slices) // 2]))
        return rows
    finally:
        shutil.rmtree(folder, ignore_errors=True)
