#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Does the base station keep real time? ofdm_sync -> ofdm_demod -> pusch_receiver (the TS
38.212 UL-SCH, qam256 MCS 27, 256-QAM, pusch2, at most 8 LDPC iterations) on a recorded uplink
burst: every TB full of random payload, a 1234-sample delay, a 9 kHz CFO and AWGN at --snr-db
per RE, held in memory and played once through the three blocks.

Reports, per numerology: air time of the burst, wall time and process CPU time of the
flowgraph, real-time factor = air / wall (>= 1: keeps up on this machine as loaded now) and
cores needed = CPU / air (what real time takes with perfect parallelism; each block is one
thread in GNU Radio, so the busiest block's CPU / air must stay below 1 as well: reported).

--paced SECONDS: wall-clock real time instead. A memory source plays the burst (made
periodic: whole frames, the delay a cyclic shift, the CFO an integer number of cycles per
burst) at the radio's sample rate for SECONDS of air, as a radio delivers it: samples arrive
by the clock, wait in the radio's FIFO (--fifo-ms) while the graph's buffer is full, and are
dropped once the FIFO overflows (counted, and the stream jumps as after a USRP overflow).
Real time = no overflow, every TB decoded, and the graph done within a few ms of the air.

Not an nrsar-bench module (those compare with a peer on the same work); docs/isac.md holds
its numbers. Run: /usr/bin/python3 -m gnuradio.nrsar.bench.base_station_realtime [--preset sdr20] [--slots 200] [--threads 2]
     [--paced 10]
"""

import argparse
import os
import time

import numpy as np
import pmt
from gnuradio import blocks, gr

from gnuradio import nrsar
from gnuradio.nrsar import backhaul, recording, runtime


def uplink(preset, slots, snr_db, seed=1, periodic=False):
    """(num, cfg, time-domain burst as complex64, payload PDUs). periodic: exactly `slots`
    slots (a multiple of a frame), the delay a cyclic shift and the CFO rounded to whole
    cycles per burst, so that the burst played in a loop is one continuous uplink."""
    num = nrsar.make_numerology(preset)
    cfg = nrsar.make_pusch_config(num, "qam256", "pusch2", "nr-ldpc")
    per_tb = nrsar.pusch_encoder(cfg).payload_bits_per_slot() // 8
    rng = np.random.default_rng(seed)
    pdus = [rng.integers(0, 256, per_tb, dtype=np.uint8).tobytes() for _ in range(slots)]
    grid, _ = backhaul.transmit_grid(cfg, pdus, slots + 1)
    n = num.num_subcarriers
    tb = gr.top_block()
    src = blocks.vector_source_c(grid.reshape(-1).tolist(), False, n)
    snk = blocks.vector_sink_c()
    tb.connect(src, nrsar.ofdm_mod(num), snk)
    tb.run()
    x = np.array(snk.data(), np.complex64)
    cfo = 9000.0
    if periodic:
        x = np.roll(x[:slots * num.symbols_per_slot * (num.fft_size + num.cp_samples)], 1234)
        cfo = round(cfo * x.size / num.sample_rate_hz()) * num.sample_rate_hz() / x.size
    else:
        x = np.concatenate([np.zeros(1234, np.complex64), x])
    t = np.arange(x.size)
    x = x * np.exp(2j * np.pi * cfo / num.sample_rate_hz() * t)
    sigma = 10 ** (-snr_db / 20) / np.sqrt(2)
    x = x + sigma * (rng.standard_normal(x.size) + 1j * rng.standard_normal(x.size))
    return num, cfg, x.astype(np.complex64), pdus


def base_station(src, num, cfg, threads):
    """src -> ofdm_sync -> ofdm_demod -> pusch_receiver run to the end: (wall s, process CPU s,
    the receiver, each block's work time [s], ofdm_sync)."""
    tb = gr.top_block()
    sync = nrsar.ofdm_sync(num, cfg.dmrs)
    demod = nrsar.ofdm_demod(num)
    rx = nrsar.pusch_receiver(cfg)
    rx.set_threads(threads)
    tb.connect(src, sync, demod, rx)
    wall, cpu = time.perf_counter(), time.process_time()
    runtime.run(tb)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    work = {name: b.pc_work_time_total() / 1e9
            for name, b in (("ofdm_sync", sync), ("ofdm_demod", demod), ("pusch_receiver", rx))}
    return wall, cpu, rx, work, sync


def run(preset="sdr20", slots=200, snr_db=35.0, threads=1):
    num, cfg, x, pdus = uplink(preset, slots, snr_db)
    cfg.max_iterations = 8
    wall, cpu, rx, blocks_cpu, _ = base_station(blocks.vector_source_c(x.tolist(), False),
                                                num, cfg, threads)
    air = slots * num.symbols_per_slot * num.symbol_s()
    return {"preset": preset, "slots": slots, "snr_db": snr_db, "threads": threads, "air_s": air, "wall_s": wall,
            "cpu_s": cpu, "realtime_factor": air / wall, "cores_needed": cpu / air,
            "block_cpu_per_air": {k: v / air for k, v in blocks_cpu.items()},
            "tbs_bits": int(rx.tbs_bits()), "code_blocks": int(rx.code_blocks()),
            "blocks_ok": int(rx.blocks_ok()), "blocks_failed": int(rx.blocks_failed()),
            "ldpc_iterations_mean": rx.ldpc_iterations_mean(),
            "info_mbps": slots * rx.tbs_bits() / air / 1e6,
            "load_average": os.getloadavg()}


class paced_source(gr.sync_block):
    """x played in a loop at fs samples per second of wall clock for `seconds`, as a radio
    delivers samples: those that arrived wait in a FIFO of `fifo` samples while the output
    buffer is full; what the FIFO cannot hold is dropped (overflows(), dropped()). Like a
    USRP source, the first sample and the first after each overflow carry `rx_time` (the
    radio's sample count / fs)."""

    def __init__(self, x, fs, seconds, fifo, chunk=8192):
        gr.sync_block.__init__(self, "paced_source", None, [np.complex64])
        self.x, self.fs, self.total = x, fs, int(round(seconds * fs))
        self.fifo, self.chunk = fifo, chunk
        self.delivered = self.lost = self.events = 0
        self.t0, self.first = None, None  # start; air time [s] of the first overflow
        self.stamp = True  # the next sample delivered gets an rx_time tag

    def work(self, input_items, output_items):
        out = output_items[0]
        if self.t0 is None:
            self.t0 = time.perf_counter()
        while True:  # wait for a chunk of samples (or the last ones) to arrive
            arrived = min(int((time.perf_counter() - self.t0) * self.fs), self.total)
            backlog = arrived - self.delivered - self.lost
            if backlog >= self.chunk or (arrived == self.total and backlog > 0):
                break
            if arrived == self.total:
                return -1  # WORK_DONE
            time.sleep((self.chunk - backlog) / self.fs)
        n = min(backlog, len(out))
        pos = (self.delivered + self.lost) % self.x.size  # the radio's sample index
        first = min(n, self.x.size - pos)
        out[:first] = self.x[pos:pos + first]
        out[first:n] = self.x[:n - first]
        if self.stamp:
            self.add_item_tag(0, self.nitems_written(0), pmt.intern("rx_time"),
                              recording.rx_time_value((self.delivered + self.lost) / self.fs))
            self.stamp = False
        self.delivered += n
        if backlog - n > self.fifo:  # overflow: the radio drops what its FIFO cannot hold
            self.lost += backlog - n - self.fifo
            self.events += 1
            self.stamp = True
            if self.first is None:
                self.first = arrived / self.fs
        return n

    def overflows(self):
        return self.events

    def dropped(self):
        return self.lost


def run_paced(preset="sdr20", seconds=10.0, snr_db=35.0, threads=2, fifo_ms=2.0):
    """The base station fed at the radio's rate for `seconds` of air (wall-clock real time)."""
    slots = 20 * 10  # 10 frames played in a loop
    num, cfg, x, _ = uplink(preset, slots, snr_db, periodic=True)
    cfg.max_iterations = 8
    fs = num.sample_rate_hz()
    src = paced_source(x, fs, seconds, int(fifo_ms * 1e-3 * fs))
    src.set_min_output_buffer(1 << 16)
    wall, cpu, rx, blocks_cpu, sync = base_station(src, num, cfg, threads)
    return {"preset": preset, "air_s": seconds, "threads": threads, "fifo_ms": fifo_ms,
            "wall_s": wall, "wall_over_air": wall / seconds, "cpu_s": cpu,
            "cores_used": cpu / seconds, "overflows": src.overflows(),
            "dropped_samples": src.dropped(), "first_overflow_s": src.first,
            "symbols_received": int(rx.nitems_read(0)),
            "block_cpu_per_air": {k: v / seconds for k, v in blocks_cpu.items()},
            "slots_sent": int(round(seconds / (num.symbols_per_slot * num.symbol_s()))),
            "blocks_ok": int(rx.blocks_ok()), "blocks_failed": int(rx.blocks_failed()),
            "blocks_lost": int(rx.blocks_lost()), "partial_slots": int(rx.partial_slots()),
            "sync_lost_samples": int(sync.lost_samples()),
            "sync_reacquisitions": int(sync.reacquisitions()),
            "sync_lock_losses": int(sync.lock_losses()),
            "sync_skipped_slots": int(sync.skipped_slots()),
            "ldpc_iterations_mean": rx.ldpc_iterations_mean(),
            "load_average": os.getloadavg(), "cpus": os.cpu_count()}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--preset", default="sdr20", choices=nrsar.numerology.preset_names())
    p.add_argument("--slots", type=int, default=200)
    p.add_argument("--snr-db", type=float, default=35.0)
    p.add_argument("--threads", type=int, choices=(1, 2), default=1,
                   help="pusch_receiver threads per slot (code blocks decoded on two)")
    p.add_argument("--paced", type=float, metavar="SECONDS",
                   help="instead: SECONDS of air at the radio's sample rate (wall clock)")
    p.add_argument("--fifo-ms", type=float, default=2.0,
                   help="with --paced: the radio's receive FIFO before it overflows")
    a = p.parse_args(argv)
    if a.slots < 1:
        p.error(f"--slots = {a.slots} must be at least 1")
    if a.paced is not None:
        if not a.paced > 0 or not a.fifo_ms >= 0:
            p.error(f"--paced = {a.paced} must be > 0 and --fifo-ms = {a.fifo_ms} >= 0")
        print(run_paced(a.preset, a.paced, a.snr_db, a.threads, a.fifo_ms))
        return
    print(run(a.preset, a.slots, a.snr_db, a.threads))


if __name__ == "__main__":
    main()
