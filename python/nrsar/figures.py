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
  presum  the second paper's figure 6 and 8 analogues (range profiles and azimuth cuts per
        presumming method), the quadratic-phase bound of eq. (P-36) checked past it, and
        the chain's run time against D (presum_study.py).

Each figure is one PNG and one CSV in --out; progress goes to stderr.
"""

import argparse
import csv
import math
import os
import sys
import tempfile
import time

import numpy as np

from . import params, presum_study, sim, theory
from . import progress

LIGHT_SPEED = 299792458.0
TARGET1 = "300,100"
PAPER_SNRS = (-20.0, 5.0, 20.0)
FILTERS = ("rf", "mf", "wf")
FIGURES = ("fig3", "fig4", "fig5", "presum")


def log(text):
    print(f"nrsar-figures: {text}", file=sys.stderr, flush=True)


def sim_args(**overrides):
    """nrsar-sim's defaults (whatever flags it has) with the given overrides."""
    args = sim.add_arguments(argparse.ArgumentParser()).parse_args([])
    for key, value in overrides.items():
        setattr(args, key, value)
    return args


def run_sim(out, **overrides):
    """One nrsar-sim run into out; returns its JSON dict."""
    return sim.run(sim_args(out=out, json=True, **overrides))


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
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for r in rows:
            w.writerow([f"{v:.6g}" if isinstance(v, float) else v for v in r])


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
    fig.savefig(png, dpi=100)
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
    fig.savefig(png, dpi=100)
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

    Returns rows (modulation, filter, snr_db, seed, nmse_db, nmse_theory_db, numpy_theory_db)."""
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
                             res["nmse_theory_db"], theory.nmse_theory_db(mod, filt, snr)))
                done += 1
                progress.step(done, total, label, level=1)
            log(f"{label}: {done}/{total} runs, {mod} {filt.upper()} SNR_in {snr:g} dB: "
                f"NMSE {np.mean([r[4] for r in rows[-len(seeds):]]):.2f} dB "
                f"(theory {rows[-1][5]:.2f}), {time.perf_counter() - start:.0f} s")
    return rows


def summarise(rows):
    """{(mod, filt, snr): (mean, min, max, theory)} over seeds (means of dB values)."""
    acc = {}
    for mod, filt, snr, _seed, nmse, th, _np in rows:
        acc.setdefault((mod, filt, snr), ([], th))[0].append(nmse)
    return {key: (float(np.mean(v)), float(np.min(v)), float(np.max(v)), th)
            for key, (v, th) in acc.items()}


def fig5(out, quick, workdir, seeds):
    snrs = (-30, -10, 10, 30) if quick else tuple(range(-30, 31, 5))
    cases = [("qam256", f) for f in FILTERS] + [("psk8", "wf")]
    rows = nmse_sweep(workdir, cases, snrs, range(1, seeds + 1), quick, "fig5")
    write_csv(os.path.join(out, "fig5.csv"),
              ("modulation", "filter", "snr_db", "seed", "nmse_db", "nmse_theory_db",
               "theory_py_db"), rows)
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
    fig.savefig(png, dpi=100)
    plt.close(fig)
    log(f"fig5: {png}")
    off = [summ[k][0] - summ[k][3] for k in summ]
    return {"fig5_offset_min_db": min(off), "fig5_offset_max_db": max(off)}


def presum(out, quick, workdir):
    """The presummer study writes its own PNGs and CSVs (presum_*) into out."""
    presum_study.main(["--out", out] + (["--quick"] if quick else []))
    return {}


def main(argv=None):
    sim.quiet_gnuradio_logs()
    parser = argparse.ArgumentParser(prog="nrsar-figures", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="nrsar-figures", help="output folder")
    parser.add_argument("--quick", action="store_true",
                        help="small sizes (small preset N = 512, 0.2 s aperture, few SNRs): "
                             "the smoke test")
    parser.add_argument("--seeds", type=int, default=3, help="seeds per fig5 point")
    parser.add_argument("--only", default=",".join(FIGURES),
                        help="comma-separated subset of " + ",".join(FIGURES))
    progress.add_arguments(parser)
    args = parser.parse_args(argv)
    progress.configure(progress.from_args(args))
    only = [x.strip() for x in args.only.split(",") if x.strip()]
    bad = [x for x in only if x not in FIGURES]
    if bad or args.seeds < 1:
        print(f"nrsar-figures: unknown figure {bad} or --seeds < 1", file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)
    summary = {}
    with tempfile.TemporaryDirectory(prefix="nrsar-figures-") as work:
        for name in only:
            progress.step(only.index(name) + 1, len(only), "figure " + name)
            func = {"fig3": fig3, "fig4": fig4, "fig5": fig5, "presum": presum}[name]
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
