#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Azimuth presummer study (second paper, figures 6-8 analogues): CSV + PNG.

    /usr/bin/python3 -m gnuradio.nrsar.figures.presum_study --out docs/figures [--quick]

1. single-pulse SNR gain per method at D (default 12): the chain TX -> echo -> MF ->
   range IFFT at SNR_in -20 dB (QPSK: no data-randomness pedestal), every method fed the
   same range-compressed pulses; SNR of a pulse = (mean power on the target's bin - noise)
   / noise, noise from bins >= 16 bins off the target. -> presum_single_pulse.csv,
   presum_range_profiles.png (one output pulse per method, figure 6 analogue).
2. focused image per method at D (nrsar-sim chain: 256-QAM, WF, paper3, SNR_in -20 dB):
   SNR_out, NMSE, PSLR / ISLR / IRW of the azimuth cut (nmse_probe), run time.
   -> presum_image.csv, presum_azimuth_cuts.png (figure 8 analogue).
3. run time and SNR_out vs D for CHEBY and DROP -> presum_runtime.csv / .png.
4. eq. (P-36) checked by running past it: coherence of the sum of one window of D pulses
   of a broadside target (window starting at closest approach, as eq. P-33), BOXCAR
   (uncompensated) and CHEBY, D up to 2 D_max -> presum_qpe.csv / .png.
"""

import dataclasses
import math
import os
import sys
import time

import numpy as np
from gnuradio import blocks, fft, gr

from gnuradio import nrsar
from gnuradio.nrsar import chain, cli, params, results, runtime, scenario
from gnuradio.nrsar.results import write_csv
from gnuradio.nrsar.options import SimOptions, Options, option

# the methods in the order of the figures' legends
METHODS = {name: params.PRESUM_METHODS[name] for name in ("drop", "boxcar", "filter_drop", "cheby")}
C = 299792458.0


def plt_module():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def single_pulse(d, preset, seconds, snr_db, seed=1, configs=None):
    """configs: {name: presum_config keywords} (default: METHODS at decimation d)."""
    if configs is None:
        configs = {name: {"method": m} for name, m in METHODS.items()}
    num = params.make_numerology(preset)
    geo = params.make_geometry("paper", aperture_s=seconds)
    scn = params.make_scene("single")
    symbols = int(geo.symbols_per_aperture(num))
    n = num.num_subcarriers
    mod = params.make_modulation("qpsk")
    tx = nrsar.nr_isac_tx(num, mod, params.make_tx_mode("data"), nrsar.srs_config(), seed)
    head = blocks.head(gr.sizeof_gr_complex * n, symbols)
    echo = nrsar.scene_echo(num, geo, scn, snr_db, seed + 1)
    tff = nrsar.tf_filter(n, params.make_filter("mf"), snr_db, False)
    ext = params.compute_extent(geo, scn)
    nfft = nrsar.fast_fft_size(n)
    margin = max(30.0, 16 * num.range_bin_m(nfft))
    rif = nrsar.range_ifft(num, nfft, fft.window.WIN_RECTANGULAR, -1.0,
                           max(0.0, ext.min_slant_range_m - 2 * margin),
                           ext.max_slant_range_m + 2 * margin)
    k = rif.num_bins()
    tb = gr.top_block()
    tb.connect(tx, head, echo, (tff, 0))
    tb.connect(head, (tff, 1))
    tb.connect(tff, rif)
    sinks = {"none": blocks.vector_sink_c(k)}
    tb.connect(rif, sinks["none"])
    blks = {}
    for name, kw in configs.items():
        blks[name] = nrsar.cheby_presum(num, geo, scn, k, rif.range_axis_first_m(),
                                        rif.range_bin_m(), nrsar.presum_config(
                                            decim=d, domain=nrsar.presum_domain.RANGE, **kw))
        sinks[name] = blocks.vector_sink_c(k)
        tb.connect(rif, blks[name], sinks[name])
    tb.run()
    data = {name: np.array(s.data(), complex).reshape(-1, k) for name, s in sinks.items()}
    full = data["none"]
    kt = int(np.argmax((np.abs(full) ** 2).mean(0)))
    far = np.abs(np.arange(k) - kt) >= 16
    rows, profiles = [], {}
    g0 = 8  # skip the first outputs (filter start-up over zero history)
    ref_snr = None
    for name, x in data.items():
        x = x[g0:] if name != "none" else x[g0 * d:]
        noise = (np.abs(x[:, far]) ** 2).mean()
        sig = (np.abs(x[:, kt]) ** 2).mean() - noise
        snr = sig / noise
        if name == "none":
            ref_snr = snr
        rows.append({"method": name, "D": 1 if name == "none" else d,
                     "pulse_snr_db": 10 * math.log10(snr),
                     "gain_db": 10 * math.log10(snr / ref_snr),
                     "theory_boxcar_db": 0.0 if name == "none" else 10 * math.log10(d),
                     # an adaptive filter (LMS) has no fixed taps
                     "noise_gain_sum_h2": 1.0 if name == "none" else
                     float(np.sum(np.abs(np.array(blks[name].taps())) ** 2))
                     if blks[name].taps() else math.nan})
        # divided by the DC gain (D; 1 for none and drop): equal signal, lower floor
        gain = 1.0 if name in ("none", "drop") else float(d)
        profiles[name] = x[len(x) // 2] / gain
    axis = rif.range_axis_first_m() + rif.range_bin_m() * np.arange(k)
    if "cheby" not in blks:
        return rows, profiles, axis, {}
    info = {"passband_hz": blks["cheby"].passband_hz(), "stopband_hz": blks["cheby"].stopband_hz(),
            "ripple_db": blks["cheby"].passband_ripple_db(),
            "atten_db": blks["cheby"].stopband_atten_db(), "taps": blks["cheby"].num_taps()}
    return rows, profiles, axis, info


def image_run(presum, d, preset, seconds, seed=1, counters=False, **overrides):
    """One nrsar-sim chain: (probe metrics, run time, image, line spacing [m], CPU time of
    the receive blocks in work(), runtime.rx_block_times: zeros unless counters)."""
    opts = SimOptions(preset=preset, presum=presum, decim=None if presum == "none" else d,
                      aperture_s=seconds, seed=seed, **overrides).validate()
    sc = scenario.of(opts)
    tb = gr.top_block()
    graph = chain.build(tb, opts, sc)
    start = time.perf_counter()
    runtime.run(tb, counters=counters)
    elapsed = time.perf_counter() - start
    k = graph["focuser"].num_output_bins()  # the image drops the guard bins
    img = np.array(graph["image_sink"].data(), complex).reshape(-1, k)
    m = {key: float(v) for key, v in graph["probe"].metrics().items()}
    line_m = sc.geo.velocity_mps * sc.num.symbol_s() * opts.presum_factor()
    times = runtime.rx_block_times(graph)
    graph["chain"].release()  # a study runs many chains in one process
    return m, elapsed, img, line_m, times


def azimuth_cut(img, line_m, half_m=4.0):
    """(along track re the peak [m], samples) of the image's brightest bin, +- half_m."""
    mi, ki = np.unravel_index(np.argmax(np.abs(img)), img.shape)
    half = int(round(half_m / line_m))
    idx = np.arange(mi - half, mi + half + 1) % img.shape[0]
    return np.arange(-half, half + 1) * line_m, img[idx, ki]


def plot_azimuth_cuts(plt, cuts, title, path):
    """{method: azimuth_cut} in dB re each cut's peak, one PNG."""
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for name, (x, c) in cuts.items():
        ax.plot(x, 20 * np.log10(np.abs(c) / np.abs(c).max() + 1e-12), lw=1,
                marker="." if name != "none" else None, ms=3, label=name)
    ax.set_xlabel("along track re peak [m]")
    ax.set_ylabel("dB re peak")
    ax.set_ylim(-60, 3)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    results.save_figure(fig, path, dpi=90)
    plt.close(fig)


def qpe_check(preset, d_list):
    """Coherence |sum| / (sum of |taps|) of the window of D pulses that starts at the
    closest approach of a target (eq. P-33 with m = 0), K = 1 bin on its range."""
    num = params.make_numerology(preset)
    geo = params.make_geometry("paper")
    t = num.symbol_s()
    x0 = 300.0
    r0 = math.hypot(x0, geo.height_m)
    f = geo.carrier_hz + 0.5 * (num.num_subcarriers - 1) * num.subcarrier_spacing_hz
    rows = []
    for d in d_list:
        for name in ("boxcar", "cheby"):
            m = METHODS[name]
            # closest approach at pulse g D (g = 4 windows in), y of the target there
            g = 4 + (4 if name == "cheby" else 0)
            p_ca = g * d
            pulses = p_ca + 3 * d
            y = geo.velocity_mps * p_ca * t
            scn = params.make_scene([(x0, y)])
            # CHEBY with D taps here (a compensated boxcar): long Remez designs at D ~ 3000
            # would only cost time; the point is the compensation.
            blk = nrsar.cheby_presum(num, geo, scn, 1, r0, 1.0, nrsar.presum_config(
                method=m, decim=d, domain=nrsar.presum_domain.RANGE,
                num_taps=d if name == "cheby" else 0, enforce_qpe_bound=False))
            tp = np.arange(pulses) * t
            r = np.sqrt(r0 ** 2 + (geo.velocity_mps * tp - y) ** 2)
            x = np.exp(-4j * np.pi * np.mod(f * r / C, 1.0)).astype(np.complex64)
            src = blocks.vector_source_c(x.tolist(), False, 1)
            snk = blocks.vector_sink_c(1)
            tb = gr.top_block()
            tb.connect(src, blk, snk)
            tb.run()
            out = np.array(snk.data())
            coh = abs(out[g]) / np.abs(np.array(blk.taps())).sum()
            qpe = 2 * math.pi * geo.velocity_mps ** 2 * d ** 2 * t ** 2 / (geo.wavelength_m() * r0)
            rows.append({"method": name, "D": d, "qpe_edge_rad": qpe,
                         "coherence_loss_db": -20 * math.log10(max(coh, 1e-12))})
    return rows


@dataclasses.dataclass
class PresumStudyOptions(Options):
    out: str = option("docs/figures", "output folder")
    preset: str = option("small", "OFDM numerology preset",
                         choices=list(nrsar.numerology.preset_names()))
    decim: int = option(12, "presumming factor D", at_least=2, at_most=4096)
    quick: bool = option(False, "0.5 s aperture, fewer D values")


def main(argv=None):
    return cli.main_json("presum_study", PresumStudyOptions, run, __doc__, argv)


def run(a):
    """The figures and tables of a (PresumStudyOptions, validated) into the folder a.out;
    returns their rows."""
    os.makedirs(a.out, exist_ok=True)
    plt = plt_module()
    seconds = 0.5 if a.quick else 2.0
    d = a.decim
    summary = {}

    rows, profiles, axis, info = single_pulse(d, a.preset, seconds, -20.0)
    write_csv(os.path.join(a.out, "presum_single_pulse.csv"), rows)
    summary["single_pulse"] = rows
    summary["design"] = info
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for name, prof in profiles.items():
        ax.plot(axis, 20 * np.log10(np.abs(prof) + 1e-12), lw=1,
                label=f"{name}" + ("" if name == "none" else f" D={d}"))
    ax.set_xlabel("slant range [m]")
    ax.set_ylabel("|pulse| [dB]")
    ax.set_title(f"one output pulse per method / DC gain (SNR_in -20 dB, {a.preset})", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    results.save_figure(fig, os.path.join(a.out, "presum_range_profiles.png"), dpi=90)
    plt.close(fig)

    img_rows, cuts = [], {}
    for name in ["none"] + list(METHODS):
        m, elapsed, img, line_m, _ = image_run(name, d, a.preset, seconds)
        img_rows.append({"method": name, "D": 1 if name == "none" else d, "runtime_s": elapsed,
                         "snr_out_db": m.get("snr_out_db"), "nmse_db": m.get("nmse_db"),
                         "pslr_azimuth_db": m.get("pslr_azimuth_db"),
                         "islr_azimuth_db": m.get("islr_azimuth_db"),
                         "irw_azimuth_m": m.get("irw_azimuth_m"),
                         "pslr_range_db": m.get("pslr_range_db"),
                         "islr_range_db": m.get("islr_range_db"),
                         "peak_error_m": m.get("peak_error_m")})
        cuts[name] = azimuth_cut(img, line_m)
    write_csv(os.path.join(a.out, "presum_image.csv"), img_rows)
    summary["image"] = img_rows
    plot_azimuth_cuts(plt, cuts, f"azimuth cut through the strongest target, D = {d}",
                      os.path.join(a.out, "presum_azimuth_cuts.png"))

    d_list = [2, 4, 8, 12, 24] if a.quick else [2, 4, 8, 12, 24, 48, 96]
    rt_rows = []
    m, elapsed, _, _, _ = image_run("none", 1, a.preset, seconds)
    rt_rows.append({"method": "none", "D": 1, "runtime_s": elapsed, "snr_out_db": m["snr_out_db"]})
    for name in ("cheby", "drop"):
        for dd in d_list:
            m, elapsed, _, _, _ = image_run(name, dd, a.preset, seconds)
            rt_rows.append({"method": name, "D": dd, "runtime_s": elapsed,
                            "snr_out_db": m["snr_out_db"]})
    write_csv(os.path.join(a.out, "presum_runtime.csv"), rt_rows)
    summary["runtime"] = rt_rows
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(8, 3.3))
    for name in ("cheby", "drop"):
        rr = [r for r in rt_rows if r["method"] == name]
        a1.plot([r["D"] for r in rr], [r["runtime_s"] for r in rr], "o-", label=name)
        a2.plot([r["D"] for r in rr], [r["snr_out_db"] for r in rr], "o-", label=name)
    for axx in (a1, a2):
        axx.axhline(rt_rows[0]["runtime_s" if axx is a1 else "snr_out_db"], color="k", ls=":",
                    label="full rate")
        axx.set_xscale("log")
        axx.set_xlabel("D")
        axx.legend(fontsize=8)
    a1.set_ylabel("chain run time [s]")
    a2.set_ylabel("image SNR_out [dB]")
    fig.tight_layout()
    results.save_figure(fig, os.path.join(a.out, "presum_runtime.png"), dpi=90)
    plt.close(fig)

    num = params.make_numerology(a.preset)
    dmax = nrsar.cheby_presum.max_decim(num, params.make_geometry("paper"),
                                        params.make_scene([(300.0, 0.0)]))
    q_list = sorted({12, 100, dmax // 4, dmax // 2, dmax, int(1.5 * dmax), 2 * dmax})
    q_rows = qpe_check(a.preset, q_list)
    write_csv(os.path.join(a.out, "presum_qpe.csv"), q_rows)
    summary["qpe"] = q_rows
    summary["dmax"] = dmax
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for name in ("boxcar", "cheby"):
        rr = [r for r in q_rows if r["method"] == name]
        ax.plot([r["D"] for r in rr], [r["coherence_loss_db"] for r in rr], "o-", label=name)
    ax.axvline(dmax, color="k", ls=":", label=f"eq. (P-36) D_max = {dmax}")
    ax.set_xscale("log")
    ax.set_xlabel("D")
    ax.set_ylabel("coherent-sum loss [dB]")
    ax.set_title("window starting at closest approach (eq. P-33)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    results.save_figure(fig, os.path.join(a.out, "presum_qpe.png"), dpi=90)
    plt.close(fig)
    return summary


if __name__ == "__main__":
    sys.exit(main())
