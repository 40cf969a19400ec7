#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Autofocus after back-projection along a navigation path with a GNSS error (issue #14).

    /usr/bin/python3 -m gnuradio.nrsar.figures.autofocus_study [--out DIR] [--seeds N]

The UAV flies the ideal line (the echo is exact, eq. 29, from focus_scenario's geometry:
1.5 m range bins, 1000 m slant range, PRF 400 Hz); it believes the navigation
params.make_navigation(truth, 'gnss', seed) (decimetres of slow error, 2 cm of receiver
noise at 0.1-2 Hz). bp_focuser images the echo from the navigation, autofocus (PGA and
minimum entropy) corrects the image. The reference of the metrics is bp_focuser's image of
the noise-free echo from the true path (SPEC 8's calibrated NMSE, mean over the image).

Autofocus cannot see a constant or linear phase: the corrected image sits where the
navigation put it (the GNSS along-track error moves the target by decimetres), so every
image is registered to the reference by the sub-line circular shift that maximises their
correlation before the NMSE, and the shift is reported (geolocation error, not focus).

Autofocus by trajectory estimation (kernel::trajectory_autofocus) corrects the path and
back-projects again. A position error's constant and linear trend over the aperture defocus
nothing (they move each target in range phase by its own line of sight, and in Doppler), so
no autofocus can see them: the *_trend_db columns measure against BP of the noise-free echo
along the truth plus that trend, the *_db columns against the perfectly navigated image.
Ground control points observe the trend: the gcp1 columns take the first target as one
(the trend along its line of sight), the gcp2 columns the first two (x and z); their
estimate of the constant and drift against the true trend's (x, z).

The true phase error at the target, 4 pi (R_nav - R_true) / lambda per pulse, is mapped to
the image's azimuth DFT bins through the target's Doppler history (bin
p = 2 (y_t - y_p) dy M / (lambda R0)), and plotted against the estimate (constant and
linear terms removed from both over the target's band). nmse_pulse_bound_db: the image of
the data corrected by that true error per pulse, the best one phase per pulse can do.
Writes autofocus_gnss.png and autofocus_gnss.csv into --out and prints one JSON object.
"""

import dataclasses
import json
import math
import os
import sys

import numpy as np
from gnuradio import blocks, gr

from .. import cli, params, results
from ..options import Options, option
from ..focus_scenario import (C, H, K, LAM, N_SUB, NUM, R_FIRST, RHO, SPP, T, V, echo_along,
                              geometry)
from ..nrsar_python import (autofocus, autofocus_config, autofocus_method, bp_config,
                            bp_focuser, bp_grid, image_entropy, trajectory,
                            trajectory_autofocus, trajectory_autofocus_config)

M = 400                          # pulses per aperture (1 s, 50 m of track)
TARGETS = [(800.0, 25.03, 1.0), (830.0, 25.03, 0.5), (770.0, 25.03, 0.3)]  # (x, y, amplitude)
SNR_DB = 10.0                    # per pulse and range-compressed sample of the first target


def image(data, nav, method=None, line_step=1):
    """bp_focuser along nav (then autofocus with method, which reads the line spacing from
    the image's tags): the image, the autofocus block and the focuser. line_step: a line
    every line_step-th pulse position (bp_config.line_step)."""
    geo = geometry(M * T)
    scn = params.make_scene([(x, y) for x, y, _ in TARGETS])
    foc = bp_focuser(NUM, geo, scn, K, R_FIRST, RHO,
                     bp_config(symbols_per_pulse=SPP, lines_per_aperture=M,
                               line_step=line_step), nav)
    tb = gr.top_block()
    src = blocks.vector_source_c(data.astype(np.complex64).ravel().tolist(), False, K)
    snk = blocks.vector_sink_c(K)
    af = None
    if method is None:
        tb.connect(src, foc, snk)
    else:
        af = autofocus(K, autofocus_config(method=method, max_iterations=100, wavelength_m=LAM))
        tb.connect(src, foc, af, snk)
    tb.run()
    return np.array(snk.data()).reshape(-1, K), af, foc


def register(img, ref):
    """img circularly shifted along azimuth by the fractional lines that maximise
    |<ref, shifted img>| (linear phase over the azimuth DFT), and the shift: the integer
    peak of the circular cross-correlation, refined in 1/64 line around it."""
    m = img.shape[0]
    F, R = np.fft.fft(img, axis=0), np.fft.fft(ref, axis=0)
    f = np.fft.fftfreq(m)
    cross = np.sum(np.conj(R) * F, axis=1)
    s0 = int(np.argmax(np.abs(np.fft.ifft(cross))))
    s0 = s0 - m if s0 > m // 2 else s0
    best = max(s0 + np.arange(-1, 1, 1 / 64),
               key=lambda s: abs(np.sum(cross * np.exp(2j * np.pi * f * s))))
    return np.fft.ifft(F * np.exp(2j * np.pi * f * best)[:, None], axis=0), best


def path(positions):
    """A trajectory through the antenna positions of the M pulses, extended at both ends
    along the end velocities (the focuser reads a little past the aperture)."""
    p = np.asarray(positions, float)
    n = np.arange(-8, 2 * M)
    i = np.clip(n, 0, M - 1)
    ext = (p[i] + np.outer(np.minimum(n, 0), p[1] - p[0]) +
           np.outer(np.maximum(n - (M - 1), 0), p[-1] - p[-2]))
    return trajectory.from_samples(list(n * T), [tuple(v) for v in ext])


def grid_of(foc):
    """kernel::bp_grid of the images bp_focuser makes in image() (its range axis, lines)."""
    g = bp_grid()
    g.num_range_bins, g.first_range_m, g.range_bin_m = K, R_FIRST, RHO
    g.wavelength_m = geometry(M * T).wavelength_m()
    g.range_centre_cycles = math.remainder(
        (NUM.num_subcarriers - 1) * NUM.subcarrier_spacing_hz * RHO / C, 1.0)
    g.upsample = bp_config().upsample
    g.num_lines, g.first_y_m, g.line_spacing_m = M, foc.line_shift() * V * T, V * T
    g.reference_height_m = H
    return g


def detrend_pulses(v):
    """v less its least-squares constant and linear trend over the pulses."""
    n = np.arange(len(v))
    A = np.stack([np.ones_like(n, dtype=float), n], axis=1)
    return v - A @ np.linalg.lstsq(A, v, rcond=None)[0]


def nmse_db(img, ref):
    """SPEC 8: N M mean|img / c - ref|^2 / max|ref|^2, c = <ref, img> / <ref, ref> (M the
    aperture's pulses, also on an image of every L-th line: the mean is per pixel)."""
    c = np.vdot(ref, img) / np.vdot(ref, ref)
    return 10 * math.log10(N_SUB * M * np.mean(np.abs(img / c - ref) ** 2) / np.max(np.abs(ref)) ** 2)


def true_phase_per_bin(truth_ant, nav_ant, line_y0, dy):
    """4 pi (R_nav - R_true) / lambda of the first target per pulse, on the image's azimuth
    DFT bins through its Doppler history; NaN where no pulse maps."""
    x, y, _ = TARGETS[0]
    r_true = np.linalg.norm(truth_ant - [x, y, 0.0], axis=1)
    r_nav = np.linalg.norm(nav_ant - [x, y, 0.0], axis=1)
    e = 4 * np.pi * (r_nav - r_true) / LAM
    r0 = math.hypot(x, H)
    p = 2 * (y - truth_ant[:, 1]) * dy * M / (LAM * r0)  # fractional bin per pulse, decreasing
    out = np.full(M, np.nan)
    bins = np.arange(math.ceil(p.min()), math.floor(p.max()) + 1)
    out[bins % M] = np.interp(bins, p[::-1], e[::-1])
    return out


def detrended(phi, mask):
    """phi on mask less its least-squares a + b u, u the bin unwrapped across 0."""
    idx = np.flatnonzero(mask)
    u = np.where(idx > M // 2, idx - M, idx).astype(float)
    A = np.stack([np.ones_like(u), u], axis=1)
    coef, *_ = np.linalg.lstsq(A, phi[idx], rcond=None)
    out = np.full(M, np.nan)
    out[idx] = phi[idx] - A @ coef
    return out, u


def run(seed, make_plot=None):
    geo = geometry(M * T)
    truth = params.make_trajectory("ideal", geo, duration_s=M * T + 1.0)
    nav = params.make_navigation(truth, "gnss", seed, M * T + 1.0)
    times = list(np.arange(M) * T)
    truth_ant = np.array(truth.positions(times))
    nav_ant = np.array(nav.positions(times))
    clean = echo_along(truth_ant, TARGETS)
    rng = np.random.default_rng(seed)
    sigma2 = N_SUB / 10 ** (SNR_DB / 10)  # the first target's sample power is N
    noisy = clean + np.sqrt(sigma2 / 2) * (rng.standard_normal(clean.shape) +
                                           1j * rng.standard_normal(clean.shape))
    ref, _, foc = image(clean, truth)
    perfect, _, _ = image(noisy, truth)
    gnss, _, _ = image(noisy, nav)
    row = {"seed": seed, "nav_rms_err_m": float(np.sqrt(np.mean(np.sum((nav_ant - truth_ant) ** 2, 1))))}
    row["nmse_perfect_db"] = nmse_db(perfect, ref)
    # What focus can reach: the truth moved by the navigation error's constant and linear
    # trend over the aperture (per axis). Neither defocuses: the offset changes each
    # target's range and phase by its own line of sight (u . offset), the drift shifts its
    # Doppler (the image moves along track, its band with it); no autofocus can see them.
    err = nav_ant - truth_ant
    trend = err - np.stack([detrend_pulses(err[:, i]) for i in range(3)], axis=1)
    row["nav_offset_m"] = float(np.linalg.norm(np.mean(err, axis=0)))
    row["nav_drift_mps"] = float(np.linalg.norm(trend[-1] - trend[0]) / ((M - 1) * T))
    ref_off, _, _ = image(clean, path(truth_ant + trend))
    row["nmse_perfect_trend_db"] = nmse_db(register(image(noisy, path(truth_ant + trend))[0],
                                                    ref_off)[0], ref_off)
    row["nmse_gnss_db"] = nmse_db(register(gnss, ref)[0], ref)
    row["nmse_gnss_trend_db"] = nmse_db(register(gnss, ref_off)[0], ref_off)
    row["entropy_perfect"] = image_entropy(perfect.astype(np.complex64))
    row["entropy_gnss"] = image_entropy(gnss.astype(np.complex64))
    dy = V * T
    true_phi = true_phase_per_bin(truth_ant, nav_ant, foc.line_shift() * dy, dy)
    # The best one phase per pulse can do: the data corrected by the first target's true
    # error 4 pi (R_nav - R_true) / lambda before bp_focuser (what is left is the other
    # targets' difference and the range the navigation gets wrong).
    x, y, _ = TARGETS[0]
    eps = 4 * np.pi * (np.linalg.norm(nav_ant - [x, y, 0.0], axis=1) -
                       np.linalg.norm(truth_ant - [x, y, 0.0], axis=1)) / LAM
    bound, _, _ = image(noisy * np.exp(-1j * eps)[:, None], nav)
    row["nmse_pulse_bound_db"] = nmse_db(register(bound, ref)[0], ref)
    row["nmse_pulse_bound_trend_db"] = nmse_db(register(bound, ref_off)[0], ref_off)
    # Autofocus by trajectory estimation: the navigation corrected along the points' lines
    # of sight, BP again. Its estimate against the true error on the first target's line
    # of sight (constant and linear trend removed from both: they only move the image).
    img, est = trajectory_autofocus(noisy.astype(np.complex64), [tuple(a) for a in nav_ant],
                                    grid_of(foc), trajectory_autofocus_config())
    row["nmse_trajectory_db"] = nmse_db(register(img, ref)[0], ref)
    row["nmse_trajectory_trend_db"] = nmse_db(register(img, ref_off)[0], ref_off)
    u = truth_ant - [x, y, 0.0]
    u /= np.linalg.norm(u, axis=1)[:, None]
    los_true = detrend_pulses(np.sum(u * (nav_ant - truth_ant), axis=1))
    los_est = detrend_pulses(np.asarray(est["los_m"]))
    row["los_true_rms_m"] = float(np.sqrt(np.mean(los_true ** 2)))
    row["los_err_rms_m"] = float(np.sqrt(np.mean((los_est - los_true) ** 2)))
    row["trajectory_iterations"] = int(est["iterations"])
    row["trajectory_points"] = len(est["points"])
    row["look_spread_rad"] = float(est["look_spread_rad"])
    # With ground control points (surveyed corner reflectors): the first target alone (the
    # reference target, as a campaign surveys its reflector; it fixes the trend along its
    # line of sight), and the first two (1 degree apart in look angle: x and z). Their
    # estimate of the navigation error's constant at the middle pulse and drift against
    # the true trend's (x, z).
    true_offset = (trend[0] + trend[-1]) / 2
    true_drift = (trend[-1] - trend[0]) / ((M - 1) * T)
    for name, gcps in (("gcp1", TARGETS[:1]), ("gcp2", TARGETS[:2])):
        cfg = trajectory_autofocus_config()
        cfg.gcp = [(gx, gy, 0.0) for gx, gy, _ in gcps]
        img, est = trajectory_autofocus(noisy.astype(np.complex64), [tuple(a) for a in nav_ant],
                                        grid_of(foc), cfg)
        reg, shift = register(img, ref)
        row[f"nmse_{name}_db"] = nmse_db(reg, ref)
        row[f"shift_{name}_lines"] = shift
        off = np.asarray(est["gcp_offset_m"]) - true_offset
        drift = np.asarray(est["gcp_drift_m"]) / T - true_drift
        row[f"{name}_offset_err_m"] = float(np.hypot(off[0], off[2]))
        row[f"{name}_drift_err_mps"] = float(np.hypot(drift[0], drift[2]))
        row[f"{name}_offset_se_m"] = float(est["gcp_offset_se_m"])
        row[f"{name}_used"] = int(est["gcp_used"])
    if make_plot is not None:
        make_plot.append(("los", np.arange(M) * T, los_true, los_est))
    for name, method in (("pga", autofocus_method.PGA), ("entropy", autofocus_method.ENTROPY)):
        img, af, _ = image(noisy, nav, method)
        reg, shift = register(img, ref)
        row[f"nmse_{name}_db"] = nmse_db(reg, ref)
        row[f"nmse_{name}_trend_db"] = nmse_db(register(img, ref_off)[0], ref_off)
        row[f"shift_{name}_lines"] = shift
        row[f"entropy_{name}"] = image_entropy(img.astype(np.complex64))
        est = np.array(af.phase_error_rad())
        mask = ~np.isnan(true_phi)
        t_d, u = detrended(true_phi, mask)
        e_d, _ = detrended(est, mask)
        row["phase_true_rms_rad"] = float(np.sqrt(np.nanmean(t_d ** 2)))
        row[f"phase_{name}_rms_rad"] = float(af.phase_rms_rad())
        row[f"phase_{name}_err_rms_rad"] = float(np.sqrt(np.nanmean((e_d - t_d) ** 2)))
        if make_plot is not None:
            make_plot.append((name, u, t_d[mask], e_d[mask]))
    return row


@dataclasses.dataclass
class AutofocusStudyOptions(Options):
    out: str = option("docs/figures", "output folder")
    seeds: int = option(4, "navigation seeds 1..N", at_least=1, at_most=100)


def main(argv=None):
    args = cli.parse("autofocus_study", AutofocusStudyOptions, __doc__, argv)
    if args is None:
        return cli.EXIT_USAGE
    curves = []
    rows = [run(s, curves if s == 1 else None) for s in range(1, args.seeds + 1)]
    results.write_csv(os.path.join(args.out, "autofocus_gnss.csv"), rows)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    (_, tl, los_true, los_est), bins = curves[0], curves[1:]
    _, u, t, _ = bins[0]
    order = np.argsort(u)
    ax.plot(u[order], t[order], "k-", lw=2, label="true (navigation error at the target)")
    for name, u, _, e in bins:
        ax.plot(u[order], e[order], ".", ms=4, label=f"estimated, {name}")
    ax.set_xlabel("azimuth DFT bin of the image (Doppler x M T)")
    ax.set_ylabel("phase error [rad], constant and slope removed")
    ax.set_title("seed 1: PGA / entropy after BP from navigation", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax2.plot(tl, 1e3 * los_true, "k-", lw=2, label="true (first target's line of sight)")
    ax2.plot(tl, 1e3 * los_est, "r.", ms=3, label="estimated, trajectory autofocus")
    ax2.set_xlabel("slow time [s]")
    ax2.set_ylabel("line-of-sight error [mm], trend removed")
    ax2.set_title("seed 1: trajectory autofocus", fontsize=10)
    ax2.legend(fontsize=8)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    results.save_figure(fig, os.path.join(args.out, "autofocus_gnss.png"), dpi=110)
    print(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
