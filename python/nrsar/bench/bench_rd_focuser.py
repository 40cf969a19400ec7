#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Flowgraph benchmark of rd_focuser against a numpy implementation of the same steps.

Same input, same run: the range-compressed echo of one point target plus white noise,
one aperture at the paper's presummed rate (PRF 2.4 kHz, v = 50 m/s, R0 = 1044 m, band
about [0, 120] Hz). Rows: our block vs numpy with the scene band, the same with the full
PRF band, and our scene band vs our full band (run time, peak and noise power).
"""

import math
import time

import numpy as np
from gnuradio import blocks, gr

from . import benchutil
from ..theory import numpy_focus
from ..nrsar_python import doppler_band, focuser_config, rd_focuser
from ..params import make_geometry, make_numerology, make_scene

C = 299792458.0


def dirichlet(x, n, nfft):
    """sum_{q<n} exp(j 2 pi q x / nfft), closed form (eq. 29 for a unit target)."""
    x = np.asarray(x, float)
    s = np.sin(np.pi * x / nfft)
    small = np.abs(s) < 1e-12
    val = np.where(small, n, np.sin(np.pi * n * x / nfft) / np.where(small, 1.0, s))
    return val * np.exp(1j * np.pi * (n - 1) * x / nfft)


def scenario(quick):
    num = make_numerology("paper")
    spp = 10  # presummed rate, PRF 2.4 kHz
    k = 128 if quick else 256
    m = 2400 if quick else 4800
    geo = make_geometry("paper", aperture_s=m * num.symbol_s() * spp)
    x, y = 300.0, 100.0
    scn = make_scene([(x, y)])
    rho = num.range_bin_m(num.fft_size)
    r0 = math.hypot(x, geo.height_m)
    first = r0 - (k // 2) * rho
    t = num.symbol_s() * spp
    lam = geo.wavelength_m()
    yp = geo.track_start_m + geo.velocity_mps * t * np.arange(m)
    r = np.sqrt(r0 ** 2 + (yp - y) ** 2)
    kq = (r - first) / rho
    n = num.num_subcarriers
    prof = dirichlet(np.arange(k)[None, :] - kq[:, None], n, num.fft_size) / math.sqrt(n)
    data = prof * np.exp(-4j * np.pi * np.mod(r / lam, 1.0))[:, None]
    rng = np.random.default_rng(1)
    noise = (rng.standard_normal(data.shape) + 1j * rng.standard_normal(data.shape)) * 3.0
    return dict(num=num, geo=geo, scn=scn, spp=spp, k=k, m=m, first=first, rho=rho, t=t,
                lam=lam, data=(data + noise).astype(np.complex64),
                noise=noise.astype(np.complex64))


def run_block(s, band, apertures, key="data"):
    """Our block on `apertures` repetitions of the aperture (one aperture per processing
    block, overlap 0), so that set-up (FFTW plans, tables) is amortised as in a stream; timed
    into a null sink. The image comes from a separate untimed one-aperture run."""
    cfg = focuser_config(symbols_per_pulse=s["spp"], overlap_lines=0, band=band)
    flat = s[key].ravel().tolist()
    item = gr.sizeof_gr_complex * s["k"]

    def build(tb, n_items):
        blk = rd_focuser(s["num"], s["geo"], s["scn"], s["k"], s["first"], s["rho"], cfg)
        tb.connect(benchutil.repeat_source(flat, s["k"]), blocks.head(item, n_items), blk,
                   blocks.null_sink(item))

    rate = benchutil.items_per_second(build, s["m"] * apertures, repeats=2) if apertures else 0
    tb = gr.top_block()
    blk = rd_focuser(s["num"], s["geo"], s["scn"], s["k"], s["first"], s["rho"], cfg)
    snk = blocks.vector_sink_c(s["k"])
    tb.connect(blocks.vector_source_c(flat, False, s["k"]), blk, snk)
    tb.run()
    img = np.array(snk.data()).reshape(-1, s["k"])
    return rate, img, blk


def copy_baseline(s, apertures):
    """The same source, head and sink around blocks.copy: the plumbing's own rate."""
    flat = s["data"].ravel().tolist()
    item = gr.sizeof_gr_complex * s["k"]

    def build(tb, n_items):
        tb.connect(benchutil.repeat_source(flat, s["k"]), blocks.head(item, n_items),
                   blocks.copy(item), blocks.null_sink(item))

    return benchutil.items_per_second(build, s["m"] * apertures, repeats=2)


def time_numpy(s, lo, hi, full, apertures, shift):
    best = float("inf")
    for _ in range(2):
        t0 = time.perf_counter()
        for _ in range(apertures):
            img = numpy_focus(s, lo, hi, full, shift)
        best = min(best, time.perf_counter() - t0)
    return s["m"] * apertures / best, img


def peak_noise_db(img, noise_img):
    """Peak power of the target image and mean noise power per pixel of the noise-only image
    (the target's sidelobes would otherwise dominate any target-free region)."""
    return (10 * math.log10(np.max(np.abs(img)) ** 2),
            10 * math.log10(np.mean(np.abs(noise_img) ** 2)))


def run(quick=False):
    s = scenario(quick)
    rows = []
    n_ap = 3 if quick else 6
    ours_s, img_s, blk = run_block(s, doppler_band.SCENE, n_ap)
    lo, hi = blk.band_lo_hz(), blk.band_hi_hz()
    ours_f, img_f, _ = run_block(s, doppler_band.FULL, n_ap)
    np_s, ref_s = time_numpy(s, lo, hi, False, n_ap, blk.line_shift())
    np_f, ref_f = time_numpy(s, lo, hi, True, 1 if quick else 2, blk.line_shift())
    size = f"K={s['k']} M={s['m']} x{n_ap}"
    err_s = 10 * math.log10(np.mean(np.abs(img_s - ref_s) ** 2) / np.max(np.abs(ref_s)) ** 2)
    plumbing = copy_baseline(s, n_ap)
    rows.append(benchutil.row(f"rd_focuser scene band ({size})", ours_s, "numpy same steps", np_s,
                              unit="lines/s", band_hz=[lo, hi],
                              mean_sq_diff_vs_numpy_db_of_peak=err_s,
                              copy_block_same_flowgraph=plumbing))
    rows.append(benchutil.row(f"rd_focuser full band ({size})", ours_f, "numpy same steps", np_f,
                              unit="lines/s", copy_block_same_flowgraph=plumbing))
    _, noise_s, _ = run_block(s, doppler_band.SCENE, 0, key="noise")
    _, noise_f, _ = run_block(s, doppler_band.FULL, 0, key="noise")
    ps, ns = peak_noise_db(img_s, noise_s)
    pf, nf = peak_noise_db(img_f, noise_f)
    rows.append(benchutil.row(f"rd_focuser scene vs full band ({size})", ours_s, "full band",
                              ours_f, unit="lines/s", peak_db_scene_minus_full=ps - pf,
                              noise_db_scene_minus_full=ns - nf,
                              band_fraction_db=10 * math.log10((hi - lo) * s["t"])))
    return rows


if __name__ == "__main__":
    benchutil.main(run, __doc__)
