#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-figures: the papers' figures from the gr-nrsar chain (nrsar-sim runs).

  fig3  the processing stages for the three paper targets, WF, SNR_in -20 dB, paper preset:
        (a) range-compressed data, (b) range-Doppler domain after the azimuth FFT,
        (c) after RCMC (eq. 41), (d) focused image. (a) and (d) are the chain's outputs;
        (b) and (c) are computed here with numpy from (a): azimuth FFT per range bin, then
        the range shift of eq. (40)-(41) per Doppler bin (Fourier shift, R0 of each bin).
  fig4  range and azimuth cuts through target 1 for RF / MF / WF at SNR_in -20, 5, 20 dB.
  fig5  NMSE vs SNR_in for RF / MF / WF with 256-QAM and the 8-PSK baseline, several seeds,
        next to NMSE_theory of SPEC 8.
  fig6  pilot-only vs data-aided imaging of target 1 (section V-C: MF, SNR_in 5 dB): SRS with
        2- and 20-slot periodicity next to data: range profiles over the whole unambiguous
        range (comb ghosts every c / (2 comb Delta f)), focused images, azimuth profiles of a
        4 s aperture (aliased replicas every v PRF / Ka at the 85.7 Hz SRS rate).
  fig7  NMSE vs SNR_in of the three schemes, with the data-aided theory of SPEC 8 and the
        pilot-only noise term N M / (P SNR_in).
  fig8  an extended scene (examples/scenes/ship_and_sea.yaml) reconstructed by the three
        schemes next to its reflectivity map.
  presum  the second paper's figure 6 and 8 analogues (range profiles and azimuth cuts per
        presumming method), the quadratic-phase bound of eq. (P-36) checked past it, and
        the chain's run time against D (presum_study.py).
  presum_compare  the second paper's method comparisons at D = 12 (presum_compare.py):
        single-pulse gain per method incl. the LMS baseline (its fig. 6), azimuth-cut metrics
        (table 5), entropy / NESZ / EPI on an extended scene (table 6, at D = 96), presum and focus
        CPU time (table 7).

Each figure is one PNG and one CSV in --out; progress goes to stderr.
"""

import csv
import dataclasses
import io
import math
import os
import sys
import tempfile
import time

import numpy as np

from .. import chain, cli, params, progress, results, scenario, theory
from ..options import SimOptions, Options, check_names, option

LIGHT_SPEED = 299792458.0
TARGET1 = "300,100"
PAPER_SNRS = (-20.0, 5.0, 20.0)
FILTERS = tuple(params.FILTERS)
FIGURES = ("fig3", "fig4", "fig5", "fig6", "fig7", "fig8", "presum", "presum_compare")


def log(text):
    print(f"nrsar-figures: {text}", file=sys.stderr, flush=True)


def run_sim(out, **overrides):
    """One nrsar-sim run into out (nrsar-sim's defaults with the given options); returns its
    JSON dict."""
    opts = SimOptions(out=out, json=True, **overrides).validate()
    os.makedirs(out, exist_ok=True)
    return chain.simulate(opts)


def load_image(result, key="image_npy"):
    return np.load(result[key])


def axis(first_step, count):
    return first_step[0] + first_step[1] * np.arange(count)


def db20(x, floor=-80.0):
    p = 20.0 * np.log10(np.abs(x) + 1e-30)
    return np.maximum(p - p.max(), floor)


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def write_csv(path, header, rows):
    text = io.StringIO()
    w = csv.writer(text)
    w.writerow(header)
    for r in rows:
        w.writerow([f"{v:.6g}" if isinstance(v, float) else v for v in r])
    results.write_text(path, text.getvalue())


# ---------------------------------------------------------------- fig3

def rcmc_numpy(rd, range_axis_m, doppler_hz, wavelength, velocity, range_centre):
    """eq. (40)-(41) on range-Doppler data rd (Doppler x range): each Doppler line is read
    at k + dk(f), dk = lambda^2 R0 f^2 / (8 v^2 rho), by a Fourier (band-limited) shift of the
    range profile; R0 of the line's centre bin (the migration changes by 1 % over the swath)."""
    k = rd.shape[1]
    rho = range_axis_m[1] - range_axis_m[0]
    r_mid = range_axis_m[k // 2]
    dk = wavelength ** 2 * r_mid * doppler_hz ** 2 / (8.0 * velocity ** 2 * rho)
    # The range spectrum of subcarriers 0..N-1 sits at [0, N / nfft) cycles per bin, across
    # Nyquist: the shift's frequencies are taken around its centre, not around 0.
    nu = range_centre + np.remainder(np.fft.fftfreq(k) - range_centre + 0.5, 1.0) - 0.5
    spec = np.fft.fft(rd, axis=1)
    return np.fft.ifft(spec * np.exp(2j * np.pi * nu[None, :] * dk[:, None]), axis=1)


def fig3(out, quick, workdir):
    log("fig3: WF, SNR_in -20 dB, three targets")
    preset = "small" if quick else "paper"
    aperture = 0.2 if quick else None
    res = run_sim(os.path.join(workdir, "fig3"), preset=preset, aperture_s=aperture,
                  scene="paper3", filter="wf", snr_db=-20.0, modulation="qam256", seed=1)
    rc = load_image(res, "range_compressed_npy")      # slow time x range
    img = load_image(res)
    m, k = rc.shape
    r_axis = axis(res["range_axis_m"], k)
    num = params.make_numerology(preset)
    geo = params.make_geometry("paper")
    tsym = num.symbol_s()
    y_track = geo.track_start_m + geo.velocity_mps * tsym * np.arange(m)
    # (b): azimuth FFT per range bin; Doppler axis centred on the scene band.
    spec = np.fft.fftshift(np.fft.fft(rc, axis=0), axes=0) / math.sqrt(m)
    f = np.fft.fftshift(np.fft.fftfreq(m, tsym))
    lo, hi = res["doppler_band_hz"]
    sel = (f >= lo - 40) & (f <= hi + 40)
    rd = spec[sel]
    fsel = f[sel]
    # (c): RCMC of eq. (41) (parabolic migration of eq. (40)).
    centre = (num.num_subcarriers - 1) / (2.0 * res["range_fft_size"])
    rd_c = rcmc_numpy(rd, r_axis, fsel, geo.wavelength_m(), geo.velocity_mps, centre)
    az = axis(res["azimuth_axis_m"], img.shape[0])

    plt = _pyplot()
    fig, axs = plt.subplots(2, 2, figsize=(10, 8), constrained_layout=True)
    ext = lambda xa, ya: [xa[0], xa[-1], ya[-1], ya[0]]
    panels = (
        (axs[0, 0], rc, ext(r_axis, y_track), "along-track position [m]",
         "(a) range compression"),
        (axs[0, 1], rd, ext(r_axis, fsel), "Doppler [Hz]", "(b) azimuth FFT"),
        (axs[1, 0], rd_c, ext(r_axis, fsel), "Doppler [Hz]", "(c) RCMC"),
        (axs[1, 1], img, ext(r_axis, az), "along-track position [m]",
         "(d) azimuth compression"),
    )
    for ax, data, extent, ylabel, title in panels:
        im = ax.imshow(db20(data, -40), aspect="auto", extent=extent, vmin=-40, vmax=0,
                       cmap="viridis", interpolation="nearest")
        ax.set_xlabel("slant range [m]")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        if not quick:
            ax.set_xlim(1020, 1060)
    if not quick:
        axs[1, 1].set_ylim(160, 80)
    fig.colorbar(im, ax=axs, label="power [dB re peak]", shrink=0.6)
    fig.suptitle(f"OFDM-SAR stages, WF, 256-QAM, SNR_in -20 dB, preset {preset}, "
                 f"M = {m} pulses", fontsize=11)
    png = os.path.join(out, "fig3.png")
    results.save_figure(fig, png, dpi=100)
    plt.close(fig)

    # CSV per stage: the brightest pixel, and the range migration of target 2 (alone at its
    # range, 1030.8 m, migrating up to 1035.7 m): power averaged over groups of rows (1/200
    # of the rows: 0.5 m of track, or a few Doppler bins), the peak range of each group within
    # [R0 - 4, R0 + 9] m, over the groups that stand above -6 dB of the window's maximum;
    # the spread of those peak ranges is the RCM that RCMC removes.
    r_t2 = math.hypot(250.0, 1000.0)
    win = (r_axis >= r_t2 - 4.0) & (r_axis <= r_t2 + 9.0)
    rows = []
    for stage, data, yax in (("range_compressed", rc, y_track), ("azimuth_fft", rd, fsel),
                             ("rcmc", rd_c, fsel), ("focused", img, az)):
        p = np.abs(data) ** 2
        i, j = np.unravel_index(np.argmax(p), p.shape)
        g = max(1, p.shape[0] // 200)
        pw = p[:p.shape[0] // g * g, win].reshape(-1, g, int(win.sum())).mean(axis=1)
        strong = pw.max(axis=1) > 0.25 * pw.max()
        col = r_axis[win][np.argmax(pw[strong], axis=1)]
        rows.append((stage, float(r_axis[j]), float(yax[i]), float(np.ptp(col))))
    write_csv(os.path.join(out, "fig3.csv"),
              ("stage", "peak_range_m", "peak_azimuth", "t2_range_migration_m"), rows)
    log(f"fig3: {png} ({res['runtime_s']:.1f} s chain)")
    return {"fig3_peak_error_m": res["peak_error_m"]}


# ---------------------------------------------------------------- fig4

def upsample_cut(cut, axis_m, factor, centre_cycles):
    """Band-limited interpolation of a cut whose spectrum is centred at centre_cycles."""
    n = len(cut)
    k = np.arange(n)
    spec = np.fft.fft(cut.astype(np.complex128) * np.exp(-2j * np.pi * centre_cycles * k))
    padded = np.zeros(n * factor, complex)
    h = n // 2
    padded[:h] = spec[:h]
    padded[-(n - h):] = spec[h:]
    fine = np.fft.ifft(padded) * factor
    return axis_m[0] + (axis_m[1] - axis_m[0]) * np.arange(n * factor) / factor, fine


def fig4(out, quick, workdir):
    preset = "small" if quick else "paper"
    aperture = 0.2 if quick else None
    x, y = (float(v) for v in TARGET1.split(","))
    rows, cuts = [], {}
    for snr in PAPER_SNRS:
        for filt in FILTERS:
            log(f"fig4: {filt.upper()} SNR_in {snr:g} dB")
            res = run_sim(os.path.join(workdir, f"fig4_{filt}_{snr:g}"), preset=preset,
                          aperture_s=aperture, target=[TARGET1], filter=filt, snr_db=snr,
                          modulation="qam256", seed=1)
            img = load_image(res)
            geo_h = 1000.0
            r_axis = axis(res["range_axis_m"], img.shape[1])
            a_axis = axis(res["azimuth_axis_m"], img.shape[0])
            # cuts through the target's true pixel (not the noisy maximum)
            kb = int(np.argmin(np.abs(r_axis - math.hypot(x, geo_h))))
            ml = int(np.argmin(np.abs(a_axis - y)))
            # range cut: 8x band-limited interpolation (the 1.5 m bins straddle the peak),
            # demodulated by the range spectrum's centre (N-1)/(2 nfft) cycles per bin
            centre = (res["subcarriers"] - 1) / (2.0 * res["range_fft_size"])
            r_axis, rng = upsample_cut(img[ml, :], r_axis, 8, centre)
            rng = db20(rng, -150)
            azi = db20(img[:, kb], -150)
            cuts[(snr, filt)] = (r_axis, rng, a_axis, azi, res)
            # CSV: +-15 m in range and +-5 m along track around the target, at most ~1000
            # samples per cut (every line is 2 mm at full rate)
            for cut, ax_m, val, centre, half in (("range", r_axis, rng, math.hypot(x, geo_h), 15),
                                                 ("azimuth", a_axis, azi, y, 5)):
                idx = np.flatnonzero(np.abs(ax_m - centre) <= half)
                peak = int(np.argmax(val))
                keep = set(idx[::max(1, len(idx) // 1000)].tolist()) | {peak}
                for i in sorted(keep):
                    rows.append((snr, filt, cut, float(ax_m[i]), float(val[i])))
    write_csv(os.path.join(out, "fig4.csv"),
              ("snr_db", "filter", "cut", "position_m", "power_db"), rows)

    plt = _pyplot()
    fig, axs = plt.subplots(2, 3, figsize=(13, 7))
    r0 = math.hypot(x, 1000.0)
    for col, snr in enumerate(PAPER_SNRS):
        for filt, style in zip(FILTERS, ("-", "--", ":")):
            r_axis, rng, a_axis, azi, res = cuts[(snr, filt)]
            lab = f"{filt.upper()} (NMSE {res['nmse_db']:.1f} dB)"
            lines = axs[0, col].plot(r_axis - r0, rng, style, label=lab)
            axs[1, col].plot(a_axis - y, azi, style, label=lab, color=lines[0].get_color())
            # the per-pixel error floor (data randomness + noise) re peak: NMSE / (N M),
            # far below the PSF's sidelobes at this processing gain
            floor = res["nmse_db"] - 10 * math.log10(res["subcarriers"] * res["symbols"])
            for r in (0, 1):
                axs[r, col].axhline(floor, ls=style, lw=0.8, color=lines[0].get_color())
        axs[0, col].set_title(f"SNR_in {snr:g} dB: range cut", fontsize=10)
        axs[1, col].set_title(f"SNR_in {snr:g} dB: azimuth cut", fontsize=10)
        axs[0, col].set_xlabel("slant range - R0 [m]")
        axs[1, col].set_xlabel("along-track - y1 [m]")
        if not quick:
            axs[0, col].set_xlim(-15, 15)
            axs[1, col].set_xlim(-5, 5)
        for r in (0, 1):
            axs[r, col].set_ylim(-120, 3)
            axs[r, col].grid(alpha=0.3)
            axs[r, col].legend(fontsize=7, loc="lower right")
        axs[0, col].set_ylabel("power [dB re peak]")
        axs[1, col].set_ylabel("power [dB re peak]")
    fig.suptitle(f"Target 1 ({TARGET1} m), 256-QAM, preset {preset}: range and azimuth cuts "
                 "(horizontal lines: error floor per pixel, NMSE - 10 log10(N M))",
                 fontsize=11)
    fig.tight_layout()
    png = os.path.join(out, "fig4.png")
    results.save_figure(fig, png, dpi=100)
    plt.close(fig)
    log(f"fig4: {png}")
    return {f"fig4_nmse_{f}_{s:g}": cuts[(s, f)][4]["nmse_db"]
            for s in PAPER_SNRS for f in FILTERS}


# ---------------------------------------------------------------- fig5 / sweeps

def sweep_config(quick):
    """Preset and aperture of the NMSE sweeps (fig5, accuracy): the paper numerology at full
    rate with a 0.4 s aperture (9600 pulses) and target 1 alone; quick: the small preset
    (N = 512), 0.2 s."""
    if quick:
        return {"preset": "small", "aperture_s": 0.2}
    return {"preset": "paper", "aperture_s": 0.4}


def nmse_sweep(workdir, cases, snrs, seeds, quick, label):
    """Measured NMSE of every (modulation, filter) in cases at every SNR and seed.

    Returns rows (modulation, filter, snr_db, seed, nmse_db, nmse_theory_db, numpy_theory_db,
    nmse_theory_band_db)."""
    cfg = sweep_config(quick)
    rows = []
    total = len(cases) * len(snrs) * len(seeds)
    done = 0
    start = time.perf_counter()
    for mod, filt in cases:
        for snr in snrs:
            for seed in seeds:
                res = run_sim(os.path.join(workdir, "sweep"), target=[TARGET1], filter=filt,
                              modulation=mod, snr_db=float(snr), seed=int(seed), **cfg)
                rows.append((mod, filt, float(snr), int(seed), res["nmse_db"],
                             res["nmse_theory_db"], theory.nmse_theory_db(mod, filt, snr),
                             res["nmse_theory_band_db"]))
                done += 1
                progress.step(done, total, label, level=1)
            log(f"{label}: {done}/{total} runs, {mod} {filt.upper()} SNR_in {snr:g} dB: "
                f"NMSE {np.mean([r[4] for r in rows[-len(seeds):]]):.2f} dB "
                f"(theory {rows[-1][5]:.2f}), {time.perf_counter() - start:.0f} s")
    return rows


def summarise(rows):
    """{(mod, filt, snr): (mean, min, max, theory, theory with the band term)} over seeds
    (means of dB values)."""
    acc = {}
    for mod, filt, snr, _seed, nmse, th, _np, band in rows:
        acc.setdefault((mod, filt, snr), ([], th, band))[0].append(nmse)
    return {key: (float(np.mean(v)), float(np.min(v)), float(np.max(v)), th, band)
            for key, (v, th, band) in acc.items()}


def fig5(out, quick, workdir, seeds):
    snrs = (-30, -10, 10, 30) if quick else tuple(range(-30, 31, 5))
    cases = [("qam256", f) for f in FILTERS] + [("psk8", "wf")]
    rows = nmse_sweep(workdir, cases, snrs, range(1, seeds + 1), quick, "fig5")
    write_csv(os.path.join(out, "fig5.csv"),
              ("modulation", "filter", "snr_db", "seed", "nmse_db", "nmse_theory_db",
               "theory_py_db", "nmse_theory_band_db"), rows)
    summ = summarise(rows)
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 5))
    colours = {"rf": "C0", "mf": "C1", "wf": "C2"}
    fine = np.linspace(min(snrs), max(snrs), 121)
    for case, (mod, filt) in enumerate(cases):
        shift = 0.4 * (case - (len(cases) - 1) / 2)  # markers side by side, not on top
        mean = np.array([summ[(mod, filt, float(s))][0] for s in snrs])
        lo = np.array([summ[(mod, filt, float(s))][1] for s in snrs])
        hi = np.array([summ[(mod, filt, float(s))][2] for s in snrs])
        c = colours[filt] if mod == "qam256" else "C3"
        name = f"{filt.upper()} 256-QAM" if mod == "qam256" else "8-PSK (WF = MF = RF)"
        ax.errorbar(np.array(snrs) + shift, mean, yerr=[mean - lo, hi - mean], fmt="o",
                    color=c, ms=4,
                    capsize=2, label=f"{name}, measured")
        ax.plot(fine, [theory.nmse_theory_db(mod, filt, s) for s in fine], "-", color=c,
                lw=1, alpha=0.7, label=f"{name}, theory")
    ax.set_xlabel("SNR_in [dB]")
    ax.set_ylabel("NMSE [dB]")
    cfg = sweep_config(quick)
    ax.set_title(f"NMSE vs SNR_in, target 1, preset {cfg['preset']}, "
                 f"aperture {cfg['aperture_s']} s, {seeds} seeds", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    png = os.path.join(out, "fig5.png")
    results.save_figure(fig, png, dpi=100)
    plt.close(fig)
    log(f"fig5: {png}")
    off = [summ[k][0] - summ[k][4] for k in summ]  # against the floor with the band term
    return {"fig5_offset_min_db": min(off), "fig5_offset_max_db": max(off)}


def presum(out, quick, workdir):
    """The presummer study writes its own PNGs and CSVs (presum_*) into out."""
    from . import presum_study  # here: `python3 -m` of the study finds it not yet imported
    presum_study.run(presum_study.PresumStudyOptions(out=out, quick=quick).validate())
    return {}


def presum_compare_figure(out, quick, workdir):
    """The second paper's comparisons write their own PNGs and CSVs (presum_compare_*)."""
    from . import presum_compare  # as presum()
    summary = presum_compare.run(presum_compare.PresumCompareOptions(
        out=out, workdir=workdir, scene=ship_and_sea_file(workdir), quick=quick).validate())
    return {f"fig6_gain_{r['method']}_db": r["gain_db"] for r in summary["fig6"]
            if r["method"] in ("lms", "cheby")}


# ---------------------------------------------------------------- fig6-8: pilot-only vs data-aided

# Section V-C: MF at SNR_in 5 dB unless said otherwise; the schemes in the paper's order.
VC_SCHEMES = (("srs20", "SRS only, 20-slot period"), ("srs2", "SRS only, 2-slot period"),
              ("data", "data-aided (every RE)"))
VC_FILTER, VC_SNR = "mf", 5.0
# Azimuth aliasing shows in the image only when the target's Doppler band Ka Ta exceeds the
# 85.7 Hz SRS rate AND the replicas, v PRF / Ka = 77 m either side, fall inside the focused
# block: a 4 s aperture (track 0..200 m, T1 at its middle) does both; the paper's 2 s block
# folds only 2 x 13 Hz of its 112 Hz band, into replicas outside its 100 m window.
VC_ALIAS_APERTURE_S = 4.0
SHIP_AND_SEA = "ship_and_sea.yaml"


def vc_predictions(preset, mode, aperture_s=None):
    """Section V-C's numbers for one scheme from the numerology and geometry alone: pulse
    rate, occupied band B and range IRW 0.886 c / (2 B), range ghost spacing c / (2 comb Delta f)
    (data: the unambiguous range c / (2 Delta f)), Ka(R0), azimuth replica spacing
    v PRF / Ka(R0) = lambda R0 PRF / (2 v), azimuth IRW 0.886 v / min(Ka Ta, PRF)."""
    num = params.make_numerology(preset)
    geo = params.make_geometry("paper", **({} if aperture_s is None else
                                           {"aperture_s": aperture_s}))
    kind, srs, spp = scenario.grid_of_mode(mode, num)
    df = num.subcarrier_spacing_hz
    x, y = (float(v) for v in TARGET1.split(","))
    r0 = math.hypot(x, geo.height_m)
    prf = 1.0 / (spp * num.symbol_s())
    ka = 2.0 * geo.velocity_mps ** 2 / (geo.wavelength_m() * r0)
    if kind == "data":
        sc = np.arange(num.num_subcarriers)
        band, ghost = num.num_subcarriers * df, LIGHT_SPEED / (2.0 * df)
    else:
        sc = srs.start_subcarrier + np.arange(srs.comb_offset, srs.num_subcarriers(), srs.comb)
        band, ghost = len(sc) * srs.comb * df, LIGHT_SPEED / (2.0 * srs.comb * df)
    doppler_band = ka * geo.aperture_s
    return {"prf_hz": prf, "ka_hz_per_s": ka, "replica_spacing_m": geo.velocity_mps * prf / ka,
            "ghost_spacing_m": ghost, "band_hz": band,
            "range_irw_m": 0.886 * LIGHT_SPEED / (2.0 * band),
            "azimuth_irw_m": 0.886 * geo.velocity_mps / min(doppler_band, prf),
            "doppler_band_hz": doppler_band, "r0_m": r0, "y0_m": y, "subcarriers": sc,
            "pulse_symbols": spp, "pilots_per_pulse": len(sc)}


def half_power_width(profile, step):
    """Half-power width of a power profile around its maximum, crossings interpolated
    linearly in power."""
    p = np.asarray(profile, float) / np.max(profile)
    j = int(np.argmax(p))
    left = j
    while left > 0 and p[left] > 0.5:
        left -= 1
    right = j
    while right < len(p) - 1 and p[right] > 0.5:
        right += 1
    xl = left + (0.5 - p[left]) / (p[left + 1] - p[left])
    xr = right - (0.5 - p[right]) / (p[right - 1] - p[right])
    return (xr - xl) * step


def range_energy_profile(img, centre_cycles, up=16):
    """Sum over the azimuth lines of abs(line)^2, each line interpolated by up (band-limited,
    around the range spectrum's centre). Azimuth defocus moves a line's energy to other lines
    but keeps it, so this is the range response free of the depth of focus (a cut through the
    peak line reads the wide SRS response narrower: its shoulders, off R0, are compressed with
    the Ka of their own range and spread in azimuth)."""
    n = img.shape[1]
    h = n // 2
    demod = np.exp(-2j * np.pi * centre_cycles * np.arange(n))
    acc = np.zeros(n * up)
    for a in range(0, img.shape[0], 2048):
        spec = np.fft.fft(img[a:a + 2048].astype(np.complex128) * demod, axis=1)
        pad = np.zeros((spec.shape[0], n * up), complex)
        pad[:, :h] = spec[:, :h]
        pad[:, -(n - h):] = spec[:, h:]
        acc += (np.abs(np.fft.ifft(pad, axis=1)) ** 2).sum(axis=0)
    return acc


def peak_near(profile_db, axis_m, centre, half_width):
    """(position, level) of the largest sample of profile_db within centre +- half_width,
    refined by a parabola through it and its neighbours."""
    sel = np.flatnonzero(np.abs(axis_m - centre) <= half_width)
    i = int(sel[np.argmax(profile_db[sel])])
    if 0 < i < len(profile_db) - 1:
        a, b, c = profile_db[i - 1:i + 2]
        den = a - 2 * b + c
        d = 0.5 * (a - c) / den if den < 0 else 0.0
        return float(axis_m[i] + d * (axis_m[1] - axis_m[0])), float(b - 0.25 * (a - c) * d)
    return float(axis_m[i]), float(profile_db[i])


def vc_range_chain(tb, preset, mode, aperture_s, r_lo, r_hi, snr_db, seed):
    """Connects nrsar-sim's front end for T1 into tb: transmitter -> head -> echo -> MF ->
    (SRS modes: the SRS symbols only, as nrsar-sim keeps them) -> range IFFT cropped to
    [r_lo, r_hi] (0, 0: every bin). Returns (range_ifft, pulses, chain dict)."""
    from gnuradio import blocks, fft, gr
    from ..nrsar_python import nr_isac_tx, range_ifft, scene_echo, tf_filter
    num = params.make_numerology(preset)
    geo = params.make_geometry("paper", aperture_s=aperture_s)
    kind, srs, spp = scenario.grid_of_mode(mode, num)
    symbols = int(geo.symbols_per_aperture(num))
    n = num.num_subcarriers
    scn = params.make_scene(TARGET1)
    tx = nr_isac_tx(num, params.make_modulation("qam256"), params.make_tx_mode(kind), srs, seed)
    head = blocks.head(gr.sizeof_gr_complex * n, symbols)
    echo = scene_echo(num, geo, scn, snr_db, seed + 1)
    tff = tf_filter(n, params.make_filter(VC_FILTER), snr_db, False)
    rif = range_ifft(num, range_ifft.fast_fft_size(n), fft.window.WIN_RECTANGULAR, -1.0,
                     r_lo, r_hi)
    tb.connect(tx, head, echo, (tff, 0))
    tb.connect(head, (tff, 1))
    tb.connect((echo, 1), blocks.null_sink(gr.sizeof_gr_complex * n))
    if spp == 1:
        tb.connect(tff, rif)
    else:
        tb.connect(tff, blocks.keep_m_in_n(gr.sizeof_gr_complex * n, 1, spp,
                                           srs.symbol_in_slot), rif)
    return rif, symbols // spp, {"num": num, "geo": geo, "scn": scn, "spp": spp}


def range_profile(preset, mode, aperture_s, snr_db=VC_SNR, seed=1):
    """(range axis [m], mean power per bin) of the range-compressed pulses of T1 over the whole
    unambiguous range c / (2 Delta f): vc_range_chain uncropped, the pulses summed in power by
    integrate_ff. No focuser: with an uncropped window it plans its output for the far range
    (docs/pilot_vs_data.md, findings) and needs gigabytes at full rate."""
    from gnuradio import blocks, gr
    tb = gr.top_block("range-profile")
    rif, pulses, _ = vc_range_chain(tb, preset, mode, aperture_s, 0.0, 0.0, snr_db, seed)
    k = rif.num_bins()
    sink = blocks.vector_sink_f(k)
    tb.connect(rif, blocks.complex_to_mag_squared(k), blocks.integrate_ff(pulses, k), sink)
    tb.run()
    prof = np.asarray(sink.data(), dtype=float)[:k] / pulses
    return rif.range_axis_first_m() + rif.range_bin_m() * np.arange(k), prof


def focused_window(preset, mode, aperture_s, r_lo, r_hi, snr_db=VC_SNR, seed=1):
    """(image, range axis [m]) of T1 focused by rd_focuser (nrsar-sim's settings) over the
    slant-range window [r_lo, r_hi] only: how a window that holds an SRS range ghost, and no
    target, focuses."""
    from gnuradio import blocks, gr
    from ..nrsar_python import doppler_band, focuser_config, rd_focuser
    tb = gr.top_block("focused-window")
    rif, pulses, c = vc_range_chain(tb, preset, mode, aperture_s, r_lo, r_hi, snr_db, seed)
    cfg = focuser_config()
    cfg.symbols_per_pulse = c["spp"]
    cfg.band = doppler_band.SCENE
    cfg.lines_per_aperture = pulses
    k = rif.num_bins()
    foc = rd_focuser(c["num"], c["geo"], c["scn"], k, rif.range_axis_first_m(),
                     rif.range_bin_m(), cfg)
    sink = blocks.vector_sink_c(k)
    tb.connect(rif, foc, sink)
    tb.run()
    img = np.asarray(sink.data(), dtype=np.complex128).reshape(-1, k)
    return img, rif.range_axis_first_m() + rif.range_bin_m() * np.arange(k)


def ghost_defocus_db(preset, mode, aperture_s=None):
    """Predicted peak of the focused range ghost re the target's: the ghost carries the azimuth
    chirp of R0 (rate Ka(R0)) but is compressed with Ka(R0 + ghost); the residual chirp rate
    Kr = 1 / (1/Ka(R0 + g) - 1/Ka(R0)) over the target's Doppler band B = Ka(R0) Ta leaves a
    Fresnel peak of amplitude sqrt(Kr) against B in focus: 10 log10(Kr / B^2)."""
    pred = vc_predictions(preset, mode, aperture_s)
    ka0 = pred["ka_hz_per_s"]
    ka_g = ka0 * pred["r0_m"] / (pred["r0_m"] + pred["ghost_spacing_m"])
    kr = 1.0 / (1.0 / ka_g - 1.0 / ka0)
    band = min(pred["doppler_band_hz"], pred["prf_hz"])
    return 10 * math.log10(kr / band ** 2)


def vc_run(workdir, name, preset, mode, **overrides):
    base = {"preset": preset, "target": [TARGET1], "filter": VC_FILTER, "snr_db": VC_SNR,
            "modulation": "qam256", "seed": 1, "mode": mode}
    base.update(overrides)
    return run_sim(os.path.join(workdir, name), **base)


def fig6(out, quick, workdir):
    """Pilot-only vs data-aided imaging of target 1: ghosts, aliasing, resolution."""
    preset = "small" if quick else "paper"
    aperture = 0.2 if quick else None
    alias_aperture = VC_ALIAS_APERTURE_S
    runs, rows = {}, []
    for mode, _label in VC_SCHEMES:
        log(f"fig6: {mode}: focused image, whole range, {alias_aperture:g} s aperture")
        pred = vc_predictions(preset, mode, aperture)
        focus = vc_run(workdir, f"fig6_{mode}", preset, mode, aperture_s=aperture)
        r_wide, prof = range_profile(preset, mode, aperture or 2.0)
        alias = vc_run(workdir, f"fig6_{mode}_alias", preset, mode, aperture_s=alias_aperture)
        # (1) range profile over the unambiguous range: mean power of the range-compressed pulses
        prof_db = 10 * np.log10(prof / prof.max() + 1e-30)
        srs_pred = vc_predictions(preset, "srs2")
        step = r_wide[1] - r_wide[0]
        # before azimuth focusing the target sits at its range over the track, eq. (8)
        t = np.linspace(0.0, aperture or 2.0, 201)
        v = params.make_geometry("paper").velocity_mps
        r_track = float(np.mean(np.hypot(pred["r0_m"], pred["y0_m"] - v * t)))
        main_r, main_db = peak_near(prof_db, r_wide, r_track, 3 * step)
        ghost_r, ghost_db = peak_near(prof_db, r_wide, main_r + srs_pred["ghost_spacing_m"],
                                      3 * step)
        # (2) focused image near the target: range IRW from the energy profile
        img = load_image(focus)
        centre = float(np.mean(pred["subcarriers"])) / focus["range_fft_size"]
        energy = range_energy_profile(img, centre)
        irw_r = half_power_width(energy, focus["range_axis_m"][1] / 16)
        # (3) azimuth profile of the long aperture: the brightest range bin of every line
        aimg = load_image(alias)
        az = axis(alias["azimuth_axis_m"], aimg.shape[0])
        az_prof = np.max(np.abs(aimg.astype(np.complex128)) ** 2, axis=1)
        az_db = 10 * np.log10(az_prof / az_prof.max() + 1e-30)
        del aimg
        apred = vc_predictions(preset, mode, alias_aperture)
        spacing = vc_predictions(preset, "srs20", alias_aperture)["replica_spacing_m"]
        y_main, lv_main = peak_near(az_db, az, apred["y0_m"], 2.0)
        reps = [peak_near(az_db, az, y_main + s * spacing, 0.15 * spacing) for s in (-1, 1)]
        if mode != "data":  # the ghost window focused: energy kept, peak defocused
            g_img, _ = focused_window(preset, mode, aperture or 2.0,
                                      main_r + srs_pred["ghost_spacing_m"] - 40,
                                      main_r + srs_pred["ghost_spacing_m"] + 40)
            t_img, _ = focused_window(preset, mode, aperture or 2.0, main_r - 40, main_r + 40)
            pg, pt = np.abs(g_img) ** 2, np.abs(t_img) ** 2
            rows += [(mode, "ghost_focused_peak_db", 10 * math.log10(pg.max() / pt.max()),
                      ghost_defocus_db(preset, mode, aperture), "dB re target peak (image)"),
                     (mode, "ghost_focused_energy_db", 10 * math.log10(pg.sum() / pt.sum()),
                      0.0, "dB re target energy (image)")]
        runs[mode] = {"focus": focus, "img": img, "r_wide": r_wide, "prof_db": prof_db,
                      "az": az, "az_db": az_db, "energy": energy, "pred": pred,
                      "apred": apred}
        pulse_rate = params.make_geometry("paper").velocity_mps / focus["azimuth_axis_m"][1]
        if mode == "data":
            pulse_rate = 1.0 / params.make_numerology(preset).symbol_s()
        rows += [
            (mode, "pulse_rate_hz", pulse_rate, pred["prf_hz"], "Hz"),
            (mode, "occupied_band_hz", float("nan"), pred["band_hz"], "Hz"),
            (mode, "ghost_offset_m", ghost_r - main_r,
             srs_pred["ghost_spacing_m"] if mode != "data" else float("nan"), "m"),
            (mode, "ghost_level_db", ghost_db - main_db, 0.0 if mode != "data" else float("nan"),
             "dB re main peak (range profile)"),
            (mode, "range_irw_m", irw_r, pred["range_irw_m"], "m"),
            (mode, "azimuth_irw_m", focus["irw_azimuth_m"], pred["azimuth_irw_m"], "m"),
            (mode, "replica_offset_minus_m", reps[0][0] - y_main,
             -apred["replica_spacing_m"] if mode == "srs20" else float("nan"), "m (4 s)"),
            (mode, "replica_offset_plus_m", reps[1][0] - y_main,
             apred["replica_spacing_m"] if mode == "srs20" else float("nan"), "m (4 s)"),
            (mode, "replica_level_minus_db", reps[0][1] - lv_main, float("nan"), "dB (4 s)"),
            (mode, "replica_level_plus_db", reps[1][1] - lv_main, float("nan"), "dB (4 s)"),
            (mode, "nmse_db", focus["nmse_db"], float("nan"), "dB"),
            (mode, "snr_out_db", focus["snr_out_db"], float("nan"), "dB"),
            (mode, "pel_db", focus["pel_db"], float("nan"), "dB"),
        ]
    write_csv(os.path.join(out, "fig6.csv"),
              ("scheme", "quantity", "measured", "predicted", "unit"), rows)

    plt = _pyplot()
    fig, axs = plt.subplots(3, 3, figsize=(15, 12), constrained_layout=True)
    for col, (mode, label) in enumerate(VC_SCHEMES):
        run = runs[mode]
        pred, focus = run["pred"], run["focus"]
        ax = axs[0, col]
        ax.plot(run["r_wide"], run["prof_db"], lw=0.8)
        g = vc_predictions(preset, "srs2")["ghost_spacing_m"]
        span = run["r_wide"][-1] + run["r_wide"][1] - run["r_wide"][0]
        for k in range(-1, 4):
            r = (pred["r0_m"] + k * g) % span
            ax.axvline(r, color="C3", ls=":", lw=0.8,
                       label="R0 + k c / (2 comb Delta f)" if k == 0 else None)
        ax.set_ylim(-60, 3)
        ax.set_xlabel("slant range [m]")
        ax.set_ylabel("mean pulse power [dB re peak]")
        ax.set_title(f"(a) {label}: range profile, {aperture or 2.0:g} s", fontsize=10)
        ax.legend(fontsize=7, loc="lower right")
        ax.grid(alpha=0.3)

        ax = axs[1, col]
        img = run["img"]
        r_ax = axis(focus["range_axis_m"], img.shape[1])
        a_ax = axis(focus["azimuth_axis_m"], img.shape[0])
        im = ax.imshow(db20(img, -40), aspect="auto", vmin=-40, vmax=0, cmap="viridis",
                       interpolation="nearest",
                       extent=[r_ax[0], r_ax[-1], a_ax[-1], a_ax[0]])
        ax.set_xlabel("slant range [m]")
        ax.set_ylabel("along-track position [m]")
        irw_r = [r[2] for r in rows if r[0] == mode and r[1] == "range_irw_m"][0]
        ax.set_title(f"(b) {label}: focused image\nrange IRW {irw_r:.2f} m "
                     f"(0.886 c/2B = {pred['range_irw_m']:.2f} m), NMSE "
                     f"{focus['nmse_db']:.1f} dB", fontsize=9)
        if not quick:
            ax.set_ylim(pred["y0_m"] + 15, pred["y0_m"] - 15)
        fig.colorbar(im, ax=ax, label="power [dB re peak]")

        ax = axs[2, col]
        ax.plot(run["az"], run["az_db"], lw=0.8)
        sp = run["apred"]["replica_spacing_m"]
        sp20 = vc_predictions(preset, "srs20", alias_aperture)["replica_spacing_m"]
        for s in (-1, 1):
            ax.axvline(run["apred"]["y0_m"] + s * sp20, color="C3", ls=":", lw=0.8,
                       label="y0 +- v PRF_srs20 / Ka" if s == 1 else None)
        ax.set_ylim(-50, 3)
        ax.set_xlabel("along-track position [m]")
        ax.set_ylabel("max over range [dB re peak]")
        ax.set_title(f"(c) {label}: azimuth profile, {alias_aperture:g} s aperture\n"
                     f"PRF {run['apred']['prf_hz']:.1f} Hz, Ka Ta "
                     f"{run['apred']['doppler_band_hz']:.0f} Hz, v PRF / Ka = {sp:.1f} m",
                     fontsize=9)
        ax.legend(fontsize=7, loc="lower right")
        ax.grid(alpha=0.3)
    fig.suptitle(f"Pilot-only (SRS comb 4, 24 RB) vs data-aided imaging of T1 ({TARGET1} m), "
                 f"MF, 256-QAM data, SNR_in {VC_SNR:g} dB, preset {preset}", fontsize=11)
    png = os.path.join(out, "fig6.png")
    results.save_figure(fig, png, dpi=90)
    plt.close(fig)
    log(f"fig6: {png}")
    return {f"fig6_{r[0]}_{r[1]}": r[2] for r in rows
            if r[1] in ("ghost_offset_m", "ghost_level_db", "range_irw_m",
                        "replica_offset_plus_m")}


def pilot_noise_nmse_db(preset, mode, snr_db, symbols):
    """The noise term of NMSE for a grid of P known unit-modulus REs under MF:
    N M / (P SNR_in) (SPEC 8's E abs(g)^2 / SNR_in / E{chi}^2 with the image normalised to
    the N M REs of the whole grid); for the data grid P = N M and it is 1 / SNR_in."""
    num = params.make_numerology(preset)
    pred = vc_predictions(preset, mode)
    p = pred["pilots_per_pulse"] * (symbols // pred["pulse_symbols"])
    return 10 * math.log10(num.num_subcarriers * symbols / p) - snr_db


def fig7(out, quick, workdir):
    """NMSE vs SNR_in of the three schemes (metrics only: no images kept)."""
    preset = "small" if quick else "paper"
    aperture = 0.2 if quick else None
    snrs = (-30.0, 0.0, 30.0) if quick else (-30.0, -20.0, -10.0, 0.0, 5.0, 10.0, 20.0, 30.0)
    rows = []
    for mode, _label in VC_SCHEMES:
        for snr in snrs:
            res = vc_run(workdir, "fig7", preset, mode, snr_db=snr, aperture_s=aperture,
                         images="none")
            noise = pilot_noise_nmse_db(preset, mode, snr, res["symbols"])
            th = theory.nmse_theory_db("qam256", VC_FILTER, snr) if mode == "data" else float("nan")
            rows.append((mode, snr, res["nmse_db"], th, noise, res["symbols"]))
            log(f"fig7: {mode} SNR_in {snr:g} dB: NMSE {res['nmse_db']:.2f} dB "
                f"(noise term {noise:.2f} dB)")
    write_csv(os.path.join(out, "fig7.csv"),
              ("scheme", "snr_db", "nmse_db", "nmse_theory_db", "noise_term_db", "symbols"),
              rows)
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 5))
    fine = np.linspace(min(snrs), max(snrs), 121)
    for i, (mode, label) in enumerate(VC_SCHEMES):
        sel = [r for r in rows if r[0] == mode]
        c = f"C{i}"
        ax.plot([r[1] for r in sel], [r[2] for r in sel], "o-", color=c, ms=4,
                label=f"{label}, measured")
        if mode == "data":
            ax.plot(fine, [theory.nmse_theory_db("qam256", VC_FILTER, s) for s in fine], "-",
                    color=c, lw=1, alpha=0.6, label="data-aided, theory (SPEC 8)")
        else:
            ax.plot([r[1] for r in sel], [r[4] for r in sel], "--", color=c, lw=1, alpha=0.7,
                    label=f"{mode}: noise term N M / (P SNR_in)")
    ax.set_xlabel("SNR_in [dB]")
    ax.set_ylabel("NMSE [dB]")
    ax.set_title(f"NMSE vs SNR_in, T1, MF, preset {preset}, "
                 f"aperture {aperture or 2.0:g} s (reference: the data-aided ideal image)",
                 fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    png = os.path.join(out, "fig7.png")
    results.save_figure(fig, png, dpi=100)
    plt.close(fig)
    log(f"fig7: {png}")
    gap = {}
    for snr in snrs:
        d = [r[2] for r in rows if r[0] == "data" and r[1] == snr][0]
        for mode in ("srs2", "srs20"):
            gap[f"fig7_gap_{mode}_{snr:g}"] = [r[2] for r in rows
                                               if r[0] == mode and r[1] == snr][0] - d
    return gap


def ship_and_sea_file(workdir):
    """examples/scenes/ship_and_sea.yaml of the source tree (found from this module in the
    source, build or test tree), else the same scene regenerated into workdir."""
    here = os.path.dirname(os.path.realpath(__file__))
    for up in range(1, 6):
        path = os.path.join(here, *([".."] * up), "examples", "scenes", SHIP_AND_SEA)
        if os.path.isfile(path):
            return os.path.normpath(path)
    from .. import scenes
    np.save(os.path.join(workdir, "ship_and_sea.npy"), scenes.ship_and_sea(seed=4))
    path = os.path.join(workdir, SHIP_AND_SEA)
    with open(path, "w") as f:
        f.write("geometry: paper\nbeam: {mode: whole_block}\n"
                "targets:\n  - {x: 250, y: 50, rcs: 4}\n"
                "maps:\n  - {file: ship_and_sea.npy, dx: 0.75, dy: 0.75, origin: [266, 26], "
                "kind: power, scale: 1.0, speckle: true, seed: 7}\n")
    return path


def fig8(out, quick, workdir):
    """An extended scene reconstructed by the three schemes next to its reflectivity map."""
    from .. import scenes
    path = ship_and_sea_file(workdir)
    sf = scenes.load_scene_file(path)
    geo = params.make_geometry("paper")
    preset = "small" if quick else "paper"
    mp = sf.maps[0]
    rcs = np.abs(np.asarray(mp.values)) ** 2            # ny x nx, rows along y
    xs = mp.x0 + mp.dx * np.arange(rcs.shape[1])
    ys = mp.y0 + mp.dy * np.arange(rcs.shape[0])
    r_map = np.hypot(xs, geo.height_m)
    runs = {}
    for mode, _label in VC_SCHEMES:
        log(f"fig8: {mode}: {path}")
        runs[mode] = run_sim(os.path.join(workdir, f"fig8_{mode}"), preset=preset, scene=path,
                             filter=VC_FILTER, snr_db=VC_SNR, modulation="qam256", seed=1,
                             mode=mode)
    plt = _pyplot()
    fig, axs = plt.subplots(1, 4, figsize=(17, 5), constrained_layout=True)
    rlim = (r_map[0] - 8, r_map[-1] + 8)
    ylim = (ys[-1] + 8, ys[0] - 8)
    pts = list(sf.points.targets)
    ref_db = 10 * np.log10(rcs / rcs.max() + 1e-6)
    im = axs[0].pcolormesh(r_map, ys, ref_db, vmin=-30, vmax=0, cmap="gray", shading="nearest")
    for t in pts:
        axs[0].plot(math.hypot(t.x_m, geo.height_m), t.y_m, "o", mfc="none", color="C3")
    axs[0].set_title("(a) reference: RCS map (before speckle)\n"
                     "+ point target (circle)", fontsize=9)
    fig.colorbar(im, ax=axs[0], label="RCS [dB re max]")
    rows = []
    # the map resampled onto each image's pixels (nearest pixel) for a similarity figure
    for i, (mode, label) in enumerate(VC_SCHEMES):
        res = runs[mode]
        img = load_image(res)
        r_ax = axis(res["range_axis_m"], img.shape[1])
        a_ax = axis(res["azimuth_axis_m"], img.shape[0])
        sel_a = (a_ax >= ys[0] - 8) & (a_ax <= ys[-1] + 8)
        sub = img[sel_a]
        ax = axs[i + 1]
        # shown as power averaged over groups of lines (at most ~500 rows: 0.1 m of track
        # at full rate, a quarter of the azimuth resolution), not every 2 mm line decimated
        g = max(1, sub.shape[0] // 500)
        shown = (np.abs(sub[:sub.shape[0] // g * g].astype(np.complex128)) ** 2).reshape(
            -1, g, sub.shape[1]).mean(axis=1)
        im = ax.imshow(db20(np.sqrt(shown), -40), aspect="auto", vmin=-35, vmax=0, cmap="gray",
                       interpolation="nearest",
                       extent=[r_ax[0], r_ax[-1], a_ax[sel_a][-1], a_ax[sel_a][0]])
        ax.set_xlim(*rlim)
        ax.set_ylim(*ylim)
        ax.set_title(f"({'bcd'[i]}) {label}", fontsize=9)
        fig.colorbar(im, ax=ax, label="power [dB re peak]")
        # similarity: intensity of the image vs the map, both summed onto cells of the
        # data-aided range resolution (1.5 m) in slant range and along track
        cell = 1.5
        re = np.arange(r_map[0], r_map[-1], cell)
        ye = np.arange(ys[0], ys[-1], cell)
        def blocks_of(values, rr, yy):
            h, _, _ = np.histogram2d(np.broadcast_to(yy[:, None], values.shape).ravel(),
                                     np.broadcast_to(rr[None, :], values.shape).ravel(),
                                     bins=[ye, re], weights=values.ravel())
            return h
        a_img = blocks_of(np.abs(sub.astype(np.complex128)) ** 2, r_ax, a_ax[sel_a])
        a_map = blocks_of(rcs, r_map, ys)
        corr = float(np.corrcoef(a_img.ravel(), a_map.ravel())[0, 1])
        # image entropy [P-3.2.1] on the same 1.5 m cells for every scheme (the pixel
        # counts differ 280x between the schemes; entropy grows with the log of it)
        p = a_img / a_img.sum()
        entropy = float(-(p[p > 0] * np.log(p[p > 0])).sum())
        rows.append((mode, corr, entropy, res["nmse_db"], res["runtime_s"]))
        for ax in (axs[i + 1], axs[0]):
            ax.set_xlabel("slant range [m]")
            ax.set_ylabel("along-track position [m]")
    axs[0].set_xlim(*rlim)
    axs[0].set_ylim(*ylim)
    fig.suptitle("Extended scene (synthetic ship and sea, examples/scenes/ship_and_sea.yaml), "
                 f"MF, SNR_in {VC_SNR:g} dB, preset {preset}; the paper's dataset image [38] is "
                 "not available here", fontsize=10)
    png = os.path.join(out, "fig8.png")
    results.save_figure(fig, png, dpi=90)
    plt.close(fig)
    write_csv(os.path.join(out, "fig8.csv"),
              ("scheme", "intensity_corr_1p5m", "entropy_1p5m_cells", "nmse_ref_target_db",
               "runtime_s"), rows)
    log(f"fig8: {png}")
    return {f"fig8_corr_{r[0]}": r[1] for r in rows}


@dataclasses.dataclass
class FiguresOptions(Options):
    out: str = option("nrsar-figures", "output folder")
    quick: bool = option(False, "small sizes (small preset N = 512, 0.2 s aperture, few "
                         "SNRs): the smoke test")
    seeds: int = option(3, "seeds per fig5 point", at_least=1, at_most=100)
    only: str = option(",".join(FIGURES), "comma-separated subset of " + ",".join(FIGURES))

    def check(self):
        check_names("--only", self.only, FIGURES)


def main(argv=None):
    args = cli.parse("nrsar-figures", FiguresOptions, __doc__, argv)
    if args is None:
        return cli.EXIT_USAGE
    only = check_names("--only", args.only, FIGURES)
    summary = {}
    with tempfile.TemporaryDirectory(prefix="nrsar-figures-") as work:
        for name in only:
            progress.step(only.index(name) + 1, len(only), "figure " + name)
            func = {"fig3": fig3, "fig4": fig4, "fig5": fig5, "fig6": fig6, "fig7": fig7,
                    "fig8": fig8, "presum": presum, "presum_compare": presum_compare_figure}[name]
            extra = (args.seeds,) if name == "fig5" else ()
            try:
                summary.update(func(args.out, args.quick, work, *extra))
            except (ValueError, RuntimeError) as err:
                print(f"nrsar-figures: {name}: {err}", file=sys.stderr)
                return 2
    progress.finish()
    for key, value in summary.items():
        log(f"{key} = {value:.3f}")
    return 0
