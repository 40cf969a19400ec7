#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Flowgraph throughput of tf_filter against stock chains computing the same, same run.

WF at vlen 3333 against the stock GNU Radio chain
    multiply_conjugate_cc(y, s) / float_to_complex(add_const_vff(complex_to_mag_squared(s)))
(all with vlen 3333), and RF against gr-radar's ofdm_divide_vcvc (y / s, a tagged-stream
block fed by stream_to_tagged_stream). Items are OFDM symbols of 3333 REs; both sides read
the same repeating 256-QAM data.
"""

import importlib.util
import math

import numpy as np
from gnuradio import blocks, gr

from gnuradio import nrsar
from gnuradio.nrsar import runtime
from gnuradio.nrsar.bench import benchutil

VLEN = 3333
SNR_DB = 5.0
PACKET = 4  # symbols per tagged-stream packet of ofdm_divide_vcvc (fits its buffers)


def _data(vlen, symbols=16, seed=1):
    rng = np.random.default_rng(seed)
    b = rng.integers(0, 2, size=(vlen * symbols, 8)).astype(float)
    a = 1 - 2 * b
    s = ((a[:, 0] * (8 - a[:, 2] * (4 - a[:, 4] * (2 - a[:, 6]))) +
          1j * a[:, 1] * (8 - a[:, 3] * (4 - a[:, 5] * (2 - a[:, 7])))) / math.sqrt(170))
    y = s * np.exp(2j * np.pi * rng.random(s.size)) + 0.5 * (
        rng.normal(size=s.size) + 1j * rng.normal(size=s.size))
    return y.astype(np.complex64).tolist(), s.astype(np.complex64).tolist()


def _sources(tb, y, s, vlen):
    return blocks.vector_source_c(y, True, vlen), blocks.vector_source_c(s, True, vlen)


def _sink(tb, n, vlen):
    """head(n) -> null_sink on the output: the only copy that bounds the run. (Heads on the
    inputs would add two 13.6 MB buffers of memory traffic to both sides: at vlen 3333 an
    item is 26664 bytes and a page-aligned buffer holds lcm(26664, 4096) bytes, 512 items,
    so every extra edge costs a cache-cold write and read of each item.)"""
    head = blocks.head(gr.sizeof_gr_complex * vlen, n)
    tb.connect(head, blocks.null_sink(gr.sizeof_gr_complex * vlen))
    return head


def _build_ours(tb, n_items, y, s, vlen, ftype):
    hy, hs = _sources(tb, y, s, vlen)
    blk = nrsar.tf_filter(vlen, ftype, SNR_DB, False)
    tb.connect(hy, (blk, 0))
    tb.connect(hs, (blk, 1))
    tb.connect(blk, _sink(tb, n_items, vlen))
    return [blk]


def _build_wf(tb, n_items, y, s, vlen, stock):
    """Our WF block or the stock WF chain; returns the blocks that compute the filter."""
    if not stock:
        return _build_ours(tb, n_items, y, s, vlen, nrsar.filter_type.WF)
    hy, hs = _sources(tb, y, s, vlen)
    num = blocks.multiply_conjugate_cc(vlen)
    mag2 = blocks.complex_to_mag_squared(vlen)
    reg = blocks.add_const_vff([10 ** (-SNR_DB / 10)] * vlen)
    f2c = blocks.float_to_complex(vlen)
    div = blocks.divide_cc(vlen)
    tb.connect(hy, (num, 0))
    tb.connect(hs, (num, 1))
    tb.connect(hs, mag2, reg, f2c)
    tb.connect(num, (div, 0))
    tb.connect(f2c, (div, 1))
    tb.connect(div, _sink(tb, n_items, vlen))
    return [num, mag2, reg, f2c, div]


def _build_rf(tb, n_items, y, s, vlen, radar_peer):
    """Our RF block or gr-radar's ofdm_divide_vcvc; returns the blocks that compute it."""
    if not radar_peer:
        return _build_ours(tb, n_items, y, s, vlen, nrsar.filter_type.RF)
    hy, hs = _sources(tb, y, s, vlen)
    from gnuradio import radar
    key = "packet_len"
    ty = blocks.stream_to_tagged_stream(gr.sizeof_gr_complex, vlen, PACKET, key)
    ts = blocks.stream_to_tagged_stream(gr.sizeof_gr_complex, vlen, PACKET, key)
    div = radar.ofdm_divide_vcvc(vlen, vlen, [], 0, key)
    tb.connect(hy, ty, (div, 0))
    tb.connect(hs, ts, (div, 1))
    tb.connect(div, _sink(tb, n_items, vlen))
    return [div]


def work_time_per_symbol(n_items, with_radar):
    """{wf, wf_stock, rf[, rf_radar]}: CPU time spent in work() per symbol [us] by our block
    and by the stock chain's five blocks (GNU Radio's performance counters)."""
    y, s = _data(VLEN)
    result = {}
    cases = [("wf", _build_wf, False), ("wf_stock", _build_wf, True), ("rf", _build_rf, False)]
    if with_radar:
        cases.append(("rf_radar", _build_rf, True))
    for name, build, peer in cases:
        tb = gr.top_block()
        used = build(tb, n_items, y, s, VLEN, peer)
        runtime.run(tb)
        # high_res_timer ticks (ns on Linux) per item each block produced
        per_item = sum(b.pc_work_time_total() / max(1, b.nitems_written(0)) for b in used)
        result[name] = per_item / 1e3
    return result


def run(quick=False):
    vlen = VLEN
    n = 2000 if quick else 20000
    y, s = _data(vlen)
    rows = []

    with_radar = importlib.util.find_spec("gnuradio.radar") is not None

    def ours_wf(tb, n_items):
        _build_wf(tb, n_items, y, s, vlen, False)

    def stock_wf(tb, n_items):
        _build_wf(tb, n_items, y, s, vlen, True)

    def ours_rf(tb, n_items):
        _build_rf(tb, n_items, y, s, vlen, False)

    def radar_rf(tb, n_items):
        _build_rf(tb, n_items, y, s, vlen, True)

    wf = benchutil.items_per_second(ours_wf, n)
    peer = benchutil.items_per_second(stock_wf, n)
    rows.append(benchutil.row("tf_filter WF vlen 3333", wf,
                              "stock chain (multiply_conjugate, mag_squared, add_const, "
                              "float_to_complex, divide_cc)", peer, vlen=vlen))
    rf = benchutil.items_per_second(ours_rf, n)
    if with_radar:
        peer = benchutil.items_per_second(radar_rf, n)
        rows.append(benchutil.row("tf_filter RF vlen 3333", rf, "gr-radar ofdm_divide_vcvc",
                                  peer, vlen=vlen))
    else:
        rows.append(benchutil.row("tf_filter RF vlen 3333", rf, "gr-radar (not installed)",
                                  None, vlen=vlen))

    # CPU time inside work(): what the filter itself costs, without the sources and the
    # scheduling over 2 cores that the flowgraph rates above include.
    wt = work_time_per_symbol(n, with_radar)
    rows.append(benchutil.row("tf_filter WF vlen 3333 work() time", 1.0 / wt["wf"],
                              "stock chain, sum over its 5 blocks", 1.0 / wt["wf_stock"],
                              unit="symbols per us of work()", vlen=vlen,
                              ours_us=wt["wf"], peer_us=wt["wf_stock"]))
    if with_radar:
        rows.append(benchutil.row("tf_filter RF vlen 3333 work() time", 1.0 / wt["rf"],
                                  "gr-radar ofdm_divide_vcvc", 1.0 / wt["rf_radar"],
                                  unit="symbols per us of work()", vlen=vlen,
                                  ours_us=wt["rf"], peer_us=wt["rf_radar"]))
    return rows


if __name__ == "__main__":
    benchutil.main(run, __doc__)
