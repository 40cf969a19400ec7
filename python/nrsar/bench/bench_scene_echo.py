#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""scene_echo throughput (resource elements/s, paper numerology, 3 targets) against a
numpy float64 evaluation of the same formula, eq. (7) with the exact range (8), in the
same run. numpy runs fewer symbols (its rate per RE does not depend on M); the ratio is
per RE. `paper_aperture_s` projects the wall time of the paper's 3333 x 48000 aperture.

Flowgraph: vector_source_c (repeating 16 random QPSK symbols) -> head -> scene_echo ->
null_sink (and a second null_sink on the reference output where noted).
"""

import time

import numpy as np

from gnuradio import blocks, gr

from . import benchutil
from ..nrsar_python import scene_echo
from ..params import make_geometry, make_numerology, make_scene

PAPER_RES = 3333 * 48000
C = 299792458.0


def _symbols(n_sc, count=16, seed=1):
    rng = np.random.default_rng(seed)
    a = np.sqrt(0.5)
    s = a * (rng.choice([-1.0, 1.0], count * n_sc) + 1j * rng.choice([-1.0, 1.0], count * n_sc))
    return s.astype(np.complex64)


def numpy_echo(num, geo, targets, s, m0, sigma, rng):
    """eq. (7)-(8) in numpy float64 for the symbols m0 .. m0 + len(s) - 1, plus noise."""
    M, N = s.shape
    m = m0 + np.arange(M, dtype=np.float64)
    yp = geo.track_start_m + geo.velocity_mps * m * num.symbol_s()
    f = geo.carrier_hz + np.arange(N) * num.subcarrier_spacing_hz
    h = np.zeros((M, N), dtype=np.complex128)
    for t in targets:
        R = np.sqrt(t.x_m ** 2 + geo.height_m ** 2 + (yp - t.y_m) ** 2)
        h += np.sqrt(t.rcs) * np.exp(-1j * 4.0 * np.pi / C * np.outer(R, f))
    y = s * h
    if sigma > 0:
        y += sigma * np.sqrt(0.5) * (rng.standard_normal((M, N)) + 1j * rng.standard_normal((M, N)))
    return y


def _numpy_rate(num, geo, scn, sigma, n_sym, block=48):
    rng = np.random.default_rng(2)
    s = _symbols(num.num_subcarriers, block).reshape(block, -1).astype(np.complex128)
    best = float("inf")
    for _ in range(2):
        start = time.perf_counter()
        for m0 in range(0, n_sym, block):
            numpy_echo(num, geo, scn.targets, s, m0, sigma, rng)
        best = min(best, time.perf_counter() - start)
    return n_sym * num.num_subcarriers / best


def run(quick=False):
    num = make_numerology("paper")
    geo = make_geometry("paper")
    scn = make_scene("paper3")
    n_sc = num.num_subcarriers
    item = gr.sizeof_gr_complex * n_sc
    n_sym = 4800 if quick else 48000  # full: the whole paper aperture
    n_np = 96 if quick else 480
    src_data = _symbols(n_sc).tolist()

    def build(snr_db, reference):
        def connect(tb, n):
            src = blocks.vector_source_c(src_data, True, n_sc)
            echo = scene_echo(num, geo, scn, snr_db, 1)
            tb.connect(src, blocks.head(item, n), echo, blocks.null_sink(item))
            if reference:
                tb.connect((echo, 1), blocks.null_sink(item))
        return connect

    def source_only(tb, n):
        src = blocks.vector_source_c(src_data, True, n_sc)
        tb.connect(src, blocks.head(item, n), blocks.null_sink(item))

    rows = []
    cases = (("scene_echo paper 3 targets, noise-free", float("inf"), False, 0.0),
             ("scene_echo paper 3 targets, 20 dB noise", 20.0, False, np.sqrt(3.0 / 100.0)),
             ("scene_echo paper 3 targets, noise + reference out", 20.0, True, np.sqrt(3.0 / 100.0)))
    for name, snr_db, reference, sigma in cases:
        ours = benchutil.items_per_second(build(snr_db, reference), n_sym) * n_sc
        peer = _numpy_rate(num, geo, scn, sigma, n_np)
        rows.append(benchutil.row(name, ours, "numpy float64 eq. (7)", peer, unit="REs/s",
                                  paper_aperture_s=PAPER_RES / ours,
                                  numpy_paper_aperture_s=PAPER_RES / peer,
                                  symbols=n_sym, numpy_symbols=n_np))
    # What the flowgraph costs without the block (source -> head -> sink): the floor.
    floor = benchutil.items_per_second(source_only, n_sym) * n_sc
    rows.append(benchutil.row("vector_source_c>head>null_sink (no echo)", floor,
                              "numpy float64 eq. (7)", rows[1]["peer_rate"], unit="REs/s",
                              paper_aperture_s=PAPER_RES / floor, symbols=n_sym))
    return rows


if __name__ == "__main__":
    benchutil.main(run, __doc__)
