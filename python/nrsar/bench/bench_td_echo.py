#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""td_echo throughput (samples/s) at the paper numerology (122.88 Msps) with the paper3
scene against gr-radar's static_target_simulator_cc with the same three targets in the same
run (ratio ours / peer; the paper needs 122.88e6 samples/s for real time). Rates per wall
second (benchutil) and per CPU second of the process (ratio_cpu; steadier on a shared machine).

Flowgraphs: vector_source_c (repeating 8 random unit-power blocks of 4096 samples) -> head
-> td_echo -> null_sink; the peer: vector_source_c -> head -> stream_to_tagged_stream
(packets of fft_size = 4096 samples) -> static_target_simulator_cc (3 targets, velocity 0,
no random phase, no self coupling, one RX) -> null_sink. The peer delays each packet
circularly by FFT (one FFT/IFFT pair per target and packet); td_echo filters the stream
with an FIR of `taps` taps per sample and target cluster.
"""

import time

import numpy as np

from gnuradio import blocks, gr

from . import benchutil
from ..nrsar_python import td_echo
from ..params import make_geometry, make_numerology, make_scene

C = 299792458.0


def _samples(count, seed=1):
    rng = np.random.default_rng(seed)
    x = np.sqrt(0.5) * (rng.standard_normal(count) + 1j * rng.standard_normal(count))
    return x.astype(np.complex64).tolist()


def _peer_block(num, geo, scn, packet):
    from gnuradio import radar
    ranges = [t.slant_range_m(geo, geo.track_start_m) for t in scn.targets]
    n = len(ranges)
    return radar.static_target_simulator_cc(
        ranges, [0.0] * n, [t.rcs for t in scn.targets], [0.0] * n, [0.0],
        int(round(num.sample_rate_hz())), geo.carrier_hz, -10.0, False, False, "packet_len")


def run(quick=False):
    num = make_numerology("paper")
    geo = make_geometry("paper")
    scn = make_scene("paper3")
    packet = num.fft_size
    n_items = 8 * 1024 * 1024 if quick else 64 * 1024 * 1024
    src_data = _samples(8 * packet)
    size = gr.sizeof_gr_complex

    def ours(snr_db, taps):
        def connect(tb, n):
            src = blocks.vector_source_c(src_data, True)
            tb.connect(src, blocks.head(size, n), td_echo(num, geo, scn, snr_db, 1, taps),
                       blocks.null_sink(size))
        return connect

    def peer(tb, n):
        src = blocks.vector_source_c(src_data, True)
        s2t = blocks.stream_to_tagged_stream(size, 1, packet, "packet_len")
        tb.connect(src, blocks.head(size, n), s2t, _peer_block(num, geo, scn, packet),
                   blocks.null_sink(size))

    def source_only(tb, n):
        src = blocks.vector_source_c(src_data, True)
        tb.connect(src, blocks.head(size, n), blocks.null_sink(size))

    try:
        peer_rate = benchutil.items_per_second(peer, n_items)
        peer_cpu = benchutil.items_per_second(peer, n_items, clock=time.process_time)
        peer_name = "gr-radar static_target_simulator_cc (4096-sample packets)"
    except ImportError:
        peer_rate, peer_cpu, peer_name = None, None, "gr-radar not installed"
    rows = []
    for name, snr_db, taps in (("td_echo paper 3 targets, 32 taps, noise-free", float("inf"), 32),
                               ("td_echo paper 3 targets, 32 taps, 20 dB noise", 20.0, 32),
                               ("td_echo paper 3 targets, 16 taps, noise-free", float("inf"), 16),
                               ("td_echo paper 3 targets, 64 taps, noise-free", float("inf"), 64)):
        rate = benchutil.items_per_second(ours(snr_db, taps), n_items)
        cpu = benchutil.items_per_second(ours(snr_db, taps), n_items, clock=time.process_time)
        rows.append(benchutil.row(name, rate, peer_name, peer_rate, unit="samples/s",
                                  realtime_factor=rate / num.sample_rate_hz(),
                                  ours_per_cpu_s=cpu, peer_per_cpu_s=peer_cpu,
                                  ratio_cpu=(cpu / peer_cpu) if peer_cpu else None,
                                  items=n_items))
    floor = benchutil.items_per_second(source_only, n_items)
    rows.append(benchutil.row("vector_source_c>head>null_sink (no echo)", floor, peer_name,
                              peer_rate, unit="samples/s", items=n_items))
    return rows


if __name__ == "__main__":
    benchutil.main(run, __doc__)
