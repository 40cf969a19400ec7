#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The one ISAC graph (nrsar-isac). The UAV's uplink carries a payload file to the base
station and images the ground with the same waveform, in one GNU Radio flowgraph:

  payload -> PDUs -> pusch_encoder -> nr_isac_tx(dmrs) -> head -+-> ofdm_mod -+
                                                                |             |
   (b) radar, --radar-domain time:                              |             |
       ofdm_mod -> td_echo -> ofdm_demod -> tf_filter(., grid) -> range_ifft -> [presum]
       -> rd_focuser -> nmse_probe  (reference branch: scene_echo's S = 1 echo, as nrsar-sim)
       --radar-domain tf: scene_echo on the grid (nrsar-sim's chain)
   (a) base station:
       ofdm_mod -> uplink_channel (delay, taps, CFO, noise) -> ofdm_sync -> ofdm_demod
       -> pusch_receiver -> PDUs -> decoded file

The image, its metrics and the JSON keys are nrsar-sim's (SPEC 9); the backhaul adds
payload_identical, backhaul_ber, backhaul_bler, throughput_mbps and the receiver's numbers.
"""

import contextlib
import math
import os
import time

import numpy as np
import pmt
from gnuradio import analog, blocks, gr

from . import (backhaul, chain, params, progress, recording, results, runtime,
               scenario)
from .options import OptionError, check_out_dir, parse_taps, read_bytes
from .nrsar_python import (nr_isac_tx, ofdm_demod, ofdm_mod, ofdm_sync, pusch_encoder,
                           pusch_receiver, scene_echo, srs_config, td_echo, uplink_channel,
                           uplink_channel_config)

def time_domain_front(ofdm_source, record_path=None):
    """echo_front for chain.build: the radar echo through the time domain,
    ofdm_source (ofdm_mod of the grid) -> td_echo -> ofdm_demod (FFT window after the CP:
    the TF model of SPEC 3 exactly); the reference echo (S = 1, no noise) is scene_echo's,
    as in nrsar-sim, from a reference-only scene_echo (its echo would be thrown away; the
    grid paces it and brings its tags). record_path:
    the received samples (td_echo's output) also go to this file (--record)."""
    def front(tb, opts, sc, grid):
        num, geo, scn = sc.num, sc.geo, sc.scene
        echo = td_echo(num, geo, scn, opts.snr_db, opts.seed + 1, opts.echo_taps,
                       path=sc.trajectory)
        demod = ofdm_demod(num)
        chain.widen_buffers(echo)
        tb.connect(ofdm_source, echo, demod)
        if record_path is not None:
            front.sink = recording.file_sink_of(record_path)
            tb.connect(echo, front.sink)
        ref = scene_echo(num, geo, scn, math.inf, opts.seed + 1, sc.trajectory)
        ref.set_reference_only(True)
        tb.connect(grid, ref)
        front.demod = demod
        return echo, demod, (ref, 0)
    return front


def common_noise_front(domain, noise_seed):
    """echo_front for comparing the two radar paths under the SAME noise: the echo is
    noise-free (td_echo / scene_echo with +inf SNR) and one seeded complex Gaussian noise
    stream of sigma^2 = total RCS / 10^(snr_db/10) per RE is added on the grid after it, so
    two runs differ only by the echo model (qa_isac, docs/isac.md)."""
    def front(tb, opts, sc, grid):
        num, geo, scn = sc.num, sc.geo, sc.scene
        n = num.num_subcarriers
        ref = scene_echo(num, geo, scn, math.inf, opts.seed + 1, sc.trajectory)
        tb.connect(grid, ref)
        if domain == "time":
            ref.set_reference_only(True)  # td_echo makes the echo
            echo, demod = td_echo(num, geo, scn, math.inf, opts.seed + 1, opts.echo_taps,
                                  path=sc.trajectory), ofdm_demod(num)
            tb.connect(grid, ofdm_mod(num), echo, demod)
            clean, ref_out = demod, (ref, 0)
        else:
            echo, clean, ref_out = ref, (ref, 0), (ref, 1)
        sigma = math.sqrt(sum(t.rcs for t in scn.targets) / 10.0 ** (opts.snr_db / 10.0))
        noise = analog.noise_source_c(analog.GR_GAUSSIAN, sigma, noise_seed)
        add = blocks.add_vcc(n)
        tb.connect(clean, (add, 0))
        tb.connect(noise, blocks.stream_to_vector(gr.sizeof_gr_complex, n), (add, 1))
        return echo, add, ref_out
    return front


def build_transmitter(tb, num, opts, payload, rv=0, start_symbol=0):
    """pusch_encoder (the payload queued as PDUs of one TB's capacity each, deterministic;
    rv: the first transmission's) -> nr_isac_tx(dmrs). Returns (encoder, tx, dmrs,
    chunks). nrsar-process regenerates a recording's grid with it (pusch_meta's fields);
    start_symbol > 0: the grid from that symbol on, the same (the encoder starts at its
    slot, given the PDUs from that slot's TB on)."""
    mod = params.make_modulation(opts.modulation)
    dmrs = params.make_dmrs(opts.dmrs, num)
    cfg = opts.pusch_config(num, max(1, len(payload) + 1))
    cfg.rv = rv
    cfg.first_slot = start_symbol // num.symbols_per_slot
    enc = pusch_encoder(cfg)
    tx = nr_isac_tx(num, mod, params.make_tx_mode("data"), srs_config(), opts.seed, dmrs,
                    start_symbol)
    tb.connect(enc, tx)
    chunks = queue_payload(enc, payload, opts.repetitions, cfg.first_slot)
    return enc, tx, dmrs, chunks


def queue_payload(enc, payload, repetitions=1, first_slot=0):
    """Posts payload to enc's pdus port as PDUs of one TB's capacity each
    (payload_bits_per_slot / 8 bytes, the last shorter): chunk s goes out whole in TB s,
    padding-only TBs follow the last. Call it before the flowgraph starts: GNU Radio's
    thread-per-block scheduler hands a block every queued message before each work call, so
    all PDUs are queued before the encoder makes its first slot and the grid is a function of
    the payload alone (the encoder does not wait for PDUs: one that arrived after its slot
    would leave a padding-only TB there). first_slot: the PDUs from that slot's TB on.
    Returns all chunks."""
    per_tb = enc.payload_bits_per_slot() // 8
    if per_tb <= 0:
        raise ValueError(f"payload bytes per TB = {per_tb} must be > 0")
    chunks = [payload[i:i + per_tb] for i in range(0, len(payload), per_tb)]
    for chunk in chunks[first_slot // repetitions:]:
        enc.to_basic_block()._post(pmt.intern("pdus"), backhaul.make_pdu(chunk))
    return chunks


# the radio graphs' payload parameter that keeps their live message strobe (docs/sdr.md)
STROBE = "strobe"


def graph_payload(enc, payload, max_queued_bytes):
    """The ISAC graphs' backhaul payload (examples/gen_isac_grcs.py, docs/sdr.md): the file
    `payload` queued into the graph's pusch_encoder before the graph starts (queue_payload:
    its grid is build_transmitter's of the file, which the recording names). 'strobe':
    nothing queued, the graph's message strobe feeds the encoder at wall-clock times that
    nothing records (its recordings cannot be processed). Returns the file's absolute path,
    or None for the strobe."""
    if payload == STROBE:
        return None
    data = read_bytes(payload, "payload", f"; give a file, or {STROBE!r} for the live "
                                           f"message strobe")
    if len(data) > max_queued_bytes:
        raise ValueError(f"payload = {payload!r}: {len(data)} bytes must be at most the "
                         f"encoder's max_queued_bytes = {max_queued_bytes} (all of it is "
                         f"queued before the start)")
    queue_payload(enc, data)
    return os.path.abspath(payload)


def graph_pusch(enc, preset, modulation, dmrs, **fields):
    """nrsar:pusch of an ISAC graph's pusch_encoder enc, whose configuration the graph's
    record snippet repeats in fields (IsacOptions' names: coding, mcs_table, mcs, n_rnti,
    n_id, scrambling, repetitions; dmrs_id): the encoder of these fields must have enc's
    TBS, G and bytes per TB (a ValueError names both), which nrsar-process checks again."""
    from .options import IsacOptions
    num = params.make_numerology(preset)
    layout = params.make_dmrs(dmrs, num, fields.pop("dmrs_id", 0))
    opts = IsacOptions(preset=preset, modulation=modulation, dmrs=dmrs, **fields)
    ref = pusch_encoder(opts.pusch_config(num))
    sizes = [(e.tbs_bits(), e.slot_bits(), e.payload_bits_per_slot() // 8) for e in (enc, ref)]
    if sizes[0] != sizes[1]:
        raise ValueError(f"the graph's pusch_encoder (TBS, G, bytes per TB) = {sizes[0]} is "
                         f"not the recorded PUSCH's {sizes[1]} ({modulation}, {fields}): keep "
                         f"the record snippet's PUSCH fields in step with the encoder block")
    return pusch_meta(opts, num, enc, layout)


def build_base_station(tb, num, opts, dmrs, source):
    """source (time-domain uplink) -> uplink_channel (delay, taps, CFO, noise: one pass) ->
    ofdm_sync -> ofdm_demod -> pusch_receiver -> message_debug (store). Returns the blocks
    by name."""
    # per sample = per RE (unitary OFDM)
    chan = uplink_channel(uplink_channel_config(
        delay_samples=opts.delay_samples, taps=parse_taps(opts.taps),
        cfo=opts.cfo_hz / num.sample_rate_hz(), noise_voltage=10.0 ** (-opts.bs_snr_db / 20.0),
        seed=opts.seed + 2))
    sync = ofdm_sync(num, dmrs)
    demod = ofdm_demod(num)
    # ofdm_sync's backoff puts a phase slope across the subcarriers; pusch_receiver's
    # channel estimate removes it before its fit (docs/isac.md, "Backoff slope")
    rx = pusch_receiver(opts.pusch_config(num))
    chain.widen_buffers(chan, sync)
    rx.set_threads(opts.rx_threads)
    store = blocks.message_debug()
    tb.connect(source, chan, sync, demod, rx)
    tb.msg_connect((rx, "pdus"), (store, "store"))
    return {"channel": chan, "sync": sync, "demod": demod, "receiver": rx, "store": store}


def backhaul_results(num, enc, bs, chunks, payload, out_path, repetitions=1):
    """Writes the decoded file (payload of every CRC-ok, non-filler TB in TB order) and
    returns the backhaul's JSON keys. A TB that failed its CRC delivers nothing: every
    payload bit of its TB counts as an error in backhaul_ber."""
    store, rx = bs["store"], bs["receiver"]
    delivered = {}
    failed_slots = []
    for i in range(store.num_messages()):
        meta, data = backhaul.pdu_fields(store.get_message(i), ("slot", "crc_ok", "filler"))
        slot = int(meta["slot"]) if meta["slot"] is not None else -1
        if not meta["crc_ok"]:
            failed_slots.append(slot)
        elif not meta["filler"]:
            delivered[slot // repetitions] = data()
    decoded = b"".join(delivered[s] for s in sorted(delivered))
    results.write_bytes(out_path, decoded)
    bit_errors = 0
    for s, chunk in enumerate(chunks):
        got = delivered.get(s)
        if got is None or len(got) != len(chunk):
            bit_errors += 8 * len(chunk)
        else:
            diff = np.bitwise_xor(np.frombuffer(got, np.uint8), np.frombuffer(chunk, np.uint8))
            bit_errors += int(np.unpackbits(diff).sum())
    ok, bad = int(rx.blocks_ok()), int(rx.blocks_failed())
    slot_s = num.symbols_per_slot * num.symbol_s()
    good_bits = 8 * sum(len(c) for s, c in enumerate(chunks) if delivered.get(s) == c)
    sync = bs["sync"]
    return {
        "payload_identical": decoded == payload,
        "payload_bytes": len(payload),
        "decoded_bytes": len(decoded),
        "decoded_file": os.path.abspath(out_path),
        "backhaul_ber": bit_errors / (8.0 * len(payload)) if payload else 0.0,
        "backhaul_bler": bad / float(ok + bad) if ok + bad else None,
        "blocks_ok": ok,
        "blocks_failed": bad,
        "failed_slots": failed_slots[:32],  # the first 32
        "failed_payload_slots": [s for s in failed_slots
                                 if 0 <= s < len(chunks) * repetitions],
        "payload_slots": len(chunks) * repetitions,
        # delivered payload bits over the air time of the slots that carried the payload
        "throughput_mbps": (good_bits / (len(chunks) * repetitions * slot_s) / 1e6
                            if chunks else 0.0),
        "capacity_mbps": enc.throughput_bps() / 1e6,
        "code_rate": float(enc.code_rate()),
        "tbs_bits": int(enc.tbs_bits()),
        "code_blocks": int(enc.code_blocks()),
        "ldpc_iterations_mean": float(rx.ldpc_iterations_mean()),
        "harq_combined_ok": int(rx.harq_combined_ok()),
        "sync_locked": bool(sync.locked()),
        "sync_cfo_hz": float(sync.cfo_hz()),
        "sync_timing_samples": int(sync.timing_samples()),
        # gaps (docs/blocks/ofdm_sync.md "Gaps"): lost TBs are in blocks_failed too
        "blocks_lost": int(rx.blocks_lost()),
        "sync_lost_samples": int(sync.lost_samples()),
        "sync_rx_time_gaps": int(sync.rx_time_gaps()),
        "sync_lock_losses": int(sync.lock_losses()),
        "sync_reacquisitions": int(sync.reacquisitions()),
        "sync_skipped_slots": int(sync.skipped_slots()),
        "sync_skipped_symbols": int(sync.skipped_symbols()),
        "bs_snr_est_db": float(rx.last_snr_db()),
        "bs_evm_db": float(rx.last_evm_db()),
    }


def pusch_meta(opts, num, enc, dmrs):
    """The meta's nrsar:pusch: with nrsar:dmrs and the payload file, what build_transmitter
    needs to make the grid again bit for bit (docs/recording.md)."""
    cfg = opts.pusch_config(num)
    return {"coding": opts.coding, "mcs_table": opts.mcs_table,
            "mcs": int(cfg.mcs) if opts.coding == "nr-ldpc" else None, "rv": int(cfg.rv),
            "repetitions": opts.repetitions, "n_rnti": opts.n_rnti, "n_id": opts.n_id,
            "scrambling": opts.scrambling, "dmrs_scrambling_id": int(dmrs.scrambling_id),
            "pdu_bytes": int(enc.payload_bits_per_slot() // 8)}


def isac_options_of(rec):
    """The IsacOptions build_transmitter regenerates a recording's PUSCH grid from
    (recording.read validated its nrsar:dmrs and nrsar:pusch)."""
    from .options import IsacOptions
    p = rec.pusch
    dmrs = params.make_dmrs(rec.dmrs, rec.num, p["dmrs_scrambling_id"])
    return IsacOptions(preset=rec.preset, modulation=rec.modulation, seed=rec.grid_seed,
                       dmrs=dmrs, coding=p["coding"], mcs_table=p["mcs_table"], mcs=p["mcs"],
                       n_rnti=p["n_rnti"], n_id=p["n_id"], scrambling=p["scrambling"],
                       repetitions=p["repetitions"])


def record_meta(opts, sc, tmp, sink, dmrs, payload, enc):
    """The SigMF meta of nrsar-isac's radar recording (docs/recording.md): td_echo's output
    (echo and noise) as the radio receives it, the PUSCH grid named by its DMRS, its
    payload's SHA-256 and path and its coding (nrsar:pusch); --record-gap's overflows
    dropped."""
    sink.close()
    gaps = recording.parse_gaps(opts.record_gap or [])
    recording.finish(tmp, sc.symbols * (sc.num.cp_samples + sc.num.fft_size), gaps)
    return recording.build_meta(
        opts, sc, tmp, recorder="nrsar-isac (gr-nrsar)",
        hw="none: simulated by gr-nrsar (pusch_encoder -> nr_isac_tx -> ofdm_mod -> td_echo "
           "with noise)",
        description=f"simulated ISAC flight, preset {opts.preset}, {opts.modulation} PUSCH "
                    f"with DMRS {opts.dmrs}, coding {opts.coding}, SNR per RE "
                    f"{opts.snr_db:g} dB",
        snr_db=opts.snr_db, dmrs=[int(x) for x in dmrs.symbols],
        payload=(opts.payload, payload), pusch=pusch_meta(opts, sc.num, enc, dmrs),
        echo={"model": "td_echo", "taps": opts.echo_taps, "noise": "td_echo",
              "noise_seed": opts.seed + 1},
        gaps=recording.file_gaps(gaps), tx_underruns=recording.SIMULATED_TX_UNDERRUNS)


def check_link(opts, num):
    """The backhaul's rules that need the numerology (before any block is built)."""
    df = num.subcarrier_spacing_hz
    if not abs(opts.cfo_hz) < df:
        raise OptionError(f"--cfo-hz = {opts.cfo_hz:g} must be below the subcarrier spacing "
                          f"{df:g} Hz in magnitude: ofdm_sync estimates the fractional CFO "
                          f"only (docs/isac.md)")


def run(opts):
    """The one ISAC graph of IsacOptions; returns nrsar-isac's JSON dict."""
    opts.validate()
    with open(opts.payload, "rb") as f:
        payload = f.read()
    sc = scenario.of(opts)
    num, symbols = sc.num, sc.symbols
    check_link(opts, num)
    check_out_dir(opts.out)
    if symbols < 2 * num.symbols_per_slot:
        raise OptionError(f"--aperture-s: symbols per aperture = {symbols} must be at least "
                          f"two slots ({2 * num.symbols_per_slot}; the last carries no payload)")
    tb = gr.top_block("nrsar-isac")
    enc, tx, dmrs, chunks = build_transmitter(tb, num, opts, payload)
    # The aperture's last slot carries no payload: it ends where the stream ends, and
    # whether the base station sees all of it depends on how many samples the channel's
    # stock blocks leave unconsumed at the end of the stream.
    slots = symbols // num.symbols_per_slot - 1
    if len(chunks) * opts.repetitions > slots:
        raise OptionError(f"--payload = {opts.payload!r}: {len(payload)} bytes need "
                          f"{len(chunks) * opts.repetitions} slots, the aperture has {slots} "
                          f"(all but its last): shorten the file or lengthen --aperture-s")
    mod = ofdm_mod(num)
    chain.widen_buffers(mod)
    with contextlib.ExitStack() as stack:
        if opts.record is not None:  # the radar receiver's samples as SigMF (--record)
            recording.check_recordable(opts, sc)
            tmp, data_path, meta_path = stack.enter_context(recording.data_file(opts.record))
        if opts.radar_domain == "time":
            front = time_domain_front(mod, tmp if opts.record is not None else None)
            graph = chain.build(tb, opts, sc, tx=tx, echo_front=front)
            graph["radar_demod"] = front.demod
        else:
            graph = chain.build(tb, opts, sc, tx=tx)
        tb.connect(graph["head"], mod)
        bs = build_base_station(tb, num, opts, dmrs, mod)
        start = time.perf_counter()
        # progress (stderr, if enabled): the aperture's symbols through the radar filter
        with progress.polling("symbols", symbols, lambda: graph["filter"].nitems_written(0)):
            runtime.run(tb)
        runtime_s = time.perf_counter() - start
        if opts.record is not None:
            meta = record_meta(opts, sc, tmp, front.sink, dmrs, payload, enc)
    result = results.image_results(opts, graph, sc, runtime_s)
    if opts.record is not None:
        results.write_json(meta_path, meta)
        result.update(recording_meta=meta_path, recording_data=data_path)
    if opts.geotiff:
        from . import geo  # GDAL and pyproj load only for --geotiff
        result.update(geo.write_geotiffs(opts, result, sc.geo.height_m))
    result.update(backhaul_results(num, enc, bs, chunks, payload,
                                   os.path.join(opts.out, "decoded.bin"), opts.repetitions))
    bs_times = {name: bs[name].pc_work_time_total() / 1e9
                for name in ("sync", "demod", "receiver")}
    # CPU time in work() of every block we hold
    named = {"pusch_encoder": enc, "nr_isac_tx": tx, "ofdm_mod": mod, "bs_channel": bs["channel"],
             "radar_echo": graph["echo"]}
    for k in ("filter", "range_ifft", "focuser", "probe"):
        blk = graph[k]  # --rx-fuse: one range_compress is the filter and the range IFFT
        if not any(blk is b for b in named.values()):
            named["radar_range_compress" if blk.name() == "range_compress"
                  else f"radar_{k}"] = blk
    named.update({f"bs_{k}": bs[k] for k in ("sync", "demod", "receiver")})
    if opts.radar_domain == "time":
        named["radar_ofdm_demod"] = graph["radar_demod"]
    result.update({
        "radar_domain": opts.radar_domain,
        "dmrs": opts.dmrs,
        "ldpc": "38.212" if opts.coding == "nr-ldpc" else "none",
        "coding": opts.coding,
        "mcs_table": opts.mcs_table,
        "mcs": int(opts.pusch_config(num).mcs) if opts.coding == "nr-ldpc" else None,
        "n_rnti": opts.n_rnti,
        "n_id": opts.n_id,
        "scrambling": opts.scrambling,
        "repetitions": opts.repetitions,
        "bs_snr_db": opts.bs_snr_db,
        "cfo_hz": opts.cfo_hz,
        "delay_samples": opts.delay_samples,
        "taps": opts.taps,
        "samples": symbols * (num.cp_samples + num.fft_size),
        "sample_rate_hz": num.sample_rate_hz(),
        "bs_rx_runtime_s": sum(bs_times.values()),
        "bs_rx_block_s": bs_times,
        "block_cpu_s": {k: round(b.pc_work_time_total() / 1e9, 3) for k, b in named.items()},
        "peak_rss_mb": runtime.peak_rss_mb(),
    })
    return result
