#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Double-precision, no-skipping reference of the nrsar-sim chain (issue #7's image-quality goal).

    /usr/bin/python3 -m gnuradio.nrsar.figures.double_reference [nrsar-sim options] [--work DIR]

1. Runs the float32 GNU Radio chain (chain.simulate, --images keep) with the given options (default:
   paper-full with presum cheby D = 10, range crop on, scene band) and keeps its image and
   SPEC 8 metrics.
2. Regenerates the transmit grid S and the echo with the same blocks and seeds (nr_isac_tx,
   scene_echo: identical output, the noise depends only on (seed, symbol)) into raw files, and
   computes the same chain in numpy float64 with nothing skipped or approximated:
   - S in float64: every float32 grid point snapped to the exact float64 constellation point;
   - echo in float64: eq. (7)-(8) evaluated in float64 (H64), plus the generator's own noise
     realisation Z = Y - S H (from the block's two outputs: out0 = S H + Z, out1 = H), so both
     chains see the same data and the same noise (the float32 rounding this carries into Z is
     ~1e-6 of sigma, about -125 dB of the signal);
   - per-RE filter (eq. 25) in float64, the reference branch (S = 1, Z = 0) likewise;
   - no presum: every symbol at the full PRF (24 kHz at paper);
   - azimuth FFT of every subcarrier, zero-padded so the compression is a linear (not
     circular) correlation over the whole aperture;
   - range IFFT + RCMC exactly: each image pixel is the band-limited range profile of eq. (29)
     (unitary IFFT over all N subcarriers, the fast chain's FFT size) evaluated at the exact
     migrated position k + Delta k(f) of eq. (40) (hyperbolic form, as the focuser) by a direct
     sum over the N subcarriers: no interpolation kernel, no table, no crop of the profile;
   - azimuth compression exp(j phi(f, R0)) (as rd_focuser), on the scene's Doppler band
     (SPEC 7; the band is part of the method, the same band the fast chain used) or on the full
     PRF band (--ref-band full; expensive);
   - inverse azimuth FFT, the lines covering the fast image's along-track window.
   Pixels are computed on the fast image's range bins (slant ranges) only: azimuth processing is
   per range bin and the exact RCMC reads the whole uncropped profile, so these pixels are those
   of a full-range image; the metrics are taken on the same pixel window in both cases
   (SPEC 8: NMSE's mean depends on the window, not on the processing).
3. Metrics of both images by the same nmse_probe kernel (the reference image's own reference
   branch as SPEC 8's ref), and NMSE_fast - NMSE_double (goal: |.| <= 0.1 dB). Also the NMSE of
   both in float64 numpy on the whole window and on the range bins at least Delta k_max +
   taps/2 from the crop edges (before nrsar-sim's guard bins, the fast RCMC kernel read zeros
   beyond the crop there; now the fast chain crops ceil(Delta k_max) + taps/2 bins wider and
   its focuser drops them, so the edge bins carry their full noise).
   --guard-m G: the fast chain crops G metres wider still on each side and both are measured
   on the window of --range-margin-m.
Prints one JSON object (keys fast, double, fast_minus_double, nmse64_db, double_time_s,
peak_rss_mb, goal_met); exit status 0 when the goal is met. Results: docs/performance.md.
Big arrays live in files under --work (column blocks, so no array of the aperture is ever in
memory); they are deleted at the end unless --keep-work.
"""

import argparse
import dataclasses
import json
import math
import os
import shutil
import sys
import time

import numpy as np

import pmt
from gnuradio import blocks, gr

from .. import chain, params, results, runtime, scenario
from ..options import PRESUM, SimOptions, check_out_dir, option
from ..nrsar_python import (constellation, focuser_config, nmse_probe, nr_isac_tx, probe_config,
                            rd_focuser, strip_pixel_weights, tag_keys)

C = 299792458.0
COLS = 128        # subcarriers per column block of the work files
ROWS = 1000       # symbols per row chunk of the echo computation


@dataclasses.dataclass
class DoubleReferenceOptions(SimOptions):
    """nrsar-sim's options (presumming by default) plus the reference's own."""
    presum: str = option("cheby", "azimuth presummer of the fast chain (cheby_presum)",
                         choices=list(PRESUM))
    out: str = option("/tmp/dref/out", "output folder")
    work: str = option("/tmp/dref/work", "folder of the raw files (about 9 GB at paper-full)")
    keep_work: bool = option(False, "keep the raw files")
    guard_m: float = option(0.0, "extra slant range the fast chain crops on each side of the "
                            "metric window [m] (its RCMC kernel then reads real bins at the "
                            "window's edges); the metrics of both images are taken on the "
                            "window of --range-margin-m", at_least=0.0)
    ref_band: str = option("scene", "azimuth band of the float64 reference (full: every FFT "
                           "bin)", choices=["scene", "full"])


def parse(argv):
    parser = argparse.ArgumentParser(prog="nrsar-double-reference", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    DoubleReferenceOptions.add_arguments(parser)
    try:
        opts = DoubleReferenceOptions.from_args(parser.parse_args(argv))
        check_out_dir(opts.out)
        check_out_dir(opts.work, "--work")
        return opts
    except ValueError as err:  # a broken rule: one line and exit 2, as argparse's own
        parser.error(str(err))


def setup(opts):
    sc = scenario.of(opts)
    return sc.num, sc.geo, sc.scene, sc.symbols


def capture(opts, num, geo, scn, symbols, work):
    """The grid and both echo outputs of the same blocks (same seeds as chain.build)
    into raw complex64 files."""
    n = num.num_subcarriers
    mode = scenario.grid_of_mode(opts.mode, num)
    tb = gr.top_block()
    tx = nr_isac_tx(num, params.make_modulation(opts.modulation),
                    params.make_tx_mode(mode[0]), mode[1], opts.seed)
    head = blocks.head(gr.sizeof_gr_complex * n, symbols)
    echo = chain.make_echo(opts, scenario.of(opts))
    paths = {k: os.path.join(work, k + ".c64") for k in ("s", "y", "h")}
    sinks = {k: blocks.file_sink(gr.sizeof_gr_complex * n, p) for k, p in paths.items()}
    for s in sinks.values():
        s.set_unbuffered(False)
    tb.connect(tx, head, echo, sinks["y"])
    tb.connect(head, sinks["s"])
    tb.connect((echo, 1), sinks["h"])
    tb.run()
    for s in sinks.values():
        s.close()
    return paths


def exact_points(points32):
    """float64 constellation and a snapping function for float32 grid samples: square QAM
    points are odd integers / sqrt(norm); other constellations are carried as they are."""
    p = np.asarray(points32, np.complex128)
    re = np.abs(p.real)
    norm = round(1.0 / (re[re > 1e-6].min() ** 2)) if np.any(re > 1e-6) else 0
    scale = math.sqrt(norm) if norm else 0.0
    if scale and np.allclose(np.round(p * scale), p * scale, atol=1e-4):
        return lambda s: (np.round(s.real * scale) + 1j * np.round(s.imag * scale)) / scale
    return lambda s: s.astype(np.complex128)


def read_rows(path, r0, rows, n):
    return np.fromfile(path, np.complex64, count=rows * n, offset=r0 * n * 8).reshape(rows, n)


def filtered_blocks(opts, num, geo, scn, symbols, paths, work):
    """float64 echo (eq. 7-8) + the generator's noise, WF/MF/RF filter (eq. 25), for both
    branches; written as column blocks (COLS subcarriers x all symbols, row-major) so the
    azimuth FFT reads each block contiguously."""
    n = num.num_subcarriers
    snap = exact_points(constellation(params.make_modulation(opts.modulation)).points())
    snr = 10.0 ** (opts.snr_db / 10.0)
    f = geo.carrier_hz + np.arange(n) * num.subcarrier_spacing_hz
    targets = [(t.x_m, t.y_m, t.rcs) for t in scn.targets]
    out = {b: os.path.join(work, b + ".c128") for b in ("img", "ref")}
    fds = {b: os.open(p, os.O_CREAT | os.O_WRONLY | os.O_TRUNC, 0o644) for b, p in out.items()}
    g_ones = {"rf": 1.0, "mf": 1.0, "wf": 1.0 / (1.0 + 1.0 / snr)}[opts.filter]
    try:
        for r0 in range(0, symbols, ROWS):
            rows = min(ROWS, symbols - r0)
            s32 = read_rows(paths["s"], r0, rows, n)
            y32 = read_rows(paths["y"], r0, rows, n).astype(np.complex128)
            h32 = read_rows(paths["h"], r0, rows, n).astype(np.complex128)
            z = y32 - s32.astype(np.complex128) * h32  # the generator's noise realisation
            del y32, h32
            s = snap(s32)
            t = (r0 + np.arange(rows)) * num.symbol_s()
            yp = geo.track_start_m + geo.velocity_mps * t
            h = np.zeros((rows, n), np.complex128)
            for (x, yt, rcs) in targets:  # eq. (7)-(8), float64
                r = np.sqrt(x * x + geo.height_m ** 2 + (yp - yt) ** 2)
                h += math.sqrt(rcs) * np.exp(-4j * np.pi / C * np.outer(r, f))
            y = s * h + z
            del z
            a2 = np.abs(s) ** 2
            if opts.filter == "mf":
                g = np.conj(s)
            elif opts.filter == "rf":
                g = np.where(a2 > 0, np.conj(s) / np.where(a2 > 0, a2, 1.0), 0.0)
            else:
                g = np.conj(s) / (a2 + 1.0 / snr)
            data = {"img": y * g, "ref": h * g_ones}
            for b, arr in data.items():
                for c0 in range(0, n, COLS):
                    w = min(COLS, n - c0)
                    os.pwrite(fds[b], np.ascontiguousarray(arr[:, c0:c0 + w]).tobytes(),
                              (c0 * symbols + r0 * w) * 16)
    finally:
        for fd in fds.values():
            os.close(fd)
    return out


def smooth_size(n):
    """Smallest 2^a 3^b 5^c >= n (numpy's pocketfft is fast there)."""
    best = 1 << (n - 1).bit_length()
    a = 1
    while a < best:
        b = a
        while b < best:
            c = b
            while c < best:
                if c >= n:
                    best = c
                c *= 5
            b *= 3
        a *= 2
    return best


def focus_reference(opts, num, geo, symbols, files, fast):
    """Azimuth FFT (zero-padded), exact RCMC + range IFFT by direct evaluation of the
    band-limited range profile, azimuth compression, inverse azimuth FFT; both branches.
    Returns {branch: image (lines x K complex128)}, the first line's along-track position."""
    n = num.num_subcarriers
    t = num.symbol_s()
    v = geo.velocity_mps
    lam = C / geo.carrier_hz
    first, rho = fast["range_axis_m"]
    k = fast["range_bins"]
    nfft = fast["range_fft_size"]
    kabs = first / rho + np.arange(k)  # bin positions in the full IFFT grid
    r0 = rho * kabs
    band_lo, band_hi = fast["doppler_band_hz"]
    az0, daz = fast["azimuth_axis_m"]
    lines_fast = fast["azimuth_lines"]
    # reference lines: the fast image's along-track window at the full PRF
    j_first = int(round((az0 - geo.track_start_m) / (v * t)))
    j_count = int(round(lines_fast * daz / (v * t)))
    # Azimuth FFT: the fast focuser's processing block (before + M + after pulses, zero
    # padded, a linear correlation) at the full PRF, D times as many points: the Doppler bins
    # are then exactly the fast chain's, so both process the same band, bin for bin. It must
    # also hold the band's filter reach f / Ka = f lam R0 / (2 v^2) beyond the aperture (the
    # longest at the farthest range; a crop from range 0, as at `tiny`, has Ka = inf in its
    # first bin) and the output window.
    reach = int(math.ceil(max(abs(band_lo), abs(band_hi)) * lam * r0.max() / (2 * v * v) / t))
    need = max(symbols + reach + max(0, -j_first), j_first + j_count)
    length = fast["focuser_fft_size"] * fast["pulse_symbols"]
    while length < need:
        length *= 2
    if opts.ref_band == "full":
        # Every Doppler bin of the full PRF: the band's reach (f / Ka at f = PRF / 2) exceeds
        # any aperture, so the correlation is circular over twice the aperture.
        length = smooth_size(max(2 * symbols, j_first + j_count))
        if length * num.num_subcarriers * 32 > 4e9:
            raise ValueError(f"--ref-band full needs {length * num.num_subcarriers * 32 / 1e9:.0f}"
                             f" GB of spectra (limit 4 GB): use a shorter aperture or preset")
    prf = 1.0 / t
    centre = 0.5 * (band_lo + band_hi)
    fr = centre + np.remainder(np.fft.fftfreq(length, t) - centre + prf / 2, prf) - prf / 2
    if opts.ref_band == "full":
        sel = np.arange(length)
    else:
        sel = np.nonzero((fr >= band_lo) & (fr <= band_hi))[0]
    spectra = {}
    for b, path in files.items():  # azimuth FFT of every subcarrier, band bins kept
        spec = np.empty((len(sel), n), np.complex128)
        for c0 in range(0, n, COLS):
            w = min(COLS, n - c0)
            blk = np.fromfile(path, np.complex128, count=symbols * w,
                              offset=c0 * symbols * 16).reshape(symbols, w)
            spec[:, c0:c0 + w] = np.fft.fft(blk, length, axis=0)[sel] / math.sqrt(length)
            del blk
        spectra[b] = spec
    ns = np.arange(n)
    out = {b: np.zeros((length, k), np.complex128) for b in files}
    chunk = 8
    for i0 in range(0, len(sel), chunk):
        idx = np.arange(i0, min(i0 + chunk, len(sel)))
        fb = fr[sel[idx]][:, None]
        u2 = np.minimum((lam * fb / (2 * v)) ** 2, 0.98)  # rd_focuser's clip (full band only)
        d = np.sqrt(1 - u2)
        pos = kabs[None, :] + r0[None, :] * u2 / (d * (1 + d)) / rho  # eq. (40), exact
        # eq. (29) evaluated at pos: (1/sqrt N) sum_n X[n] exp(j 2 pi n pos / Nfft)
        kern = np.exp(2j * np.pi / nfft * ns[None, :, None] * pos[:, None, :]) / math.sqrt(n)
        comp = np.exp(-4j * np.pi * r0[None, :] / lam * u2 / (1 + d))
        for b in files:
            out[b][sel[idx]] = np.einsum("in,ink->ik", spectra[b][idx], kern) * comp
    del spectra
    images = {}
    for b in files:
        img = np.fft.ifft(out[b], axis=0) * math.sqrt(length)
        # lines before the track start (j < 0) are the FFT's last lines (circular index)
        images[b] = img[(j_first + np.arange(j_count)) % length]
        out[b] = None
    u2_max = np.minimum((lam * np.abs(fr[sel]).max() / (2 * v)) ** 2, 0.98)
    info = {"max_migration_bins": float(r0.max() * u2_max / (math.sqrt(1 - u2_max) *
                                                        (1 + math.sqrt(1 - u2_max))) / rho),
            "azimuth_fft": length, "band_bins": int(len(sel)), "lines": j_count,
            "first_line": j_first, "azimuth_first_m": geo.track_start_m + j_first * v * t,
            "line_m": v * t}
    return images, info


def fast_focuser_geometry(opts, num, geo, scn, symbols, fast):
    """Azimuth FFT size of the fast chain's focuser: the same rd_focuser as chain.build
    builds (same configuration), queried, not run."""
    pulse_symbols = scenario.grid_of_mode(opts.mode, num)[2] * opts.presum_factor()
    cfg = focuser_config()
    cfg.symbols_per_pulse = pulse_symbols
    cfg.band = params.DOPPLER_BANDS[opts.band]
    cfg.rcmc_taps = opts.rcmc_taps
    cfg.lines_per_aperture = symbols // pulse_symbols
    foc = rd_focuser(num, geo, scn, fast["range_bins"], fast["range_axis_m"][0],
                     fast["range_axis_m"][1], cfg)
    return {"focuser_fft_size": int(foc.fft_size()), "pulse_symbols": pulse_symbols,
            "focuser_band_bins": int(foc.band_bins()), "line_shift": int(foc.line_shift())}


class ArraySource(gr.sync_block):
    """An image (lines x K) as a stream of complex64 K-vectors with tags on the first line
    (vector_source_c refuses some long vectors: set_output_multiple)."""

    def __init__(self, image, tags):
        gr.sync_block.__init__(self, "array_source", [], [(np.complex64, image.shape[1])])
        self.image = image
        self.tags = tags
        self.pos = 0

    def work(self, input_items, output_items):
        out = output_items[0]
        if self.pos == 0:
            for t in self.tags:
                self.add_item_tag(0, self.nitems_written(0), t.key, t.value)
        n = min(len(out), self.image.shape[0] - self.pos)
        if n <= 0:
            return -1
        out[:n] = self.image[self.pos:self.pos + n]
        self.pos += n
        return n


def metric_window(opts, num, geo, scn):
    """(first bin's slant range [m], bins) of the crop chain.build makes with
    --range-margin-m (the metric window): the same range_ifft, queried, not run."""
    from gnuradio import fft
    from ..nrsar_python import range_ifft
    nfft = scenario.fft_size_of(opts, num.num_subcarriers)
    ext = params.compute_extent(geo, scn)
    margin = max(opts.range_margin_m, 16 * num.range_bin_m(nfft))
    rif = range_ifft(num, nfft, fft.window.WIN_RECTANGULAR, -1.0,
                     max(0.0, ext.min_slant_range_m - margin), ext.max_slant_range_m + margin)
    return rif.range_axis_first_m(), int(rif.num_bins())


def run_fast(opts):
    """chain.simulate's float32 chain (its result dict), with the reference branch's image
    kept too: the fast chain's own SPEC 8 reference image."""
    fast, graph = chain.simulate_graph(opts, keep_reference=True)
    k = fast["range_bins"]
    img = np.asarray(graph["image_sink"].data(), np.complex64).reshape(-1, k)
    ref = np.asarray(graph["reference_sink"].data(), np.complex64).reshape(-1, k)
    return fast, img, ref


def interior_nmse_db(img, ref, nm, edge, weights):
    """SPEC 8 NMSE in float64 on the range bins at least `edge` bins from the crop edges
    (where the fast RCMC's kernel reads zeros beyond the crop)."""
    return nmse64_db(img[:, edge:-edge].astype(np.complex128),
                     ref[:, edge:-edge].astype(np.complex128), nm, weights[:, edge:-edge])


def probe_metrics(opts, num, geo, scn, symbols, img, ref, az_first, az_step, fast):
    """SPEC 8 metrics of (img, ref) by nmse_probe (the chain's own probe kernel)."""
    lines, k = img.shape
    first, rho = fast["range_axis_m"]
    mod = params.make_modulation(opts.modulation)
    band_lo, band_hi = fast["doppler_band_hz"]  # as nrsar-sim's probe: one zero-padded aperture
    probe = nmse_probe(num, geo, scn, constellation(mod).points(), params.make_filter(opts.filter),
                       opts.snr_db, k, probe_config(reference_input=True, lines_per_aperture=lines,
                                                    symbols_per_aperture=symbols,
                                                    band_lo_hz=band_lo, band_hi_hz=band_hi,
                                                    zero_padded=True))
    def tag(key, value):
        return gr.tag_utils.python_to_tag((0, pmt.intern(key), value, pmt.PMT_F))

    tags = [tag(tag_keys.aperture, pmt.from_uint64(0)),
            tag(tag_keys.azimuth_axis, pmt.make_tuple(
                pmt.from_double(az_first), pmt.from_double(az_step), pmt.from_uint64(lines))),
            tag(tag_keys.range_axis, pmt.make_tuple(
                pmt.from_double(first), pmt.from_double(rho), pmt.from_uint64(k)))]
    tb = gr.top_block()
    src_i = ArraySource(img, tags)
    src_r = ArraySource(ref, tags)
    tb.connect(src_i, (probe, 0))
    tb.connect(src_r, (probe, 1))
    tb.run()
    return {key: float(val) for key, val in probe.metrics().items()}


def strip_weights(geo, shape, az_first, az_step, fast):
    """The probe's per-pixel NMSE weights of a zero-padded aperture (SPEC 8) for an image of
    `shape` on the fast image's range axis and band."""
    lines, k = shape
    first, rho = fast["range_axis_m"]
    w = strip_pixel_weights(lines, k, az_first, az_step, first, rho, geo.track_start_m,
                            geo.track_start_m + lines * az_step, *fast["doppler_band_hz"],
                            geo.wavelength_m(), geo.velocity_mps)
    return np.asarray(w, np.float64).reshape(shape)


def nmse64_db(img, ref, nm, weights):
    """SPEC 8's calibrated NMSE in float64 numpy (cross-check of the probe on the float64
    image): the weighted mean over the pixels of non-zero weight."""
    c = np.vdot(ref, img) / np.vdot(ref, ref)
    err = np.abs(img / c - ref) ** 2
    return 10 * math.log10(nm * np.sum(weights * err) / np.count_nonzero(weights) /
                           np.max(np.abs(ref)) ** 2)


def run(argv=None):
    opts = parse(argv)
    num, geo, scn, symbols = setup(opts)
    result = {"command": "double_reference " + " ".join(argv or sys.argv[1:]),
              "load_avg": os.getloadavg()}
    fast_json = os.path.join(opts.work, "fast.json")
    if opts.guard_m > 0:  # the fast chain crops wider; metrics on the original window
        first_w, k_w = metric_window(opts, num, geo, scn)
    fast, img_fast, ref_fast = run_fast(  # 1. the float32 chain, images kept
        opts.replace(range_margin_m=opts.range_margin_m + opts.guard_m))
    if opts.guard_m > 0:
        k0 = int(round((first_w - fast["range_axis_m"][0]) / fast["range_axis_m"][1]))
        img_fast = img_fast[:, k0:k0 + k_w]
        ref_fast = ref_fast[:, k0:k0 + k_w]
        fast["guard_bins"] = [k0, fast["range_bins"] - k0 - k_w]
        fast["probe_wide_window"] = {k: fast[k] for k in ("nmse_db", "snr_out_db", "range_bins")}
        fast["range_axis_m"] = [first_w, fast["range_axis_m"][1]]
        fast["range_bins"] = k_w
        fast.update(probe_metrics(opts, num, geo, scn, symbols, img_fast, ref_fast,
                                  fast["azimuth_axis_m"][0], fast["azimuth_axis_m"][1], fast))
    results.write_json(fast_json, fast)
    results.write_npy(os.path.join(opts.work, "fast_ref.npy"), ref_fast)
    results.write_npy(os.path.join(opts.work, "fast_img.npy"), img_fast)
    del img_fast, ref_fast
    fast.update(fast_focuser_geometry(opts, num, geo, scn, symbols, fast))
    result["fast"] = fast
    rss_after_fast = runtime.peak_rss_mb()
    t0 = time.perf_counter()
    paths = capture(opts, num, geo, scn, symbols, opts.work)
    t1 = time.perf_counter()
    files = filtered_blocks(opts, num, geo, scn, symbols, paths, opts.work)
    for p in paths.values():
        os.remove(p)
    t2 = time.perf_counter()
    images, info = focus_reference(opts, num, geo, symbols, files, fast)
    t3 = time.perf_counter()
    nm = num.num_subcarriers * symbols
    met = probe_metrics(opts, num, geo, scn, symbols, images["img"], images["ref"],
                        info["azimuth_first_m"], info["line_m"], fast)
    w_double = strip_weights(geo, images["img"].shape, info["azimuth_first_m"], info["line_m"],
                             fast)
    met["nmse64_db"] = nmse64_db(images["img"], images["ref"], nm, w_double)
    results.write_npy(os.path.join(opts.out, "image_double.npy"), images["img"])
    results.write_npy(os.path.join(opts.out, "reference_double.npy"), images["ref"])
    # float64 NMSE of both images on the whole window and on the interior range bins
    img_fast = np.load(os.path.join(opts.work, "fast_img.npy"))
    ref_fast = np.load(os.path.join(opts.work, "fast_ref.npy"))
    edge = int(math.ceil(info["max_migration_bins"])) + opts.rcmc_taps // 2
    w_fast = strip_weights(geo, img_fast.shape, *fast["azimuth_axis_m"], fast)
    result["nmse64_db"] = {
        "fast": nmse64_db(img_fast.astype(np.complex128), ref_fast.astype(np.complex128), nm,
                          w_fast),
        "double": met["nmse64_db"], "interior_edge_bins": edge,
        "fast_interior": interior_nmse_db(img_fast, ref_fast, nm, edge, w_fast),
        "double_interior": interior_nmse_db(images["img"], images["ref"], nm, edge, w_double)}
    del img_fast, ref_fast
    t4 = time.perf_counter()
    if not opts.keep_work:
        shutil.rmtree(opts.work, ignore_errors=True)
    result["double"] = met
    result["double_info"] = info
    result["double_time_s"] = {"capture": t1 - t0, "echo_filter": t2 - t1, "focus": t3 - t2,
                               "metrics": t4 - t3, "total": t4 - t0}
    result["peak_rss_mb"] = {"after_fast": rss_after_fast, "end": runtime.peak_rss_mb()}
    diff = {}
    for key in ("nmse_db", "snr_out_db", "pslr_db", "islr_db", "irw_range_m", "irw_azimuth_m",
                "pel_db", "peak_error_m"):
        a, b = fast.get(key), met.get(key)
        diff[key] = None if a is None or b is None or not math.isfinite(b) else a - b
    result["fast_minus_double"] = diff
    result["goal_met"] = diff["nmse_db"] is not None and abs(diff["nmse_db"]) <= 0.1
    result["load_avg_end"] = os.getloadavg()
    return result


def main(argv=None):
    runtime.quiet_gnuradio_logs()
    res = run(argv)
    print(json.dumps(res, indent=1, default=float))
    return 0 if res["goal_met"] else 1


if __name__ == "__main__":
    sys.exit(main())
