#!/usr/bin/python3
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
"""Flowgraph benchmark of extended_scene_echo: a speckled 256 x 256 map (65536 scatterers) at
the paper numerology, against scene_echo summing the same scatterers exactly (K x N, AVX2) in
the same run, with the error of the fast generator against the exact sum."""

import numpy as np
from gnuradio import blocks, gr

from . import benchutil
from ..nrsar_python import extended_scene_echo, extended_scene_kernel, scene, point_target, scene_echo
from ..params import make_geometry, make_numerology
from ..scenes import make_map


def _symbols(n_sc, count=16, seed=1):
    rng = np.random.default_rng(seed)
    a = np.sqrt(0.5)
    s = a * (rng.choice([-1.0, 1.0], count * n_sc) + 1j * rng.choice([-1.0, 1.0], count * n_sc))
    return s.astype(np.complex64)


def scene_256(n=256, spacing=0.5):
    """n x n unit-RCS speckled map centred on (300, 50) m."""
    return make_map(np.ones((n, n)), spacing, spacing, 300.0 - n * spacing / 2,
                    50.0 - n * spacing / 2, speckle=True, seed=3)


def run(quick=False):
    num = make_numerology("paper")
    geo = make_geometry("paper")
    n_sc = num.num_subcarriers
    item = gr.sizeof_gr_complex * n_sc
    mp = scene_256(128 if quick else 256)
    k = extended_scene_kernel(num, geo, scene(), [mp])
    xs, ys, amps = k.scatterers()
    pts = scene([point_target(float(x), float(y), float(abs(a)) ** 2, float(np.angle(a)))
                 for x, y, a in zip(xs, ys, amps)])
    src_data = _symbols(n_sc).tolist()
    n_ours = 200 if quick else 1000
    n_peer = 4 if quick else 16

    def build(make):
        def connect(tb, n):
            src = blocks.vector_source_c(src_data, True, n_sc)
            tb.connect(src, blocks.head(item, n), make(), blocks.null_sink(item))
        return connect

    peer = benchutil.items_per_second(build(lambda: scene_echo(num, geo, pts)), n_peer, 1) * n_sc
    ref = {m: k.reference_exact(m).astype(np.complex128) for m in (0, 24000)}
    rows = []
    for taps, over in ((8, 2.0), (6, 2.0), (4, 2.0), (8, 1.5)):
        ours = benchutil.items_per_second(
            build(lambda: extended_scene_echo(num, geo, scene(), [mp], taps=taps,
                                              oversampling=over)), n_ours, 2) * n_sc
        kk = extended_scene_kernel(num, geo, scene(), [mp], taps=taps, oversampling=over)
        err = np.mean([np.sum(np.abs(kk.reference(m) - r) ** 2) / np.sum(np.abs(r) ** 2)
                       for m, r in ref.items()])
        rows.append(benchutil.row(
            f"extended_scene_echo {mp.ny}x{mp.nx} map, L={taps}, O={over:g}", ours,
            "scene_echo (exact K x N sum, same scatterers)", peer, unit="REs/s",
            scatterers=len(amps), error_db=float(10 * np.log10(err)), grid=kk.grid_size()))
    return rows


if __name__ == "__main__":
    benchutil.main(run, __doc__)
