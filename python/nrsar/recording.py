#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""SigMF recordings of a flight: what the radio received, and what the processor needs.

    with recording.recorder(tb, opts, sc, grid, "DIR") as rec:   # nrsar-sim --record DIR
        runtime.run(tb)                       # grid -> ofdm_mod -> td_echo -> file_sink
    rec.meta_path, rec.data_path              # DIR/flight.sigmf-meta, DIR/flight.sigmf-data

    rec = recording.read("DIR/flight.sigmf-meta")   # Recording, validated (ValueError)

NAME.sigmf-data holds the received complex baseband samples (cf32_le, symbol 0's cyclic
prefix at sample hardware_delay_samples); NAME.sigmf-meta is SigMF 1.0.0 JSON with the
`nrsar` extension (numerology, grid, scene, geometry, origin, ...): every key is documented in
docs/recording.md. The data file is written under a temporary name and renamed when it is
complete, then the meta (results.atomic): a meta never names a data file that is not whole.
A reader error is one ValueError that names the file and the field.
"""

import contextlib
import dataclasses
import datetime
import hashlib
import json
import math
import os
import typing

import numpy as np
import pmt
from gnuradio import blocks, gr

from . import params, results
from .nrsar_python import ofdm_mod, td_echo
from .options import IsacOptions, OptionError, check_out_dir, parse_gaps, parse_origin

SIGMF_VERSION = "1.0.0"
EXTENSION = {"name": "nrsar", "version": "1.0.0", "optional": False}
DATATYPE = "cf32_le"
SAMPLE_BYTES = 8  # cf32: two little-endian float32
DEFAULT_NAME = "flight"

NUMEROLOGY_FIELDS = ("subcarrier_spacing_hz", "num_subcarriers", "fft_size", "cp_samples",
                     "symbols_per_slot", "slots_per_frame")
GEOMETRY_FIELDS = ("carrier_hz", "velocity_mps", "height_m", "track_start_m", "aperture_s")
SRS_FIELDS = ("start_subcarrier", "num_rb", "comb", "comb_offset", "period_slots",
              "symbol_in_slot")


def rf_centre_hz(num, geo):
    """core:frequency: the RF frequency at the baseband's 0 Hz. The TF model puts subcarrier
    n at fc + n Delta f (SPEC 3), ofdm_mod puts it at (n - k0) Delta f: DC is fc + k0 Delta f."""
    return geo.carrier_hz + num.dc_subcarrier() * num.subcarrier_spacing_hz


def target_dicts(scn):
    return [{"x_m": t.x_m, "y_m": t.y_m, "rcs": t.rcs, "phase_deg": math.degrees(t.phase_rad)}
            for t in scn.targets]


def origin_dict(text):
    if text is None:
        return None
    lat, lon, heading = parse_origin(text)
    return {"lat_deg": lat, "lon_deg": lon, "heading_deg": heading}


def sha512_of(path):
    digest = hashlib.sha512()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


# A simulated transmitter (nrsar-sim, nrsar-isac) feeds the echo model in the same
# flowgraph, which waits for it: no clock drains it, so it cannot underrun. Its count is 0,
# known; null stays for a radio graph whose sink is not counted (the Soapy graph).
SIMULATED_TX_UNDERRUNS = 0


def build_meta(opts, sc, data_path, *, recorder, hw, description, snr_db=None, echo=None,
               gaps=(), dmrs=None, payload=None, pusch=None, hardware_delay_s=0.0,
               start=None, tx_underruns=None):
    """The SigMF meta dict of a recording of sc's flight (docs/recording.md). gaps: (sample
    index, lost samples) of each overflow; payload: (path, bytes) of a backhaul payload;
    pusch: its coding (isac_chain.pusch_meta; None: not recorded); tx_underruns: the
    transmitter's underrun events (None: not counted)."""
    num, geo = sc.num, sc.geo
    sym_len = num.cp_samples + num.fft_size
    delay = int(round(hardware_delay_s * num.sample_rate_hz()))
    start = start or datetime.datetime.now(datetime.timezone.utc)
    glob = {
        "core:datatype": DATATYPE,
        "core:sample_rate": num.sample_rate_hz(),
        "core:version": SIGMF_VERSION,
        "core:num_channels": 1,
        "core:sha512": sha512_of(data_path),
        "core:hw": hw,
        "core:recorder": recorder,
        "core:description": description,
        "core:extensions": [dict(EXTENSION)],
        "nrsar:preset": opts.preset,
        "nrsar:numerology": {k: getattr(num, k) for k in NUMEROLOGY_FIELDS},
        "nrsar:modulation": opts.modulation,
        "nrsar:mode": opts.mode,
        "nrsar:srs": {k: getattr(sc.srs, k) for k in SRS_FIELDS},
        "nrsar:dmrs": dmrs,
        "nrsar:grid_seed": opts.seed,
        "nrsar:payload_sha256": hashlib.sha256(payload[1]).hexdigest() if payload else None,
        "nrsar:payload_path": os.path.abspath(payload[0]) if payload else None,
        "nrsar:pusch": pusch,
        "nrsar:scene": target_dicts(sc.scene),
        "nrsar:reference_target": target_dicts(sc.scene)[0],
        "nrsar:geometry": {k: getattr(geo, k) for k in GEOMETRY_FIELDS},
        "nrsar:symbols": sc.symbols,
        "nrsar:symbol_samples": sym_len,
        "nrsar:trajectory": flight_text(opts, "trajectory", "motion", 0),
        "nrsar:navigation": flight_text(opts, "nav", "nav_error", 1),
        "nrsar:hardware_delay_s": hardware_delay_s,
        "nrsar:origin": origin_dict(opts.origin),
        "nrsar:snr_db": snr_db,
        "nrsar:echo": echo,
        "nrsar:tx_underruns": tx_underruns,
    }
    captures = [{"core:sample_start": 0, "core:frequency": rf_centre_hz(num, geo),
                 "core:datetime": start.strftime("%Y-%m-%dT%H:%M:%S.%fZ")}]
    # one aperture of the geometry's duration, less what the overflows lost
    aperture = sc.symbols * sym_len - sum(lost for _, lost in gaps)
    annotations = [{"core:sample_start": delay, "core:sample_count": aperture,
                    "core:label": "aperture 0", "nrsar:aperture": 0}]
    for sample, lost in gaps:
        annotations.append({"core:sample_start": int(sample), "core:sample_count": 0,
                            "core:label": "overflow", "nrsar:lost_samples": int(lost)})
    annotations.sort(key=lambda a: a["core:sample_start"])
    return {"global": glob, "captures": captures, "annotations": annotations}


def flight_text(opts, file_field, model_field, seed_offset):
    """The meta's nrsar:trajectory / nrsar:navigation: the CSV file, 'MODEL seed N', or None
    (the ideal line, perfect navigation)."""
    path = getattr(opts, file_field, None)
    if path is not None:
        return os.path.abspath(path)
    model = getattr(opts, model_field, "none")
    if model == "none":
        return None
    return f"{model} seed {opts.motion_seed + seed_offset}"


def check_recordable(opts, sc, folder=None, flag="--record"):
    """--record's rules that need the scenario (before the run): a writable folder (folder,
    default opts.record), and point targets (td_echo echoes point targets, not a scene
    file's maps)."""
    folder = opts.record if folder is None else folder
    if sc.scene_file is not None:
        raise OptionError(f"{flag} = {folder!r} needs point targets: td_echo has no "
                          f"reflectivity maps (--scene {opts.scene!r} is a scene file)")
    check_out_dir(folder, flag)
    flight = sc.symbols * (sc.num.cp_samples + sc.num.fft_size)
    for sample, count in parse_gaps(opts.record_gap or []):
        if sample + count >= flight:
            raise OptionError(f"--record-gap = '{sample}:{count}' must end before the "
                              f"flight's last sample {flight - 1} (a received sample "
                              f"follows every overflow)")


def file_gaps(gaps):
    """[(flight sample, lost)] -> [(file sample of the first sample after the gap, lost)]:
    where a radio's recording marks each overflow."""
    out, before = [], 0
    for sample, lost in gaps:
        out.append((sample - before, lost))
        before += lost
    return out


def drop_gaps(path, gaps, chunk=1 << 22):
    """Rewrites the cf32 file at path without the samples of the gaps [(flight sample,
    lost)], streaming (what the radio would have delivered)."""
    keep, pos = [], 0
    for sample, lost in gaps:
        keep.append((pos, sample))
        pos = sample + lost
    keep.append((pos, os.path.getsize(path) // SAMPLE_BYTES))
    with open(path, "rb") as src, open(path + ".gaps", "wb") as dst:
        for first, end in keep:
            src.seek(first * SAMPLE_BYTES)
            left = (end - first) * SAMPLE_BYTES
            while left > 0:
                block = src.read(min(chunk, left))
                dst.write(block)
                left -= len(block)
    os.replace(path + ".gaps", path)


def model_warnings(sc, taps=32):
    """Where the recorded time-domain echo is not the TF model of the simulated image
    (docs/blocks/td_echo.md): the farthest round trip plus the FIR's look-ahead must fit in
    the CP, and the band must leave guard subcarriers (N < fft_size)."""
    num = sc.num
    ext = params.compute_extent(sc.geo, sc.scene)
    reach = 2.0 * ext.max_slant_range_m / 299792458.0 * num.sample_rate_hz() + taps / 2
    out = []
    if reach > num.cp_samples:
        out.append(f"--record: the farthest round trip plus td_echo's look-ahead is "
                   f"{reach:.1f} samples, more than the CP of {num.cp_samples}: the recording "
                   f"differs from the simulated TF echo (use sdr20, paper or nr273)")
    if num.num_subcarriers >= num.fft_size:
        out.append(f"--record: {num.num_subcarriers} subcarriers fill the {num.fft_size}-point "
                   f"FFT: td_echo cannot delay the band edge by a fraction of a sample, the "
                   f"recording differs from the simulated TF echo (use sdr20, paper or nr273)")
    return out


@dataclasses.dataclass
class Recorder:
    meta_path: str
    data_path: str
    echo: object
    sink: object


@contextlib.contextmanager
def data_file(folder, name=DEFAULT_NAME):
    """Yields (temporary path, data path, meta path) of a recording in folder: the graph
    writes the flight into the temporary path, `finish` checks it, the caller builds the
    meta on it (build_meta hashes it); on leaving, the data file is renamed into place, on
    an exception nothing is left. Write the meta after the with-block."""
    data_path = os.path.join(folder, name + ".sigmf-data")
    meta_path = os.path.join(folder, name + ".sigmf-meta")
    with results.atomic(data_path) as tmp:
        yield tmp, os.path.abspath(data_path), os.path.abspath(meta_path)


def finish(tmp, samples, gaps):
    """After the graph ran: checks that tmp holds the flight's `samples` and drops the
    samples of the gaps [(flight sample, lost)] (the radio's overflows)."""
    got = os.path.getsize(tmp)
    if got != samples * SAMPLE_BYTES:
        raise RuntimeError(f"--record: the recording holds {got} bytes, the flight "
                           f"{samples * SAMPLE_BYTES} (the graph stopped early)")
    if gaps:
        drop_gaps(tmp, gaps)


def file_sink_of(tmp):
    sink = blocks.file_sink(gr.sizeof_gr_complex, tmp, False)
    sink.set_unbuffered(False)
    return sink


@contextlib.contextmanager
def recorder(tb, opts, sc, grid, tf_echo, folder, name=DEFAULT_NAME):
    """The recording a radio would have made of nrsar-sim's flight, wired into tb: the
    transmit grid -> ofdm_mod -> td_echo (noise-free) plus the simulation's own noise draw in
    the time domain -> file_sink. tf_echo is the simulation's scene_echo (out0 Y = H S + Z,
    out1 H): its noise Z = Y - H S, through ofdm_mod, is white with scene_echo's variance in
    every FFT window on the N used subcarriers (band-limited, as behind a radio's channel
    filter; the CP a copy, as for the signal), so the recording and the simulated image hold
    the same draw. --record-gap drops samples as an overflow would. Run the graph inside the
    with-block; on success the data file is renamed into place and the meta written; on an
    exception neither exists."""
    num = sc.num
    samples = sc.symbols * (num.cp_samples + num.fft_size)
    gaps = parse_gaps(opts.record_gap or [])
    with data_file(folder, name) as (tmp, data_path, meta_path):
        n = num.num_subcarriers
        echo = td_echo(num, sc.geo, sc.scene, math.inf, opts.seed + 1, path=sc.trajectory)
        clean = blocks.multiply_vcc(n)  # H S
        noise = blocks.sub_cc(n)        # Z = Y - H S
        received = blocks.add_cc()
        sink = file_sink_of(tmp)
        tb.connect(grid, ofdm_mod(num), echo, (received, 0))
        tb.connect((tf_echo, 1), (clean, 0))
        tb.connect(grid, (clean, 1))
        tb.connect((tf_echo, 0), (noise, 0))
        tb.connect(clean, (noise, 1))
        tb.connect(noise, ofdm_mod(num), (received, 1))
        tb.connect(received, sink)
        rec = Recorder(meta_path=meta_path, data_path=data_path, echo=echo, sink=sink)
        yield rec
        sink.close()
        finish(tmp, samples, gaps)
        meta = build_meta(
            opts, sc, tmp, recorder="nrsar-sim (gr-nrsar)",
            hw="none: simulated by gr-nrsar (ofdm_mod -> td_echo, plus scene_echo's noise "
               "through ofdm_mod)",
            description=f"simulated flight, preset {opts.preset}, scene of "
                        f"{len(sc.scene.targets)} point targets, SNR per RE "
                        f"{opts.snr_db:g} dB",
            snr_db=opts.snr_db,
            echo={"model": "td_echo", "taps": echo.taps(), "noise": "scene_echo",
                  "noise_seed": opts.seed + 1},
            gaps=file_gaps(gaps), tx_underruns=SIMULATED_TX_UNDERRUNS)
    results.write_json(meta_path, meta)


# ---------------------------------------------------------------------------------------
# Reading


@dataclasses.dataclass
class Recording:
    """A validated recording (read())."""
    meta_path: str
    data_path: str
    meta: dict
    preset: str
    num: object
    geo: object
    scene: object
    srs: object
    modulation: str
    mode: str
    grid_seed: int
    symbols: int
    symbol_samples: int
    samples: int                 # complex samples in the data file
    hardware_delay_samples: int  # samples before symbol 0's cyclic prefix
    origin: typing.Optional[str]  # 'LAT,LON,HEADING_DEG' or None
    snr_db: typing.Optional[float]
    gaps: list                   # (file sample after the gap, lost samples) of each overflow
    datetime: str
    trajectory: typing.Any = None  # the true path of nrsar:trajectory; None: the straight track
    navigation: typing.Any = None  # the path of nrsar:navigation; None: the truth
    dmrs: list = None              # nrsar:dmrs (None: no DMRS, the PRBS grid of grid_seed)
    pusch: dict = None             # nrsar:pusch of a DMRS recording (PUSCH_FIELDS)
    payload_sha256: str = None     # of a DMRS recording
    payload_path: str = None       # of a DMRS recording; None: not recorded


class _Meta:
    """Typed access to the meta's fields; every failure is one ValueError that names the
    file and the field."""

    def __init__(self, path):
        self.path = path

    def fail(self, where, text):
        raise ValueError(f"{os.path.basename(self.path)}: {where} {text}")

    def get(self, obj, key, kind, where, optional=False):
        if not isinstance(obj, dict):
            self.fail(where, "must be a JSON object")
        if key not in obj:
            self.fail(f"{where} {key}", "is missing")
        value = obj[key]
        if value is None and optional:
            return None
        name = f"{where} {key}"
        if kind is float:
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value):
                self.fail(name, f"= {value!r} must be a finite number")
            return float(value)
        if kind is int:
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not float(value).is_integer():
                self.fail(name, f"= {value!r} must be a whole number")
            return int(value)
        if not isinstance(value, kind):
            self.fail(name, f"= {value!r} must be {kind.__name__}")
        return value

    def fields(self, obj, key, names, kinds, where):
        sub = self.get(obj, key, dict, where)
        return {n: self.get(sub, n, kinds.get(n, int), f"{where} {key}") for n in names}


def _scene_of(m, glob):
    targets = m.get(glob, "nrsar:scene", list, "global")
    if not targets:
        m.fail("global nrsar:scene", "must hold at least one target")
    rows = []
    for i, t in enumerate(targets):
        where = f"global nrsar:scene[{i}]"
        rows.append(tuple(m.get(t, k, float, where) for k in ("x_m", "y_m", "rcs", "phase_deg")))
    ref = m.get(glob, "nrsar:reference_target", dict, "global")
    ref_row = tuple(m.get(ref, k, float, "global nrsar:reference_target")
                    for k in ("x_m", "y_m", "rcs", "phase_deg"))
    if ref_row != rows[0]:
        m.fail("global nrsar:reference_target", f"= {ref_row} must be the scene's first "
               f"target {rows[0]} (the metrics' reference)")
    try:
        return params.make_scene([(x, y, rcs, math.radians(ph)) for x, y, rcs, ph in rows])
    except ValueError as err:
        m.fail("global nrsar:scene", f"is invalid: {err}")


def _flight_path(m, glob, key, models, make):
    """The path the meta's key names (flight_text): None for null, a seeded model for
    'MODEL seed N', else the CSV file at that path, built by make(spec, seed). Errors name
    the key and the text."""
    text = m.get(glob, key, str, "global", optional=True)
    if text is None:
        return None
    words = text.split()
    model = len(words) == 3 and words[0] in models and words[0] != "none" \
        and words[1] == "seed" and words[2].isdigit()
    if not model and not os.path.isfile(text):
        m.fail(f"global {key}", f"= {text!r} names no readable file (nor 'MODEL seed N', MODEL "
               f"one of {', '.join(n for n in models if n != 'none')}): the flight's CSV "
               f"must stay where the recording names it")
    try:
        return make(words[0], int(words[2])) if model else make(text, 0)
    except ValueError as err:
        m.fail(f"global {key}", f"= {text!r}: {err}")


def _flight_of(m, glob, num, geo, scn, pulse_symbols):
    """(truth, navigation) of nrsar:trajectory and nrsar:navigation (None: the straight track,
    the truth), built as nrsar-sim's scenario.flight_of built them, the truth checked
    against the scene as scenario.of checks it."""
    truth = _flight_path(m, glob, "nrsar:trajectory", params.MOTIONS,
                         lambda spec, seed: params.make_trajectory(spec, geo, seed=seed))
    if truth is not None:
        try:
            params.check_scenario(num, geo, scn, truth, pulse_symbols)
        except ValueError as err:
            m.fail("global nrsar:trajectory", f"= {glob['nrsar:trajectory']!r}: {err}")
    base = truth if truth is not None else params.make_trajectory("ideal", geo)
    nav = _flight_path(m, glob, "nrsar:navigation", params.NAV_ERRORS,
                       lambda spec, seed: params.make_navigation(base, spec, seed=seed, geo=geo))
    return truth, nav


PUSCH_FIELDS = ("coding", "mcs_table", "mcs", "rv", "repetitions", "n_rnti", "n_id",
                "scrambling", "dmrs_scrambling_id", "pdu_bytes")


def _pusch_of(m, glob, num, modulation, mode):
    """(dmrs, pusch, payload SHA-256, payload path) of a PUSCH recording (nrsar:dmrs set:
    the grid is pusch_encoder's of the payload file, isac_chain.pusch_meta), or Nones. Every
    field checked against the limits of IsacOptions and pusch_config."""
    dmrs = m.get(glob, "nrsar:dmrs", list, "global", optional=True)
    if not dmrs:
        if glob.get("nrsar:pusch") is not None:
            m.fail("global nrsar:pusch", "must be null without nrsar:dmrs (a PRBS grid)")
        return None, None, None, None
    if not all(isinstance(s, int) and not isinstance(s, bool) for s in dmrs):
        m.fail("global nrsar:dmrs", f"= {dmrs!r} must be a list of whole numbers")
    if mode != "data":
        m.fail("global nrsar:mode", f"= {mode!r} must be data with nrsar:dmrs (a PUSCH grid)")
    sha = m.get(glob, "nrsar:payload_sha256", str, "global", optional=True)
    if sha is None:
        m.fail("global nrsar:payload_sha256", "is null: the grid of a DMRS recording is the "
               "PUSCH of its payload, which the recorder did not record (a radio graph's "
               "live strobe PDUs, payload 'strobe'): nrsar-process cannot regenerate it")
    if len(sha) != 64 or any(c not in "0123456789abcdef" for c in sha):
        m.fail("global nrsar:payload_sha256", f"= {sha!r} must be 64 lower-case hex digits")
    path = m.get(glob, "nrsar:payload_path", str, "global", optional=True)
    sub = m.get(glob, "nrsar:pusch", dict, "global")
    where = "global nrsar:pusch"
    p = {k: m.get(sub, k, str if k in ("coding", "mcs_table", "scrambling") else int, where,
                  optional=k == "mcs") for k in PUSCH_FIELDS}
    # the choices and limits nrsar-isac's flags of the same names have (IsacOptions)
    rules = {f.name: f.metadata for f in dataclasses.fields(IsacOptions)}
    choices = {k: rules[k]["choices"] for k in ("coding", "mcs_table", "scrambling")}
    choices["repetitions"] = IsacOptions.REPETITIONS
    for key, allowed in choices.items():
        if p[key] not in allowed:
            m.fail(f"{where} {key}", f"= {p[key]!r} must be one of "
                   f"{', '.join(str(a) for a in allowed)}")
    limits = {k: (rules[k]["at_least"], rules[k]["at_most"]) for k in ("n_rnti", "n_id")}
    limits.update({"rv": (0, 3), "dmrs_scrambling_id": (0, 65535), "pdu_bytes": (1, 65535)})
    for key, (lo, hi) in limits.items():
        if not lo <= p[key] <= hi:
            m.fail(f"{where} {key}", f"= {p[key]} must be within {lo} .. {hi}")
    if (p["mcs"] is None) != (p["coding"] == "none"):
        m.fail(f"{where} mcs", f"= {p['mcs']!r} must be null with coding none and a whole "
               f"number with nr-ldpc (coding {p['coding']!r})")
    if p["coding"] == "none" and p["repetitions"] != 1:
        m.fail(f"{where} repetitions", f"= {p['repetitions']} must be 1 with coding none")
    try:
        params.make_pusch_config(num, modulation, dmrs, p["coding"], p["mcs_table"], p["mcs"],
                                 rv=p["rv"], repetitions=p["repetitions"], n_rnti=p["n_rnti"],
                                 n_id=p["n_id"], scrambling=p["scrambling"])
        params.make_dmrs(dmrs, num, p["dmrs_scrambling_id"])
    except ValueError as err:  # the MCS's Qm against nrsar:modulation, DMRS positions, ...
        m.fail(where, f"with nrsar:dmrs {dmrs} and nrsar:modulation {modulation!r} is "
               f"invalid: {err}")
    return dmrs, p, sha, path


def read(meta_path):
    """The Recording of NAME.sigmf-meta (and NAME.sigmf-data beside it), validated: the
    SigMF core fields, the nrsar fields and their consistency, and the data file's size.
    Raises ValueError naming the file and the field."""
    m = _Meta(meta_path)
    try:
        with open(meta_path) as f:
            meta = json.load(f)
    except OSError as err:
        raise ValueError(f"{meta_path}: cannot be read: {err.strerror or err}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise ValueError(f"{os.path.basename(meta_path)}: is not JSON: {err}") from None
    if not isinstance(meta, dict):
        m.fail("the meta", "must be a JSON object with global, captures, annotations")
    glob = m.get(meta, "global", dict, "the meta's")
    datatype = m.get(glob, "core:datatype", str, "global")
    if datatype != DATATYPE:
        m.fail("global core:datatype", f"= {datatype!r} must be {DATATYPE} (the only type "
               f"nrsar-process reads)")
    version = m.get(glob, "core:version", str, "global")
    if version.split(".")[0] != SIGMF_VERSION.split(".")[0]:
        m.fail("global core:version", f"= {version!r} must be SigMF {SIGMF_VERSION}")
    for key in ("core:hw", "core:recorder"):
        m.get(glob, key, str, "global")
    channels = m.get(glob, "core:num_channels", int, "global") if "core:num_channels" in glob \
        else 1
    if channels != 1:
        m.fail("global core:num_channels", f"= {channels} must be 1")
    extensions = m.get(glob, "core:extensions", list, "global")
    if not any(isinstance(e, dict) and e.get("name") == "nrsar" for e in extensions):
        m.fail("global core:extensions", "must declare the nrsar extension")

    preset = m.get(glob, "nrsar:preset", str, "global")
    num_fields = m.fields(glob, "nrsar:numerology", NUMEROLOGY_FIELDS,
                          {"subcarrier_spacing_hz": float}, "global")
    try:
        num = params.make_numerology(preset, **num_fields)
    except ValueError as err:
        m.fail("global nrsar:numerology", f"is invalid: {err}")
    rate = m.get(glob, "core:sample_rate", float, "global")
    if not math.isclose(rate, num.sample_rate_hz(), rel_tol=1e-9):
        m.fail("global core:sample_rate", f"= {rate:g} Hz disagrees with nrsar:numerology "
               f"(fft_size x subcarrier_spacing_hz = {num.sample_rate_hz():g} Hz)")
    geo_fields = m.fields(glob, "nrsar:geometry", GEOMETRY_FIELDS,
                          {k: float for k in GEOMETRY_FIELDS}, "global")
    try:
        geo = params.make_geometry("paper", **geo_fields)
    except ValueError as err:
        m.fail("global nrsar:geometry", f"is invalid: {err}")
    modulation = m.get(glob, "nrsar:modulation", str, "global")
    if modulation not in params.MODULATIONS:
        m.fail("global nrsar:modulation", f"= {modulation!r} must be one of "
               f"{', '.join(sorted(params.MODULATIONS))}")
    from .options import MODES
    mode = m.get(glob, "nrsar:mode", str, "global")
    if mode not in MODES:
        m.fail("global nrsar:mode", f"= {mode!r} must be one of {', '.join(sorted(MODES))}")
    srs = params.make_srs(**m.fields(glob, "nrsar:srs", SRS_FIELDS, {}, "global"))
    period = MODES[mode][1]
    if period is not None and srs.period_slots != period:
        m.fail("global nrsar:srs period_slots", f"= {srs.period_slots} disagrees with "
               f"nrsar:mode {mode!r} ({period} slots)")
    try:
        if MODES[mode][0] != "data":  # a data grid carries no SRS (nr_isac_tx ignores it)
            srs.validate(num)
    except ValueError as err:
        m.fail("global nrsar:srs", f"is invalid: {err}")
    dmrs, pusch, sha, payload_path = _pusch_of(m, glob, num, modulation, mode)
    seed = m.get(glob, "nrsar:grid_seed", int, "global")
    scn = _scene_of(m, glob)
    symbols = m.get(glob, "nrsar:symbols", int, "global")
    sym_len = m.get(glob, "nrsar:symbol_samples", int, "global")
    if sym_len != num.cp_samples + num.fft_size:
        m.fail("global nrsar:symbol_samples", f"= {sym_len} must be cp_samples + fft_size = "
               f"{num.cp_samples + num.fft_size}")
    aperture = int(geo.symbols_per_aperture(num))
    if symbols != aperture:
        m.fail("global nrsar:symbols", f"= {symbols} must be the symbols of one aperture of "
               f"nrsar:geometry aperture_s ({aperture})")
    delay_s = m.get(glob, "nrsar:hardware_delay_s", float, "global")
    if delay_s < 0:
        m.fail("global nrsar:hardware_delay_s", f"= {delay_s:g} must be at least 0")
    delay = int(round(delay_s * rate))
    origin = m.get(glob, "nrsar:origin", dict, "global", optional=True)
    origin_text = None
    if origin is not None:
        origin_text = ",".join(repr(m.get(origin, k, float, "global nrsar:origin"))
                               for k in ("lat_deg", "lon_deg", "heading_deg"))
        try:
            parse_origin(origin_text, "global nrsar:origin")
        except ValueError as err:
            raise ValueError(f"{os.path.basename(meta_path)}: {err}") from None
    snr_db = m.get(glob, "nrsar:snr_db", float, "global", optional=True)
    truth, nav = _flight_of(m, glob, num, geo, scn,
                            params.symbols_per_pulse(MODES[mode][0], num, srs))

    captures = m.get(meta, "captures", list, "the meta's")
    if not captures:
        m.fail("captures", "must hold at least one capture")
    cap = captures[0]
    if m.get(cap, "core:sample_start", int, "captures[0]") != 0:
        m.fail("captures[0] core:sample_start", "must be 0")
    freq = m.get(cap, "core:frequency", float, "captures[0]")
    if not math.isclose(freq, rf_centre_hz(num, geo), abs_tol=1.0):
        m.fail("captures[0] core:frequency", f"= {freq:.0f} Hz disagrees with nrsar:geometry "
               f"carrier_hz + dc_subcarrier x spacing = {rf_centre_hz(num, geo):.0f} Hz")
    when = m.get(cap, "core:datetime", str, "captures[0]")
    if len(captures) > 1:
        m.fail("captures", f"has {len(captures)} captures: nrsar-process reads one")

    gaps = []
    for i, a in enumerate(m.get(meta, "annotations", list, "the meta's")):
        where = f"annotations[{i}]"
        start = m.get(a, "core:sample_start", int, where)
        if a.get("core:label") == "overflow":
            lost = m.get(a, "nrsar:lost_samples", int, where)
            if lost < 1:
                m.fail(f"{where} nrsar:lost_samples", f"= {lost} must be at least 1")
            if gaps and start <= gaps[-1][0]:
                m.fail(f"{where} core:sample_start", f"= {start} must follow the previous "
                       f"overflow's {gaps[-1][0]}")
            gaps.append((start, lost))
    lost_total = sum(lost for _, lost in gaps)
    aperture_end = delay + symbols * sym_len - lost_total  # file samples of the aperture
    for start, lost in gaps:
        if not delay <= start < aperture_end:
            m.fail("annotations overflow core:sample_start", f"= {start} must lie in the "
                   f"aperture's samples [{delay}, {aperture_end}) of the data file")

    data_path = meta_path[:-len(".sigmf-meta")] + ".sigmf-data"
    try:
        size = os.path.getsize(data_path)
    except OSError as err:
        raise ValueError(f"{os.path.basename(data_path)}: the data file cannot be read: "
                         f"{err.strerror or err}") from None
    if size % SAMPLE_BYTES:
        raise ValueError(f"{os.path.basename(data_path)}: {size} bytes is no whole number of "
                         f"{DATATYPE} samples ({SAMPLE_BYTES} bytes each): the last sample is "
                         f"truncated")
    samples = size // SAMPLE_BYTES
    need = aperture_end
    if samples < need:
        lost_text = f", less {lost_total} lost in overflows" if lost_total else ""
        raise ValueError(f"{os.path.basename(data_path)}: holds {samples} samples, the meta "
                         f"says {need} (nrsar:symbols {symbols} x nrsar:symbol_samples "
                         f"{sym_len} after a hardware delay of {delay}{lost_text}): the data "
                         f"file is shorter than the meta")
    return Recording(meta_path=meta_path, data_path=data_path, meta=meta, preset=preset,
                     num=num, geo=geo, scene=scn, srs=srs, modulation=modulation, mode=mode,
                     grid_seed=seed, symbols=symbols, symbol_samples=sym_len, samples=samples,
                     hardware_delay_samples=delay, origin=origin_text, snr_db=snr_db,
                     gaps=gaps, datetime=when, trajectory=truth, navigation=nav, dmrs=dmrs,
                     pusch=pusch, payload_sha256=sha, payload_path=payload_path)


def rx_time_value(t):
    """The `rx_time` tag value of t seconds, as a USRP source writes it: (uint64 whole
    seconds, double fraction)."""
    whole = math.floor(t)
    return pmt.make_tuple(pmt.from_uint64(int(whole)), pmt.from_double(t - whole))


class rx_time_stamper(gr.sync_block):
    """Passes the recorded samples through and tags them with `rx_time` where a radio's
    source would (docs/recording.md, "Gaps"): the first sample at t0, and the first sample
    after each overflow at t0 + (its file index + the samples lost so far) / fs, so that
    ofdm_demod's rx_time alignment (tx_start_time = t0) puts the lost symbols back as zeros.
    gaps: [(stream index of the first sample after the gap, lost samples)]."""

    def __init__(self, fs, gaps, t0=1.0):
        gr.sync_block.__init__(self, "rx_time_stamper", [np.complex64], [np.complex64])
        stamps, lost = {0: 0}, 0
        for index, count in gaps:
            lost += count
            stamps[index] = lost
        self.stamps = sorted((index, (t0 * fs + index + lost) / fs)
                             for index, lost in stamps.items())
        self.key = pmt.intern("rx_time")
        self.next = 0

    def work(self, input_items, output_items):
        n = len(output_items[0])
        output_items[0][:] = input_items[0][:n]
        end = self.nitems_written(0) + n
        while self.next < len(self.stamps) and self.stamps[self.next][0] < end:
            index, t = self.stamps[self.next]
            self.add_item_tag(0, index, self.key, rx_time_value(t))
            self.next += 1
        return n


class tx_underrun_counter(gr.basic_block):
    """Counts the transmitter's underruns from a UHD sink's `async_msgs` port (gr-uhd posts
    one message per async event: a dict whose `event_code` lists `underflow`,
    `underflow_in_packet`, `burst_ack`, ...; the console's `U`). An underrun sends nothing
    for a while: the radar's echo lacks those symbols while the receive stream stays whole,
    so no rx_time tag marks it (docs/recording.md, "Transmit underruns"). count(): events
    with an underflow code; times(): the first 32 events' device times [s] (None without
    a time_spec); other events are ignored."""

    UNDERFLOW = ("underflow", "underflow_in_packet")

    def __init__(self):
        gr.basic_block.__init__(self, "tx_underrun_counter", None, None)
        self.message_port_register_in(pmt.intern("async_msgs"))
        self.set_msg_handler(pmt.intern("async_msgs"), self.handle)
        self._count, self._times = 0, []

    def handle(self, msg):
        # (uhd_async_msg . {event_code: (underflow ...), time_spec: (secs . frac), channel})
        if not pmt.is_pair(msg):
            return
        try:
            events = pmt.dict_ref(pmt.cdr(msg), pmt.intern("event_code"), pmt.PMT_NIL)
            spec = pmt.dict_ref(pmt.cdr(msg), pmt.intern("time_spec"), pmt.PMT_NIL)
        except Exception:  # not gr-uhd's event dict (pmt's wrong_type): not an event
            return
        codes = []
        while pmt.is_pair(events):
            codes.append(pmt.write_string(pmt.car(events)))
            events = pmt.cdr(events)
        if not any(c in self.UNDERFLOW for c in codes):
            return
        self._count += 1
        if len(self._times) < 32:
            self._times.append(pmt.to_long(pmt.car(spec)) + pmt.to_double(pmt.cdr(spec))
                               if pmt.is_pair(spec) else None)

    def count(self):
        return self._count

    def times(self):
        return list(self._times)


class sigmf_sink(gr.sync_block):
    """A radio's receive stream recorded as SigMF (the ISAC radio graphs' `record_dir`,
    docs/recording.md): the samples go to FOLDER/NAME.sigmf-data (a temporary name until the
    flowgraph stops), the `rx_time` tags a USRP source puts on its first sample and after
    every overflow become `overflow` annotations (the samples lost: the stamp's time less
    the samples received since the first stamp), and at stop() the meta is written with the
    `nrsar` fields of opts (SimOptions or IsacOptions of the graph's radar), the hardware
    delay (samples before symbol 0's CP: the RX lead plus the TX -> RX latency), the DMRS
    positions, the backhaul payload file and its coding (pusch: nrsar:pusch,
    isac_chain.graph_pusch; with payload_path nrsar-process regenerates the grid). Without
    rx_time tags the recording has no gaps (a source that does not stamp cannot say).
    tx_underruns: the graph's tx_underrun_counter, whose count goes into the meta
    (`nrsar:tx_underruns`; null without one)."""

    def __init__(self, folder, opts, hardware_delay_s=0.0, hw="", dmrs=None,
                 payload_path=None, recorder="gr-nrsar sigmf_sink", name=DEFAULT_NAME,
                 tx_underruns=None, pusch=None):
        gr.sync_block.__init__(self, "sigmf_sink", [np.complex64], None)
        from . import scenario
        opts.validate()
        self.opts, self.sc = opts, scenario.of(opts)
        check_recordable(opts, self.sc, folder, "record_dir")
        if not (math.isfinite(hardware_delay_s) and hardware_delay_s >= 0):
            raise OptionError(f"hardware_delay_s = {hardware_delay_s!r} must be finite and "
                              f">= 0")
        self.hardware_delay_s, self.hw, self.recorder = hardware_delay_s, hw, recorder
        self.dmrs = None if dmrs is None else [int(s) for s in dmrs]
        self.payload_path, self.pusch = payload_path, pusch
        self.tx_underruns = tx_underruns
        self.fs = self.sc.num.sample_rate_hz()
        self._stack = contextlib.ExitStack()
        self.tmp, self.data_path, self.meta_path = self._stack.enter_context(
            data_file(folder, name))
        self._file = open(self.tmp, "wb")
        self.key = pmt.intern("rx_time")
        self.first = None  # (whole s, fraction) of the first stamp
        self.gaps, self.lost = [], 0
        self.started = datetime.datetime.now(datetime.timezone.utc)

    def work(self, input_items, output_items):
        x = input_items[0]
        for t in self.get_tags_in_window(0, 0, len(x), self.key):
            value = t.value
            if not (pmt.is_tuple(value) and pmt.length(value) >= 2):
                continue
            full = pmt.to_uint64(pmt.tuple_ref(value, 0)) \
                if pmt.is_uint64(pmt.tuple_ref(value, 0)) else pmt.to_long(pmt.tuple_ref(value, 0))
            frac = pmt.to_double(pmt.tuple_ref(value, 1))
            if self.first is None:
                self.first = (full, frac, t.offset)
                continue
            # samples since the first stamp by the clock, against those received
            by_clock = round(((full - self.first[0]) + (frac - self.first[1])) * self.fs)
            gap = by_clock - (t.offset - self.first[2]) - self.lost
            if gap > 0:
                self.gaps.append((int(t.offset), int(gap)))
                self.lost += gap
        x.tofile(self._file)
        return len(x)

    def stop(self):
        self._file.close()
        try:
            payload = None
            if self.payload_path:
                with open(self.payload_path, "rb") as f:
                    payload = (self.payload_path, f.read())
            meta = build_meta(
                self.opts, self.sc, self.tmp, recorder=self.recorder, hw=self.hw,
                description=f"radio recording, preset {self.opts.preset}, "
                            f"{self.opts.modulation}",
                snr_db=None, gaps=self.gaps, dmrs=self.dmrs, payload=payload, pusch=self.pusch,
                hardware_delay_s=self.hardware_delay_s, start=self.started,
                tx_underruns=None if self.tx_underruns is None else self.tx_underruns.count())
            self._stack.close()  # the data file under its name
            results.write_json(self.meta_path, meta)
        except Exception as err:  # the flowgraph stops anyway: say why there is no recording
            gr.logger("sigmf_sink").error(f"no recording written: {err}")
            self._stack.__exit__(type(err), err, None)
        return True
