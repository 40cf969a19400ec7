#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-sim: one headless run of the imaging chain as a GNU Radio flowgraph.

    nr_isac_tx -> scene_echo -> tf_filter -> range_ifft -> rd_focuser -> nmse_probe
                      |  (reference echo: S = 1, no noise)       ^ reference image
                      +-> range_ifft -> rd_focuser --------------+

The tf_filter's second input is the transmit grid (the UAV knows what it sent). The focused
image (azimuth x range, complex64) is written as .npy and as a PNG in dB with axes in metres,
the range-compressed data likewise; the JSON summary carries the image metrics of SPEC 8
for the first target and names the files and axes (SPEC section 9).
"""

import argparse
import json
import math
import os
import resource
import sys
import time

import numpy as np

import pmt
from gnuradio import blocks, fft, gr

from . import params
from . import progress
from .nrsar_python import (constellation, focuser_config, doppler_band, nmse_probe, nr_isac_tx,
                           probe_config, range_ifft, rd_focuser, scene_echo, srs_config, tag_keys,
                           tf_filter)
from .nrsar_python import cheby_presum, presum_domain, presum_method

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
                        help="point targets: a preset (paper3, single) or 'X,Y[,RCS[,PHASE_DEG]];...' in metres, "
                             "or a YAML scene file (maps, speckle, beam; see nrsar.scenes)")
    parser.add_argument("--target", action="append", default=None, metavar="X,Y[,RCS[,PHASE_DEG]]",
                        help="add a point target (ground range X, along-track Y in metres, "
                             "RCS linear power, phase in degrees); repeatable, replaces --scene; the first is the "
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
    parser.add_argument("--band", default="scene", choices=["scene", "estimate", "full"],
                        help="azimuth processing band: the scene's Doppler band from the geometry, "
                             "estimated from the data, or the full PRF")
    parser.add_argument("--rcmc-taps", type=int, default=16,
                        help="length of the windowed-sinc RCMC interpolator, eq. (41)")
    parser.add_argument("--range-margin-m", type=float, default=30.0,
                        help="slant range kept on each side of the scene's swath [m] "
                             "(at least 16 range bins; the chain crops the RCMC's reach "
                             "wider and the focuser drops it again)")
    parser.add_argument("--presum", default="none", choices=sorted(PRESUM),
                        help="azimuth presummer after the range IFFT (cheby_presum), both branches")
    parser.add_argument("--decim", type=int, default=10,
                        help="presumming factor D (pulses per output pulse; with --presum)")
    # stress: knobs of the run-time / error sweep (nrsar-bench --sweep)
    parser.add_argument("--presum-domain", default="range", choices=["range", "tf"],
                        help="presum after the range IFFT (range) or before it (tf: saves D-1 "
                             "of every D IFFTs)")
    parser.add_argument("--range-crop", default="on", choices=["on", "off"],
                        help="crop the range-compressed data to the scene's swath +- margin "
                             "(off: keep every IFFT bin)")
    parser.add_argument("--images", default="keep", choices=["keep", "none"],
                        help="keep the range-compressed data and the image in memory and write "
                             ".npy/.png (keep), or send them to null sinks (none: metrics only, "
                             "the memory of a streaming receiver)")
    # perf: tf_filter switches (docs/performance.md)
    parser.add_argument("--cm-path", default="on", choices=["on", "off"],
                        help="tf_filter's constant-modulus shortcut (PSK/QPSK data: g = c conj(s))")
    parser.add_argument("--filter-threads", type=int, default=1, choices=[1, 2],
                        help="threads per tf_filter work() call")
    parser.add_argument("--seed", type=int, default=1, help="seed of the data PRBS and the noise")
    parser.add_argument("--out", default="nrsar-out", help="output folder")
    parser.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    return parser


# cheby_presum: --presum choices
PRESUM = {"none": None, "drop": presum_method.DROP, "boxcar": presum_method.BOXCAR,
          "cheby": presum_method.CHEBY, "filter_drop": presum_method.FILTER_DROP}


def presum_factor(args):
    return 1 if PRESUM[getattr(args, "presum", "none")] is None else args.decim


def make_scene_from_args(args):
    if args.target:
        return params.make_scene(args.target)
    if scene_file_of(args) is not None:
        return scene_file_of(args).extent_scene
    return params.make_scene(args.scene)


def scene_file_of(args):
    """The parsed YAML scene file when --scene names an existing file (cached on args), else None.
    Its extent_scene (points, then the corners of every map) stands for the scene in the
    checks, the crop and the metrics: the reference target is its first point (or a map corner)."""
    if not (isinstance(getattr(args, "scene", None), str) and os.path.isfile(args.scene)):
        return None
    if getattr(args, "_scene_file", None) is None:
        from . import scenes
        sf = scenes.load_scene_file(args.scene)
        sf.extent_scene = scenes.bounding_scene(sf.points, sf.maps)
        args._scene_file = sf
    return args._scene_file


def make_echo(num, geo, scn, args):
    """scene_echo for point targets, extended_scene_echo for a YAML scene file."""
    sf = None if args.target else scene_file_of(args)
    if sf is None:
        return scene_echo(num, geo, scn, args.snr_db, args.seed + 1)
    from .nrsar_python import antenna_beam, extended_scene_echo
    return extended_scene_echo(num, geo, sf.points, sf.maps, sf.beam or antenna_beam(),
                               args.snr_db, args.seed + 1)


def fft_size_from_arg(arg, num_subcarriers):
    if arg == "exact":
        return num_subcarriers
    if arg == "fast":
        return range_ifft.fast_fft_size(num_subcarriers)
    return int(arg)


def grid_of_mode(mode_arg, num):
    """(tx mode name, SRS layout, symbols per pulse) of a --mode value. The SRS band is
    the paper's (subcarriers 1667..1954) where it fits, else centred."""
    mode, period = MODES[mode_arg]
    srs = srs_config()
    if period:
        srs.period_slots = period
    if mode != "data" and srs.start_subcarrier + srs.num_subcarriers() > num.num_subcarriers:
        srs.start_subcarrier = (num.num_subcarriers - srs.num_subcarriers()) // 2
    return mode, srs, params.symbols_per_pulse(mode, num, srs)


def scene_echo_front(tb, num, geo, scn, args, grid):
    """The TF-domain radar channel (default of build_chain): scene_echo on the grid.
    Returns (echo block, echo endpoint, reference-echo endpoint)."""
    echo = make_echo(num, geo, scn, args)
    tb.connect(grid, echo)
    return echo, (echo, 0), (echo, 1)


# guard
def rcmc_guard_bins(num, geo, scn, args, nfft, r_max_m):
    """Range bins the RCMC reads beyond an image edge at slant range r_max_m: the largest
    migration over the focuser's processed band (scene band with the focuser's margin, or
    the pulse rate for --band full), hyperbolic, eq. (41), plus rcmc_taps / 2 kernel bins."""
    ext = params.compute_extent(geo, scn)
    bw = ext.max_doppler_hz - ext.min_doppler_hz
    margin = 0.1 * bw + 2.0 / geo.aperture_s  # the focuser's automatic band margin
    f_max = max(abs(ext.min_doppler_hz - margin), abs(ext.max_doppler_hz + margin))
    if args.band == "full":
        _, _, spp = grid_of_mode(args.mode, num)
        f_max = 0.5 / (num.symbol_s() * spp * presum_factor(args))
    u = 299792458.0 / geo.carrier_hz * f_max / (2.0 * geo.velocity_mps)
    rho = num.range_bin_m(nfft)
    if u * u < 0.99:
        mig = r_max_m * (1.0 / math.sqrt(1.0 - u * u) - 1.0) / rho
    else:
        mig = r_max_m * u * u / 2.0 / rho  # the focuser's fallback, eq. (40)
    return int(math.ceil(mig)) + args.rcmc_taps // 2


def guarded_crop(num, geo, scn, args, nfft, crop):
    """(wider crop, guard bins g): the range_ifft crop widened by g bins on each side, so
    that the focuser (cfg.guard_bins = g) outputs exactly the bins of `crop`, each of whose
    RCMC kernels reads data, not zeros past the crop (docs/blocks/rd_focuser.md, guard)."""
    rho = num.range_bin_m(nfft)
    g = rcmc_guard_bins(num, geo, scn, args, nfft, crop[1])  # the far edge migrates most
    return (max(0.0, crop[0] - g * rho), crop[1] + g * rho), g


def memory_estimate_bytes(rif, foc, symbols, keep):
    """Bytes the chain holds at once: per branch the focuser's processing block, its
    output aperture and its band tables (K x (before + 2 M + after + 2.5 B), B processed
    Doppler bins; ESTIMATE also keeps K x fft_size spectra), and with --images keep the
    range-compressed data and the image of the aperture, twice (the sinks' vectors and
    the numpy arrays written from them). Measured: paper, 0.1 s, --range-crop off:
    estimate 4.4 GiB, peak RSS 5.0 GiB."""
    k = rif.num_bins()
    m = foc.lines_per_aperture()
    block = k * (foc.overlap_before() + 2 * m + foc.overlap_after() + 2.5 * foc.band_bins())
    if foc.config().band == doppler_band.ESTIMATE:
        block += k * foc.fft_size()
    sinks = 2 * (k * symbols + foc.num_output_bins() * m) if keep else 0
    return int(8 * (2 * block + sinks))


def check_memory(rif, foc, symbols, keep, limit_bytes=None):
    """Refuses (ValueError) a chain that would need more than half the machine's memory,
    naming the size and the options that reduce it (an uncropped range window at the full
    pulse rate is the usual culprit)."""
    need = memory_estimate_bytes(rif, foc, symbols, keep)
    if limit_bytes is None:
        limit_bytes = 0.5 * os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    if need > limit_bytes:
        raise ValueError(
            f"the imaging chain needs about {need / 2**30:.1f} GiB ({rif.num_bins()} range "
            f"bins x {foc.lines_per_aperture()} lines per aperture, {symbols} symbols kept), "
            f"more than {limit_bytes / 2**30:.1f} GiB (half the memory): use --range-crop on, "
            f"--presum cheby, a shorter --aperture-s or --images none")


def build_chain(tb, num, geo, scn, args, symbols, tx=None, echo_front=scene_echo_front):
    """Connects the imaging chain and its reference branch into top block tb.

    tx: the grid source (default: nr_isac_tx of --mode, --modulation, --seed); echo_front
    (tb, num, geo, scn, args, grid) -> (echo block, echo endpoint, reference endpoint) builds
    the radar channel from the grid (default: scene_echo_front; nrsar-isac also has a
    time-domain one). Returns the blocks by name: the sinks hold the range-compressed data
    and the focused image; the probe holds the metrics of the first target."""
    mode, srs, pulse_symbols = grid_of_mode(args.mode, num)
    n = num.num_subcarriers
    modulation = params.make_modulation(args.modulation)
    filter_type = params.make_filter(args.filter)
    if tx is None:
        tx = nr_isac_tx(num, modulation, params.make_tx_mode(mode), srs, args.seed)
    head = blocks.head(gr.sizeof_gr_complex * n, symbols)
    tb.connect(tx, head)
    echo, echo_out, ref_out = echo_front(tb, num, geo, scn, args, head)
    tff = tf_filter(n, filter_type, args.snr_db, args.estimate_snr)
    tff.set_constant_modulus_path(getattr(args, "cm_path", "on") == "on")  # perf
    tff.set_threads(getattr(args, "filter_threads", 1))  # perf

    extent = params.compute_extent(geo, scn)
    nfft = fft_size_from_arg(args.fft_size, n)
    # At least 16 bins each side, so the probe has target-free bins for SNR_out.
    margin = max(args.range_margin_m, 16 * num.range_bin_m(nfft))
    crop = (max(0.0, extent.min_slant_range_m - margin), extent.max_slant_range_m + margin)
    guard = 0
    if getattr(args, "range_crop", "on") == "off":
        crop = (0.0, 0.0)  # every bin
    else:  # guard: crop wider by the RCMC's reach; the focuser drops it again
        crop, guard = guarded_crop(num, geo, scn, args, nfft, crop)
    tf_domain = getattr(args, "presum_domain", "range") == "tf"
    cfg = focuser_config()
    cfg.symbols_per_pulse = pulse_symbols
    cfg.band = {"scene": doppler_band.SCENE, "estimate": doppler_band.ESTIMATE,
                "full": doppler_band.FULL}[args.band]
    cfg.rcmc_taps = args.rcmc_taps
    cfg.guard_bins = guard
    cfg.lines_per_aperture = symbols // cfg.symbols_per_pulse
    # cheby_presum: the focuser sees pulses D times further apart (the presummer also
    # tags the new pulse interval on its first output).
    decim = presum_factor(args)
    spp = cfg.symbols_per_pulse
    cfg.symbols_per_pulse = spp * decim
    cfg.lines_per_aperture = symbols // cfg.symbols_per_pulse
    presummers = []

    def range_and_focus():
        """(block taking the filtered TF pulses, range IFFT, focuser)"""
        rif = range_ifft(num, nfft, fft.window.WIN_RECTANGULAR, -1.0, *crop)
        foc = rd_focuser(num, geo, scn, rif.num_bins(), rif.range_axis_first_m(),
                         rif.range_bin_m(), cfg)
        if decim == 1:
            tb.connect(rif, foc)
            return rif, rif, foc
        if tf_domain:  # stress: presum the TF pulses, then range-compress D times fewer
            pre = cheby_presum(num, geo, scn, PRESUM[args.presum], decim, presum_domain.TF,
                               n, symbols_per_pulse=spp)
            tb.connect(pre, rif, foc)
            presummers.append(pre)
            return pre, rif, foc
        pre = cheby_presum(num, geo, scn, PRESUM[args.presum], decim, presum_domain.RANGE,
                           rif.num_bins(), rif.range_axis_first_m(), rif.range_bin_m(),
                           symbols_per_pulse=spp)
        presummers.append(pre)
        tb.connect(rif, pre, foc)
        return rif, rif, foc

    entry, rif, foc = range_and_focus()
    entry_ref, rif_ref, foc_ref = range_and_focus()
    # The reference branch is the same chain fed with S = 1 and Z = 0 (SPEC 8): the
    # reference echo, filtered against an all-ones grid, so the filter's scale (WF's
    # 1 / (1 + 1/SNR)) is common to both branches and PEL measures the data's randomness.
    ones = blocks.vector_source_c([1.0 + 0.0j] * n, True, n)
    tff_ref = tf_filter(n, filter_type, args.snr_db, False)
    k = foc.num_output_bins()  # guard: the image's bins (the crop minus the guard bins)
    # One aperture with zeros around it (linear correlation unless overlap_lines = 0): the
    # probe normalises its lines to full correlation windows of the processed band (SPEC 8).
    probe = nmse_probe(num, geo, scn, constellation(modulation).points(), filter_type,
                       args.snr_db, k, probe_config(
                           reference_input=True, symbols_per_aperture=symbols,
                           band_lo_hz=foc.band_lo_hz(), band_hi_hz=foc.band_hi_hz(),
                           zero_padded=cfg.overlap_lines != 0))
    if getattr(args, "images", "keep") == "none":  # stress: metrics only
        range_sink = blocks.null_sink(gr.sizeof_gr_complex * rif.num_bins())
        image_sink = blocks.null_sink(gr.sizeof_gr_complex * k)
    else:
        range_sink = blocks.vector_sink_c(rif.num_bins(), symbols)
        image_sink = blocks.vector_sink_c(k, symbols)
    tb.connect(echo_out, (tff, 0))
    tb.connect(head, (tff, 1))
    tb.connect(ref_out, (tff_ref, 0))
    tb.connect(ones, (tff_ref, 1))
    if spp == 1:
        tb.connect(tff, entry)
        tb.connect(tff_ref, entry_ref)
    else:
        # Pilot-only imaging: the pulses are the SRS symbols, one every spp symbols at
        # symbol_in_slot of every SRS slot; both branches keep exactly those. (The focuser
        # takes pulse p at p spp Tsym: the symbol_in_slot Tsym offset, 13 x 41.7 us = 2.7 cm
        # of track, is below a tenth of a resolution cell.)
        for source, sink in ((tff, entry), (tff_ref, entry_ref)):
            tb.connect(source,
                       blocks.keep_m_in_n(gr.sizeof_gr_complex * n, 1, spp, srs.symbol_in_slot),
                       sink)
    check_memory(rif, foc, symbols, getattr(args, "images", "keep") != "none")  # guard
    tb.connect(rif, range_sink)
    tb.connect(foc, image_sink)
    tb.connect(foc, (probe, 0))
    tb.connect(foc_ref, (probe, 1))
    return {"tx": tx, "echo": echo, "filter": tff, "range_ifft": rif, "focuser": foc,
            "probe": probe, "range_sink": range_sink, "image_sink": image_sink,
            "presum": presummers[0] if presummers else None,
            "head": head,  # perf: nrsar-soak streams many apertures by resetting its length
            "focuser_ref": foc_ref}  # dref: the reference branch's image (double_reference)


# stress: run-time split and memory of a run
def run_with_counters(tb):
    """tb.run() with GNU Radio's performance counters on (the executors read
    GR_CONF_PERFCOUNTERS_ON when they start, so setting it for the run is enough)."""
    old = os.environ.get("GR_CONF_PERFCOUNTERS_ON")
    os.environ["GR_CONF_PERFCOUNTERS_ON"] = "True"
    try:
        tb.run()
    finally:
        if old is None:
            del os.environ["GR_CONF_PERFCOUNTERS_ON"]
        else:
            os.environ["GR_CONF_PERFCOUNTERS_ON"] = old


def rx_block_times(chain):
    """CPU time [s] each block of the receive chain (main branch: filter, range IFFT,
    presummer, focuser, probe) spent in work(), from pc_work_time_total (high-resolution
    timer ticks, ns on Linux). The reference branch and the generator are excluded."""
    names = ("filter", "range_ifft", "presum", "focuser", "probe")
    return {name: chain[name].pc_work_time_total() / 1e9 for name in names
            if chain.get(name) is not None}


def peak_rss_mb():
    """Peak resident set size of this process so far [MiB] (ru_maxrss is in KiB on Linux)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def rss_mb():
    """Current resident set size of this process [MiB] (VmRSS of /proc/self/status)."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def azimuth_axis_of(sink, fallback):
    """[first, step] of the focused image's azimuth axis from the focuser's tag."""
    for tag in sink.tags():
        if pmt.eq(tag.key, pmt.intern(tag_keys.azimuth_axis)):
            return [pmt.to_double(pmt.tuple_ref(tag.value, 0)),
                    pmt.to_double(pmt.tuple_ref(tag.value, 1))]
    return fallback


def write_png(path, image, range_axis, azimuth_axis, title, azimuth_limits=None,
              floor_db=-40):
    """Image in dB re its peak, slant range across, along-track position down."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    power_db = 20 * np.log10(np.abs(image) + 1e-30)
    power_db -= power_db.max()
    k, m = image.shape[1], image.shape[0]
    extent = [range_axis[0] - range_axis[1] / 2, range_axis[0] + range_axis[1] * (k - 0.5),
              azimuth_axis[0] + azimuth_axis[1] * (m - 0.5), azimuth_axis[0] - azimuth_axis[1] / 2]
    fig, ax = plt.subplots(figsize=(6, 5))
    im = ax.imshow(power_db, aspect="auto", extent=extent, vmin=floor_db, vmax=0,
                   cmap="viridis", interpolation="nearest")
    if azimuth_limits:
        ax.set_ylim(max(azimuth_limits), min(azimuth_limits))
    ax.set_xlabel("slant range [m]")
    ax.set_ylabel("along-track position [m]")
    ax.set_title(title, fontsize=10)
    fig.colorbar(im, ax=ax, label="power [dB re peak]")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def scenario_of(args):
    """(num, geo, scn, warnings, symbols, pulse_symbols) of the command line."""
    num = params.make_numerology(args.preset)
    geo_overrides = {} if args.aperture_s is None else {"aperture_s": args.aperture_s}
    geo = params.make_geometry(args.geometry, **geo_overrides)
    scn = make_scene_from_args(args)
    sf = None if args.target else scene_file_of(args)
    if sf is not None:  # the scene file's numerology and geometry replace the presets
        num = sf.numerology or num
        if sf.geometry is not None:
            fields = ("carrier_hz", "velocity_mps", "height_m", "track_start_m", "aperture_s")
            geo = params.make_geometry("paper", **{**{k: getattr(sf.geometry, k) for k in fields},
                                                   **geo_overrides})
    pulse_symbols = grid_of_mode(args.mode, num)[2]
    warnings = params.check_scenario(num, geo, scn, pulse_symbols)
    symbols = int(geo.symbols_per_aperture(num))
    return num, geo, scn, warnings, symbols, pulse_symbols


def run(args):
    num, geo, scn, warnings, symbols, pulse_symbols = scenario_of(args)
    tb = gr.top_block("nrsar-sim")
    chain = build_chain(tb, num, geo, scn, args, symbols)
    start = time.perf_counter()
    # progress: percent of the aperture's symbols through the filter (stderr, if enabled)
    with progress.polling("symbols", symbols, lambda: chain["filter"].nitems_written(0)):
        run_with_counters(tb)
    runtime_s = time.perf_counter() - start
    return image_results(args, chain, num, geo, scn, warnings, symbols, pulse_symbols,
                         runtime_s)


def image_results(args, chain, num, geo, scn, warnings, symbols, pulse_symbols, runtime_s):
    """After the run: writes the .npy/.png files and returns the JSON dict of SPEC 9."""
    rx_times = rx_block_times(chain)

    rif, probe = chain["range_ifft"], chain["probe"]
    # guard: the image (and the range-compressed data written with it) keeps the crop's
    # inner bins; the focuser dropped guard bins on each side.
    k = chain["focuser"].num_output_bins()
    guard = chain["focuser"].config().guard_bins
    range_axis = [rif.range_axis_first_m() + guard * rif.range_bin_m(), rif.range_bin_m()]
    slow_time_axis = [geo.track_start_m, geo.velocity_mps * num.symbol_s() * pulse_symbols]
    if getattr(args, "presum_domain", "range") == "tf":  # stress: presummed before the IFFT
        slow_time_axis[1] *= presum_factor(args)
    keep = getattr(args, "images", "keep") != "none"
    if keep:
        compressed = np.asarray(chain["range_sink"].data(), dtype=np.complex64).reshape(
            -1, rif.num_bins())[:, guard:guard + k]
        image = np.asarray(chain["image_sink"].data(), dtype=np.complex64).reshape(-1, k)
        azimuth_axis = azimuth_axis_of(chain["image_sink"], slow_time_axis)
    else:  # stress: null sinks; the probe's line count and the focuser's axis
        image = np.zeros((chain["focuser"].lines_per_aperture(), 0), np.complex64)
        compressed = None
        azimuth_axis = [geo.track_start_m + chain["focuser"].line_shift() *
                        chain["focuser"].pulse_interval_s() * geo.velocity_mps,
                        chain["focuser"].pulse_interval_s() * geo.velocity_mps]

    ref_y = scn.targets[0].y_m
    last_y = azimuth_axis[0] + azimuth_axis[1] * (image.shape[0] - 1)
    if not azimuth_axis[0] <= ref_y <= last_y:
        warnings = list(warnings) + [
            f"the reference target (y = {ref_y:g} m) is outside the focused image "
            f"[{azimuth_axis[0]:.1f}, {last_y:.1f}] m: the scene spans more along-track than "
            f"one aperture covers; lengthen --aperture-s or image fewer targets"]

    os.makedirs(args.out, exist_ok=True)
    files = {}
    ys = [t.y_m for t in scn.targets]
    label = f"{args.filter.upper()}, {args.modulation}, SNR_in {args.snr_db:g} dB"
    for name, data, axis, title, limits in (
            ("range_compressed", compressed, slow_time_axis, "range-compressed", None),
            ("image", image, azimuth_axis, "focused image", (min(ys) - 15, max(ys) + 15))):
        if not keep:
            files[name + "_npy"] = files[name + "_png"] = None
            continue
        files[name + "_npy"] = os.path.abspath(os.path.join(args.out, name + ".npy"))
        files[name + "_png"] = os.path.abspath(os.path.join(args.out, name + ".png"))
        np.save(files[name + "_npy"], data)
        write_png(files[name + "_png"], data, range_axis, axis, f"{title}, {label}",
                  azimuth_limits=limits)

    metrics = {key: float(value) for key, value in probe.metrics().items()}
    result = {
        "preset": args.preset,
        "filter": args.filter,
        "modulation": args.modulation,
        "mode": args.mode,
        "snr_db": args.snr_db,
        "symbols": symbols,
        "subcarriers": num.num_subcarriers,
        "range_bins": k,
        "range_fft_size": rif.fft_size(),
        "azimuth_lines": image.shape[0],
        "runtime_s": runtime_s,
        # stress: receive chain alone = CPU time in work() of its blocks (perf counters)
        "rx_runtime_s": sum(rx_times.values()),
        "rx_block_s": rx_times,
        "image_npy": files["image_npy"],
        "image_png": files["image_png"],
        "range_compressed_npy": files["range_compressed_npy"],
        "range_compressed_png": files["range_compressed_png"],
        "range_axis_m": range_axis,
        "azimuth_axis_m": azimuth_axis,
        "doppler_band_hz": [chain["focuser"].band_lo_hz(), chain["focuser"].band_hi_hz()],
        "rcmc_applied": bool(chain["focuser"].rcmc_applied()),
        "nonfinite": chain["echo"].nonfinite_count() + chain["filter"].nonfinite_count(),
        "empty_res": chain["filter"].empty_re_count(),
        "warnings": list(warnings),
        "presum": args.presum,
        "decim": presum_factor(args),
    }
    if chain["presum"] is not None:
        result["warnings"] += list(chain["presum"].warnings())
    metrics["nmse_minus_theory_band_db"] = metrics.get("nmse_db", math.nan) - metrics.get(
        "nmse_theory_band_db", math.nan)
    for key in ("nmse_db", "nmse_theory_db", "nmse_theory_band_db", "nmse_minus_theory_band_db",
                "pel_db", "snr_out_db", "islr_db", "pslr_db",
                "irw_range_m", "irw_azimuth_m", "peak_error_m"):
        value = metrics.get(key, float("nan"))
        result[key] = value if math.isfinite(value) else None  # JSON has no NaN
    if MODES[args.mode][0] != "data":
        # SPEC 8's theory is that of data-aided grids
        result["nmse_theory_db"] = result["nmse_theory_band_db"] = None
        result["nmse_minus_theory_band_db"] = None
    # stress: after the images are written, so the .npy/.png step counts too
    result["peak_rss_mb"] = peak_rss_mb()
    return result


def quiet_gnuradio_logs():
    """Large vectors make GNU Radio's buffer allocator warn about alignment padding on
    every connection; the apps keep errors only."""
    gr.logging().set_default_level(gr.log_levels.err)


def main(argv=None, prog="nrsar-sim", add=None, runner=None, doc=__doc__,
         errors=(ValueError, RuntimeError)):
    """The command line of nrsar-sim; nrsar-isac passes its own parser, run and doc."""
    quiet_gnuradio_logs()
    parser = (add or add_arguments)(argparse.ArgumentParser(
        prog=prog, description=doc,
        formatter_class=argparse.RawDescriptionHelpFormatter))
    progress.add_arguments(parser)
    args = parser.parse_args(argv)
    progress.configure(progress.from_args(args))
    try:
        result = (runner or run)(args)
    except errors as err:
        progress.finish()
        print(f"{prog}: {err}", file=sys.stderr)
        return 2
    progress.finish()
    if args.json:
        print(json.dumps(result))
    else:
        for key, value in result.items():
            print(f"{key:28s} {value}")
    return 0
