#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The receive front end (per-RE filter -> range IFFT -> presum by D) against stock GNU Radio
blocks doing the same steps, same run, same input (paper numerology, 3333 REs per symbol):

    ours:  tf_filter (MF)  -> range_ifft (3360-point, cropped to the swath)
           -> cheby_presum (boxcar, D = 10)
    stock: multiply_conjugate_cc(3333) -> fft_vcc(3333, inverse) -> integrate_cc(10, 3333)

integrate_cc(D, vlen) sums D consecutive vectors: the boxcar presum. The stock chain has no
crop (every one of the 3333 bins goes on) and no fast FFT size: that is what a stock flowgraph
does. A second stock row puts keep_one_in_n (the paper's drop-by-10 shortcut) in place of the
sum. Rates are input symbols per second (flowgraph) and CPU time in work() per symbol (GNU
Radio performance counters).
"""


import numpy as np
from gnuradio import blocks, fft, gr

from gnuradio import nrsar
from gnuradio.nrsar import runtime
from gnuradio.nrsar.bench import benchutil

VLEN = 3333
D = 10


def _data(symbols=16, seed=2):
    rng = np.random.default_rng(seed)
    n = VLEN * symbols
    y = (rng.normal(size=n) + 1j * rng.normal(size=n)).astype(np.complex64)
    s = np.exp(2j * np.pi * rng.random(n)).astype(np.complex64)
    return y.tolist(), s.tolist()


def _sources(tb, y, s):
    return blocks.vector_source_c(y, True, VLEN), blocks.vector_source_c(s, True, VLEN)


def build_ours(tb, n_items, y, s):
    num = nrsar.make_numerology("paper")
    geo = nrsar.make_geometry("paper")
    scn = nrsar.make_scene("paper3")
    sy, ss = _sources(tb, y, s)
    tff = nrsar.tf_filter(VLEN, nrsar.filter_type.MF, 20.0, False)
    ext = nrsar.compute_extent(geo, scn)
    rif = nrsar.range_ifft(num, nrsar.range_ifft.fast_fft_size(VLEN),
                           fft.window.WIN_RECTANGULAR, -1.0,
                           ext.min_slant_range_m - 30.0, ext.max_slant_range_m + 30.0)
    pre = nrsar.cheby_presum(num, geo, scn, rif.num_bins(), rif.range_axis_first_m(),
                             rif.range_bin_m(), nrsar.presum_config(
                                 method=nrsar.presum_method.BOXCAR, decim=D,
                                 domain=nrsar.presum_domain.RANGE))
    head = blocks.head(gr.sizeof_gr_complex * rif.num_bins(), n_items // D)
    tb.connect(sy, (tff, 0))
    tb.connect(ss, (tff, 1))
    tb.connect(tff, rif, pre, head, blocks.null_sink(gr.sizeof_gr_complex * rif.num_bins()))
    return [tff, rif, pre]


def build_stock(tb, n_items, y, s, drop=False):
    sy, ss = _sources(tb, y, s)
    mul = blocks.multiply_conjugate_cc(VLEN)
    ifft = fft.fft_vcc(VLEN, False, [], False, 1)
    pre = blocks.keep_one_in_n(gr.sizeof_gr_complex * VLEN, D) if drop else \
        blocks.integrate_cc(D, VLEN)
    head = blocks.head(gr.sizeof_gr_complex * VLEN, n_items // D)
    tb.connect(sy, (mul, 0))
    tb.connect(ss, (mul, 1))
    tb.connect(mul, ifft, pre, head, blocks.null_sink(gr.sizeof_gr_complex * VLEN))
    return [mul, ifft, pre]


def work_time_per_symbol(n_items):
    """work() CPU us per input symbol, per chain (GNU Radio's performance counters)."""
    y, s = _data()
    result = {}
    for name, build in (("ours", build_ours), ("stock", build_stock),
                        ("stock_drop", lambda tb, n, y, s: build_stock(tb, n, y, s, True))):
        tb = gr.top_block()
        used = build(tb, n_items, y, s)
        runtime.run(tb)
        result[name] = sum(b.pc_work_time_total() for b in used) / n_items / 1e3
    return result


def run(quick=False):
    n = 2000 if quick else 20000
    y, s = _data()
    ours = benchutil.items_per_second(lambda tb, k: build_ours(tb, k, y, s), n)
    stock = benchutil.items_per_second(lambda tb, k: build_stock(tb, k, y, s), n)
    drop = benchutil.items_per_second(lambda tb, k: build_stock(tb, k, y, s, True), n)
    wt = work_time_per_symbol(n)
    unit = "input symbols/s"
    return [
        benchutil.row("rx chain MF > IFFT > boxcar D10", ours,
                      "stock multiply_conjugate_cc > fft_vcc 3333 > integrate_cc", stock,
                      unit=unit, vlen=VLEN),
        benchutil.row("rx chain MF > IFFT > boxcar D10 vs drop", ours,
                      "stock multiply_conjugate_cc > fft_vcc 3333 > keep_one_in_n", drop,
                      unit=unit, vlen=VLEN),
        benchutil.row("rx chain work() time", 1.0 / wt["ours"],
                      "stock chain (integrate_cc), 3 blocks summed", 1.0 / wt["stock"],
                      unit="symbols per us of work()", ours_us=wt["ours"], peer_us=wt["stock"]),
    ]


if __name__ == "__main__":
    benchutil.main(run, __doc__)
