#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""range_compress (tf_filter and range_ifft in one pass) against the two blocks in a row and
against a bare fft_vcc, same run, same input (paper numerology: 3333 REs, 256-QAM grid, WF,
Hann, 3360 points cropped to 90 bins).

Rows: the flowgraph rate of the fused block against tf_filter -> range_ifft; the CPU time in
work() of both (GNU Radio's performance counters: the fused block against the two summed);
and the fused block's work() time against `fft.fft_vcc` 3360 fed symbols already padded
(the transform alone, no filter, window or crop: the floor range compression can reach).
"""

import math

import numpy as np
from gnuradio import blocks, fft, gr

from gnuradio import nrsar
from gnuradio.nrsar import runtime
from gnuradio.nrsar.bench import benchutil

N = 3333
NFFT = 3360
R_MIN, R_MAX = 1000.0, 1450.0  # 90 bins of 4.46 m, the paper swath's size


def _grid(symbols=16, seed=3):
    rng = np.random.default_rng(seed)
    y = rng.normal(size=(symbols, N)) + 1j * rng.normal(size=(symbols, N))
    lv = 2 * rng.integers(0, 16, size=(symbols, N, 2)) - 15
    s = (lv[..., 0] + 1j * lv[..., 1]) / math.sqrt(170)
    return (y.astype(np.complex64).ravel().tolist(), s.astype(np.complex64).ravel().tolist())


def _fused(num):
    return nrsar.range_compress(num, nrsar.range_compress_config(
        filter=nrsar.filter_type.WF, snr_db=-20.0, fft_size=NFFT, window=fft.window.WIN_HANN,
        r_min_m=R_MIN, r_max_m=R_MAX))


def build(tb, n_items, y, s, fused):
    """Sources of y and s -> (range_compress | tf_filter -> range_ifft) -> head -> null sink;
    returns the receive blocks."""
    num = nrsar.make_numerology("paper")
    sy, ss = blocks.vector_source_c(y, True, N), blocks.vector_source_c(s, True, N)
    if fused:
        front = [_fused(num)]
        first = last = front[0]
    else:
        front = [nrsar.tf_filter(N, nrsar.filter_type.WF, -20.0, False),
                 nrsar.range_ifft(num, NFFT, fft.window.WIN_HANN, -1.0, R_MIN, R_MAX)]
        tb.connect(front[0], front[1])
        first, last = front
    tb.connect(sy, (first, 0))
    tb.connect(ss, (first, 1))
    k = last.num_bins()
    tb.connect(last, blocks.head(gr.sizeof_gr_complex * k, n_items),
               blocks.null_sink(gr.sizeof_gr_complex * k))
    return front


def work_us(n_items, y, s):
    """work() us per symbol: fused, separate (summed), and fft_vcc 3360 fed padded symbols."""
    result = {}
    for name in ("fused", "separate"):
        tb = gr.top_block()
        used = build(tb, n_items, y, s, name == "fused")
        runtime.run(tb)
        result[name] = sum(b.pc_work_time_total() for b in used) / n_items / 1e3
    rng = np.random.default_rng(4)
    x = np.zeros((16, NFFT), np.complex64)
    x[:, :N] = rng.normal(size=(16, N)) + 1j * rng.normal(size=(16, N))
    f = fft.fft_vcc(NFFT, False, list(fft.window.hann(N)) + [0.0] * (NFFT - N), False, 1)
    tb = gr.top_block()
    tb.connect(blocks.vector_source_c(x.ravel().tolist(), True, NFFT),
               blocks.head(gr.sizeof_gr_complex * NFFT, n_items), f,
               blocks.null_sink(gr.sizeof_gr_complex * NFFT))
    runtime.run(tb)
    result["fft_vcc"] = f.pc_work_time_total() / n_items / 1e3
    return result


def run(quick=False):
    n = 2000 if quick else 20000
    y, s = _grid()
    fused = benchutil.items_per_second(lambda tb, k: build(tb, k, y, s, True), n)
    separate = benchutil.items_per_second(lambda tb, k: build(tb, k, y, s, False), n)
    us = work_us(n, y, s)
    return [
        benchutil.row("range_compress WF 3333 -> 3360, 90 bins", fused,
                      "tf_filter > range_ifft, same parameters", separate,
                      unit="symbols/s", vlen=N),
        benchutil.row("range_compress work() time", 1.0 / us["fused"],
                      "tf_filter + range_ifft work() summed", 1.0 / us["separate"],
                      unit="symbols per us of work()", ours_us=us["fused"],
                      peer_us=us["separate"]),
        benchutil.row("range_compress (filter, window, 3360 IFFT, crop) work() time",
                      1.0 / us["fused"], "fft.fft_vcc 3360 fed pre-padded symbols",
                      1.0 / us["fft_vcc"], unit="symbols per us of work()",
                      ours_us=us["fused"], peer_us=us["fft_vcc"]),
    ]


if __name__ == "__main__":
    benchutil.main(run, __doc__)
