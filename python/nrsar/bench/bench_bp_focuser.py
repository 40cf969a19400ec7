#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Flowgraph benchmark of bp_focuser against a numpy back-projection of the same grid.

Same input, same run: the range-compressed echo of one point target plus white noise at the
paper's presummed rate (PRF 2.4 kHz, v = 50 m/s, R0 = 1044 m), one aperture of M pulses
onto M lines x K bins. Rate in back-projections per second (pixels x pulses / s). Rows: our
block (one and two threads) against theory.numpy_bp (float64, vectorised over the pixels
of each pulse), with the image difference; our U = 8 against U = 2 (the upsampling cost)
and against the 8-tap short sinc; FFBP (subaperture 32, beams x8) against BP on two threads,
its rate counted as BP's back-projections (the equivalent rate) and its image's NMSE
against BP's. The paper-full aperture (48000 pulses presummed by D = 10: 4800 pulses,
K = 256; --quick 2400 x 128) by exact BP on two threads: CPU seconds per aperture with an
image line every 8th pulse position (0.167 m; the paper scene's 155 Hz Doppler band gives
an azimuth resolution v / B = 0.32 m, so 1.9 lines per resolution) against one line per
pulse, in the same run, and whether its image is every 8th line of the full one.
"""

import math
import time

import numpy as np
from gnuradio import blocks, gr

from . import benchutil
from .bench_rd_focuser import scenario
from ..theory import numpy_bp
from ..nrsar_python import bp_config, bp_focuser


def run_block(s, cfg, apertures):
    """Our block on `apertures` repetitions of the aperture into a null sink (set-up amortised
    as in a stream); the image from a separate untimed one-aperture run."""
    flat = s["data"].ravel().tolist()
    item = gr.sizeof_gr_complex * s["k"]

    def build(tb, n_items):
        blk = bp_focuser(s["num"], s["geo"], s["scn"], s["k"], s["first"], s["rho"], cfg)
        tb.connect(benchutil.repeat_source(flat, s["k"]), blocks.head(item, n_items), blk,
                   blocks.null_sink(item))

    pulses_per_s = benchutil.items_per_second(build, s["m"] * apertures, repeats=2)
    tb = gr.top_block()
    blk = bp_focuser(s["num"], s["geo"], s["scn"], s["k"], s["first"], s["rho"], cfg)
    snk = blocks.vector_sink_c(s["k"])
    tb.connect(blocks.vector_source_c(flat, False, s["k"]), blk, snk)
    tb.run()
    # every pulse is projected onto M x K pixels
    return pulses_per_s * s["m"] * s["k"], np.array(snk.data()).reshape(-1, s["k"]), blk


def paper_full(quick, step=8):
    """The paper-full aperture by exact BP on two threads: the CPU seconds of one aperture
    (all threads) and its image, at one line per pulse and at `step`."""
    s = scenario(quick)

    def cpu_image(line_step):
        cfg = bp_config(symbols_per_pulse=s["spp"], num_threads=2, line_step=line_step)
        tb = gr.top_block()
        blk = bp_focuser(s["num"], s["geo"], s["scn"], s["k"], s["first"], s["rho"], cfg)
        snk = blocks.vector_sink_c(s["k"])
        tb.connect(blocks.vector_source_c(s["data"].ravel().tolist(), False, s["k"]), blk, snk)
        t0 = time.process_time()
        tb.run()
        return time.process_time() - t0, np.array(snk.data()).reshape(-1, s["k"])

    cpu1, img1 = cpu_image(1)
    cpu8, img8 = cpu_image(step)
    aperture_s = s["m"] * s["t"]
    size = f"K={s['k']} M={s['m']} pulses, {aperture_s:g} s aperture"
    return benchutil.row(f"bp_focuser exact BP line_step {step} vs 1, 2 threads ({size})",
                         1.0 / cpu8, "line_step 1", 1.0 / cpu1, unit="apertures/CPU-s",
                         cpu_s_per_aperture=cpu8, peer_cpu_s_per_aperture=cpu1,
                         aperture_s=aperture_s,
                         every_lth_line_max_diff_of_peak=float(
                             np.abs(img8 - img1[::step]).max() / np.abs(img1).max()))


def run(quick=False):
    s = scenario(True)  # K = 128, M = 2400: numpy needs seconds per aperture already
    m = 600 if quick else 1200
    s = dict(s, m=m, data=s["data"][:m], geo=s["geo"])
    s["geo"].aperture_s = m * s["t"]
    num = s["num"]
    fc_r = math.remainder((num.num_subcarriers - 1) * num.subcarrier_spacing_hz * s["rho"]
                          / 299792458.0, 1.0)
    rows = []
    n_ap = 1 if quick else 2
    size = f"K={s['k']} M={m} pulses=lines"
    ours1, img, blk = run_block(s, bp_config(symbols_per_pulse=s["spp"], num_threads=1), n_ap)
    ours2, _, _ = run_block(s, bp_config(symbols_per_pulse=s["spp"], num_threads=2), n_ap)
    ours_u2, _, _ = run_block(s, bp_config(symbols_per_pulse=s["spp"], upsample=2), n_ap)
    ours_sinc, _, _ = run_block(s, bp_config(symbols_per_pulse=s["spp"], sinc_taps=8), n_ap)
    bp2, img2, _ = run_block(s, bp_config(symbols_per_pulse=s["spp"], num_threads=2), 1)
    ffbp, img_f, _ = run_block(s, bp_config(symbols_per_pulse=s["spp"], num_threads=2,
                                            ffbp_subaperture=32, ffbp_beam_oversample=8.0), n_ap)
    ffbp_err = 10 * math.log10(np.sum(np.abs(img_f - img2) ** 2) / np.sum(np.abs(img2) ** 2))
    geo = s["geo"]
    dy = geo.velocity_mps * s["t"]
    yp = geo.track_start_m + dy * np.arange(m)
    ant = np.stack([np.zeros(m), yp, np.full(m, geo.height_m)], axis=1)
    y_lines = geo.track_start_m + dy * (blk.line_shift() + np.arange(m))
    t0 = time.perf_counter()
    ref = numpy_bp(s["data"], ant, s["first"], s["rho"], s["lam"], fc_r, 8, y_lines,
                   geo.height_m)
    np_rate = m * m * s["k"] / (time.perf_counter() - t0)
    err = 10 * math.log10(np.sum(np.abs(img - ref) ** 2) / np.sum(np.abs(ref) ** 2))
    rows.append(benchutil.row(f"bp_focuser 1 thread ({size})", ours1, "numpy same grid",
                              np_rate, unit="back-projections/s", simd=blk.simd(),
                              nmse_vs_numpy_db=err))
    rows.append(benchutil.row(f"bp_focuser 2 threads ({size})", ours2, "numpy same grid",
                              np_rate, unit="back-projections/s"))
    rows.append(benchutil.row(f"bp_focuser U=8 vs U=2 ({size})", ours1, "U=2", ours_u2,
                              unit="back-projections/s"))
    rows.append(benchutil.row(f"bp_focuser sinc 8 taps vs U=8 linear ({size})", ours_sinc,
                              "U=8 linear", ours1, unit="back-projections/s"))
    rows.append(benchutil.row(f"bp_focuser FFBP L=32 beams x8, 2 threads ({size})", ffbp,
                              "BP 2 threads", ours2, unit="back-projections/s",
                              nmse_vs_bp_db=ffbp_err))
    rows.append(paper_full(quick))
    return rows


if __name__ == "__main__":
    benchutil.main(run, __doc__)
