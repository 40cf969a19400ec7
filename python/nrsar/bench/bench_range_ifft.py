#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Flowgraph throughput of range_ifft against gnuradio.fft.fft_vcc, same run.

N = 3333 subcarriers with a Hamming window, no crop. The peer is fft_vcc (inverse, same
window, one FFTW thread) at the same transform size. For the padded sizes it runs twice:
fed symbols already padded to the FFT size (padding for free, and no 1/sqrt(N) scale: this
favours the peer, whose input items of 4096 or 3360 complex also get page-sized buffers
of a few hundred kB where 3333-complex items get 13.6 MB ones), and padded by stock blocks
from the same 3333-vectors our block reads (the chain a user would build). At 3360 points the
pre-padded peer runs a third time with its input edge given the 512 items (13.6 MB) a
3333-wide edge gets (page granularity): the same cache-cold input as our block, so that row
compares the blocks' own work.
"""

import numpy as np
from gnuradio import blocks, fft, gr

from gnuradio import nrsar
from gnuradio.nrsar import runtime
from gnuradio.nrsar.bench import benchutil

N = 3333
# GNU Radio's smallest buffer for 3333-complex items: lcm(26664, 4096) bytes = 512 items.
EDGE_ITEMS = 512


def _symbols(n, length, count=8, seed=2):
    rng = np.random.default_rng(seed)
    x = np.zeros((count, length), dtype=np.complex64)
    x[:, :n] = rng.normal(size=(count, n)) + 1j * rng.normal(size=(count, n))
    return x.ravel().tolist()


def _source(x, vlen, items, edge=0):
    """vector_source > head of `items` vectors; edge: their output buffers in items."""
    src = blocks.vector_source_c(x, True, vlen)
    head = blocks.head(gr.sizeof_gr_complex * vlen, items)
    if edge:
        src.set_min_output_buffer(edge)
        head.set_min_output_buffer(edge)
    return src, head


def work_time_per_symbol(n_items, x_n):
    """(ours, fft_vcc, fft_vcc through an EDGE_ITEMS buffer) us in work() per symbol at 3360
    points (GNU Radio's performance counters, wall clock inside work()). The peer's
    3360-wide items get 430 kB buffers, whose items arrive from the core's cache, where
    3333-wide ones get 13.6 MB: the third figure gives the peer's input that buffer too."""
    nfft = nrsar.fast_fft_size(N)
    num = nrsar.make_numerology("paper")
    blk = nrsar.range_ifft(num, nfft, fft.window.WIN_HAMMING)
    window = list(fft.window.hamming(N)) + [0.0] * (nfft - N)
    f = fft.fft_vcc(nfft, False, window, False, 1)
    f_edge = fft.fft_vcc(nfft, False, window, False, 1)
    x_pad = _symbols(N, nfft)
    result = []
    for block, x, vlen, edge in ((blk, x_n, N, 0), (f, x_pad, nfft, 0),
                                 (f_edge, x_pad, nfft, EDGE_ITEMS)):
        tb = gr.top_block()
        out = blk.num_bins() if block is blk else nfft
        tb.connect(*_source(x, vlen, n_items, edge), block, blocks.null_sink(gr.sizeof_gr_complex * out))
        runtime.run(tb)
        result.append(block.pc_work_time_total() / n_items / 1e3)
    return result


def run(quick=False):
    n_items = 2000 if quick else 20000
    num = nrsar.make_numerology("paper")
    rows = []
    x_n = _symbols(N, N)
    for nfft in (N, nrsar.fast_fft_size(N), 4096):
        def ours(tb, items, nfft=nfft):
            src = blocks.vector_source_c(x_n, True, N)
            head = blocks.head(gr.sizeof_gr_complex * N, items)
            blk = nrsar.range_ifft(num, nfft, fft.window.WIN_HAMMING)
            tb.connect(src, head, blk, blocks.null_sink(gr.sizeof_gr_complex * blk.num_bins()))

        x_pad = _symbols(N, nfft)
        window = list(fft.window.hamming(N)) + [0.0] * (nfft - N)

        def peer(tb, items, nfft=nfft, x_pad=x_pad, window=window, edge=0):
            f = fft.fft_vcc(nfft, False, window, False, 1)
            tb.connect(*_source(x_pad, nfft, items, edge), f, blocks.null_sink(gr.sizeof_gr_complex * nfft))

        def peer_padded(tb, items, nfft=nfft, window=window):
            # The stock way to pad 3333-vectors to nfft: vector_to_stream, stream_mux with
            # a null_source, stream_to_vector.
            src = blocks.vector_source_c(x_n, True, N)
            head = blocks.head(gr.sizeof_gr_complex * N, items)
            v2s = blocks.vector_to_stream(gr.sizeof_gr_complex, N)
            mux = blocks.stream_mux(gr.sizeof_gr_complex, [N, nfft - N])
            s2v = blocks.stream_to_vector(gr.sizeof_gr_complex, nfft)
            f = fft.fft_vcc(nfft, False, window, False, 1)
            tb.connect(src, head, v2s, (mux, 0))
            tb.connect(blocks.null_source(gr.sizeof_gr_complex), (mux, 1))
            tb.connect(mux, s2v, f, blocks.null_sink(gr.sizeof_gr_complex * nfft))

        a = benchutil.items_per_second(ours, n_items)
        b = benchutil.items_per_second(peer, n_items)
        rows.append(benchutil.row(f"range_ifft N 3333 fft {nfft}", a,
                                  f"fft.fft_vcc {nfft} (inverse, Hamming)"
                                  + (", fed pre-padded symbols" if nfft > N else ""), b,
                                  fft_size=nfft))
        if nfft == nrsar.fast_fft_size(N):
            d = benchutil.items_per_second(lambda tb, items: peer(tb, items, edge=EDGE_ITEMS),
                                           n_items)
            rows.append(benchutil.row(f"range_ifft N 3333 fft {nfft}", a,
                                      f"fft.fft_vcc {nfft} fed pre-padded symbols through a "
                                      f"{EDGE_ITEMS}-item buffer (as a 3333-wide edge)", d,
                                      fft_size=nfft))
        if nfft > N:
            c = benchutil.items_per_second(peer_padded, n_items)
            rows.append(benchutil.row(f"range_ifft N 3333 fft {nfft}", a,
                                      f"fft.fft_vcc {nfft} padded by stream_mux", c,
                                      fft_size=nfft))
    ours_us, peer_us, edge_us = work_time_per_symbol(n_items, x_n)
    rows.append(benchutil.row("range_ifft 3333 -> 3360 work() time", 1.0 / ours_us,
                              "fft.fft_vcc 3360 fed pre-padded symbols", 1.0 / peer_us,
                              unit="symbols per us of work()", ours_us=ours_us,
                              peer_us=peer_us))
    rows.append(benchutil.row("range_ifft 3333 -> 3360 work() time", 1.0 / ours_us,
                              f"fft.fft_vcc 3360 fed pre-padded symbols through a {EDGE_ITEMS}-"
                              "item buffer (as a 3333-wide edge)", 1.0 / edge_us,
                              unit="symbols per us of work()", ours_us=ours_us,
                              peer_us=edge_us))
    # The block at the fast size against the stock block at the unpadded size: the speed
    # a user gains by padding.
    rows.append(benchutil.row(f"range_ifft fft {rows[1]['fft_size']} vs fft_vcc 3333",
                              rows[1]["ours"], "fft.fft_vcc 3333", rows[0]["peer_rate"]))
    return rows


if __name__ == "__main__":
    benchutil.main(run, __doc__)
