#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-sim: one headless run of the imaging chain as a GNU Radio flowgraph.

    nr_isac_tx -> scene_echo -> tf_filter (reference: the transmit grid) -> range_ifft -> sink

The range-compressed data (azimuth x range, complex64) is written as .npy and as a PNG in
dB with axes in metres, and a JSON summary names the files and axes (SPEC section 9).
The focuser, presummer and image metrics join this chain in later issues.
"""

import argparse
import json
import os
import sys
import time

import numpy as np

from gnuradio import blocks, fft, gr

from . import params
from .nrsar_python import nr_isac_tx, range_ifft, scene_echo, srs_config, tf_filter

MODES = {"data": ("data", None), "srs2": ("srs", 2), "srs20": ("srs", 20)}


def add_arguments(parser):
    """The options shared by the apps (one line of physics per flag)."""
    parser.add_argument("--preset", default="paper",
                        help="OFDM numerology preset: %(default)s = 3333 x 30 kHz, 24 kHz PRF; "
                             "small = 512 subcarriers; tiny = 64 (tests)")
    parser.add_argument("--geometry", default="paper",
                        help="platform preset (fc 3.5 GHz, v 50 m/s, H 1000 m); default %(default)s")
    parser.add_argument("--aperture-s", type=float, default=None,
                        help="slow-time span to simulate [s] (default: the geometry's, 2 s)")
    parser.add_argument("--scene", default="paper3",
                        help="point targets: a preset (paper3, single) or 'X,Y[,RCS];...' in metres")
    parser.add_argument("--target", action="append", default=None, metavar="X,Y[,RCS]",
                        help="add a point target (ground range X, along-track Y in metres, "
                             "RCS linear power); repeatable, replaces --scene; the first is the "
                             "reference target")
    parser.add_argument("--filter", default="wf", choices=sorted(params.FILTERS),
                        help="per-RE filter: rf = 1/s, mf = conj(s), wf = Wiener (eq. 25)")
    parser.add_argument("--snr-db", type=float, default=-20.0,
                        help="input SNR per RE: sum of RCS powers / noise power [dB]")
    parser.add_argument("--estimate-snr", action="store_true",
                        help="let the Wiener filter estimate SNR_in from the data")
    parser.add_argument("--modulation", default="qam256", choices=sorted(params.MODULATIONS),
                        help="constellation of the data REs (38.211 Gray mapping, unit power)")
    parser.add_argument("--mode", default="data", choices=sorted(MODES),
                        help="data = every RE (data-aided); srs2 / srs20 = SRS pilot only, "
                             "one comb-4 symbol every 2 / 20 slots")
    parser.add_argument("--fft-size", default="fast",
                        help="range IFFT size: 'fast' (next fast size >= N), 'exact' (N) or a number")
    parser.add_argument("--range-margin-m", type=float, default=30.0,
                        help="slant range kept on each side of the scene's swath [m]")
    parser.add_argument("--seed", type=int, default=1, help="seed of the data PRBS and the noise")
    parser.add_argument("--out", default="nrsar-out", help="output folder")
    parser.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    return parser


def make_scene_from_args(args):
    if args.target:
        return params.make_scene(args.target)
    return params.make_scene(args.scene)


def fft_size_from_arg(arg, num_subcarriers):
    if arg == "exact":
        return num_subcarriers
    if arg == "fast":
        return range_ifft.fast_fft_size(num_subcarriers)
    return int(arg)


def build_chain(tb, num, geo, scn, args, symbols):
    """Connects the chain into top block tb; returns its blocks by name."""
    mode, period = MODES[args.mode]
    srs = srs_config()
    if period:
        srs.period_slots = period
    if mode != "data" and srs.start_subcarrier + srs.num_subcarriers() > num.num_subcarriers:
        srs.start_subcarrier = (num.num_subcarriers - srs.num_subcarriers()) // 2
    n = num.num_subcarriers
    tx = nr_isac_tx(num, params.make_modulation(args.modulation), params.make_tx_mode(mode),
                    srs, args.seed)
    head = blocks.head(gr.sizeof_gr_complex * n, symbols)
    echo = scene_echo(num, geo, scn, args.snr_db, args.seed + 1)
    tff = tf_filter(n, params.make_filter(args.filter), args.snr_db, args.estimate_snr)
    extent = params.compute_extent(geo, scn)
    nfft = fft_size_from_arg(args.fft_size, n)
    rif = range_ifft(num, nfft, fft.window.WIN_RECTANGULAR, 0.0,
                     max(0.0, extent.min_slant_range_m - args.range_margin_m),
                     extent.max_slant_range_m + args.range_margin_m)
    sink = blocks.vector_sink_c(rif.num_bins(), symbols)
    tb.connect(tx, head, echo, (tff, 0))
    tb.connect(head, (tff, 1))
    tb.connect(tff, rif, sink)
    return {"tx": tx, "echo": echo, "filter": tff, "range_ifft": rif, "sink": sink}


def write_png(path, image, range_axis, azimuth_axis, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    power_db = 20 * np.log10(np.abs(image) + 1e-30)
    power_db -= power_db.max()
    k, m = image.shape[1], image.shape[0]
    extent = [range_axis[0], range_axis[0] + range_axis[1] * (k - 1),
              azimuth_axis[0] + azimuth_axis[1] * (m - 1), azimuth_axis[0]]
    fig, ax = plt.subplots(figsize=(6, 5))
    im = ax.imshow(power_db, aspect="auto", extent=extent, vmin=-40, vmax=0, cmap="viridis",
                   interpolation="nearest")
    ax.set_xlabel("slant range [m]")
    ax.set_ylabel("platform along-track position [m]")
    ax.set_title(title)
    fig.colorbar(im, ax=ax, label="power [dB re peak]")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run(args):
    num = params.make_numerology(args.preset)
    geo_overrides = {} if args.aperture_s is None else {"aperture_s": args.aperture_s}
    geo = params.make_geometry(args.geometry, **geo_overrides)
    scn = make_scene_from_args(args)
    warnings = params.check_scenario(num, geo, scn,
                                     params.symbols_per_pulse(MODES[args.mode][0], num))
    symbols = int(geo.symbols_per_aperture(num))

    tb = gr.top_block("nrsar-sim")
    chain = build_chain(tb, num, geo, scn, args, symbols)
    sink, rif = chain["sink"], chain["range_ifft"]
    start = time.perf_counter()
    tb.run()
    runtime_s = time.perf_counter() - start

    k = rif.num_bins()
    image = np.asarray(sink.data(), dtype=np.complex64).reshape(-1, k)
    range_axis = [rif.range_axis_first_m(), rif.range_bin_m()]
    azimuth_axis = [geo.track_start_m, geo.velocity_mps * num.symbol_s()]

    # Peak of the reference target in the range profile summed over slow time.
    ref = scn.targets[0]
    closest_m = ref.slant_range_m(geo, min(max(ref.y_m, geo.track_start_m),
                                           geo.track_start_m + geo.velocity_mps * geo.aperture_s))
    profile = np.sum(np.abs(image) ** 2, axis=0)

    os.makedirs(args.out, exist_ok=True)
    npy_path = os.path.join(args.out, "range_compressed.npy")
    png_path = os.path.join(args.out, "range_compressed.png")
    np.save(npy_path, image)
    write_png(png_path, image, range_axis, azimuth_axis,
              f"range-compressed, {args.filter.upper()}, SNR_in {args.snr_db:g} dB")

    return {
        "stage": "range_compressed",
        "preset": args.preset,
        "filter": args.filter,
        "modulation": args.modulation,
        "mode": args.mode,
        "snr_db": args.snr_db,
        "symbols": symbols,
        "subcarriers": num.num_subcarriers,
        "range_bins": k,
        "range_fft_size": rif.fft_size(),
        "runtime_s": runtime_s,
        "res_per_s": symbols * num.num_subcarriers / runtime_s,
        "image_npy": os.path.abspath(npy_path),
        "image_png": os.path.abspath(png_path),
        "range_axis_m": range_axis,
        "azimuth_axis_m": azimuth_axis,
        "reference_closest_range_m": closest_m,
        "brightest_range_m": range_axis[0] + range_axis[1] * int(np.argmax(profile)),
        "nonfinite": chain["echo"].nonfinite_count() + chain["filter"].nonfinite_count(),
        "empty_res": chain["filter"].empty_re_count(),
        "warnings": list(warnings),
    }


def main(argv=None):
    parser = add_arguments(argparse.ArgumentParser(
        prog="nrsar-sim", description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter))
    args = parser.parse_args(argv)
    try:
        result = run(args)
    except (ValueError, RuntimeError) as err:
        print(f"nrsar-sim: {err}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps(result))
    else:
        for key, value in result.items():
            print(f"{key:28s} {value}")
    return 0
