#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Flowgraph throughput of cheby_presum (pulses/s) against stock gr::filter decimation.

K = 256 range bins per pulse, D = 10, 4 D = 40 taps, paper preset (PRF 24 kHz).

Peers (the same taps, no phase compensation, which stock blocks do not have):
- `fir_filter_ccc x K (vector_to_streams)`: the stock way on vectors: vector_to_streams
  splits each pulse into K streams, K filter.fir_filter_ccc(D, taps) decimate each range
  bin, streams_to_vector rebuilds the pulses (K + 2 blocks, one thread each).
- `fir_filter_ccc, range-major stream`: one fir_filter_ccc(D) over data already corner
  turned (every range bin's pulses contiguous): the FIR arithmetic alone, without the
  transpose a real chain would need (favours the peer).
Also: the end-to-end TF filter -> range IFFT stage with the presummer before the IFFT
(TF domain, N = 3333, IFFT at PRF / D) against after it (range domain, K bins, IFFT at
the full PRF): input symbols/s of the two chains.
"""

import numpy as np
from gnuradio import blocks, fft, filter, gr

from gnuradio import nrsar
from gnuradio.nrsar.bench import benchutil

K = 256
D = 10


def _pulses(k, count=64, seed=5):
    rng = np.random.default_rng(seed)
    x = rng.normal(size=(count, k)) + 1j * rng.normal(size=(count, k))
    return x.astype(np.complex64).ravel().tolist()


def run(quick=False):
    num = nrsar.make_numerology("paper")
    geo = nrsar.make_geometry("paper")
    scn = nrsar.make_scene("paper3")
    n_items = 4000 if quick else 40000
    rows = []
    x = _pulses(K)
    probe = nrsar.cheby_presum(num, geo, scn, K, 1000.0, 1.5, nrsar.presum_config(
        method=nrsar.presum_method.CHEBY, decim=D, domain=nrsar.presum_domain.RANGE))
    taps = [complex(t) for t in probe.prototype()]

    def ours(tb, items, method=nrsar.presum_method.CHEBY):
        src = blocks.vector_source_c(x, True, K)
        head = blocks.head(gr.sizeof_gr_complex * K, items)
        blk = nrsar.cheby_presum(num, geo, scn, K, 1000.0, 1.5, nrsar.presum_config(
            method=method, decim=D, domain=nrsar.presum_domain.RANGE))
        tb.connect(src, head, blk, blocks.null_sink(gr.sizeof_gr_complex * K))

    def peer_streams(tb, items):
        src = blocks.vector_source_c(x, True, K)
        head = blocks.head(gr.sizeof_gr_complex * K, items)
        v2s = blocks.vector_to_streams(gr.sizeof_gr_complex, K)
        s2v = blocks.streams_to_vector(gr.sizeof_gr_complex, K)
        tb.connect(src, head, v2s)
        for i in range(K):
            f = filter.fir_filter_ccc(D, taps)
            tb.connect((v2s, i), f, (s2v, i))
        tb.connect(s2v, blocks.null_sink(gr.sizeof_gr_complex * K))

    def peer_stream(tb, items):
        # items pulses x K bins as one range-major stream of complex samples.
        src = blocks.vector_source_c(x, True)
        head = blocks.head(gr.sizeof_gr_complex, items * K)
        f = filter.fir_filter_ccc(D, taps)
        tb.connect(src, head, f, blocks.null_sink(gr.sizeof_gr_complex))

    cheby = benchutil.items_per_second(ours, n_items)
    n_peer = max(n_items // 10, 400) if quick else n_items // 4
    streams = benchutil.items_per_second(peer_streams, n_peer, repeats=1 if quick else 2)
    stream = benchutil.items_per_second(peer_stream, n_items)
    rows.append(benchutil.row(f"cheby_presum K={K} D={D} (CHEBY, 40 taps)", cheby,
                              "fir_filter_ccc x K (vector_to_streams)", streams,
                              unit="pulses/s"))
    rows.append(benchutil.row(f"cheby_presum K={K} D={D} (CHEBY, 40 taps)", cheby,
                              "fir_filter_ccc, range-major stream (no transpose)", stream,
                              unit="pulses/s"))
    for name, method in (("FILTER_DROP", nrsar.presum_method.FILTER_DROP),
                         ("BOXCAR", nrsar.presum_method.BOXCAR),
                         ("DROP", nrsar.presum_method.DROP)):
        rate = benchutil.items_per_second(lambda tb, it, m=method: ours(tb, it, m), n_items)
        rows.append(benchutil.row(f"cheby_presum K={K} D={D} ({name})", rate,
                                  "cheby_presum CHEBY", cheby, unit="pulses/s"))

    # Before vs after the range IFFT (paper numerology, fast FFT size, crop of K bins).
    n = num.num_subcarriers
    nfft = nrsar.fast_fft_size(n)
    rif0 = nrsar.range_ifft(num, nfft, fft.window.WIN_RECTANGULAR, -1.0, 990.0, 0.0)
    first, rho = rif0.range_axis_first_m(), rif0.range_bin_m()
    r_max = first + (K - 1) * rho + 1e-6
    xs = _pulses(n, count=16)
    n_sym = 2400 if quick else 24000

    def before(tb, items):
        src = blocks.vector_source_c(xs, True, n)
        head = blocks.head(gr.sizeof_gr_complex * n, items)
        pre = nrsar.cheby_presum(num, geo, scn, n, cfg=nrsar.presum_config(
            method=nrsar.presum_method.CHEBY, decim=D, domain=nrsar.presum_domain.TF))
        rif = nrsar.range_ifft(num, nfft, fft.window.WIN_RECTANGULAR, -1.0, first, r_max)
        tb.connect(src, head, pre, rif, blocks.null_sink(gr.sizeof_gr_complex * rif.num_bins()))

    def after(tb, items, crop=True):
        src = blocks.vector_source_c(xs, True, n)
        head = blocks.head(gr.sizeof_gr_complex * n, items)
        if crop:
            rif = nrsar.range_ifft(num, nfft, fft.window.WIN_RECTANGULAR, -1.0, first, r_max)
        else:
            rif = nrsar.range_ifft(num, nfft, fft.window.WIN_RECTANGULAR, -1.0)
        first_m = rif.range_axis_first_m()
        pre = nrsar.cheby_presum(num, geo, scn, rif.num_bins(), first_m, rho, nrsar.presum_config(
            method=nrsar.presum_method.CHEBY, decim=D, domain=nrsar.presum_domain.RANGE))
        tb.connect(src, head, rif, pre, blocks.null_sink(gr.sizeof_gr_complex * rif.num_bins()))

    r_before = benchutil.items_per_second(before, n_sym, repeats=2)
    r_after = benchutil.items_per_second(after, n_sym, repeats=2)
    r_after_full = benchutil.items_per_second(lambda tb, it: after(tb, it, False), n_sym,
                                              repeats=2)
    rows.append(benchutil.row(f"presum before IFFT (TF, N={n}, IFFT {nfft} at PRF/{D})",
                              r_before, f"presum after IFFT, crop K={K} bins", r_after,
                              unit="symbols/s"))
    rows.append(benchutil.row(f"presum before IFFT (TF, N={n}, IFFT {nfft} at PRF/{D})",
                              r_before, f"presum after IFFT, no crop (K={nfft})", r_after_full,
                              unit="symbols/s"))
    return rows


if __name__ == "__main__":
    benchutil.main(run, __doc__)
