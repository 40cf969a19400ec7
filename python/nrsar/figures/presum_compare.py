#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The second paper's method comparisons at D = 12 (its figure 6, tables 5-7): CSV + PNG.

    /usr/bin/python3 -m gnuradio.nrsar.figures.presum_compare --out docs/figures [--quick]

Methods: drop (direct downsampling), boxcar, filter_drop (filtering then downsampling),
lms (the paper's LMS baseline, kernel/lms_presum.h) and cheby (the proposed method).

1. fig. 6: single-pulse SNR gain per method (single_pulse: scene `single`,
   QPSK, MF, SNR_in chosen so a range-compressed pulse has 0 dB SNR as in the paper's
   -40 dB + 40 dB), plus LMS over its step mu against the misadjustment theory
   (2 - mu) / mu (Lrho / (1 + L rho))^2 -> presum_compare_fig6.csv / .png.
2. table 5: azimuth-cut PSLR / ISLR / IRW, SNR_out, NMSE of the focused point target per
   method (nrsar-sim chain, paper3) -> presum_compare_table5.csv / .png.
3. table 6: image entropy, NESZ and EPI per method on the extended scene
   (examples/scenes/ship_and_sea.yaml) per flight (--flights: the ideal line, `gusty` with
   perfect navigation, `gusty` with `rtk` navigation; the presummer and the focuser
   compensate from the navigation) -> presum_compare_table6.csv / .png. The metrics are the
   kernel's (nrsar.image_entropy, edge_preservation_index, nesz_db). At D = --table6-decim
   (96: PRF / D = 250 Hz, 1.33 x the scene's 188 Hz processed Doppler band, the paper's own
   oversampling of 1.1-1.4 of its eq. 16): at D = 12 the output rate is 10.6 x the band, a
   boxcar droops 0.1 dB over it and the focuser's band removes the noise every method
   aliases, so the methods cannot differ (docs/figures.md).
4. table 7: CPU time in work() of the presummer and of the focuser per method, from the
   runs of table 5 -> presum_compare_table7.csv / .png.
"""

import dataclasses
import math
import os
import sys
import typing

import numpy as np

from gnuradio import nrsar
from gnuradio.nrsar import chain, cli, params, results, scenes
from .presum_study import (PresumStudyOptions, azimuth_cut, image_run, plot_azimuth_cuts,
                           plt_module, single_pulse)
from gnuradio.nrsar.results import write_csv
from gnuradio.nrsar.options import OptionError, SimOptions, check_names, option

D_PAPER = 12
D_TABLE6 = 96  # PRF / D near the scene's Doppler band, as in the paper (module doc)
# the paper's fig. 6 / text [P-3.1]: single-pulse gain at D = 12 [dB]
PAPER_GAIN_DB = {"drop": 0.0, "lms": 7.0, "cheby": 9.0}
# table 7 [P-3.2.2]: filter without decimation 155.89 s presum / 629.27 s total,
# proposed 200.73 s / 436.59 s (BP of the measured scene)
PAPER_TIME_S = {"none": (155.89, 629.27), "cheby": (200.73, 436.59)}
METHODS = ("drop", "boxcar", "filter_drop", "lms", "cheby")
LMS_STEPS = (0.05, 0.1, 0.2, 1.0 / 3.0, 0.5, 1.0)
PULSE_SNR_DB = 0.0  # the paper's range-compressed pulse SNR (-40 dB echo, 40 dB compression)


def lms_floor_gain_db(step, taps, rho):
    """Single-pulse gain of the LMS line enhancer measured against the noise floor of the
    other range bins: steady-state misadjustment M = mu / (2 - mu) of normalised LMS leaves
    M sigma^2 of noise in a noise-only bin, and a tone of per-pulse SNR rho comes out with
    amplitude L rho / (1 + L rho) (the Wiener predictor)."""
    m = step / (2.0 - step)
    alpha = taps * rho / (1.0 + taps * rho)
    return 10.0 * math.log10(alpha ** 2 / m)


# ---------------------------------------------------------------- image metrics [P-3.2.1]

def nesz_map_db(power_noise, power_scene, sigma0_scene):
    """NESZ from the image [36], calibrated on a distributed target of known mean sigma0
    instead of a point target: a pixel of area A holds the return of an RCS sigma0 A with the
    energy P_scene - P_noise, so kernel::nesz_db gives sigma0 P_noise / (P_scene - P_noise)."""
    return nrsar.nesz_db(power_noise, power_scene - power_noise, sigma0_scene, 1.0)


# ---------------------------------------------------------------- runs

def fig6_rows(preset, seconds, d, seed=1):
    """Single-pulse gains per method and LMS steps: single_pulse rows plus the
    theory of each (boxcar 10 log10 D, FIR D^2 / sum h^2, LMS lms_floor_gain_db)."""
    num = params.make_numerology(preset)
    # SNR_in per RE for a 0 dB pulse: MF range compression over N subcarriers gains N
    snr_in = PULSE_SNR_DB - 10.0 * math.log10(num.num_subcarriers)
    lms = params.PRESUM_METHODS["lms"]
    configs = {name: {"method": params.PRESUM_METHODS[name]} for name in METHODS}
    for mu in LMS_STEPS:
        configs[f"lms mu={mu:.3g}"] = {"method": lms, "lms_step": mu}
    rows, profiles, axis, _ = single_pulse(d, preset, seconds, snr_in, seed, configs)
    rho = 10.0 ** (rows[0]["pulse_snr_db"] / 10.0)
    for r in rows:
        name = r["method"]
        r["lms_step"] = configs.get(name, {}).get("lms_step", math.nan)
        if name == "none":
            theory = 0.0
        elif name == "drop":
            theory = 0.0
        elif name.startswith("lms"):
            if math.isnan(r["lms_step"]):
                r["lms_step"] = nrsar.presum_config().lms_step
            theory = lms_floor_gain_db(r["lms_step"], 4 * d, rho)
        else:
            theory = 10.0 * math.log10(d * d / r["noise_gain_sum_h2"])
        r["theory_gain_db"] = theory
        r["paper_gain_db"] = PAPER_GAIN_DB.get(name, math.nan)
    return rows, profiles, axis


def chain_rows(preset, d, methods=METHODS, seed=1):
    """Tables 5 and 7: one nrsar-sim chain (paper3, the geometry's 2 s) per method;
    azimuth-cut metrics of the reference target and the CPU time of the presummer and of
    the focuser."""
    t5, t7, cuts = [], [], {}
    for name in ("none",) + tuple(methods):
        m, elapsed, img, line_m, rx = image_run(name, d, preset, None, seed, counters=True)
        t5.append({"method": name, "D": 1 if name == "none" else d,
                   "pslr_azimuth_db": m.get("pslr_azimuth_db"),
                   "islr_azimuth_db": m.get("islr_azimuth_db"),
                   "irw_azimuth_m": m.get("irw_azimuth_m"),
                   "snr_out_db": m.get("snr_out_db"), "nmse_db": m.get("nmse_db"),
                   "peak_error_m": m.get("peak_error_m")})
        presum_s = rx.get("presum", 0.0)
        t7.append({"method": name, "D": 1 if name == "none" else d,
                   "presum_cpu_s": presum_s, "focus_cpu_s": rx.get("focuser", 0.0),
                   "presum_plus_focus_s": presum_s + rx.get("focuser", 0.0),
                   "chain_wall_s": elapsed,
                   "paper_presum_s": PAPER_TIME_S.get(name, (math.nan,))[0],
                   "paper_total_s": PAPER_TIME_S.get(name, (math.nan, math.nan))[1]})
        cuts[name] = azimuth_cut(img, line_m)
    return t5, t7, cuts


FLIGHTS = ("none", "gusty", "gusty+rtk")  # --motion[+--nav-error] of table 6


def table6_rows(scene_path, workdir, preset, d, snr_db, flight="none", methods=METHODS, seed=1):
    """Entropy, NESZ and EPI of the extended scene per method. The full-rate image ("none",
    the image before enhancement) is read at the presummed lines' along-track positions so
    every method is measured on the same pixel grid. NESZ: noise from the range bins beyond
    the map's far edge (+ 4 bins of range sidelobes), scene power over the bins centred on
    the map's footprint, whose mean sigma0 is the map's mean RCS per m^2 (with coarse bins,
    `small`'s 9.8 m, the bins are only partly covered: the offset is common to all methods).
    EPI and entropy over that footprint (+- 2 bins in range). flight: --motion, or
    --motion+--nav-error (FLIGHTS); the full-rate image of the same flight is the reference."""
    mp = scenes.load_scene_file(scene_path).maps[0]
    geo = params.make_geometry("paper")
    rcs = np.abs(np.asarray(mp.values)) ** 2
    sigma0 = float(rcs.mean() / (mp.dx * mp.dy))
    r_lo, r_hi = (math.hypot(mp.x0 + mp.dx * i, geo.height_m) for i in (0, rcs.shape[1] - 1))
    y_lo, y_hi = mp.y0, mp.y0 + mp.dy * (rcs.shape[0] - 1)
    motion, _, nav_error = flight.partition("+")
    extra = {"motion": motion, "nav_error": nav_error or "none"}
    images = {}
    for name in ("none",) + tuple(methods):
        out = os.path.join(workdir, f"table6_{flight}_{name}")
        os.makedirs(out, exist_ok=True)
        res = chain.simulate(SimOptions(
            out=out, json=True, preset=preset, scene=scene_path, snr_db=snr_db, seed=seed,
            presum=name, decim=None if name == "none" else d, **extra).validate())
        img = np.load(res["image_npy"])
        r_ax = res["range_axis_m"][0] + res["range_axis_m"][1] * np.arange(img.shape[1])
        y_ax = res["azimuth_axis_m"][0] + res["azimuth_axis_m"][1] * np.arange(img.shape[0])
        images[name] = (img, r_ax, y_ax)
    _, r_ax, y_grid = images[methods[-1]]
    bin_m = r_ax[1] - r_ax[0]
    rows = []
    for name, (img, r_ax, y_ax) in images.items():
        lines = np.clip(np.round((y_grid - y_ax[0]) / (y_ax[1] - y_ax[0])).astype(int), 0,
                        len(y_ax) - 1)
        images[name] = img[lines]
    ref = images["none"]
    foot_r = (r_ax >= r_lo) & (r_ax <= r_hi)
    near_r = (r_ax >= r_lo - 2 * bin_m) & (r_ax <= r_hi + 2 * bin_m)
    foot_y = (y_grid > y_lo + 2.0) & (y_grid < y_hi - 2.0)
    noise_r = r_ax > r_hi + 4 * bin_m
    for name, img in images.items():
        p = np.abs(img.astype(np.complex128)) ** 2
        p_scene = float(p[np.ix_(foot_y, foot_r)].mean())
        p_noise = float(p[:, noise_r].mean())
        sub = np.ix_(foot_y, near_r)
        rows.append({"method": name, "D": 1 if name == "none" else d, "motion": motion,
                     "nav_error": extra["nav_error"],
                     "entropy": nrsar.image_entropy(img[sub]),
                     "nesz_db": nesz_map_db(p_noise, p_scene, sigma0),
                     "epi": nrsar.edge_preservation_index(ref[sub], img[sub]),
                     "scene_to_noise_db": 10.0 * math.log10(p_scene / p_noise)})
    return rows


# ---------------------------------------------------------------- figures

PARTS = ("fig6", "table5", "table6", "table7")


@dataclasses.dataclass
class PresumCompareOptions(PresumStudyOptions):
    """The study's --out, --preset and --decim (the paper's D = 12), and table 6's own."""
    table6_decim: int = option(D_TABLE6, "D of table 6 (--quick: --decim)", at_least=2,
                               at_most=4096)
    snr_db: float = option(-40.0, "SNR_in of table 6 [dB]", at_least=-100.0, at_most=100.0)
    flights: str = option(",".join(FLIGHTS), "flights of table 6: --motion[+--nav-error], "
                          "comma-separated")
    quick: bool = option(False, "fig. 6 over 0.5 s; tables 5-7 for drop, lms and cheby only, "
                         "table 6 on the ideal flight")
    only: str = option(",".join(PARTS), "comma-separated subset of " + ",".join(PARTS))
    workdir: typing.Optional[str] = option(None, "folder of table 6's recordings (default: a "
                                           "temporary one)")
    scene: str = option(os.path.join("examples", "scenes", "ship_and_sea.yaml"),
                        "extended scene of table 6")

    def check(self):
        check_names("--only", self.only, PARTS)
        for f in self.flights.split(","):
            motion, plus, nav_error = f.partition("+")
            if motion not in params.MOTIONS or (plus and nav_error not in params.NAV_ERRORS):
                raise OptionError(f"--flights = {self.flights!r}: {f!r} must be "
                                  f"MOTION[+NAV_ERROR], MOTION one of "
                                  f"{', '.join(params.MOTIONS)}, NAV_ERROR one of "
                                  f"{', '.join(params.NAV_ERRORS)}")
        if "table6" in self.only and not os.path.isfile(self.scene):
            raise OptionError(f"--scene = {self.scene!r} is not a file")


def main(argv=None):
    return cli.main_json("presum_compare", PresumCompareOptions, run, __doc__, argv)


def run(a):
    """The figures and tables of a (PresumCompareOptions, validated) into the folder a.out;
    returns their rows."""
    os.makedirs(a.out, exist_ok=True)
    plt = plt_module()
    only = set(check_names("--only", a.only, PARTS))
    seconds = 0.5 if a.quick else 2.0
    d = a.decim
    methods = ("drop", "lms", "cheby") if a.quick else METHODS
    summary = {}
    out = lambda name: os.path.join(a.out, name)  # noqa: E731

    if "fig6" in only:
        rows, profiles, axis = fig6_rows(a.preset, seconds, d)
        write_csv(out("presum_compare_fig6.csv"), rows)
        summary["fig6"] = rows
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
        for name in ("none",) + METHODS:
            a1.plot(axis, 20 * np.log10(np.abs(profiles[name]) + 1e-12), lw=1,
                    label=name + ("" if name == "none" else f" D={d}"))
        a1.set_xlabel("slant range [m]")
        a1.set_ylabel("|pulse| / DC gain [dB]")
        a1.set_title("one output pulse per method (fig. 6 analogue)", fontsize=9)
        a1.legend(fontsize=7)
        lms = [r for r in rows if r["method"].startswith("lms ")]
        mus = [r["lms_step"] for r in lms]
        a2.semilogx(mus, [r["gain_db"] for r in lms], "o", label="LMS measured")
        fine = np.geomspace(min(mus), max(mus), 100)
        rho = 10 ** (rows[0]["pulse_snr_db"] / 10)
        a2.semilogx(fine, [lms_floor_gain_db(m, 4 * d, rho) for m in fine], "-",
                    label="(2 - mu) / mu theory")
        for name, style in (("cheby", "C3--"), ("boxcar", "C2:")):
            g = next(r["gain_db"] for r in rows if r["method"] == name)
            a2.axhline(g, color=style[:2], ls=style[2:], label=f"{name} measured")
        a2.axhline(PAPER_GAIN_DB["lms"], color="k", ls="-.", lw=0.8, label="paper LMS 7 dB")
        a2.axhline(PAPER_GAIN_DB["cheby"], color="k", ls=":", lw=0.8,
                   label="paper proposed 9 dB")
        a2.set_xlabel("LMS normalised step mu")
        a2.set_ylabel(f"single-pulse gain at D = {d} [dB]")
        a2.legend(fontsize=7)
        fig.tight_layout()
        results.save_figure(fig, out("presum_compare_fig6.png"), dpi=90)
        plt.close(fig)

    if only & {"table5", "table7"}:
        t5, t7, cuts = chain_rows(a.preset, d, methods)
        write_csv(out("presum_compare_table5.csv"), t5)
        write_csv(out("presum_compare_table7.csv"), t7)
        summary["table5"], summary["table7"] = t5, t7
        plot_azimuth_cuts(plt, cuts, f"azimuth cut through T1 per method, D = {d} (table 5)",
                          out("presum_compare_table5.png"))
        fig, ax = plt.subplots(figsize=(6.5, 3.6))
        names = [r["method"] for r in t7]
        ax.bar(names, [r["presum_cpu_s"] for r in t7], label="presum (CPU in work)")
        ax.bar(names, [r["focus_cpu_s"] for r in t7],
               bottom=[r["presum_cpu_s"] for r in t7], label="focus (rd_focuser)")
        ax.set_ylabel("CPU time [s]")
        ax.set_title(f"processing time per method, {a.preset}, 2 s (table 7)",
                     fontsize=9)
        ax.legend(fontsize=8)
        fig.tight_layout()
        results.save_figure(fig, out("presum_compare_table7.png"), dpi=90)
        plt.close(fig)

    if "table6" in only:
        import tempfile
        with tempfile.TemporaryDirectory(prefix="presum-compare-") as tmp:
            flights = ["none"] if a.quick else a.flights.split(",")
            d = d if a.quick else a.table6_decim
            rows = [r for f in flights
                    for r in table6_rows(a.scene, a.workdir or tmp, a.preset, d, a.snr_db, f,
                                         methods)]
        write_csv(out("presum_compare_table6.csv"), rows)
        summary["table6"] = rows
        fig, axs = plt.subplots(1, 3, figsize=(12, 3.5))
        names = list(dict.fromkeys(r["method"] for r in rows))
        keys = list(dict.fromkeys((r["motion"], r["nav_error"]) for r in rows))
        width = 0.8 / len(keys)
        for ax, key, label in zip(axs, ("entropy", "nesz_db", "epi"),
                                  ("image entropy", "NESZ [dB]", "EPI")):
            for j, (motion, nav) in enumerate(keys):
                vals = {r["method"]: r[key] for r in rows
                        if (r["motion"], r["nav_error"]) == (motion, nav)}
                ax.bar(np.arange(len(names)) + j * width, [vals[n] for n in names], width,
                       label=f"{motion}, nav {nav}")
            ax.set_xticks(np.arange(len(names)) + 0.4 - width / 2, names)
            ax.set_title(label, fontsize=9)
            ax.tick_params(axis="x", labelsize=7)
        axs[0].legend(fontsize=7)
        fig.suptitle(f"extended scene (ship_and_sea), D = {d}, SNR_in {a.snr_db:g} dB "
                     f"(table 6)", fontsize=9)
        fig.tight_layout()
        results.save_figure(fig, out("presum_compare_table6.png"), dpi=90)
        plt.close(fig)
    return summary


if __name__ == "__main__":
    sys.exit(main())
