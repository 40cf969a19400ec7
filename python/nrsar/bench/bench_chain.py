#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Chain-level benchmark of the focusing (rows collected by nrsar-bench):

1. rd_focuser throughput and its scaling with M (lines per aperture) and K (range bins):
   the same point target + noise at the presummed paper rate (PRF 2.4 kHz), scene band,
   vector_source -> head -> rd_focuser -> null_sink; ratios against the smallest size.
2. Full-band vs scene-band focusing in the whole nrsar-sim chain (paper numerology, target 1,
   WF, 256-QAM, SNR_in 10 dB): run time and NMSE against NMSE_theory.
3. The receive chain tf_filter -> range_ifft -> rd_focuser against numpy doing the same
   (eq. 25 WF filter, unitary range IFFT with the same crop, the same focusing steps as
   theory.numpy_focus), on the same recorded inputs (echo and transmit grid from
   nr_isac_tx -> scene_echo, written to files), in the same run; NMSE of both images
   (SPEC 8, each against its own implementation's noise-free reference image).
"""

import math
import os
import tempfile
import time

import numpy as np
from gnuradio import blocks, fft, gr

from .. import chain, params, runtime
from ..options import SimOptions
from ..theory import numpy_focus
from . import benchutil, bench_rd_focuser
from ..nrsar_python import (doppler_band, focuser_config, nr_isac_tx, range_ifft, rd_focuser,
                           scene_echo, srs_config, tf_filter)

C = 299792458.0
SNR_DB = 10.0


# ------------------------------------------------------------- 1. scaling with M and K

def focus_data(k, m, spp=10):
    """Range-compressed point target (T1) + noise at PRF 2.4 kHz, K bins around R0."""
    num = params.make_numerology("paper")
    geo = params.make_geometry("paper", aperture_s=m * num.symbol_s() * spp)
    x, y = 300.0, 100.0
    rho = num.range_bin_m(num.fft_size)
    r0 = math.hypot(x, geo.height_m)
    first = r0 - (k // 2) * rho
    t = num.symbol_s() * spp
    yp = geo.track_start_m + geo.velocity_mps * t * np.arange(m)
    r = np.sqrt(r0 ** 2 + (yp - y) ** 2)
    n = num.num_subcarriers
    prof = bench_rd_focuser.dirichlet(np.arange(k)[None, :] - ((r - first) / rho)[:, None],
                                      n, num.fft_size) / math.sqrt(n)
    data = prof * np.exp(-4j * np.pi * np.mod(r / geo.wavelength_m(), 1.0))[:, None]
    rng = np.random.default_rng(1)
    data = data + 3.0 * (rng.standard_normal(data.shape) + 1j * rng.standard_normal(data.shape))
    return num, geo, params.make_scene([(x, y)]), first, rho, data.astype(np.complex64)


def focus_rate(k, m, apertures):
    num, geo, scn, first, rho, data = focus_data(k, m)
    cfg = focuser_config(symbols_per_pulse=10, overlap_lines=0, band=doppler_band.SCENE)
    flat = data.ravel().tolist()
    item = gr.sizeof_gr_complex * k

    def build(tb, n_items):
        blk = rd_focuser(num, geo, scn, k, first, rho, cfg)
        tb.connect(benchutil.repeat_source(flat, k), blocks.head(item, n_items), blk,
                   blocks.null_sink(item))

    return benchutil.items_per_second(build, m * apertures, repeats=2)


def scaling_rows(quick):
    ks = (64, 128) if quick else (64, 128, 256, 512)
    ms = (1200, 2400) if quick else (1200, 2400, 4800, 9600)
    base = None
    rows = []
    for k in ks:
        for m in ms:
            if not quick and k * m > 256 * 9600:
                continue
            # enough apertures that the fixed costs (flowgraph start, FFT plans) amortise
            rate = focus_rate(k, m, max(2, (4800 if quick else 19200) // m))
            if base is None:
                base = (k, m, rate)
            rows.append(benchutil.row(f"rd_focuser scene band K={k} M={m}", rate,
                                      f"K={base[0]} M={base[1]} (same run)", base[2],
                                      unit="lines/s", pixels_per_s=rate * k))
    return rows


# ------------------------------------------------------------- 2. full vs scene band

def band_rows(quick):
    preset, aperture = ("small", 0.2) if quick else ("paper", 0.4)
    res = {}
    with tempfile.TemporaryDirectory(prefix="bench_chain_") as out:
        for band in ("scene", "full"):
            opts = SimOptions(preset=preset, aperture_s=aperture, band=band, target=["300,100"],
                              filter="wf", snr_db=SNR_DB, out=out).validate()
            chain.simulate(opts)  # first run plans the FFTs; time the second
            res[band] = chain.simulate(opts)
    s, f = res["scene"], res["full"]
    return [benchutil.row(f"chain {preset} {aperture} s: scene-band vs full-band focusing",
                          s["symbols"] / s["runtime_s"], "full band",
                          f["symbols"] / f["runtime_s"], unit="symbols/s",
                          runtime_scene_s=s["runtime_s"], runtime_full_s=f["runtime_s"],
                          nmse_scene_db=s["nmse_db"], nmse_full_db=f["nmse_db"],
                          nmse_theory_db=s["nmse_theory_db"],
                          band_scene_hz=s["doppler_band_hz"])]


# ------------------------------------------------------------- 3. chain vs numpy

def record_inputs(num, geo, scn, symbols, workdir):
    """nr_isac_tx -> scene_echo once; echo, reference echo and grid to files."""
    n = num.num_subcarriers
    tx = nr_isac_tx(num, params.make_modulation("qam256"), params.make_tx_mode("data"),
                    srs_config(), 1)
    head = blocks.head(gr.sizeof_gr_complex * n, symbols)
    echo = scene_echo(num, geo, scn, SNR_DB, 2)
    files = {key: os.path.join(workdir, key + ".c64") for key in ("y", "yref", "s")}
    tb = gr.top_block()
    tb.connect(tx, head, echo, blocks.file_sink(gr.sizeof_gr_complex * n, files["y"]))
    tb.connect((echo, 1), blocks.file_sink(gr.sizeof_gr_complex * n, files["yref"]))
    tb.connect(head, blocks.file_sink(gr.sizeof_gr_complex * n, files["s"]))
    tb.run()
    return files


def ours_chain(num, geo, scn, files, nfft, crop, cfg, filtered=True):
    n = num.num_subcarriers
    tb = gr.top_block()
    rif = range_ifft(num, nfft, fft.window.WIN_RECTANGULAR, -1.0, *crop)
    foc = rd_focuser(num, geo, scn, rif.num_bins(), rif.range_axis_first_m(),
                     rif.range_bin_m(), cfg)
    sink = blocks.vector_sink_c(rif.num_bins())
    ysrc = blocks.file_source(gr.sizeof_gr_complex * n, files["y" if filtered else "yref"])
    if filtered:
        tff = tf_filter(n, params.make_filter("wf"), SNR_DB, False)
        tb.connect(ysrc, (tff, 0))
        tb.connect(blocks.file_source(gr.sizeof_gr_complex * n, files["s"]), (tff, 1))
        tb.connect(tff, rif)
    else:
        tb.connect(ysrc, rif)
    tb.connect(rif, foc, sink)
    start = time.perf_counter()
    tb.run()
    elapsed = time.perf_counter() - start
    img = np.asarray(sink.data(), dtype=np.complex64).reshape(-1, rif.num_bins())
    return elapsed, img, rif, foc


def numpy_chain(num, geo, files, rif, foc, filtered=True):
    """The same chain in numpy (complex64 inputs; numpy's FFT computes in float64)."""
    n = num.num_subcarriers
    y = np.fromfile(files["y" if filtered else "yref"], dtype=np.complex64).reshape(-1, n)
    if filtered:
        s = np.fromfile(files["s"], dtype=np.complex64).reshape(-1, n)
        y = y * (np.conj(s) / (np.abs(s) ** 2 + np.float32(10 ** (-SNR_DB / 10))))  # eq. (25)
    nfft, k0, k = rif.fft_size(), rif.first_bin(), rif.num_bins()
    rc = np.fft.ifft(y, n=nfft, axis=1)[:, k0:k0 + k] * (nfft / math.sqrt(n))    # eq. (29)
    s = {"data": rc, "geo": geo, "lam": geo.wavelength_m(), "t": num.symbol_s(),
         "rho": rif.range_bin_m(), "first": rif.range_axis_first_m(), "num": num}
    return numpy_focus(s, foc.band_lo_hz(), foc.band_hi_hz(), False,
                                        foc.line_shift())


def nmse_db(img, ref, nm):
    """SPEC 8: calibrated NMSE of img against its noise-free reference."""
    img = img.astype(np.complex128)
    ref = ref.astype(np.complex128)
    c = np.vdot(ref, img) / np.vdot(ref, ref)
    return 10 * math.log10(nm * np.mean(np.abs(img / c - ref) ** 2) / np.max(np.abs(ref)) ** 2)


def chain_rows(quick):
    num = params.make_numerology("paper")
    aperture = 0.1 if quick else 0.2
    geo = params.make_geometry("paper", aperture_s=aperture)
    scn = params.make_scene(["300,100"])
    symbols = int(geo.symbols_per_aperture(num))
    extent = params.compute_extent(geo, scn)
    nfft = range_ifft.fast_fft_size(num.num_subcarriers)
    margin = max(30.0, 16 * num.range_bin_m(nfft))
    crop = (extent.min_slant_range_m - margin, extent.max_slant_range_m + margin)
    cfg = focuser_config(overlap_lines=0, lines_per_aperture=symbols)
    with tempfile.TemporaryDirectory(prefix="bench_chain_") as work:
        files = record_inputs(num, geo, scn, symbols, work)
        ours_chain(num, geo, scn, files, nfft, crop, cfg)  # warm-up: FFT plans, page cache
        t_ours, img, rif, foc = ours_chain(num, geo, scn, files, nfft, crop, cfg)
        _, ref, _, _ = ours_chain(num, geo, scn, files, nfft, crop, cfg, filtered=False)
        start = time.perf_counter()
        img_np = numpy_chain(num, geo, files, rif, foc)
        t_np = time.perf_counter() - start
        ref_np = numpy_chain(num, geo, files, rif, foc, filtered=False)
    nm = num.num_subcarriers * symbols
    diff = 10 * math.log10(np.mean(np.abs(img - img_np) ** 2) / np.max(np.abs(img_np)) ** 2)
    return [benchutil.row(f"chain tf_filter->range_ifft->rd_focuser (paper, M={symbols}, "
                          f"K={rif.num_bins()})", symbols / t_ours,
                          "numpy same chain, same inputs", symbols / t_np, unit="symbols/s",
                          nmse_ours_db=nmse_db(img, ref, nm),
                          nmse_numpy_db=nmse_db(img_np, ref_np, nm),
                          mean_sq_diff_db_of_peak=diff,
                          seconds_ours=t_ours, seconds_numpy=t_np)]


def run(quick=False):
    runtime.quiet_gnuradio_logs()
    return chain_rows(quick) + band_rows(quick) + scaling_rows(quick)


if __name__ == "__main__":
    benchutil.main(run, __doc__)
