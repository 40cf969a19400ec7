#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The options of the imaging chain: one typed, validated object from the command line to GRC.

Each option is a dataclass field with its type, default, allowed values and help; the
command-line parser is generated from the fields (`SimOptions.add_arguments(parser)`,
`SimOptions.from_args(namespace)`), scripts build the object directly
(`SimOptions(preset="small", target=["300,100"])`), and `validate()` checks every field and
the rules between them before any work starts. A broken rule raises OptionError (a
ValueError) whose message names the flag, the value and the limit, e.g.
`--decim = 0 must be at least 1`; the apps answer it with exit code 2.

    SimOptions    nrsar-sim: numerology, scene, filter, range / azimuth processing, outputs
    IsacOptions   nrsar-isac: SimOptions plus the backhaul (payload, DMRS, channel)
    SoakOptions   nrsar-soak: SimOptions plus the soak's duration and leak bound
    ProcessOptions nrsar-process: the receive-side fields of SimOptions (the recording
                  supplies the rest)
"""

import dataclasses
import math
import os
import tempfile
import typing

from . import params
from .nrsar_python import (geometry as geometry_type, numerology as numerology_type,
                           trajectory_autofocus_config)

# 38.211 5.2.1's c_init has 31 bits; the chain seeds the noise with seed + 1 and the
# base station's channel with seed + 2.
SEED_MAX = 2**31 - 3


class OptionError(ValueError):
    """An option broke a rule; the message names the flag, the value and the limit."""


def option(default, help, *, choices=None, at_least=None, above=None, at_most=None,
           below=None, finite=True, metavar=None, positional=False):
    """A dataclass field with what the parser and validate() need to know about it
    (positional: a word of the command line, not a flag)."""
    meta = {"help": help, "choices": choices, "at_least": at_least, "above": above,
            "at_most": at_most, "below": below, "finite": finite, "metavar": metavar,
            "positional": positional}
    if isinstance(default, list):
        return dataclasses.field(default_factory=lambda: list(default), metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def flag_of(name):
    return "--" + name.replace("_", "-")


def _base_type(annotation):
    """(python type, optional?) of a field annotation: float, Optional[int], List[str], ..."""
    if isinstance(annotation, str):
        annotation = eval(annotation, vars(typing))  # from __future__-style annotations
    origin = typing.get_origin(annotation)
    if origin is typing.Union:
        inner = [a for a in typing.get_args(annotation) if a is not type(None)]
        return _base_type(inner[0])[0], True
    if origin is list:
        return list, True
    return annotation, False


class Options:
    """Parser generation and validation shared by every options dataclass."""

    @classmethod
    def add_arguments(cls, parser):
        """Adds one flag per field (types, choices and defaults from the dataclass)."""
        hints = typing.get_type_hints(cls)
        for f in dataclasses.fields(cls):
            meta = f.metadata
            kind, optional = _base_type(hints[f.name])
            default = f.default if f.default is not dataclasses.MISSING else f.default_factory()
            help_text = meta["help"] + _limits_text(meta)
            if meta.get("positional"):
                # positional="optional": the word may be left out (its default)
                extra = {"nargs": "?", "default": default} \
                    if meta["positional"] == "optional" else {}
                parser.add_argument(f.name, metavar=meta["metavar"], help=help_text, **extra)
                continue
            if kind is bool:
                parser.add_argument(flag_of(f.name), action="store_true", help=help_text)
                continue
            kwargs = {"default": default, "help": help_text, "metavar": meta["metavar"]}
            if kind is list:
                kwargs.update(action="append", default=None)
            elif kind in (int, float):
                kwargs["type"] = kind
            if meta["choices"] is not None:
                kwargs["choices"] = list(meta["choices"])
                kwargs.pop("metavar")
            if default is not None and kind is not list:
                kwargs["help"] += " (default %(default)s)"
            parser.add_argument(flag_of(f.name), **kwargs)
        return parser

    @classmethod
    def from_args(cls, namespace):
        """The options of an argparse namespace (extra attributes, e.g. --progress, are
        ignored), validated."""
        values = {f.name: getattr(namespace, f.name) for f in dataclasses.fields(cls)
                  if hasattr(namespace, f.name)}
        opts = cls(**values)
        opts.validate()
        return opts

    @classmethod
    def parse(cls, argv, prog=None):
        """The options of command-line words, as the program would parse them, validated."""
        import argparse
        return cls.from_args(cls.add_arguments(argparse.ArgumentParser(prog=prog))
                             .parse_args(argv))

    def replace(self, **changes):
        """A copy with some fields changed, validated."""
        opts = dataclasses.replace(self, **changes)
        opts.validate()
        return opts

    def validate(self):
        """Checks every field (type, finiteness, range, choices), then the rules between
        fields (check()). Raises OptionError."""
        hints = typing.get_type_hints(type(self))
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            kind, optional = _base_type(hints[f.name])
            if value is None:
                if not optional:
                    raise OptionError(f"{flag_of(f.name)} must be given")
                continue
            setattr(self, f.name, _checked(f.name, value, kind, f.metadata))
        self.check()
        return self

    def check(self):
        """Rules between fields (subclasses extend it)."""


def _limits_text(meta):
    parts = []
    for key, word in (("at_least", ">="), ("above", ">"), ("at_most", "<="), ("below", "<")):
        if meta[key] is not None:
            parts.append(f"{word} {_number(meta[key])}")
    return f"; {', '.join(parts)}" if parts else ""


def _number(value):
    return str(value) if isinstance(value, int) else f"{value:g}"


def _checked(name, value, kind, meta):
    """value converted to kind and checked against meta's rules (OptionError otherwise)."""
    flag = flag_of(name)
    if kind is bool:
        if not isinstance(value, bool):
            raise OptionError(f"{flag} = {value!r} must be true or false")
        return value
    if kind is list:
        if isinstance(value, str) or not all(isinstance(v, str) for v in value):
            raise OptionError(f"{flag} = {value!r} must be a list of strings")
        return list(value)
    if kind in (int, float):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise OptionError(f"{flag} = {value!r} must be a number")
        if kind is int:
            if isinstance(value, float) and not value.is_integer():
                raise OptionError(f"{flag} = {value!r} must be a whole number")
            value = int(value)
        else:
            value = float(value)
            if meta["finite"] and not math.isfinite(value):
                raise OptionError(f"{flag} = {value} must be finite")
            if math.isnan(value):
                raise OptionError(f"{flag} = nan must be a number")
        rules = (("at_least", lambda v, b: v >= b, "must be at least"),
                 ("above", lambda v, b: v > b, "must be above"),
                 ("at_most", lambda v, b: v <= b, "must be at most"),
                 ("below", lambda v, b: v < b, "must be below"))
        for key, ok, words in rules:
            if meta[key] is not None and not ok(value, meta[key]):
                raise OptionError(f"{flag} = {_number(value)} {words} {_number(meta[key])}")
    elif not isinstance(value, str):
        raise OptionError(f"{flag} = {value!r} must be text")
    if meta["choices"] is not None and value not in meta["choices"]:
        raise OptionError(f"{flag} = {value!r} must be one of {', '.join(meta['choices'])}")
    return value


def read_bytes(path, name, why=""):
    """The bytes of the file `path`, given as `name` (a flag or a meta field): OptionError
    naming it, the path, the reason and `why` when it cannot be read."""
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as err:
        raise OptionError(f"{name} = {path!r} cannot be read ({err.strerror or err}){why}") \
            from None


def check_out_dir(path, flag="--out"):
    """Creates the output folder and proves it writable with a scratch file, before any
    work starts (a root process passes os.access() everywhere, so only a write tells)."""
    if os.path.exists(path) and not os.path.isdir(path):
        raise OptionError(f"{flag} = {path!r} is a file, not a folder")
    try:
        os.makedirs(path, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path, prefix=".nrsar-write-test-"):
            pass
    except OSError as err:
        raise OptionError(f"{flag} = {path!r} is not a writable folder: "
                          f"{err.strerror or err}") from None
    return path


def check_names(flag, text, allowed):
    """A comma-separated list of names, each one of `allowed` (OptionError naming the first
    that is not); returns the names in the given order."""
    names = [n.strip() for n in str(text).split(",") if n.strip()]
    if not names:
        raise OptionError(f"{flag} = {text!r} names nothing: give some of {', '.join(allowed)}")
    for n in names:
        if n not in allowed:
            raise OptionError(f"{flag} = {text!r}: {n!r} is not one of {', '.join(allowed)}")
    return names


# UTM is defined from 80 deg S to 84 deg N (the polar caps use UPS, which geo.py does not
# write).
UTM_LAT_RANGE = (-80.0, 84.0)


def parse_origin(text, flag="--origin"):
    """'LAT,LON,HEADING_DEG' -> (lat, lon, heading) in degrees, each checked: latitude within
    UTM's [-80, 84], longitude within [-180, 180], heading within [0, 360)."""
    parts = [p.strip() for p in str(text).split(",")]
    if len(parts) != 3:
        raise OptionError(f"{flag} = {text!r} must be LAT,LON,HEADING_DEG (3 numbers, "
                          f"got {len(parts)})")
    names = ("latitude", "longitude", "heading")
    values = []
    for name, part in zip(names, parts):
        try:
            v = float(part)
        except ValueError:
            raise OptionError(f"{flag} = {text!r}: {name} {part!r} is not a number") from None
        if not math.isfinite(v):
            raise OptionError(f"{flag} = {text!r}: {name} = {part} must be finite")
        values.append(v)
    lat, lon, heading = values
    if not UTM_LAT_RANGE[0] <= lat <= UTM_LAT_RANGE[1]:
        raise OptionError(f"{flag} = {text!r}: latitude = {lat:g} must be within "
                          f"[{UTM_LAT_RANGE[0]:g}, {UTM_LAT_RANGE[1]:g}] (UTM)")
    if not -180.0 <= lon <= 180.0:
        raise OptionError(f"{flag} = {text!r}: longitude = {lon:g} must be within [-180, 180]")
    if not 0.0 <= heading < 360.0:
        raise OptionError(f"{flag} = {text!r}: heading = {heading:g} must be within [0, 360)")
    return lat, lon, heading


MAX_GCP = trajectory_autofocus_config.max_gcp  # the kernel's bound


def parse_gcps(texts, flag="--autofocus-gcp"):
    """['X,Y[,Z]', ...] (metres, scene frame; Z default 0) -> [(x, y, z)]: numbers, finite,
    at most MAX_GCP of them."""
    texts = texts or []
    if len(texts) > MAX_GCP:
        raise OptionError(f"{flag} given {len(texts)} times must be given at most {MAX_GCP} "
                          f"times")
    points = []
    for text in texts:
        parts = [p.strip() for p in str(text).split(",")]
        if len(parts) not in (2, 3):
            raise OptionError(f"{flag} = {text!r} must be X,Y[,Z] (2 or 3 numbers, got "
                              f"{len(parts)})")
        try:
            values = [float(p) for p in parts]
        except ValueError:
            raise OptionError(f"{flag} = {text!r} must be X,Y[,Z] in metres (numbers)") from None
        if not all(map(math.isfinite, values)):
            raise OptionError(f"{flag} = {text!r} must be finite")
        points.append(tuple(values + [0.0] * (3 - len(values))))
    return points


def check_map_options(opts):
    """The rules of --origin and --geotiff (SimOptions and ProcessOptions)."""
    if opts.origin is not None:
        parse_origin(opts.origin)
    if opts.geotiff and opts.images == "none":
        raise OptionError("--geotiff needs the image: --images = 'none' keeps none")
    if getattr(opts, "record", None) is not None and not opts.record.strip():
        raise OptionError("--record = '' must name a folder")
    if getattr(opts, "record_gap", None):
        if opts.record is None:
            raise OptionError(f"--record-gap = {opts.record_gap[0]!r} needs --record DIR")
        parse_gaps(opts.record_gap)


def parse_gaps(texts):
    """['SAMPLE:COUNT', ...] -> sorted [(sample, count)] of non-overlapping gaps."""
    gaps = []
    for text in texts:
        try:
            sample, count = (int(w) for w in text.split(":"))
        except ValueError:
            raise OptionError(f"--record-gap = {text!r} must be SAMPLE:COUNT (whole "
                              f"numbers)") from None
        if sample < 0 or count < 1:
            raise OptionError(f"--record-gap = {text!r} needs SAMPLE >= 0 and COUNT >= 1")
        gaps.append((sample, count))
    gaps.sort()
    for (s0, c0), (s1, _) in zip(gaps, gaps[1:]):
        if s1 <= s0 + c0:
            raise OptionError(f"--record-gap = '{s1}:...' must start after the gap "
                              f"'{s0}:{c0}' ends (gaps are separated by received samples)")
    return gaps


def check_flight_options(opts):
    """The rules of --trajectory / --motion and --nav / --nav-error (the files' contents are
    checked when the scenario is built, still before any block)."""
    for path_flag, model_flag in (("trajectory", "motion"), ("nav", "nav_error")):
        path, model = getattr(opts, path_flag), getattr(opts, model_flag)
        if path is None:
            continue
        if model != "none":
            raise OptionError(f"{flag_of(path_flag)} = {path!r} and {flag_of(model_flag)} = "
                              f"{model!r} both name the path: give one")
        if not os.path.isfile(path):
            raise OptionError(f"{flag_of(path_flag)} = {path!r} is not a readable file")


def check_split(opts):
    """The rules of --split zmq: the address is tcp://HOST:PORT (loopback unless
    --split-bind-any) or ipc://PATH, the key file readable."""
    addr = opts.split_address
    if addr.startswith("ipc://") and len(addr) > len("ipc://"):
        pass
    elif addr.startswith("tcp://") and ":" in addr[len("tcp://"):]:
        host, _, port = addr[len("tcp://"):].rpartition(":")
        if port != "*" and not (port.isdigit() and 1 <= int(port) <= 65535):
            raise OptionError(f"--split-address = {addr!r}: port {port!r} must be * or "
                              f"1..65535")
        if host.strip("[]") in ("*", "0.0.0.0", "::", "") and not opts.split_bind_any:
            raise OptionError(f"--split-address = {addr!r} binds every interface: give a "
                              f"host address (default 127.0.0.1) or --split-bind-any")
    else:
        raise OptionError(f"--split-address = {addr!r} must be tcp://HOST:PORT or "
                          f"ipc://PATH")
    if opts.split_key is not None:
        from . import link
        link.read_key(opts.split_key)
    if opts.record is not None:
        raise OptionError("--record with --split zmq: record in a one-graph run")


# The pulse modes of the transmit grid: (tx mode, SRS period in slots)
MODES = {"data": ("data", None), "srs2": ("srs", 2), "srs20": ("srs", 20)}

# --presum choices (cheby_presum's methods; none = no presummer)
PRESUM = ("none",) + tuple(params.PRESUM_METHODS)

# Presumming factor when --presum is given without --decim
DEFAULT_DECIM = 10


@dataclasses.dataclass
class SimOptions(Options):
    """Options of one run of the imaging chain (nrsar-sim, and the base of the others)."""
    preset: str = option("paper", "OFDM numerology preset: paper = 3333 x 30 kHz, 24 kHz PRF; "
                         "small = 512 subcarriers; tiny = 64 (tests); nr273; sdr20",
                         choices=list(numerology_type.preset_names()))
    geometry: str = option("paper", "platform preset (fc 3.5 GHz, v 50 m/s, H 1000 m; short: "
                           "0.1 s)", choices=list(geometry_type.preset_names()))
    aperture_s: typing.Optional[float] = option(
        None, "slow-time span to simulate [s] (default: the geometry's, 2 s)", above=0.0,
        at_most=3600.0)
    scene: str = option("paper3", "point targets: a preset (paper3, single), "
                        "'X,Y[,RCS[,PHASE_DEG]];...' in metres, or a YAML scene file (maps, "
                        "speckle, beam; see nrsar.scenes)")
    target: typing.Optional[typing.List[str]] = option(
        None, "add a point target (ground range X, along-track Y in metres, RCS linear "
        "power, phase in degrees); repeatable, replaces --scene; the first is the reference "
        "target", metavar="X,Y[,RCS[,PHASE_DEG]]")
    filter: str = option("wf", "per-RE filter: rf = 1/s, mf = conj(s), wf = Wiener (eq. 25)",
                         choices=sorted(params.FILTERS))
    snr_db: float = option(-20.0, "input SNR per RE: sum of RCS powers / noise power [dB]",
                           at_least=-200.0, at_most=300.0)
    estimate_snr: bool = option(False, "let the Wiener filter estimate SNR_in from the data")
    modulation: str = option("qam256", "constellation of the data REs (38.211 Gray mapping, "
                             "unit power)", choices=sorted(params.MODULATIONS))
    mode: str = option("data", "data = every RE (data-aided); srs2 / srs20 = SRS pilot only, "
                       "one comb-4 symbol every 2 / 20 slots", choices=sorted(MODES))
    fft_size: str = option("fast", "range IFFT size: 'fast' (next fast size >= N), 'exact' "
                           "(N) or a number >= N")
    band: str = option("scene", "azimuth processing band: the scene's Doppler band from the "
                       "geometry, estimated from the data, or the full PRF",
                       choices=list(params.DOPPLER_BANDS))
    focuser: str = option("rd", "image former, both branches: rd = range-Doppler (rd_focuser), "
                          "bp = time-domain back-projection along the navigation (bp_focuser), "
                          "ffbp = its fast factorized form", choices=["rd", "bp", "ffbp"])
    moco: str = option("on", "rd_focuser's motion compensation from the navigation (first and "
                       "second order, docs/flight.md); a no-op on the ideal line, so 'on' "
                       "changes no ideal-line output; 'resample': 'on' after resampling the "
                       "pulses onto a uniform along-track grid", choices=["on", "off", "resample"])
    ffbp_subaperture: int = option(32, "--focuser ffbp: pulses per subaperture (the speed-up "
                                   "approaches it)", at_least=2, at_most=65536)
    ffbp_beams: float = option(8.0, "--focuser ffbp: beams per Nyquist beam of a subaperture "
                               "(error power pi^4 / (600 x^4))", at_least=1.0, at_most=64.0)
    ffbp_levels: int = option(1, "--focuser ffbp: polar levels (1: two-level; n > 1: the "
                              "subimages merged --ffbp-merge-factor at a time n - 1 times, "
                              "recursive FFBP: faster on long apertures, each level one more "
                              "interpolation's error)", at_least=1, at_most=8)
    ffbp_merge_factor: int = option(4, "--focuser ffbp with --ffbp-levels > 1: subimages per "
                                    "merged subimage", at_least=2, at_most=16)
    bp_line_step: int = option(1, "--focuser bp/ffbp: an image line every this many pulse "
                               "positions along track (1: one per pulse, rd_focuser's grid); "
                               "must divide the pulses per aperture, and the line rate PRF / "
                               "(D L) must cover the scene's Doppler band; the azimuth "
                               "resolution v / B_doppler needs about v / (2 B_doppler) per line "
                               "(docs/blocks/bp_focuser.md, \"Real time\")",
                               at_least=1, at_most=4096)
    image_grid: str = option("slant", "bp/ffbp image grid: slant = slant range x along track "
                             "(rd_focuser's), ground = ground range x along track on the "
                             "scene's plane", choices=["slant", "ground"])
    autofocus: str = option("none", "autofocus of the data branch's image after the focuser "
                            "(the reference branch stays the calibration standard): pga = "
                            "phase gradient, entropy = minimum image entropy, trajectory = "
                            "bp/ffbp: the navigation corrected from the prominent points' "
                            "phase histories and the aperture back-projected again",
                            choices=list(params.AUTOFOCUS_METHODS) + ["trajectory"])
    autofocus_iterations: int = option(4, "--autofocus trajectory: back-projections that "
                                       "estimate, at most", at_least=1, at_most=50)
    autofocus_points: int = option(8, "--autofocus trajectory: prominent points whose phase "
                                   "histories it reads", at_least=1, at_most=64)
    autofocus_tolerance_m: float = option(1e-4, "--autofocus trajectory: stop when an "
                                          "iteration's correction is below this rms [m]",
                                          above=0.0, below=1.0)
    autofocus_significance: float = option(2.0, "--autofocus trajectory: keep the path's "
                                           "correction only when its rms exceeds this many "
                                           "standard errors of the phase histories' noise "
                                           "(0: always)", at_least=0.0, at_most=100.0)
    autofocus_gcp: typing.Optional[typing.List[str]] = option(
        None, "--autofocus trajectory: a ground control point (a surveyed corner reflector) "
        f"at X, Y[, Z] in the scene frame [m] inside the image; repeatable, at most {MAX_GCP}: "
        "they fix the navigation error's constant and drift, which focus cannot see (JSON "
        "autofocus_gcp_*; docs/blocks/bp_focuser.md)", metavar="X,Y[,Z]")
    autofocus_gcp_along_track_se_m: float = option(
        0.05, "--autofocus-gcp: solve the navigation's along-track offset e_y when GCPs spread "
        "along track predict its standard error below this [m] (0: never; docs/blocks/"
        "bp_focuser.md, \"Solving e_y\")", at_least=0.0, at_most=1.0)
    autofocus_gcp_speed_se_mps: float = option(
        0.02, "--autofocus-gcp: solve the navigation's along-track speed error d_y when GCPs "
        "spread along track predict its standard error below this [m/s] (0: never; docs/"
        "blocks/bp_focuser.md, \"The along-track speed\")", at_least=0.0, at_most=1.0)
    rcmc_taps: int = option(16, "length of the windowed-sinc RCMC interpolator, eq. (41)",
                            at_least=2, at_most=256)
    range_margin_m: float = option(30.0, "slant range kept on each side of the scene's swath "
                                   "[m] (at least 16 range bins; the chain crops the RCMC's "
                                   "reach wider and the focuser drops it again)",
                                   at_least=0.0, at_most=1e5)
    presum: str = option("none", "azimuth presummer after the range IFFT (cheby_presum), "
                         "both branches", choices=list(PRESUM))
    decim: typing.Optional[int] = option(
        None, f"presumming factor D (pulses per output pulse; needs --presum; default "
        f"{DEFAULT_DECIM})", at_least=1, at_most=4096)
    presum_domain: str = option("range", "presum after the range IFFT (range) or before it "
                                "(tf: saves D-1 of every D IFFTs)",
                                choices=list(params.PRESUM_DOMAINS))
    range_crop: str = option("on", "crop the range-compressed data to the scene's swath +- "
                             "margin (off: keep every IFFT bin)", choices=["on", "off"])
    images: str = option("keep", "keep the range-compressed data and the image in memory and "
                         "write .npy/.png (keep), or send them to null sinks (none: metrics "
                         "only, the memory of a streaming receiver)", choices=["keep", "none"])
    cm_path: str = option("on", "tf_filter's constant-modulus shortcut (PSK/QPSK data: "
                          "g = c conj(s))", choices=["on", "off"])
    filter_threads: int = option(1, "threads per tf_filter work() call", at_least=1,
                                 at_most=2)
    rx_fuse: str = option("on", "range_compress (tf_filter and range_ifft in one pass, the "
                          "same output) where the chain allows it: full-rate pulses, presum "
                          "after the IFFT, one filter thread (off: the two blocks)",
                          choices=["on", "off"])
    seed: int = option(1, "seed of the data PRBS (31-bit c_init) and the noise (seed + 1)",
                       at_least=0, at_most=SEED_MAX)
    trajectory: typing.Optional[str] = option(
        None, "the true flight path the echo flies: a CSV file t_s,x_m,y_m,z_m[,roll_rad,"
        "pitch_rad,yaw_rad] (SPEC 3 frame, t = 0 at the first symbol, 10 Hz or more, covering "
        "the aperture; attitude steers the beam of a scene file); replaces --motion",
        metavar="FILE")
    motion: str = option("none", "the true flight path: the ideal line (none) or a seeded "
                         "motion model added to it (calm: cm, gusty: dm; docs/flight.md)",
                         choices=list(params.MOTIONS))
    motion_seed: int = option(0, "seed of --motion (and of --nav-error: motion seed + 1)",
                              at_least=0, at_most=SEED_MAX)
    nav: typing.Optional[str] = option(
        None, "what the UAV believes (the processing's path): a CSV file like --trajectory; "
        "replaces --nav-error", metavar="FILE")
    nav_error: str = option("none", "navigation = the true path plus a seeded measurement "
                            "error: none, rtk (cm) or gnss (dm; docs/flight.md)",
                            choices=list(params.NAV_ERRORS))
    out: str = option("nrsar-out", "output folder (created; checked writable before the run)")
    json: bool = option(False, "print one JSON object on stdout")
    record: typing.Optional[str] = option(
        None, "also write the recording a radio would have made of the flight into this "
        "folder: the time-domain echo (ofdm_mod -> td_echo, with noise) as SigMF "
        "flight.sigmf-data / flight.sigmf-meta (docs/recording.md; point targets only)",
        metavar="DIR")
    record_gap: typing.Optional[typing.List[str]] = option(
        None, "with --record: an overflow the recording suffers, COUNT samples lost from "
        "sample SAMPLE of the flight on (repeat the flag for more gaps; SigMF annotations)",
        metavar="SAMPLE:COUNT")
    geotiff: bool = option(False, "also write the focused image as GeoTIFFs (power in dB, "
                           "complex) in the UTM zone of --origin (docs/recording.md)")
    geotiff_grid: str = option("ground", "pixel grid of the GeoTIFF: ground range "
                               "sqrt(r^2 - H^2) resampled to a regular grid, or the slant "
                               "range bins as they are", choices=["ground", "slant"])
    origin: typing.Optional[str] = option(
        None, "the frame's origin on the map: latitude, longitude [deg, WGS 84] of the ground "
        "point below the track at y = 0 and the heading of the flight [deg clockwise from "
        "true north]; the scene (x > 0) lies to the right of the heading",
        metavar="LAT,LON,HEADING_DEG")
    # The UAV / ground split over gr-zeromq (docs/scale.md; python/nrsar/split.py)
    split: str = option("none", "run the chain as two processes, the UAV's graph (up to the "
                        "cut) and the ground's (the focuser), joined by gr-zeromq; each line "
                        "signed with --split-key and numbered", choices=["none", "zmq"])
    split_at: str = option("presum", "where the chain is cut: after the presummer (the "
                           "reduced stream; range when there is none) or after the range "
                           "IFFT", choices=["presum", "range"])
    split_pattern: str = option("push", "gr-zeromq pattern: push (PUSH/PULL, one ground) or "
                                "pub (PUB/SUB, several grounds may listen)",
                                choices=["push", "pub"])
    split_address: str = option("tcp://127.0.0.1:*", "address the UAV binds (the ground "
                                "connects): loopback by default, port * = any free one; "
                                "all interfaces (*, 0.0.0.0, ::) only with --split-bind-any")
    split_bind_any: bool = option(False, "allow --split-address on all interfaces (anyone who "
                                  "reaches the port may connect: the key check rejects "
                                  "their lines, it does not hide ours)")
    split_key: typing.Optional[str] = option(
        None, "shared key file of the link (>= 32 bytes, mode 0600); default: a random key "
        "for this run, shared by its two processes", metavar="FILE")
    split_queue_lines: int = option(1024, "UAV link queue [lines]: when full, new lines are "
                                    "dropped and counted (the radio path never waits; "
                                    "without --split-line-rate the simulation waits up to "
                                    "--split-idle-s first)",
                                    at_least=1, at_most=10**6)
    split_hwm: int = option(16, "ZMQ high-water mark of each side [messages]", at_least=1,
                            at_most=10**6)
    split_idle_s: float = option(10.0, "the ground ends the stream (zero-filled) after this "
                                 "long without a valid line, the UAV closes its link this "
                                 "long after its last line [s]", above=0.0, at_most=3600.0)
    split_line_rate: float = option(0.0, "UAV lines per second at the cut (throttle; 0 = as "
                                    "fast as the CPU: a simulation has no radio clock)",
                                    at_least=0.0, at_most=1e9)

    def check(self):
        check_map_options(self)
        check_flight_options(self)
        if self.geotiff and self.origin is None:
            raise OptionError("--geotiff needs --origin LAT,LON,HEADING_DEG (where the frame "
                              "lies on the map)")
        self.check_processing()
        if self.split != "none":
            check_split(self)

    def check_processing(self):
        """The rules between the receive-side fields (ProcessOptions keeps them too)."""
        if self.decim is not None and self.presum == "none":
            raise OptionError(f"--decim = {self.decim} needs a presummer: give --presum "
                              f"({', '.join(PRESUM[1:])}), or leave --decim out")
        text = self.fft_size.strip().lower()
        if text not in ("fast", "exact"):
            try:
                size = int(text)
            except ValueError:
                raise OptionError(f"--fft-size = {self.fft_size!r} must be 'fast', 'exact' "
                                  f"or a whole number") from None
            if size < 1:
                raise OptionError(f"--fft-size = {size} must be at least 1")
        if not self.out.strip():
            raise OptionError("--out = '' must name a folder")
        if self.image_grid != "slant" and self.focuser == "rd":
            raise OptionError(f"--image-grid = {self.image_grid!r} needs --focuser bp or ffbp "
                              f"(rd_focuser images slant range)")
        if self.bp_line_step != 1 and self.focuser == "rd":
            raise OptionError(f"--bp-line-step = {self.bp_line_step} needs --focuser bp or "
                              f"ffbp (rd_focuser images one line per pulse)")
        if self.bp_line_step != 1 and self.autofocus == "trajectory":
            raise OptionError(f"--bp-line-step = {self.bp_line_step} with --autofocus "
                              f"trajectory: it estimates the path on one image line per pulse "
                              f"(use --bp-line-step 1)")
        if self.ffbp_levels != 1 and self.focuser != "ffbp":
            raise OptionError(f"--ffbp-levels = {self.ffbp_levels} needs --focuser ffbp")
        if self.autofocus == "trajectory" and self.focuser == "rd":
            raise OptionError("--autofocus = 'trajectory' needs --focuser bp or ffbp (it "
                              "back-projects along the corrected path)")
        if self.autofocus_gcp and self.autofocus != "trajectory":
            raise OptionError(f"--autofocus-gcp = {self.autofocus_gcp[0]!r} needs --autofocus "
                              f"trajectory")
        parse_gcps(self.autofocus_gcp)

    def presum_factor(self):
        """D of the presummer (1 without one)."""
        if self.presum == "none":
            return 1
        return self.decim if self.decim is not None else DEFAULT_DECIM


DEFAULT_TAPS = "1,0,0,0.3+0.2j,0,0,0,0,-0.1j"


@dataclasses.dataclass
class IsacOptions(SimOptions):
    """nrsar-isac: the imaging chain's options plus the backhaul's."""
    # --repetitions' values: pusch-AggregationFactor of 38.214 6.1.2.1 (not a field)
    REPETITIONS = (1, 2, 4, 8)
    payload: str = option("/usr/share/common-licenses/GPL-3", "file sent over the backhaul")
    dmrs: str = option("pusch2", "PUSCH DMRS layout: pusch1, pusch2, pusch4 or 'l0,l1,..'")
    coding: str = option("nr-ldpc", "channel coding of the uplink: the UL-SCH of TS 38.212 "
                         "(CRC, LDPC, rate matching) or none (CRC24A, hard decisions)",
                         choices=["nr-ldpc", "none"])
    mcs_table: str = option("qam256", "MCS table of TS 38.214 (Table 5.1.3.1-1 qam64, -2 "
                            "qam256)", choices=["qam64", "qam256"])
    mcs: typing.Optional[int] = option(None, "MCS index of --mcs-table; its Qm must be "
                                       "--modulation's (default: the highest such MCS, "
                                       "qam256 -> 27, R 0.93)", at_least=0, at_most=28)
    n_rnti: int = option(0x4601, "C-RNTI of the UAV: c_init = n_RNTI 2^15 + n_ID "
                         "(38.211 6.3.1.1)", at_least=0, at_most=65535)
    n_id: int = option(0, "data scrambling identity n_ID", at_least=0, at_most=1023)
    scrambling: str = option("standard", "data scrambling: standard (38.211, the same every "
                             "slot) or per-slot (the module's: a fresh sequence every slot, "
                             "no slot-periodic radar reference)",
                             choices=["standard", "per-slot"])
    repetitions: int = option(1, "slots per TB (pusch-AggregationFactor: rv 0, 2, 3, 1, "
                              "combined at the base station): 1, 2, 4 or 8", at_least=1,
                              at_most=8)
    bs_snr_db: float = option(50.0, "per-RE SNR at the base station [dB] (taps normalised to "
                              "unit energy)", at_least=-50.0, at_most=200.0)
    cfo_hz: float = option(9000.0, "carrier frequency offset UAV -> base station [Hz]; "
                           "ofdm_sync estimates |CFO| < Delta f (30 kHz at paper)")
    delay_samples: int = option(1234, "timing offset before the burst [samples]",
                                at_least=0, at_most=10**9)
    taps: str = option(DEFAULT_TAPS, "multipath taps of the channel, comma-separated complex "
                       "at the sample rate, normalised to unit energy ('1' = flat)")
    radar_domain: str = option("time", "radar echo through ofdm_mod -> td_echo -> ofdm_demod "
                               "(time) or scene_echo on the grid (tf)", choices=["time", "tf"])
    echo_taps: int = option(32, "td_echo fractional-delay FIR length", at_least=2,
                            at_most=1024)
    rx_threads: int = option(1, "pusch_receiver threads per slot (1, or 2: the code blocks "
                             "decoded on two); at most the machine's cores", at_least=1,
                             at_most=2)

    def check(self):
        super().check()
        if self.record is not None and self.radar_domain != "time":
            raise OptionError(f"--record = {self.record!r} needs --radar-domain time (the "
                              f"recording is the time-domain echo)")
        if self.split != "none":
            raise OptionError(f"--split = {self.split!r} is nrsar-sim's (nrsar-isac runs one "
                              f"graph)")
        if self.mode != "data":
            raise OptionError(f"--mode = {self.mode!r} must be data (the grid is the PUSCH)")
        if not os.path.isfile(self.payload):
            raise OptionError(f"--payload = {self.payload!r} is not a readable file")
        parse_taps(self.taps)
        params.make_dmrs(self.dmrs)
        self.check_coding()
        cores = os.cpu_count() or 1
        if self.rx_threads > cores:
            raise OptionError(f"--rx-threads = {self.rx_threads} must be at most the {cores} "
                              f"CPU cores of this machine")

    def check_coding(self):
        """The MCS against its table and --modulation; --repetitions needs the LDPC."""
        if self.repetitions not in self.REPETITIONS:
            raise OptionError(f"--repetitions = {self.repetitions} must be 1, 2, 4 or 8 "
                              f"(pusch-AggregationFactor of 38.214 6.1.2.1)")
        if self.coding == "none":
            if self.mcs is not None:
                raise OptionError(f"--mcs = {self.mcs} needs --coding nr-ldpc")
            if self.repetitions != 1:
                raise OptionError(f"--repetitions = {self.repetitions} needs --coding nr-ldpc "
                                  f"(the base station combines soft bits)")
            return
        if self.modulation not in params.QAM_BITS:
            raise OptionError(f"--modulation = {self.modulation!r} must be qpsk, qam16, qam64 "
                              f"or qam256 with --coding nr-ldpc")
        if self.mcs is None:
            return
        rows = 28 if self.mcs_table == "qam256" else 29
        if self.mcs >= rows:
            raise OptionError(f"--mcs = {self.mcs} must be at most {rows - 1} in --mcs-table "
                              f"{self.mcs_table} (38.214 Table 5.1.3.1-{1 if rows == 29 else 2}; "
                              f"the rows above are reserved)")
        qm = params.nr_mcs(self.mcs_table, self.mcs)[0]
        if qm != params.QAM_BITS[self.modulation]:
            raise OptionError(f"--mcs = {self.mcs} of --mcs-table {self.mcs_table} has Qm = {qm}, "
                              f"--modulation {self.modulation} has "
                              f"{params.QAM_BITS[self.modulation]} bits per symbol")

    def pusch_config(self, num, max_queued_bytes=1 << 20):
        """The pusch_config of the backhaul (pusch_encoder and pusch_receiver)."""
        return params.make_pusch_config(
            num, self.modulation, params.make_dmrs(self.dmrs, num), self.coding,
            self.mcs_table, self.mcs, n_rnti=self.n_rnti, n_id=self.n_id,
            scrambling=self.scrambling, repetitions=self.repetitions,
            max_queued_bytes=max_queued_bytes)


def parse_taps(text):
    """'1,0,0.3+0.2j' -> taps normalised to unit energy (OptionError names --taps)."""
    import numpy as np
    try:
        taps = np.array([complex(t.replace(" ", "")) for t in text.split(",") if t.strip()],
                        np.complex128)
    except ValueError:
        raise OptionError(f"--taps = {text!r} must be comma-separated complex numbers "
                          f"like 1,0.3+0.2j") from None
    energy = float(np.sum(np.abs(taps) ** 2))
    if taps.size == 0 or not math.isfinite(energy) or energy == 0:
        raise OptionError(f"--taps = {text!r} must hold at least one finite non-zero tap")
    return [complex(t) for t in taps / math.sqrt(energy)]


@dataclasses.dataclass
class SoakOptions(SimOptions):
    """nrsar-soak: a long stream through the chain, RSS sampled; presums by default."""
    presum: str = option("cheby", "azimuth presummer after the range IFFT (cheby_presum), "
                         "both branches", choices=list(PRESUM))
    images: str = option("none", "keep (write) the images or not; a streaming receiver keeps "
                         "none", choices=["keep", "none"])
    out: str = option("nrsar-soak-out", "output folder (created; checked writable first)")
    minutes: float = option(10.0, "radar time to stream [min]", above=0.0, at_most=10080.0)
    interval_s: float = option(2.0, "wall time between RSS samples [s]", above=0.0,
                               at_most=3600.0)
    warmup: float = option(0.25, "fraction of the radar time excluded from the fit (buffers, "
                           "FFT plans, allocator arenas fill first); at least 2 apertures",
                           at_least=0.0, below=1.0)
    max_slope_mb_per_min: float = option(2.0, "largest RSS slope accepted [MiB per minute of "
                                         "radar time]", at_least=0.0)

    def check(self):
        super().check()
        if self.images != "none":
            raise OptionError(f"--images = {self.images!r} must be none: a soak streams "
                              f"without end, and kept images would grow with it")
        if self.record is not None:
            raise OptionError("--record is nrsar-sim's: a soak streams without end")
        for path, model in (("trajectory", "motion"), ("nav", "nav_error")):
            if getattr(self, path) is not None or getattr(self, model) != "none":
                raise OptionError(f"{flag_of(path)} / {flag_of(model)}: a soak streams "
                                  f"without end, a flight path covers one aperture")
        if self.split != "none":
            raise OptionError("--split is nrsar-sim's: a soak measures one process")


# The fields of SimOptions a recording supplies (docs/recording.md): nrsar-process takes the
# numerology, geometry, scene, grid and seed from the meta, never from flags.
RECORDED_FIELDS = ("preset", "geometry", "aperture_s", "scene", "target", "snr_db",
                   "modulation", "mode", "seed", "record", "trajectory", "motion",
                   "motion_seed", "nav", "nav_error", "record_gap")


class _ProcessRules(Options):
    """Rules of ProcessOptions: SimOptions' own between its receive-side fields."""

    def check(self):
        if self.dask_make_certs is not None:
            check_certificate_folder(self.dask_make_certs)
            if self.recording or self.dask is not None or self.strip_aperture_s is not None:
                raise OptionError(f"--dask-make-certs = {self.dask_make_certs!r} only writes "
                                  f"the set: give it alone (no RECORDING, --dask, "
                                  f"--strip-aperture-s)")
            return
        if not self.recording.endswith(".sigmf-meta"):
            raise OptionError(f"RECORDING = {self.recording!r} must name a .sigmf-meta file")
        check_map_options(self)
        SimOptions.check_processing(self)
        if self.dask is not None:
            check_dask(self)
        if self.bp_line_step != 1 and self.strip_aperture_s is not None:
            raise OptionError(f"--bp-line-step = {self.bp_line_step} with --strip-aperture-s: "
                              f"the strip's tasks stitch one image line per pulse (use "
                              f"--bp-line-step 1)")
        if self.strip_overlap_s is not None and self.strip_aperture_s is None:
            raise OptionError(f"--strip-overlap-s = {self.strip_overlap_s:g} needs "
                              f"--strip-aperture-s (the strip it overlaps)")

    def presum_factor(self):
        return SimOptions.presum_factor(self)


CERTIFICATES = ("ca.pem", "cert.pem", "key.pem")


def check_certificate_folder(folder, flag="--dask-make-certs"):
    """OptionError unless folder can take a new set: a folder (or a new one) holding none
    of CERTIFICATES (a set is never overwritten: its cluster would lose its clients)."""
    if not folder.strip() or (os.path.exists(folder) and not os.path.isdir(folder)):
        raise OptionError(f"{flag} = {folder!r} must name a folder")
    held = [n for n in CERTIFICATES if os.path.lexists(os.path.join(folder, n))]
    if held:
        raise OptionError(f"{flag} = {folder!r} already holds {', '.join(held)}: remove "
                          f"them first (a set is never overwritten)")


def check_dask(opts):
    """--dask is local:N (N workers) or tcp:// / tls://HOST:PORT, with a strip to cut."""
    spec = opts.dask
    if spec.startswith("local:"):
        n = spec[len("local:"):]
        if not n.isdigit() or not 1 <= int(n) <= 256:
            raise OptionError(f"--dask = {spec!r}: local:N needs N within 1..256")
    elif not (spec.startswith(("tcp://", "tls://")) and ":" in spec.split("://", 1)[1]):
        raise OptionError(f"--dask = {spec!r} must be local:N or tcp://HOST:PORT")
    if opts.strip_aperture_s is None:
        raise OptionError(f"--dask = {spec!r} needs --strip-aperture-s (the apertures the "
                          f"strip is cut into)")


def _process_fields():
    """ProcessOptions' fields: the recording, an SNR override, then every field of
    SimOptions that is not recorded (a new receive-side field of SimOptions, e.g. a focuser
    choice, becomes a flag of nrsar-process too)."""
    hints = typing.get_type_hints(SimOptions)
    fields = [
        ("recording", str, option("", "the recording's NAME.sigmf-meta (NAME.sigmf-data "
                                  "beside it)", positional="optional", metavar="RECORDING")),
        ("snr_db", typing.Optional[float], option(
            None, "SNR per RE [dB] for the Wiener filter and the theory (default: the "
            "recording's nrsar:snr_db)", at_least=-200.0, at_most=300.0)),
        ("payload", typing.Optional[str], option(
            None, "the backhaul payload file of a PUSCH recording (nrsar:dmrs), whose grid is "
            "regenerated from it (default: the recording's nrsar:payload_path; its SHA-256 "
            "must be nrsar:payload_sha256)", metavar="FILE")),
        ("nav", typing.Optional[str], option(
            None, "image along this navigation (a CSV file like nrsar-sim's --nav) instead of "
            "the recording's nrsar:navigation", metavar="FILE")),
        ("strip_aperture_s", typing.Optional[float], option(
            None, "process the recording as a strip of apertures of this length [s], each "
            "with the focuser's overlap, stitched into strip_image.npy (docs/scale.md)",
            above=0.0, at_most=3600.0)),
        ("strip_overlap_s", typing.Optional[float], option(
            None, "rd_focuser's history and look-ahead around each strip aperture [s] "
            "(default: its overlap-save extent of the scene band, every pulse that focuses "
            "into the aperture); a task reads its aperture plus this on each side "
            "(docs/scale.md)", at_least=0.0, at_most=3600.0)),
        ("strip_window", int, option(
            0, "strip apertures submitted and not yet written at once (0: twice the "
            "workers): what the strip holds in memory, whatever its length (docs/scale.md)",
            at_least=0, at_most=4096)),
        ("dask", typing.Optional[str], option(
            None, "run the strip's apertures as Dask tasks: local:N (N worker processes on "
            "127.0.0.1) or tcp://HOST:PORT (a scheduler); always TLS with certificates "
            "(local: a self-signed set made for the run)", metavar="local:N|tcp://HOST:PORT")),
        ("dask_tls_ca", typing.Optional[str], option(None, "CA certificate of a remote "
                                                     "--dask scheduler", metavar="PEM")),
        ("dask_tls_cert", typing.Optional[str], option(None, "client certificate for a "
                                                       "remote --dask", metavar="PEM")),
        ("dask_tls_key", typing.Optional[str], option(None, "client key for a remote --dask",
                                                      metavar="PEM")),
        ("dask_make_certs", typing.Optional[str], option(
            None, "write a self-signed CA, certificate and key (ca.pem, cert.pem, key.pem; "
            "mode 0600) into this folder for a scheduler and workers started by hand, "
            "then exit (docs/scale.md)", metavar="DIR")),
    ]
    for f in dataclasses.fields(SimOptions):
        if f.name in RECORDED_FIELDS or f.name.startswith("split"):
            continue
        if f.default_factory is not dataclasses.MISSING:
            field = dataclasses.field(default_factory=f.default_factory, metadata=f.metadata)
        else:
            field = dataclasses.field(default=f.default, metadata=f.metadata)
        fields.append((f.name, hints[f.name], field))
    return fields


ProcessOptions = dataclasses.make_dataclass("ProcessOptions", _process_fields(),
                                            bases=(_ProcessRules,))
ProcessOptions.__doc__ = ("nrsar-process: forms the images of a SigMF recording with the "
                          "receive-side options of nrsar-sim (the recording supplies the "
                          "numerology, geometry, scene and transmit grid).")
