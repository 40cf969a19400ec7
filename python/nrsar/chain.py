#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The imaging chain, built in one place: a hier block and the graph around it.

    nr_isac_tx -> head -> echo front -+-> imaging_chain --> image, range-compressed data
                      |  (transmit grid)  ^     (tf_filter -> range_ifft -> [cheby_presum]
                      +-------------------+      -> rd_focuser, the same for the reference
                                                 echo S = 1, Z = 0 -> nmse_probe)

`imaging_chain` (nrsar.imaging_chain) is the receive side as a gr.hier_block2: inputs
0 = echo, 1 = transmit grid, 2 = reference echo (N-vectors, TF domain); outputs 0 = focused
image, 1 = range-compressed data, 2 = reference image (K-vectors / range-bin vectors). Its
blocks are attributes (filter, range_ifft, presum, focuser, focuser_ref, probe, autofocus:
None unless --autofocus, which puts it after the data branch's focuser).

`build(tb, opts, sc)` wires the whole simulation into a top block (the transmitter, the echo
front, the chain and its sinks) and returns the blocks by name. Hooks instead of patches:
`tx=` replaces the grid source, `echo_front=` the radar channel (nrsar-isac's time-domain
echo), `keep_reference=True` keeps the reference image in a sink too.
"""

import contextlib
import dataclasses
import math
import os
import tempfile
import time

import numpy as np
from gnuradio import blocks, fft, gr

from . import params, progress, recording, results, runtime, scenario
from .nrsar_python import (cheby_presum, constellation, doppler_band, focuser_config,
                           nmse_probe, nr_isac_tx, presum_config, presum_domain, probe_config,
                           range_ifft, range_compress, range_compress_config,
                           rd_focuser, scene_echo, tf_filter, bp_config, bp_focuser,
                           moco_order, image_grid, autofocus, autofocus_config)
from .options import OptionError, check_out_dir, parse_gcps
from .scenario import fft_size_of



def rcmc_guard_bins(opts, sc, nfft, r_max_m):
    """Range bins the RCMC reads beyond an image edge at slant range r_max_m: the largest
    migration over the focuser's processed band (scene band with the focuser's margin, or
    the pulse rate for --band full), hyperbolic, eq. (41), plus rcmc_taps / 2 kernel bins."""
    num, geo = sc.num, sc.geo
    ext = params.compute_extent(geo, sc.scene)
    bw = ext.max_doppler_hz - ext.min_doppler_hz
    margin = 0.1 * bw + 2.0 / geo.aperture_s  # the focuser's automatic band margin
    f_max = max(abs(ext.min_doppler_hz - margin), abs(ext.max_doppler_hz + margin))
    if opts.band == "full":
        f_max = 0.5 / (num.symbol_s() * sc.pulse_symbols * opts.presum_factor())
    u = 299792458.0 / geo.carrier_hz * f_max / (2.0 * geo.velocity_mps)
    rho = num.range_bin_m(nfft)
    if u * u < 0.99:
        mig = r_max_m * (1.0 / math.sqrt(1.0 - u * u) - 1.0) / rho
    else:
        mig = r_max_m * u * u / 2.0 / rho  # the focuser's fallback, eq. (40)
    return int(math.ceil(mig)) + opts.rcmc_taps // 2


def range_crop(opts, sc, nfft):
    """(crop [first, last] slant range [m] for range_ifft, guard bins): the scene's swath
    +- --range-margin-m (at least 16 bins, so the probe has target-free bins for SNR_out),
    widened by the RCMC's reach that the focuser drops again (cfg.guard_bins); (0, 0) and no
    guard keeps every bin (--range-crop off)."""
    if opts.range_crop == "off":
        return (0.0, 0.0), 0
    num = sc.num
    extent = params.compute_extent(sc.geo, sc.scene)
    rho = num.range_bin_m(nfft)
    margin = max(opts.range_margin_m, 16 * rho)
    crop = (max(0.0, extent.min_slant_range_m - margin), extent.max_slant_range_m + margin)
    # the far edge migrates most; back-projection reads no bins beyond the image
    g = rcmc_guard_bins(opts, sc, nfft, crop[1]) if opts.focuser == "rd" else 0
    # the focuser drops g bins from both sides: at most the bins above 0 m (--band full's
    # reach can exceed the near edge's range; a clamped near side would shift the image
    # out of the swath), so the near columns read zeros beyond the guard at the widest
    # migrations
    g = min(g, int(crop[0] / rho))
    return (crop[0] - g * rho, crop[1] + g * rho), g


def bp_config_of(opts, cfg, autofocus=False):
    """bp_focuser's configuration of the options, on rd_focuser's pulse rate and aperture;
    autofocus: the data branch, which `--autofocus trajectory` corrects."""
    grid = image_grid.GROUND if opts.image_grid == "ground" else image_grid.SLANT
    if cfg.lines_per_aperture % opts.bp_line_step:
        raise OptionError(f"--bp-line-step = {opts.bp_line_step} must divide the pulses per "
                          f"aperture at the focuser, {cfg.lines_per_aperture} (--aperture-s "
                          f"over the pulse interval after --decim)")
    return bp_config(symbols_per_pulse=cfg.symbols_per_pulse,
                     lines_per_aperture=cfg.lines_per_aperture, grid=grid,
                     line_step=opts.bp_line_step,
                     ffbp_subaperture=opts.ffbp_subaperture if opts.focuser == "ffbp" else 0,
                     ffbp_beam_oversample=opts.ffbp_beams,
                     ffbp_levels=opts.ffbp_levels if opts.focuser == "ffbp" else 1,
                     ffbp_merge_factor=opts.ffbp_merge_factor,
                     first_aperture=cfg.first_aperture, apertures=cfg.apertures,
                     trajectory_autofocus=autofocus and opts.autofocus == "trajectory",
                     autofocus_iterations=opts.autofocus_iterations,
                     autofocus_points=opts.autofocus_points,
                     autofocus_tolerance_m=opts.autofocus_tolerance_m,
                     autofocus_significance=opts.autofocus_significance,
                     autofocus_gcp=parse_gcps(opts.autofocus_gcp) if autofocus else [],
                     autofocus_gcp_along_track_se_m=opts.autofocus_gcp_along_track_se_m,
                     autofocus_gcp_speed_se_mps=opts.autofocus_gcp_speed_se_mps)


def check_line_step(opts, sc, cfg):
    """OptionError when --bp-line-step samples the image along track below the scene's
    Doppler band (params.compute_extent over the aperture): lines at PRF / (D L) then alias
    the targets' azimuth spectrum, and autofocus (a phase per Doppler bin) and the probe's
    band-limited peak search would read the aliases (docs/blocks/bp_focuser.md)."""
    step = opts.bp_line_step
    if step == 1:
        return
    band = params.compute_extent(sc.geo, sc.scene).doppler_bandwidth_hz()
    rate = 1.0 / (sc.num.symbol_s() * cfg.symbols_per_pulse)  # the focuser's pulse rate
    if rate / step < band:
        raise OptionError(f"--bp-line-step = {step} samples the image along track at "
                          f"{rate / step:.2f} Hz, below the scene's Doppler band "
                          f"{band:.2f} Hz: at most {max(1, int(rate // band))} at the "
                          f"focuser's pulse rate {rate:.1f} Hz")


def check_gcps_in_image(opts, geo, foc, cfg, symbols):
    """OptionError naming the --autofocus-gcp that lies off the image: its slant range from
    the ideal line, sqrt(x^2 + (H - z)^2), outside bp_focuser foc's range axis (an aperture's
    image holds a GCP only where its echo is on the bins), or its y outside the lines the
    run images (cfg's apertures, else those of the symbols; a GCP between two apertures'
    lines is in neither image and would be skipped)."""
    first_r = foc.first_range_m()
    last_r = first_r + (foc.num_output_bins() - 1) * foc.range_bin_m()
    m = foc.lines_per_aperture()
    dy = geo.velocity_mps * foc.pulse_interval_s()
    apertures = cfg.apertures or max(1, symbols // (cfg.symbols_per_pulse * m))
    first_y = geo.track_start_m + (cfg.first_aperture * m + foc.line_shift()) * dy
    last_y = first_y + (apertures * m - 1) * dy
    for text, (x, y, z) in zip(opts.autofocus_gcp or [], parse_gcps(opts.autofocus_gcp)):
        r = math.hypot(x, geo.height_m - z)
        if not first_r <= r <= last_r:
            raise OptionError(f"--autofocus-gcp = {text!r} lies outside the image: slant "
                              f"range {r:.1f} m, the image's is [{first_r:.1f}, "
                              f"{last_r:.1f}] m")
        if not first_y <= y <= last_y:
            raise OptionError(f"--autofocus-gcp = {text!r} lies outside the image: "
                              f"along-track y {y:.1f} m, the image's is [{first_y:.1f}, "
                              f"{last_y:.1f}] m")


def focuser_config_of(opts, sc, guard_bins):
    """The rd_focuser configuration of the options: the focuser sees pulses D times further
    apart behind a presummer (which also tags the new pulse interval on its first output)."""
    cfg = focuser_config()
    cfg.symbols_per_pulse = sc.pulse_symbols * opts.presum_factor()
    cfg.band = params.DOPPLER_BANDS[opts.band]
    cfg.rcmc_taps = opts.rcmc_taps
    cfg.guard_bins = guard_bins
    cfg.lines_per_aperture = sc.symbols // cfg.symbols_per_pulse
    if sc.strip is not None:  # a strip's task: its apertures of the flight (docs/scale.md)
        cfg.lines_per_aperture, cfg.first_aperture, cfg.apertures, cfg.overlap_lines = sc.strip
    cfg.moco = moco_order.OFF if opts.moco == "off" else moco_order.SECOND
    cfg.moco_resample = opts.moco == "resample"
    return cfg


def memory_estimate_bytes(rif, foc, symbols, keep):
    """Bytes the chain holds at once: per branch the focuser's processing block, its
    output aperture and its band tables (K x (before + 2 M + after + 2.5 B), B processed
    Doppler bins; ESTIMATE also keeps K x fft_size spectra), and with --images keep the
    range-compressed data and the image of the aperture, twice (the sinks' vectors and
    the numpy arrays written from them). Measured: paper, 0.1 s, --range-crop off:
    estimate 4.4 GiB, peak RSS 5.0 GiB."""
    k = rif.num_bins()
    m = foc.lines_per_aperture()
    if isinstance(foc, bp_focuser):  # pulses, image and output queue; 64 upsampled pulses
        block = k * (3 * m + 64 * foc.config().upsample)
        sinks = 2 * (k * symbols + k * m) if keep else 0
        return int(8 * (2 * block + sinks))
    # The kernel's own band selection (before the first block it builds no kernel).
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


def fusable(opts, sc):
    """Whether --rx-fuse puts range_compress in place of tf_filter -> range_ifft: only where
    nothing comes between them (full-rate pulses, presum after the IFFT) and one filter
    thread."""
    return (opts.rx_fuse == "on" and sc.pulse_symbols == 1 and opts.filter_threads == 1
            and (opts.presum_factor() == 1 or opts.presum_domain != "tf"))


def receive_path(opts, sc, crop, cfg, nav, focuser=True, autofocus=False, fused=None):
    """The blocks of one branch after its tf_filter: (block taking the filtered TF pulses,
    range IFFT, focuser, presummer or None, [the path as one tuple to connect]). nav: the
    path the presummer compensates and the focuser images along (the data branch: the
    navigation; the reference branch: the truth). focuser=False: the path ends before the
    focuser (None; the split UAV's graph). autofocus: the data branch (bp_config_of).
    fused = (estimate_snr, constant-modulus path, unit grid): the range IFFT is a
    range_compress with the branch's filter, taking echo and grid (unit grid: the echo
    only, S = 1)."""
    num, geo, scn = sc.num, sc.geo, sc.scene
    n = num.num_subcarriers
    nfft = fft_size_of(opts, n)
    decim = opts.presum_factor()
    if fused is None:
        rif = range_ifft(num, nfft, fft.window.WIN_RECTANGULAR, -1.0, *crop)
    else:
        rif = range_compress(num, range_compress_config(
            filter=params.make_filter(opts.filter), snr_db=opts.snr_db,
            estimate_snr=fused[0], fft_size=nfft, r_min_m=crop[0], r_max_m=crop[1],
            unit_grid=fused[2]))
        rif.set_constant_modulus_path(fused[1])
    if not focuser:
        foc = None
    elif opts.focuser in ("bp", "ffbp"):
        check_line_step(opts, sc, cfg)
        foc = bp_focuser(num, geo, scn, rif.num_bins(), rif.range_axis_first_m(),
                         rif.range_bin_m(), bp_config_of(opts, cfg, autofocus), nav)
        if autofocus:
            check_gcps_in_image(opts, geo, foc, cfg, sc.symbols)
    else:
        foc = rd_focuser(num, geo, scn, rif.num_bins(), rif.range_axis_first_m(),
                         rif.range_bin_m(), cfg, nav)
    tail = (foc,) if focuser else ()
    if decim == 1:
        return rif, rif, foc, None, [(rif,) + tail]
    method = params.PRESUM_METHODS[opts.presum]
    # a strip's task: the presummer's first output is the focuser's first line
    first = foc.stream_first_line() if focuser else 0
    if opts.presum_domain == "tf":  # presum the TF pulses, range-compress D x fewer
        pre = cheby_presum(num, geo, scn, n, cfg=presum_config(
            method=method, decim=decim, domain=presum_domain.TF,
            symbols_per_pulse=sc.pulse_symbols, first_output=first), nav=nav)
        return pre, rif, foc, pre, [(pre, rif) + tail]
    pre = cheby_presum(num, geo, scn, rif.num_bins(), rif.range_axis_first_m(),
                       rif.range_bin_m(), presum_config(
                           method=method, decim=decim, domain=presum_domain.RANGE,
                           symbols_per_pulse=sc.pulse_symbols, first_output=first), nav)
    return rif, rif, foc, pre, [(rif, pre) + tail]


def data_filter(opts, n):
    """The data branch's tf_filter of the options."""
    tff = tf_filter(n, params.make_filter(opts.filter), opts.snr_db, opts.estimate_snr)
    tff.set_constant_modulus_path(opts.cm_path == "on")
    tff.set_threads(opts.filter_threads)
    return tff


def reference_filter(opts, n):
    """(tf_filter, all-ones grid) of the reference branch: the same chain fed with S = 1 and
    Z = 0 (SPEC 8), the reference echo filtered against an all-ones grid, so the filter's
    scale (WF's 1 / (1 + 1/SNR)) is common to both branches and PEL measures the data's
    randomness."""
    return (tf_filter(n, params.make_filter(opts.filter), opts.snr_db, False),
            blocks.vector_source_c([1.0 + 0.0j] * n, True, n))


def connect_pulses(graph, source, sink, sc):
    """source -> sink, keeping only the pulse symbols in pilot-only imaging."""
    if sc.pulse_symbols == 1:
        graph.connect(source, sink)
    else:
        # Pilot-only imaging: the pulses are the SRS symbols, one every spp symbols at
        # symbol_in_slot of every SRS slot; both branches keep exactly those. (The focuser
        # takes pulse p at p spp Tsym: the symbol_in_slot Tsym offset, 13 x 41.7 us = 2.7 cm
        # of track, is below a tenth of a resolution cell.)
        n = sc.num.num_subcarriers
        graph.connect(source,
                      blocks.keep_m_in_n(gr.sizeof_gr_complex * n, 1, sc.pulse_symbols,
                                         sc.srs.symbol_in_slot),
                      sink)


def make_probe(opts, sc, foc, cfg, reference):
    """nmse_probe behind focuser foc. One aperture with zeros around it (linear correlation
    unless overlap_lines = 0): the probe normalises its lines to full correlation windows of
    the processed band (SPEC 8); a window longer than the focuser's circular block (the full
    band: tens of seconds of track) wraps, and the probe counts the data in every copy of the
    block (block_lines). Back-projection has no processed band: every pixel
    correlates all the aperture's pulses along its own history, so its window is full and
    its band the target's own (docs/blocks/bp_focuser.md, "NMSE")."""
    band, zero_padded = (foc.band_lo_hz(), foc.band_hi_hz()), cfg.overlap_lines != 0
    if isinstance(foc, bp_focuser):
        ext = params.compute_extent(sc.geo, params.make_scene(sc.scene.targets[:1]))
        band, zero_padded = (ext.min_doppler_hz, ext.max_doppler_hz), False
    return nmse_probe(sc.num, sc.geo, sc.scene,
                      constellation(params.make_modulation(opts.modulation)).points(),
                      params.make_filter(opts.filter), opts.snr_db, foc.num_output_bins(),
                      probe_config(reference_input=reference, symbols_per_aperture=sc.symbols,
                                   band_lo_hz=band[0], band_hi_hz=band[1],
                                   zero_padded=zero_padded,
                                   block_lines=foc.fft_size() if zero_padded else 0))


# Sample-rate edges (the ISAC graph's, a recording's source): GNU Radio's default buffers
# (64 KiB) cut the 245 M samples of the paper aperture into calls of at most 4096 samples,
# and the thread wake-ups between the blocks cost more than the blocks' work
# (docs/performance.md, "make demo"); 1 MiB per edge.
SAMPLE_EDGE_BYTES = 1 << 20


def widen_buffers(*blks):
    """Sets each block's output buffers to SAMPLE_EDGE_BYTES (before the graph starts)."""
    for b in blks:
        item = b.output_signature().sizeof_stream_item(0)
        b.set_min_output_buffer(max(1, SAMPLE_EDGE_BYTES // item))


def make_autofocus(opts, sc, bins):
    """The data branch's autofocus of --autofocus (None without). PGA deramps by the
    focuser's azimuth chirp on a slant-range grid (the axes from the image's tags;
    docs/blocks/autofocus.md)."""
    if opts.autofocus in ("none", "trajectory"):  # trajectory: in the data branch's bp_focuser
        return None
    slant = opts.focuser == "rd" or opts.image_grid == "slant"
    return autofocus(bins, autofocus_config(
        method=params.make_autofocus_method(opts.autofocus),
        wavelength_m=sc.geo.wavelength_m() if slant else 0.0))


class imaging_chain(gr.hier_block2):
    """The receive side of SPEC 3-8 for one options object (module doc).

    sc: the options' scenario (default: scenario.of(opts)). reference=False leaves the
    reference branch out (a radio's graph has no noise-free echo): inputs 0 = echo, 1 = grid,
    outputs 0 = image, 1 = range-compressed data, and the probe measures against its PSF
    model (nmse_probe, reference_input false). The probe's metrics dict of every aperture
    also leaves on the hier block's message port "metrics"."""

    def __init__(self, opts, sc=None, keep_images=True, reference=True):
        sc = scenario.of(opts) if sc is None else sc
        n = sc.num.num_subcarriers
        nfft = fft_size_of(opts, n)
        crop, guard = range_crop(opts, sc, nfft)
        cfg = focuser_config_of(opts, sc, guard)

        # The data branch images along the navigation, the reference branch (the same
        # flight's noise-free echo) along the truth: PEL and NMSE measure the data, the noise
        # and what the navigation gets wrong (docs/flight.md).
        fuse = fusable(opts, sc)
        entry, rif, foc, pre, paths = receive_path(
            opts, sc, crop, cfg, sc.navigation, autofocus=True,
            fused=(opts.estimate_snr, opts.cm_path == "on", False) if fuse else None)
        branches = [(entry, paths)]
        if reference:
            entry_ref, rif_ref, foc_ref, _, paths_ref = receive_path(
                opts, sc, crop, cfg, sc.trajectory, fused=(False, True, True) if fuse else None)
            branches.append((entry_ref, paths_ref))
        k = foc.num_output_bins()  # the image's bins (the crop minus the guard bins)
        vec = gr.sizeof_gr_complex
        gr.hier_block2.__init__(
            self, "imaging_chain",
            gr.io_signature.makev(len(branches) + 1, len(branches) + 1,
                                  [vec * n] * (len(branches) + 1)),
            gr.io_signature.makev(len(branches) + 1, len(branches) + 1,
                                  [vec * k, vec * rif.num_bins()] + [vec * k] * reference))
        self.message_port_register_hier_out("metrics")
        for _, path in branches:
            for blocks_in_path in path:
                self.connect(*blocks_in_path)
        # --rx-fuse: range_compress is filter and range IFFT (it takes echo and grid).
        tff = rif if fuse else data_filter(opts, n)
        probe = make_probe(opts, sc, foc, cfg, reference)
        self.connect((self, 0), (tff, 0))
        self.connect((self, 1), (tff, 1))
        filters = [tff]
        if reference:
            if fuse:  # range_compress's unit grid: S = 1 without an all-ones stream
                tff_ref = rif_ref
            else:
                tff_ref, ones = reference_filter(opts, n)
                self.connect(ones, (tff_ref, 1))
            self.connect((self, 2), (tff_ref, 0))
            filters.append(tff_ref)
        if not fuse:
            for source, (sink, _) in zip(filters, branches):
                connect_pulses(self, source, sink, sc)
        check_memory(rif, foc, sc.symbols, keep_images)
        # Autofocus on the data branch only: the reference branch is the calibration
        # standard (SPEC 8, the noise-free echo's image), so NMSE and PEL measure how close
        # the autofocused image comes to it.
        image = af = make_autofocus(opts, sc, k)
        if af is None:
            image = foc
        else:
            self.connect(foc, af)
        self.connect(image, (self, 0))
        self.connect(rif, (self, 1))
        self.connect(image, (probe, 0))
        if reference:
            self.connect(foc_ref, (self, 2))
            self.connect(foc_ref, (probe, 1))
        self.msg_connect(probe, "metrics", self, "metrics")
        self.filter, self.range_ifft, self.presum, self.focuser = tff, rif, pre, foc
        self.filter_ref = filters[1] if reference else None
        self.focuser_ref = foc_ref if reference else None
        self.probe = probe
        self.autofocus = af

    def release(self):
        """Frees the chain's blocks after its graph has run (the chain cannot run again).
        GNU Radio 3.10 never frees a hier block whose child is msg_connected to the hier
        block's own port ("metrics"; its edge and block lists hold the hier block itself),
        nor its children with their kernels, buffers and FFT objects: a process that builds
        many graphs (a Dask worker, distributed_process) releases each."""
        self.msg_disconnect(self.probe, "metrics", self, "metrics")
        self.disconnect_all()

    # The probe's last metrics, for GRC's function probes and GUI labels
    def nmse_db(self):
        return self.probe.nmse_db()

    def snr_out_db(self):
        return self.probe.snr_out_db()


@dataclasses.dataclass
class Layout:
    """The axes of imaging_chain's outputs: image bins K (output 0 and 2), range-compressed
    bins (output 1), the image's first bin [m] and the bin spacing [m]."""
    image_bins: int
    range_bins: int
    first_range_m: float
    range_bin_m: float


def layout(opts):
    """The Layout of the chain the options build, without building it (GRC's vector lengths
    and axes)."""
    sc = scenario.of(opts)
    nfft = fft_size_of(opts, sc.num.num_subcarriers)
    crop, guard = range_crop(opts, sc, nfft)
    rif = range_ifft(sc.num, nfft, fft.window.WIN_RECTANGULAR, -1.0, *crop)
    return Layout(image_bins=rif.num_bins() - 2 * guard, range_bins=rif.num_bins(),
                  first_range_m=rif.range_axis_first_m() + guard * rif.range_bin_m(),
                  range_bin_m=rif.range_bin_m())


def make_echo(opts, sc):
    """scene_echo for point targets, extended_scene_echo for a YAML scene file, flying the
    true path sc.trajectory."""
    sf = sc.scene_file
    if sf is None:
        return scene_echo(sc.num, sc.geo, sc.scene, opts.snr_db, opts.seed + 1, sc.trajectory)
    from .nrsar_python import antenna_beam, extended_scene_echo
    return extended_scene_echo(sc.num, sc.geo, sf.points, sf.maps, sf.beam or antenna_beam(),
                               opts.snr_db, opts.seed + 1, path=sc.trajectory)


def scene_echo_front(tb, opts, sc, grid):
    """The TF-domain radar channel (build's default): scene_echo on the grid, flying the
    true path. Returns (echo block, echo endpoint, reference-echo endpoint)."""
    echo = make_echo(opts, sc)
    tb.connect(grid, echo)
    return echo, (echo, 0), (echo, 1)


def make_transmitter(opts, sc, start_symbol=0):
    """nr_isac_tx of --mode, --modulation and --seed, its grid from symbol start_symbol on."""
    return nr_isac_tx(sc.num, params.make_modulation(opts.modulation),
                      params.make_tx_mode(sc.tx_mode), sc.srs, opts.seed,
                      start_symbol=start_symbol)


class array_sink(gr.hier_block2):
    """vector_sink_c's interface (data(), tags()) without its cost: vector_sink_c.data() makes
    a Python list of complex objects, 40 bytes per sample (+124 MiB for one 48000 x 56
    image). Here the samples go to an unlinked temporary file (file_sink) and data() reads
    them back as one complex64 array; a tag_debug that saves all tags keeps tags()."""

    def __init__(self, vlen):
        item = gr.sizeof_gr_complex * vlen
        gr.hier_block2.__init__(self, "array_sink", gr.io_signature(1, 1, item),
                                gr.io_signature(0, 0, 0))
        fd, path = tempfile.mkstemp(prefix="nrsar-", suffix=".cf32")
        self._file = os.fdopen(fd, "rb")
        self._sink = blocks.file_sink(item, path, False)
        os.unlink(path)  # the two open descriptors keep it until the sink is gone
        self._tags = blocks.tag_debug(item, "", "")
        self._tags.set_display(False)
        self._tags.set_save_all(True)
        self.connect(self, self._sink)
        self.connect(self, self._tags)

    def data(self):
        """The samples (after the run: closes the file), one flat complex64 array."""
        self._sink.close()
        self._file.seek(0)
        return np.fromfile(self._file, np.complex64)

    def tags(self):
        return self._tags.current_tags()

    def nitems_read(self, port):
        """Items that reached the file so far (a hier block has no counter of its own)."""
        return self._sink.nitems_read(port)


def build(tb, opts, sc, tx=None, echo_front=scene_echo_front, keep_reference=False,
          reference=True):
    """Wires transmitter -> head (one aperture) -> echo front -> imaging_chain -> sinks into
    tb. The sinks hold the range-compressed data, the focused image (vector sinks, or null
    sinks with --images none) and, with keep_reference, the reference image; reference=False
    leaves the reference branch out (the echo front's reference endpoint is None; the
    probe measures against its PSF model, reference_sink None). Returns the
    blocks by name (tx, head, echo, chain, filter, range_ifft, presum, focuser, focuser_ref,
    probe, range_sink, image_sink, reference_sink, autofocus (None without))."""
    n = sc.num.num_subcarriers
    keep = opts.images != "none"
    if tx is None:
        tx = make_transmitter(opts, sc)
    head = blocks.head(gr.sizeof_gr_complex * n, sc.symbols)
    tb.connect(tx, head)
    echo, echo_out, ref_out = echo_front(tb, opts, sc, head)
    chain = imaging_chain(opts, sc, keep, reference)
    k, bins = chain.focuser.num_output_bins(), chain.range_ifft.num_bins()
    if keep:
        range_sink, image_sink = array_sink(bins), array_sink(k)
    else:  # metrics only
        range_sink = blocks.null_sink(gr.sizeof_gr_complex * bins)
        image_sink = blocks.null_sink(gr.sizeof_gr_complex * k)
    reference_sink = None
    if reference:
        reference_sink = (array_sink(k) if keep_reference
                          else blocks.null_sink(gr.sizeof_gr_complex * k))
        tb.connect(ref_out, (chain, 2))
        tb.connect((chain, 2), reference_sink)
    tb.connect(echo_out, (chain, 0))
    tb.connect(head, (chain, 1))
    tb.connect((chain, 0), image_sink)
    tb.connect((chain, 1), range_sink)
    return {"tx": tx, "head": head, "echo": echo, "chain": chain, "filter": chain.filter,
            "range_ifft": chain.range_ifft, "presum": chain.presum, "focuser": chain.focuser,
            "focuser_ref": chain.focuser_ref, "probe": chain.probe, "range_sink": range_sink,
            "autofocus": chain.autofocus,
            "image_sink": image_sink, "reference_sink": reference_sink}


def simulate_graph(opts, keep_reference=False):
    """One run of nrsar-sim for SimOptions (validated here too): builds the graph, runs one
    aperture (Ctrl-C: runtime.Interrupted, nothing written), writes the images into opts.out.
    Returns (the JSON dict of SPEC 9, the blocks by name)."""
    sc = scenario.of(opts.validate())
    check_out_dir(opts.out)
    if opts.record is not None:
        recording.check_recordable(opts, sc)
    tb = gr.top_block("nrsar-sim")
    graph = build(tb, opts, sc, keep_reference=keep_reference)
    start = time.perf_counter()
    with contextlib.ExitStack() as stack:
        if opts.record is not None:  # the radio's recording of the same grid (--record)
            rec = stack.enter_context(recording.recorder(tb, opts, sc, graph["head"],
                                                         graph["echo"], opts.record))
        # progress: percent of the aperture's symbols through the filter (stderr)
        with progress.polling("symbols", sc.symbols, lambda: graph["filter"].nitems_written(0)):
            runtime.run(tb)
    result = results.image_results(opts, graph, sc, time.perf_counter() - start)
    graph["chain"].release()  # figures and tests run many graphs in one process
    if opts.record is not None:
        result.update(recording_meta=rec.meta_path, recording_data=rec.data_path)
        result["warnings"] += recording.model_warnings(sc, rec.echo.taps())
    if opts.geotiff:
        from . import geo  # GDAL and pyproj load only for --geotiff
        result.update(geo.write_geotiffs(opts, result, sc.geo.height_m))
    return result, graph


def simulate(opts):
    """nrsar-sim's JSON dict of one run (simulate_graph; --split zmq: split.simulate, the
    UAV and the ground in two processes)."""
    if opts.split != "none":
        from . import split  # split builds on this module
        return split.simulate(opts)
    return simulate_graph(opts)[0]
