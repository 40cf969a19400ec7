#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Does the radar receive path keep real time? (issue 16, docs/performance.md)

The UAV's radar graph with the radio replaced by memory: the echo of the paper3 scene
(nr_isac_tx -> scene_echo, SNR_in -20 dB) is generated once, held in memory and replayed
without a throttle, so the graph runs as fast as it can. Radio time = symbols x symbol
duration; processing time = wall time of the flowgraph. Variants:

    paper TF:  echo grid -> tf_filter (WF) -> range_ifft -> cheby_presum D10 -> rd_focuser
               -> nmse_probe (PSF model), with the transmit grid as tf_filter's reference
    paper TD:  the same behind ofdm_demod, fed the time-domain echo at 122.88 Msps
    sdr20 TD + TX: the sdr20 radar receive path as above (30.72 Msps) and, in the same
               graph, the transmitter pusch_encoder -> nr_isac_tx -> ofdm_mod into a sink
    paper TF / TD, range_compress: the first two with --rx-fuse on (the filter and the
               range IFFT in one block, range_compress)
    --flight-s 60: the sdr20 TD + TX graph for a flight of 60 s of radio time, one
               focuser aperture (2 s) of echo and transmit grid replayed cyclically from
               files (both with the aperture's period, so the filter's reference matches the
               echo), image_sink writing every aperture's .npy and PNG: peak RSS in each
               quarter of the flight, and how far the apertures' images (of the same echo) differ
               (--presum boxcar: the same graph without cheby's motion compensation)

Profile: CPU time of every block thread (/proc/self/task/*/schedstat, sampled while the
graph runs; GNU Radio names a block's thread after the block) against the time its work()
calls took (GNU Radio's performance counters). The difference is the scheduler's share of
that thread: buffer bookkeeping, tags, waking neighbours. The rows compare the radio's rate
with the processing rate (ratio >= 1: real time on this machine as loaded now).
Run alone: /usr/bin/python3 -m gnuradio.nrsar.bench.bench_rx_realtime [--quick]
[--flight-s S [--presum boxcar]]
"""

import math
import os
import tempfile
import threading
import time
from dataclasses import dataclass

import numpy as np
from gnuradio import blocks, gr

from .. import chain, isac_chain, runtime, scenario
from ..nrsar_python import image_sink, ofdm_demod, ofdm_mod
from ..options import IsacOptions, SimOptions
from . import benchutil

HELD = 240  # symbols generated once and replayed (the radio's samples in memory)


class ThreadCpu:
    """CPU seconds of each thread of this process, sampled every `period` s while started
    (a thread's last sample is kept after it exits), and (time, progress(), RSS MiB) at each
    sample."""

    def __init__(self, progress, period=0.02):
        self.period, self.seen, self._stop = period, {}, threading.Event()
        self.progress, self.track = progress, []
        self._thread = threading.Thread(target=self._loop, daemon=True)

    def sample(self):
        self.track.append((time.perf_counter(), self.progress(), runtime.rss_mb()))
        self.seen.update(self.read())

    @staticmethod
    def read():
        seen = {}
        for tid in os.listdir("/proc/self/task"):
            try:
                with open(f"/proc/self/task/{tid}/comm") as f:
                    comm = f.read().strip()
                with open(f"/proc/self/task/{tid}/schedstat") as f:
                    ns = int(f.read().split()[0])
            except (OSError, ValueError, IndexError):
                continue  # the thread ended between listdir and open
            seen[tid] = (comm, ns / 1e9)
        return seen

    def spent(self):
        """{tid: (comm, CPU s during the run)}."""
        return {tid: (comm, s - self.before.get(tid, (comm, 0.0))[1])
                for tid, (comm, s) in self.seen.items()}

    def _loop(self):
        while not self._stop.wait(self.period):
            self.sample()

    def __enter__(self):
        self.before = self.read()  # threads older than the run: count only what they add
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()

    def of_block(self, block):
        """CPU seconds of the thread GNU Radio named after block (name + unique id, cut to
        the 15 characters Linux keeps)."""
        name = f"{block.name()}{block.unique_id()}"[:15]
        return sum(s for comm, s in self.spent().values() if comm == name)

    def steady_rate(self, total):
        """Items per second between 10 % and 90 % of total (start-up and drain left out)."""
        inside = [(t, n) for t, n, _ in self.track if 0.1 * total <= n <= 0.9 * total]
        if len(inside) < 2 or inside[-1][0] == inside[0][0]:
            return float("nan")
        return (inside[-1][1] - inside[0][1]) / (inside[-1][0] - inside[0][0])


def replay(opts, sc, time_domain, symbols=HELD, folder=None):
    """(echo source, grid source, echo items per symbol): sources that repeat, with one
    period, the echo of `symbols` symbols (TF, or its OFDM modulation when time_domain) and
    their transmit grid, generated once and held in memory (folder: in files there)."""
    n = sc.num.num_subcarriers
    vlens = (1 if time_domain else n, n)
    tb = gr.top_block()
    head = blocks.head(gr.sizeof_gr_complex * n, symbols)
    tb.connect(chain.make_transmitter(opts, sc), head)
    echo, echo_out, ref_out = chain.scene_echo_front(tb, opts, sc, head)
    tb.connect(ref_out, blocks.null_sink(gr.sizeof_gr_complex * n))
    if folder:
        paths = [os.path.join(folder, name) for name in ("echo.c64", "grid.c64")]
        out, grid = (blocks.file_sink(gr.sizeof_gr_complex * v, p) for v, p in zip(vlens, paths))
    else:
        out, grid = blocks.vector_sink_c(vlens[0]), blocks.vector_sink_c(n)
    tb.connect(head, grid)
    tb.connect(echo_out, ofdm_mod(sc.num), out) if time_domain else tb.connect(echo_out, out)
    tb.run()
    if folder:
        out.close()  # flushed before the sources open the files
        grid.close()
        sources = [blocks.file_source(gr.sizeof_gr_complex * v, p, True)
                   for v, p in zip(vlens, paths)]
    else:
        sources = [blocks.vector_source_c(np.array(s.data(), np.complex64), True, v)
                   for s, v in zip((out, grid), vlens)]
    return sources[0], sources[1], out.nitems_read(0) // symbols


@dataclass
class VariantRun:
    """What one run_variant measured."""
    radio_s: float  # radio time of the symbols run
    wall_s: float  # the flowgraph's wall time, start-up and drain included
    process_cpu_s: float
    profile: dict  # {block name: (its thread's CPU s, its work() s)}
    steady: float  # steady processing rate, radio s per s (ThreadCpu.steady_rate)
    others: list  # [(other thread, CPU s)], busiest first
    cpu: ThreadCpu
    blocks: dict  # {block name: the block profiled}


def run_variant(preset, time_domain, transmit, symbols, chunk=0, fuse="off", flight=None,
                presum="cheby"):
    """One run: a VariantRun. fuse: --rx-fuse (range_compress in place of tf_filter ->
    range_ifft). flight: a folder; one aperture is replayed from files there and image_sink
    writes its images there (symbols: a whole number of apertures). presum: the presummer's
    method (--presum)."""
    opts = SimOptions(preset=preset, images="none", presum=presum, decim=10, rx_fuse=fuse)
    sc = scenario.of(opts.validate())
    n = sc.num.num_subcarriers
    src, grid, per_symbol = replay(opts, sc, time_domain, sc.symbols if flight else HELD,
                                   flight)
    tb = gr.top_block()
    rx = chain.imaging_chain(opts, sc, keep_images=False, reference=False)
    head = blocks.head(gr.sizeof_gr_complex * (1 if time_domain else n), symbols * per_symbol)
    named = {"tf_filter": rx.filter, "range_ifft": rx.range_ifft, "cheby_presum": rx.presum,
             "rd_focuser": rx.focuser, "nmse_probe": rx.probe}
    if rx.filter is rx.range_ifft:  # one range_compress
        named = {"range_compress": named.pop("tf_filter"), **named}
        del named["range_ifft"]
    tb.connect(src, head)
    if chunk:  # the sample buffer in front of ofdm_demod: up to `chunk` symbols per call
        head.set_min_output_buffer(2 * chunk * per_symbol)
    if time_domain:
        demod = ofdm_demod(sc.num)
        tb.connect(head, demod, (rx, 0))
        named["ofdm_demod"] = demod
    else:
        tb.connect(head, (rx, 0))
    tb.connect(grid, (rx, 1))
    k = rx.focuser.num_output_bins()
    if flight:  # every aperture kept: they are compared after the run
        named["image_sink"] = image_sink(k, os.path.join(flight, "image"),
                                         keep=symbols // sc.symbols)
        tb.connect((rx, 0), named["image_sink"])
    else:
        tb.connect((rx, 0), blocks.null_sink(gr.sizeof_gr_complex * k))
    tb.connect((rx, 1), blocks.null_sink(gr.sizeof_gr_complex * rx.range_ifft.num_bins()))
    if transmit:  # the UAV's own transmitter in the same graph, into the radio's sink
        iopts = IsacOptions(preset=preset, images="none", presum="cheby", decim=10)
        payload = bytes(np.random.default_rng(1).integers(0, 256, 40000, dtype=np.uint8))
        enc, tx, _, _ = isac_chain.build_transmitter(tb, sc.num, iopts, payload)
        mod = ofdm_mod(sc.num)
        tb.connect(tx, blocks.head(gr.sizeof_gr_complex * n, symbols), mod,
                   blocks.null_sink(gr.sizeof_gr_complex))
        named.update(pusch_encoder=enc, nr_isac_tx=tx, ofdm_mod=mod)
    runtime.quiet_gnuradio_logs()
    # a flight's minutes: sample less often (the sampler's own CPU)
    with ThreadCpu(lambda: rx.filter.nitems_written(0), 0.1 if flight else 0.02) as cpu:
        wall, proc = time.perf_counter(), time.process_time()
        runtime.run(tb)
        wall, proc = time.perf_counter() - wall, time.process_time() - proc
    cpu.sample()
    profile = {k: (cpu.of_block(b), b.pc_work_time_total() / 1e9) for k, b in named.items()}
    mine = {f"{b.name()}{b.unique_id()}"[:15] for b in named.values()}
    others = sorted(((c, s) for c, s in cpu.spent().values() if c not in mine),
                    key=lambda cs: -cs[1])
    return VariantRun(symbols * sc.num.symbol_s(), wall, proc, profile,
                      cpu.steady_rate(symbols) * sc.num.symbol_s(), others, cpu, named)


# ofdm_demod asks for a whole symbol (4384 samples at paper) per output, and GNU Radio's
# default buffer of 8192 complex samples holds fewer than two: with it every block behind the
# demodulator runs once per symbol, and the scheduler's cost per call outweighs the work.
# A sample buffer of 2 x 16 symbols (the radio source's min output buffer) lets it run 16.
CHUNK = 16
VARIANTS = (("paper TF", "paper", False, False), ("paper TD", "paper", True, False),
            ("sdr20 TD + TX", "sdr20", True, True))
# The same paths with range_compress (--rx-fuse on): the filter and the IFFT in one pass.
FUSED = (("paper TF, range_compress", "paper", False, False),
         ("paper TD, range_compress", "paper", True, False))


def run(quick=False):
    symbols = 4800 if quick else 24000
    rows, unfused = [], {}
    default = run_variant("paper", True, False, symbols)
    for label, preset, td, tx in VARIANTS:
        v = run_variant(preset, td, tx, symbols, CHUNK if td else 0)
        radio, proc, profile = v.radio_s, v.process_cpu_s, v.profile
        extra = {f"{k}_cpu_per_radio_s": round(c / radio, 4) for k, (c, _) in profile.items()}
        extra.update({f"{k}_work_per_radio_s": round(w / radio, 4)
                      for k, (_, w) in profile.items()})
        rows.append(benchutil.row(
            f"radar rx path {label}: radio s per s", v.steady,
            "real time (the radio's rate)", 1.0, unit="radio s / s (steady)", radio_s=radio,
            wall_s=round(v.wall_s, 3), process_cpu_s=round(proc, 3),
            load_average=round(os.getloadavg()[0], 1), **extra))
        rows.append(benchutil.row(
            f"radar rx path {label}: radio s per CPU s", radio / proc,
            "2 cores' real time", 0.5, unit="radio s / CPU s"))
        if label == "paper TD":
            rows.append(benchutil.row(
                f"radar rx path paper TD, {CHUNK}-symbol sample buffer", radio / proc,
                "GNU Radio's default sample buffer", default.radio_s / default.process_cpu_s,
                unit="radio s / CPU s"))
        if label.startswith("paper"):
            unfused[label] = radio / proc
    for label, preset, td, tx in FUSED:
        v = run_variant(preset, td, tx, symbols, CHUNK if td else 0, fuse="on")
        rows.append(benchutil.row(
            f"radar rx path {label}: radio s per CPU s", v.radio_s / v.process_cpu_s,
            "tf_filter > range_ifft (run before)", unfused[label.split(",")[0]],
            unit="radio s / CPU s", **{f"{k}_cpu_per_radio_s": round(c / v.radio_s, 4)
                                       for k, (c, _) in v.profile.items()}))
    return rows


def print_profile(label, v):
    radio, wall, proc, profile = v.radio_s, v.wall_s, v.process_cpu_s, v.profile
    print(f"{label}: radio {radio:.3f} s, wall {wall:.3f} s with start-up, steady rate "
          f"x{v.steady:.2f} real time; process CPU {proc:.3f} s = {proc / radio:.2f} CPU s "
          f"per radio s; load {os.getloadavg()[0]:.1f}")
    for k, (c, w) in sorted(profile.items(), key=lambda kv: -kv[1][0]):
        print(f"  {k:14s} thread CPU {c:7.3f} s ({c / radio:5.2f} per radio s)  "
              f"work() {w:7.3f} s")
    print(f"  other threads  {proc - sum(c for c, _ in profile.values()):7.3f} s: " +
          ", ".join(f"{comm} {s:.3f}" for comm, s in v.others[:6]))


def flight(seconds, presum="cheby"):
    """--flight-s: the sdr20 TD + TX graph for `seconds` of radio time rounded to whole
    apertures; prints the profile, the peak RSS of each quarter and how far each
    aperture's image differs from the second one's (max |difference| over its peak).
    The first aperture lacks the history and the last the look-ahead of the others. The
    replayed echo is the first aperture's while the navigation flies on: cheby compensates
    each pulse along the line of sight from where the navigation says the UAV is, so its
    images part from the second one's with the distance flown; boxcar (no compensation)
    images the same echo the same way every time (a drift would be numerical)."""
    sc = scenario.of(SimOptions(preset="sdr20").validate())
    aperture_s = sc.symbols * sc.num.symbol_s()
    apertures = round(seconds / aperture_s) if math.isfinite(seconds) else 0
    if apertures < 2:  # the first aperture has no history: compare from the second
        raise ValueError(f"--flight-s = {seconds} must be >= {1.5 * aperture_s:g} "
                         f"(2 apertures of {aperture_s:g} s)")
    print(f"load {os.getloadavg()[0]:.1f} before generating one aperture of echo")
    with tempfile.TemporaryDirectory(prefix="nrsar-flight-") as folder:
        v = run_variant("sdr20", True, True, apertures * sc.symbols, CHUNK, flight=folder,
                        presum=presum)
        cpu, named = v.cpu, v.blocks
        print_profile(f"sdr20 TD + TX, {presum} presum, {apertures} apertures", v)
        print(f"processing s per radio s {v.wall_s / v.radio_s:.3f} (with start-up and drain); "
              f"transmitted {named['ofdm_mod'].nitems_written(0)} samples")
        total = apertures * sc.symbols
        quarters = [[r for _, n, r in cpu.track if q * total / 4 <= n <= (q + 1) * total / 4]
                    for q in range(4)]
        used, free = runtime.heap_mb()  # free bytes that grow: fragmentation (docs/soak.md)
        print(f"peak RSS {max(r for _, _, r in cpu.track):.0f} MiB; peak of each quarter of the "
              f"flight " + ", ".join(f"{max(q, default=float('nan')):.1f}" for q in quarters) +
              f" MiB ({len(cpu.track)} samples); glibc heap at the end: {used:.1f} MiB in use, "
              f"{free:.1f} MiB free in its arenas")
        sink = named["image_sink"]
        files = [f for f in sink.kept_files() if f.endswith(".npy")]
        print(f"image_sink: {sink.apertures_written()} apertures written, {len(files)} .npy "
              f"kept, non-finite samples {sink.nonfinite_count()}")
        ref = np.load(files[1])
        diffs = [float(np.abs(np.load(f) - ref).max() / np.abs(ref).max()) for f in files]
        print(f"image vs aperture 1, max |difference| / peak: first {diffs[0]:.2e}, "
              f"apertures 2..{len(files) - 2}: max {max(diffs[2:-1], default=0):.2e}, "
              f"last {diffs[-1]:.2e}; all: " + " ".join(f"{d:.1e}" for d in diffs))


def main():
    import argparse
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--flight-s", type=float, default=0.0,
                   help="run only the sdr20 flight of this many radio seconds (module doc)")
    p.add_argument("--presum", choices=("cheby", "boxcar"), default="cheby",
                   help="the flight's presummer (flight())")
    a = p.parse_args()
    if a.flight_s:
        try:
            flight(a.flight_s, a.presum)
        except ValueError as e:
            p.error(str(e))
        return
    symbols = 4800 if a.quick else 24000
    for label, preset, td, tx in (VARIANTS + FUSED +
                                  (("paper TD, default buffer", "paper", True, False),)):
        chunk = CHUNK if td and "default" not in label else 0
        print_profile(label, run_variant(
            preset, td, tx, symbols, chunk, fuse="on" if "range_compress" in label else "off"))


if __name__ == "__main__":
    main()
