#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nmse_probe against numpy computing the same point-target metrics on the same aperture.

Ours: vector_source -> nmse_probe (reference input), lines/s through the flowgraph, the
metrics computed once per aperture. Peer: numpy (float64) implementing SPEC section 8 the
same way (c_hat, NMSE, SNR_out over the same noise region, FFT-interpolated cuts), timed on
the same image in the same process. The rows also carry the largest disagreement between
the two sets of figures.
"""

import time

import numpy as np
import pmt
from gnuradio import blocks, gr

from . import benchutil
from ..nrsar_python import nmse_probe, probe_config, tag_keys
from ..params import make_filter, make_geometry, make_numerology, make_scene

C = 299792458.0


def _dirichlet(u, band, period):
    n = np.arange(band) - band // 2
    return np.exp(2j * np.pi * np.outer(u, n) / period).sum(axis=1) / band


def _image(lines, bins, n_sub, seed=5):
    rng = np.random.default_rng(seed)
    k0, m0 = 0.41 * bins + 0.37, 0.47 * lines + 0.61
    rk = _dirichlet(np.arange(bins) - k0, n_sub, bins)
    am = _dirichlet(np.arange(lines) - m0, lines // 8, lines)
    ref = np.outer(am, rk)
    noise = 0.003 * (rng.standard_normal(ref.shape) + 1j * rng.standard_normal(ref.shape))
    return (0.7 * np.exp(0.3j) * ref + noise).astype(np.complex64), ref.astype(np.complex64), k0, m0


def _cut(cut, cells_per_sample, window_cells):
    """IRW [samples], PSLR [dB], main, side, peak power of one cut (numpy)."""
    n = len(cut)
    up = int(min(64, max(1, np.ceil(16 * cells_per_sample))))
    X = np.fft.fft(cut)
    Y = np.zeros(n * up, complex)
    h = n // 2
    Y[:(n + 1) // 2] = X[:(n + 1) // 2]
    Y[n * up - (n - h - 1):] = X[h + 1:]
    if n % 2 == 0 and up > 1:
        Y[h] = X[h] / 2
        Y[n * up - h] = X[h] / 2
    p = np.abs(np.fft.ifft(Y) * up) ** 2
    i = int(np.argmax(p))
    half = p[i] / 2
    lft, rgt = i, i
    while p[lft - 1] >= half:
        lft -= 1
    while p[rgt + 1] >= half:
        rgt += 1
    irw = ((rgt + (p[rgt] - half) / (p[rgt] - p[rgt + 1])) -
           (lft - (p[lft] - half) / (p[lft] - p[lft - 1]))) / up
    jl, jr = i, i
    while p[jl - 1] < p[jl]:
        jl -= 1
    while p[jr + 1] < p[jr]:
        jr += 1
    w = int(np.ceil(window_cells / cells_per_sample * up))
    lo, hi = max(0, i - w), min(len(p) - 1, i + w)
    main = p[jl:jr + 1].sum()
    side = p[lo:hi + 1].sum() - main
    pslr = 10 * np.log10(max(p[lo:jl].max(), p[jr + 1:hi + 1].max()) / p[i])
    return irw, pslr, main, side, p[i]


def numpy_metrics(img, ref, nm, region, range_cells_per_bin, az_cells_per_line, window=20.0):
    img = img.astype(np.complex128)
    ref = ref.astype(np.complex128)
    c = np.vdot(ref, img) / np.vdot(ref, ref)
    nmse = nm * np.mean(np.abs(img / c - ref) ** 2) / np.max(np.abs(ref) ** 2)
    noise = np.mean(np.abs(img - c * ref)[:, region] ** 2)
    m, k = np.unravel_index(np.argmax(np.abs(img)), img.shape)
    irw_r, pslr_r, main_r, side_r, p_r = _cut(img[m, :], range_cells_per_bin, window)
    irw_a, pslr_a, main_a, side_a, p_a = _cut(img[:, k], az_cells_per_line, window)
    peak = p_r * p_a / np.abs(img[m, k]) ** 2
    return {
        "nmse_db": 10 * np.log10(nmse),
        "pel_db": -20 * np.log10(abs(c)),
        "snr_out_db": 10 * np.log10(peak / noise),
        "islr_db": 10 * np.log10((side_r + side_a) / (main_r + main_a)),
        "pslr_db": max(pslr_r, pslr_a),
        "irw_range_bins": irw_r,
        "irw_azimuth_lines": irw_a,
    }


def run(quick=False):
    lines, bins, n_sub = (960, 256, 128) if quick else (4800, 512, 256)
    num = make_numerology("paper", num_subcarriers=n_sub)
    geo = make_geometry("paper")
    scn = make_scene("single")
    t = scn.targets[0]
    R0 = float(np.hypot(t.x_m, geo.height_m))
    rho_r = C / (2 * n_sub * num.subcarrier_spacing_hz)
    rho_a = (C / geo.carrier_hz) * R0 / (2 * geo.velocity_mps * geo.aperture_s)
    dr, dy = rho_r * n_sub / bins, rho_a / 8
    img, ref, k0, m0 = _image(lines, bins, n_sub)
    r_first, y_first = R0 - k0 * dr, t.y_m - m0 * dy
    consts = [complex(a, b) / 170 ** 0.5 for a in range(-15, 16, 2) for b in range(-15, 16, 2)]
    flat_img = img.ravel().tolist()
    flat_ref = ref.ravel().tolist()
    src = pmt.intern("bench")
    tags = []
    for key, val in ((tag_keys.aperture, pmt.from_uint64(0)),
                     (tag_keys.azimuth_axis, pmt.make_tuple(pmt.from_double(y_first), pmt.from_double(dy),
                                                            pmt.from_uint64(lines))),
                     (tag_keys.range_axis, pmt.make_tuple(pmt.from_double(r_first), pmt.from_double(dr),
                                                          pmt.from_uint64(bins)))):
        tags.append(gr.python_to_tag((0, pmt.intern(key), val, src)))
    probes = []

    def build(tb, n_items):
        probe = nmse_probe(num, geo, scn, consts, make_filter("mf"), 5.0, bins,
                           probe_config(reference_input=True))
        tb.connect(blocks.vector_source_c(flat_img, False, bins, tags), (probe, 0))
        tb.connect(blocks.vector_source_c(flat_ref, False, bins), (probe, 1))
        probes.append(probe)

    ours = benchutil.items_per_second(build, lines, repeats=2 if quick else 3)
    got = probes[-1].metrics()

    r = R0 - k0 * dr + np.arange(bins) * dr
    region = np.abs(r - R0) > 10 * rho_r
    nm = n_sub * geo.symbols_per_aperture(num)
    best = float("inf")
    for _ in range(2 if quick else 3):
        start = time.perf_counter()
        ref_metrics = numpy_metrics(img, ref, nm, region, dr / rho_r, dy / rho_a)
        best = min(best, time.perf_counter() - start)
    peer = lines / best
    diff = max(abs(got["nmse_db"] - ref_metrics["nmse_db"]),
               abs(got["pel_db"] - ref_metrics["pel_db"]),
               abs(got["snr_out_db"] - ref_metrics["snr_out_db"]),
               abs(got["islr_db"] - ref_metrics["islr_db"]),
               abs(got["pslr_db"] - ref_metrics["pslr_db"]))
    irw_diff = max(abs(got["irw_range_m"] / dr - ref_metrics["irw_range_bins"]),
                   abs(got["irw_azimuth_m"] / dy - ref_metrics["irw_azimuth_lines"]))
    return [benchutil.row(f"nmse_probe {lines}x{bins} aperture", ours, "numpy float64 metrics", peer,
                          unit="lines/s", max_db_difference=diff, max_irw_difference_samples=irw_diff)]


if __name__ == "__main__":
    benchutil.main(run, __doc__)
