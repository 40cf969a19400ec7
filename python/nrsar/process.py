#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-process: the images of a SigMF recording, offline, through the blocks of nrsar-sim.

    file_source(NAME.sigmf-data) -> ofdm_demod -+-> imaging_chain -> image, metrics
    nr_isac_tx(recorded seed) -> head ----------+   (transmit grid regenerated)
                       +-> scene_echo (recorded scene, S = 1 reference echo) -> reference

A PUSCH recording (nrsar:dmrs, nrsar-isac's) regenerates its grid as nrsar-isac made it:
payload file (nrsar:payload_path or --payload, its SHA-256 checked) -> PDUs -> pusch_encoder
(nrsar:pusch) -> nr_isac_tx(dmrs), isac_chain.build_transmitter.

The recording (recording.read) supplies the numerology, geometry, scene, grid and seed, and
the flight: the echo flew nrsar:trajectory, the processing images along nrsar:navigation
(--nav FILE replaces it), as nrsar-sim did; the options (ProcessOptions) are nrsar-sim's
receive-side ones. The graph streams: the samples
are read from the file as the chain consumes them (with --images none nothing grows with
the recording). The JSON has nrsar-sim's keys, plus the recording's.
"""

import dataclasses
import hashlib
import math
import time

from gnuradio import blocks, gr

from . import chain, params, progress, recording, results, runtime, scenario
from .nrsar_python import ofdm_demod, scene_echo
from .options import MODES, OptionError, SimOptions, check_out_dir, read_bytes
from .scenario import Scenario, fft_size_of


def sim_options_of(opts, rec):
    """The SimOptions nrsar-sim would have run with: the recording's scene and grid, the
    processing options of opts."""
    fields = {f.name: getattr(opts, f.name) for f in dataclasses.fields(SimOptions)
              if hasattr(opts, f.name) and f.name != "snr_db"}
    snr_db = opts.snr_db if opts.snr_db is not None else rec.snr_db
    if snr_db is None:
        raise OptionError(f"--snr-db must be given: {rec.meta_path} names no nrsar:snr_db "
                          f"(the Wiener filter and the theory need the SNR per RE)")
    fields.update(preset=rec.preset, modulation=rec.modulation, mode=rec.mode,
                  seed=rec.grid_seed, snr_db=snr_db, origin=opts.origin or rec.origin,
                  target=["%r,%r,%r,%r" % (t.x_m, t.y_m, t.rcs, math.degrees(t.phase_rad))
                          for t in rec.scene.targets], record=None)
    if opts.geotiff and fields["origin"] is None:
        raise OptionError(f"--geotiff needs --origin LAT,LON,HEADING_DEG: {rec.meta_path} "
                          f"names no nrsar:origin")
    return SimOptions(**fields).validate()


def scenario_of(sim_opts, rec):
    """The Scenario of the recording (its numerology, geometry, scene, SRS layout and
    flight: the truth of nrsar:trajectory, the navigation of nrsar:navigation or --nav)."""
    num, geo = rec.num, rec.geo
    mode = MODES[rec.mode][0]
    pulse_symbols = params.symbols_per_pulse(mode, num, rec.srs)
    fft_size_of(sim_opts, num.num_subcarriers)
    warnings = list(params.check_scenario(num, geo, rec.scene, pulse_symbols))
    truth = rec.trajectory
    nav = rec.navigation if rec.navigation is not None else truth
    if sim_opts.nav is not None:  # --nav replaces the recorded navigation
        nav = scenario._flagged("--nav", sim_opts.nav, params.make_navigation, truth,
                                sim_opts.nav, geo=geo)
    return Scenario(num=num, geo=geo, scene=rec.scene, scene_file=None, tx_mode=mode,
                    srs=rec.srs, pulse_symbols=pulse_symbols, symbols=rec.symbols,
                    warnings=warnings, trajectory=truth, navigation=nav)


def recording_front(rec, reference=True):
    """echo_front for chain.build: the recorded samples (after the hardware delay) ->
    ofdm_demod; the reference echo is scene_echo's S = 1 output on the regenerated grid,
    flying the recorded truth, as in nrsar-sim (reference=False: none, for build's
    reference=False)."""
    def front(tb, opts, sc, grid):
        num = sc.num
        lost = sum(count for _, count in rec.gaps)
        source = blocks.file_source(gr.sizeof_gr_complex, rec.data_path, False,
                                    rec.hardware_delay_samples,
                                    rec.symbols * rec.symbol_samples - lost)
        chain.widen_buffers(source)  # ofdm_demod needs a whole symbol (4384 samples at paper)
        if rec.gaps:  # the overflows stamped as a radio's source does; lost symbols -> zeros
            stamper = recording.rx_time_stamper(
                num.sample_rate_hz(),
                [(start - rec.hardware_delay_samples, count) for start, count in rec.gaps])
            demod = ofdm_demod(num, -1, 1.0)
            tb.connect(source, stamper, demod)
            tb.rx_time_stamper = stamper  # a Python block lives as long as its object
        else:
            demod = ofdm_demod(num)
            tb.connect(source, demod)
        if not reference:
            return demod, demod, None
        ref = scene_echo(num, sc.geo, sc.scene, math.inf, opts.seed + 1, sc.trajectory)
        tb.connect(grid, ref)
        tb.connect((ref, 0), blocks.null_sink(gr.sizeof_gr_complex * num.num_subcarriers))
        return demod, demod, (ref, 1)
    return front


def payload_of(opts, rec):
    """The bytes of a PUSCH recording's payload file (--payload, else nrsar:payload_path),
    checked against nrsar:payload_sha256 (ValueError naming the field)."""
    path = opts.payload or rec.payload_path
    flag = "--payload" if opts.payload else "global nrsar:payload_path"
    if path is None:
        raise OptionError(f"{rec.meta_path}: global nrsar:payload_path is null: give the "
                          f"payload file with --payload FILE (the grid is its PUSCH)")
    payload = read_bytes(path, flag, f": the grid of {rec.meta_path} is the PUSCH of that file")
    sha = hashlib.sha256(payload).hexdigest()
    if sha != rec.payload_sha256:
        raise OptionError(f"{flag} = {path!r}: its SHA-256 {sha} is not the recording's "
                          f"global nrsar:payload_sha256 {rec.payload_sha256}: not the file "
                          f"that was sent")
    return payload


def make_transmitter(opts, rec, sim_opts, sc, tb, start_symbol=0):
    """The transmit grid of the recording from symbol start_symbol: nr_isac_tx of the seed
    (chain.make_transmitter), or for a PUSCH recording the payload's PUSCH
    (isac_chain.build_transmitter, as nrsar-isac built it; from a later symbol the encoder
    starts at its slot with the payload from that slot's TB on)."""
    if rec.dmrs is None:
        if opts.payload:
            raise OptionError(f"--payload = {opts.payload!r} needs a PUSCH recording: "
                              f"{rec.meta_path} has no nrsar:dmrs (its grid is the PRBS of "
                              f"nrsar:grid_seed)")
        return chain.make_transmitter(sim_opts, sc, start_symbol)
    from . import isac_chain
    payload = payload_of(opts, rec)
    enc, tx, _, _ = isac_chain.build_transmitter(tb, rec.num, isac_chain.isac_options_of(
        rec), payload, rec.pusch["rv"], start_symbol)
    per_tb = enc.payload_bits_per_slot() // 8
    if per_tb != rec.pusch["pdu_bytes"]:
        raise OptionError(f"{rec.meta_path}: global nrsar:pusch pdu_bytes = "
                          f"{rec.pusch['pdu_bytes']} is not this pusch_encoder's {per_tb} "
                          f"bytes per TB: the payload would be cut into other PDUs")
    return tx


def run(opts):
    """nrsar-process's JSON dict of one recording (validated ProcessOptions; a strip:
    distributed_process.run)."""
    if opts.strip_aperture_s is not None or opts.dask_make_certs is not None:
        from . import distributed_process  # builds on this module
        if opts.dask_make_certs is not None:
            check_out_dir(opts.dask_make_certs, "--dask-make-certs")
            return {"dask_certificates": distributed_process.write_certificates(
                opts.dask_make_certs)}
        return distributed_process.run(opts)
    rec = recording.read(opts.recording)
    sim_opts = sim_options_of(opts, rec)
    sc = scenario_of(sim_opts, rec)
    # here, not in scenario_of: a strip's flight (distributed_process) outlasts its apertures
    sc.warnings += scenario.range_grid_warnings(sc, fft_size_of(sim_opts, sc.num.num_subcarriers))
    check_out_dir(sim_opts.out)
    tb = gr.top_block("nrsar-process")
    graph = chain.build(tb, sim_opts, sc, tx=make_transmitter(opts, rec, sim_opts, sc, tb),
                        echo_front=recording_front(rec))
    start = time.perf_counter()
    with progress.polling("symbols", sc.symbols, lambda: graph["filter"].nitems_written(0)):
        runtime.run(tb)
    result = results.image_results(sim_opts, graph, sc, time.perf_counter() - start)
    demod = graph["echo"]
    result.update(recording_meta=rec.meta_path, recording_data=rec.data_path,
                  recording_samples=rec.samples, recording_datetime=rec.datetime,
                  samples_read=int(demod.nitems_read(0)), overflows=len(rec.gaps),
                  lost_samples=sum(count for _, count in rec.gaps))
    # the radio graph's transmitter underruns (None: the recorder did not count them); the
    # echo lacks their symbols unmarked (docs/recording.md, "Transmit underruns")
    underruns = rec.meta["global"].get("nrsar:tx_underruns")
    result["tx_underruns"] = underruns
    if underruns:
        result["warnings"].append(f"the transmitter underran {underruns} times during the "
                                  f"recording: the echo lacks those symbols (not zeroed)")
    if sim_opts.geotiff:
        from . import geo
        result.update(geo.write_geotiffs(sim_opts, result, sc.geo.height_m))
    return result
