#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Flowgraph throughput of image_sink against blocks.file_sink, same run.

Focused-image-like lines (K = 512, speckle plus bright points), apertures of M = 256 lines
tagged every 256 items by lines_per_aperture. Ours writes a .npy and a viridis .png per
aperture (ring of 4 files); the peer, GNU Radio's file_sink, writes the raw complex64 stream
to one file (the least a recorder does: no header, no picture, no file per aperture).
Files go to a temporary folder that is removed afterwards.
"""

import shutil
import tempfile

import numpy as np
from gnuradio import blocks, gr

from gnuradio import nrsar
from gnuradio.nrsar.bench import benchutil

K = 512
M = 256


def _lines(count=M, seed=3):
    rng = np.random.default_rng(seed)
    x = (rng.normal(size=(count, K)) + 1j * rng.normal(size=(count, K))).astype(np.complex64)
    x.ravel()[::5000] *= 10.0
    return x.ravel().tolist()


def run(quick=False):
    n_items = 4 * M if quick else 40 * M
    lines = _lines()
    folder = tempfile.mkdtemp(prefix="nrsar_bench_image_sink_")
    try:
        rows = []
        for png in (False, True):
            def ours(tb, items, png=png):
                src = benchutil.repeat_source(lines, K)
                head = blocks.head(gr.sizeof_gr_complex * K, items)
                sink = nrsar.image_sink(K, folder + "/img", write_npy=True, write_png=png,
                                        keep=4, lines_per_aperture=M)
                tb.connect(src, head, sink)

            def peer(tb, items):
                src = benchutil.repeat_source(lines, K)
                head = blocks.head(gr.sizeof_gr_complex * K, items)
                sink = blocks.file_sink(gr.sizeof_gr_complex * K, folder + "/raw.bin")
                tb.connect(src, head, sink)

            rate_ours = benchutil.items_per_second(ours, n_items)
            rate_peer = benchutil.items_per_second(peer, n_items)
            what = ".npy + viridis .png" if png else ".npy"
            rows.append(benchutil.row(f"image_sink {what} per {M} x {K} aperture", rate_ours,
                                      "blocks.file_sink (raw stream)", rate_peer,
                                      unit="lines/s"))
        return rows
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    benchutil.main(run, __doc__)
