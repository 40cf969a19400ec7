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

Not an nrsar-bench module (those compare with a peer on the same work); docs/isac.md holds
its numbers. Run: /usr/bin/python3 -m gnuradio.nrsar.bench.base_station_realtime [--preset sdr20] [--slots 200] [--threads 2]
"""

import argparse
import os
import time

import numpy as np
from gnuradio import blocks, gr

from gnuradio import nrsar
from gnuradio.nrsar import backhaul, runtime


def uplink(preset, slots, snr_db, seed=1):
    """(num, cfg, time-domain burst as complex64, payload PDUs)."""
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
    x = np.concatenate([np.zeros(1234, np.complex64), x])
    t = np.arange(x.size)
    x = x * np.exp(2j * np.pi * 9000.0 / num.sample_rate_hz() * t)
    sigma = 10 ** (-snr_db / 20) / np.sqrt(2)
    x = x + sigma * (rng.standard_normal(x.size) + 1j * rng.standard_normal(x.size))
    return num, cfg, x.astype(np.complex64), pdus


def run(preset="sdr20", slots=200, snr_db=35.0, threads=1):
    num, cfg, x, pdus = uplink(preset, slots, snr_db)
    cfg.max_iterations = 8
    tb = gr.top_block()
    src = blocks.vector_source_c(x.tolist(), False)
    sync = nrsar.ofdm_sync(num, cfg.dmrs)
    demod = nrsar.ofdm_demod(num)
    rx = nrsar.pusch_receiver(cfg)
    rx.set_threads(threads)
    tb.connect(src, sync, demod, rx)
    wall, cpu = time.perf_counter(), time.process_time()
    runtime.run(tb)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    air = slots * num.symbols_per_slot * num.symbol_s()
    blocks_cpu = {name: b.pc_work_time_total() / 1e9
                  for name, b in (("ofdm_sync", sync), ("ofdm_demod", demod),
                                  ("pusch_receiver", rx))}
    return {"preset": preset, "slots": slots, "snr_db": snr_db, "threads": threads, "air_s": air, "wall_s": wall,
            "cpu_s": cpu, "realtime_factor": air / wall, "cores_needed": cpu / air,
            "block_cpu_per_air": {k: v / air for k, v in blocks_cpu.items()},
            "tbs_bits": int(rx.tbs_bits()), "code_blocks": int(rx.code_blocks()),
            "blocks_ok": int(rx.blocks_ok()), "blocks_failed": int(rx.blocks_failed()),
            "ldpc_iterations_mean": rx.ldpc_iterations_mean(),
            "info_mbps": slots * rx.tbs_bits() / air / 1e6,
            "load_average": os.getloadavg()}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--preset", default="sdr20")
    p.add_argument("--slots", type=int, default=200)
    p.add_argument("--snr-db", type=float, default=35.0)
    p.add_argument("--threads", type=int, choices=(1, 2), default=1,
                   help="pusch_receiver threads per slot (code blocks decoded on two)")
    a = p.parse_args(argv)
    print(run(a.preset, a.slots, a.snr_db, a.threads))


if __name__ == "__main__":
    main()
