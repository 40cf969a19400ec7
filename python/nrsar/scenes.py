#!/usr/bin/python3
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
"""Extended scenes: reflectivity maps, the antenna beam, and the YAML scene file format.

    make_map(values, dx, dy, x0=0, y0=0, kind="power", scale=1, speckle=False, seed=0)
    make_beam(mode="whole_block", az_aperture_m=0.1, el_aperture_m=0.1, el_center_deg=45, cutoff=8)
    load_scene_file(path) -> SceneFile(points, maps, beam, geometry, numerology)

Scene file (YAML; every key optional except that a file needs targets or maps):

    numerology: paper                 # preset name, or {preset: paper, <field>: value, ...}
    geometry: {preset: paper, track_start_m: -20}   # or a preset name
    beam: {mode: azimuth, az_aperture_m: 0.1, el_aperture_m: 0.1, el_center_deg: 45, cutoff: 8}
    targets:                          # point targets, the first is the reference target
      - {x: 300, y: 100, rcs: 1, phase_deg: 0}
    maps:
      - file: sea.npy                 # .npy (2-D, real or complex), .pgm (P2/P5) or .png;
                                      # relative paths are relative to the scene file
        dx: 0.5                       # pixel spacing along x (ground range) and y [m]
        dy: 0.5
        origin: [280, 80]             # (x, y) of pixel [0, 0] = row 0, column 0 [m]
        kind: power                   # power: value = RCS of the pixel; amplitude: complex a
        scale: 1.0                    # values are multiplied by scale (power) first
        speckle: true                 # multiply by CN(0, 1), seeded
        seed: 1

Rows of the image are along y (azimuth), columns along x (ground range). Errors raise
SceneFileError (a ValueError) naming the file, the line and the field.
"""

import math
import os
from dataclasses import dataclass, field

import numpy as np

from .nrsar_python import (antenna_beam, point_target, reflectivity_map, scene)
from . import params

BEAM_MODES = params.BEAM_MODES


def make_map(values, dx, dy, x0=0.0, y0=0.0, kind="power", scale=1.0, speckle=False, seed=0):
    """A reflectivity_map from a 2-D array (rows = y, columns = x).

    kind "power": values are RCS per pixel (>= 0), amplitude sqrt(scale * value);
    kind "amplitude": values (real or complex) are the amplitudes, times scale."""
    a = np.asarray(values)
    if a.ndim != 2:
        raise ValueError(f"map values must be 2-D, got shape {a.shape}")
    if kind == "power":
        if np.iscomplexobj(a):
            raise ValueError("map kind 'power' needs real values (use kind 'amplitude')")
        a = np.asarray(a, dtype=np.float64) * float(scale)
        if not np.all(np.isfinite(a)) or np.any(a < 0):
            raise ValueError("map power values must be finite and >= 0")
        amp = np.sqrt(a).astype(np.complex64)
    elif kind == "amplitude":
        amp = (np.asarray(a, dtype=np.complex128) * float(scale)).astype(np.complex64)
    else:
        raise ValueError(f"map kind = '{kind}' must be 'power' or 'amplitude'")
    m = reflectivity_map()
    m.values = np.ascontiguousarray(amp)
    m.dx, m.dy, m.x0, m.y0 = float(dx), float(dy), float(x0), float(y0)
    m.speckle = bool(speckle)
    m.speckle_seed = int(seed)
    m.validate()
    return m


def make_beam(mode="whole_block", az_aperture_m=0.1, el_aperture_m=0.1, el_center_deg=45.0,
              cutoff=8.0):
    """antenna_beam of eqs. (1)-(3); mode whole_block (the paper), azimuth or azimuth_elevation."""
    if isinstance(mode, str):
        if mode not in BEAM_MODES:
            raise ValueError(f"beam mode = '{mode}' must be one of {sorted(BEAM_MODES)}")
        mode = BEAM_MODES[mode]
    b = antenna_beam()
    b.mode = mode
    b.az_aperture_m = float(az_aperture_m)
    b.el_aperture_m = float(el_aperture_m)
    b.el_center_rad = math.radians(float(el_center_deg))
    b.cutoff = float(cutoff)
    b.validate()
    return b


def read_image(path):
    """2-D array from .npy, .pgm (P2 ASCII or P5 binary, 8/16 bit) or .png (grey, or the mean of RGB)."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".npy":
        try:
            return np.load(path, allow_pickle=False)
        except OSError:
            raise
        except Exception as e:  # scene_file_fuzz: a broken header raises whatever it raises
            raise ValueError(f"{path}: not a readable .npy file ({type(e).__name__}: {e})") \
                from None
    if ext == ".pgm":
        return _read_pgm(path)
    if ext == ".png":
        import matplotlib.image
        try:
            img = np.asarray(matplotlib.image.imread(path), dtype=np.float64)
        except OSError:
            raise
        except Exception as e:  # scene_file_fuzz
            raise ValueError(f"{path}: not a readable .png file ({type(e).__name__}: {e})") \
                from None
        if img.ndim == 3:
            img = img[..., :3].mean(axis=2)
        return img
    raise ValueError(f"unsupported image type '{ext}' (use .npy, .pgm or .png)")


def _read_pgm(path):
    with open(path, "rb") as f:
        data = f.read()
    tokens, pos = [], 0
    # header: magic, width, height, maxval, with '#' comments
    while len(tokens) < 4:
        while pos < len(data) and data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            while pos < len(data) and data[pos:pos + 1] not in (b"\n", b"\r"):
                pos += 1
            continue
        start = pos
        while pos < len(data) and not data[pos:pos + 1].isspace():
            pos += 1
        if start == pos:
            raise ValueError(f"{path}: truncated PGM header")
        tokens.append(data[start:pos])
    magic = tokens[0]
    try:
        w, h, maxval = (int(t) for t in tokens[1:])
    except ValueError:
        raise ValueError(f"{path}: bad PGM header {tokens}") from None
    if magic == b"P5":
        dt = np.dtype(">u2") if maxval > 255 else np.uint8
        raw = np.frombuffer(data, dtype=dt, count=w * h, offset=pos + 1)
    elif magic == b"P2":
        raw = np.array(data[pos:].split()[:w * h], dtype=np.int64)
    else:
        raise ValueError(f"{path}: not a PGM file (magic {magic!r}, want P2 or P5)")
    if raw.size != w * h:
        raise ValueError(f"{path}: {raw.size} pixels, header says {w} x {h}")
    return raw.reshape(h, w).astype(np.float64)


class SceneFileError(ValueError):
    """A scene file error: names the file, the line and the field."""


def _printable(text, limit=80):
    """Message text with non-printable characters escaped and at most limit characters."""
    text = str(text)
    text = "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)
    return text if len(text) <= limit else text[:limit] + "..."


@dataclass
class SceneFile:
    points: object = None
    maps: list = field(default_factory=list)
    beam: object = None
    geometry: object = None
    numerology: object = None
    path: str = ""


def _node_value(node):
    import yaml
    if isinstance(node, yaml.MappingNode):
        return {k.value: v for k, v in node.value}
    return node.value


class _Ctx:
    def __init__(self, path):
        self.path = path

    def fail(self, node, fieldname, msg):
        line = node.start_mark.line + 1 if node is not None else 1
        raise SceneFileError(f"{self.path}:{line}: {_printable(fieldname)}: "
                             f"{_printable(msg, 300)}")

    def keys(self, node, fieldname):
        """scene_file_fuzz: keys are names (a '? [1, 2]: x' key is a list, not hashable)."""
        import yaml
        for k, _ in node.value:
            if not isinstance(k, yaml.ScalarNode):
                self.fail(k, fieldname, "keys must be names")

    def mapping(self, node, fieldname, allowed):
        import yaml
        if not isinstance(node, yaml.MappingNode):
            self.fail(node, fieldname, "must be a mapping (key: value)")
        self.keys(node, fieldname)
        out = {}
        for k, v in node.value:
            if k.value not in allowed:
                self.fail(k, f"{fieldname}.{k.value}",
                          f"unknown key (allowed: {', '.join(sorted(allowed))})")
            out[k.value] = v
        return out

    def number(self, node, fieldname):
        import yaml
        if not isinstance(node, yaml.ScalarNode):
            self.fail(node, fieldname, "must be a number")
        try:
            v = float(node.value)
        except ValueError:
            self.fail(node, fieldname, f"'{node.value}' is not a number")
        if not math.isfinite(v):
            self.fail(node, fieldname, f"{node.value} must be finite")
        return v

    def integer(self, node, fieldname, maximum=2**64 - 1):
        v = self.number(node, fieldname)
        if v != int(v) or v < 0 or v > maximum:  # scene_file_fuzz: the C++ field's range
            self.fail(node, fieldname,
                      f"{node.value} must be an integer from 0 to {maximum}")
        return int(v)

    def string(self, node, fieldname):
        import yaml
        if not isinstance(node, yaml.ScalarNode) or node.value == "":
            self.fail(node, fieldname, "must be a non-empty string")
        return node.value

    def boolean(self, node, fieldname):
        v = str(node.value).lower() if node is not None else ""
        if v in ("true", "yes", "on", "1"):
            return True
        if v in ("false", "no", "off", "0"):
            return False
        self.fail(node, fieldname, f"'{node.value}' must be true or false")

    def sequence(self, node, fieldname):
        import yaml
        if not isinstance(node, yaml.SequenceNode):
            self.fail(node, fieldname, "must be a list")
        return node.value

    def preset_with_overrides(self, node, fieldname, maker):
        import yaml
        if isinstance(node, yaml.ScalarNode):
            try:
                return maker(node.value)
            except ValueError as e:
                self.fail(node, fieldname, str(e))
        if not isinstance(node, yaml.MappingNode):
            self.fail(node, fieldname, "must be a preset name or a mapping")
        self.keys(node, fieldname)
        preset, overrides = "paper", {}
        for k, v in node.value:
            if k.value == "preset":
                preset = self.string(v, f"{fieldname}.preset")
            else:
                overrides[k.value] = (self.number(v, f"{fieldname}.{k.value}"), v)
        try:
            return maker(preset, **{k: (int(v) if v == int(v) and k in _INT_FIELDS else v)
                                    for k, (v, _) in overrides.items()})
        except (ValueError, AttributeError, TypeError) as e:
            # name the first override the message mentions, else the mapping
            bad = next((n for k, (_, n) in overrides.items() if k in str(e)), node)
            self.fail(bad, fieldname, str(e))


_INT_FIELDS = {"num_subcarriers", "fft_size", "cp_samples", "symbols_per_slot", "slots_per_frame"}

_TARGET_KEYS = {"x", "y", "rcs", "phase_deg"}
_MAP_KEYS = {"file", "dx", "dy", "origin", "kind", "scale", "speckle", "seed"}
_BEAM_KEYS = {"mode", "az_aperture_m", "el_aperture_m", "el_center_deg", "cutoff"}
_TOP_KEYS = {"numerology", "geometry", "beam", "targets", "maps"}


def load_scene_file(path):
    """Parse a YAML scene file (format in the module docstring) into a SceneFile."""
    import yaml
    ctx = _Ctx(path)
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise SceneFileError(f"{path}:1: file: cannot read: {e.strerror or e}") from None
    # scene_file_fuzz: bytes go to the YAML reader, which decodes them (UTF-8/16 with a BOM)
    # and reports bad bytes as a YAMLError with their position, not a UnicodeDecodeError.
    try:
        root = yaml.compose(data)
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None) or getattr(e, "context_mark", None)
        if mark is not None:
            line = mark.line + 1
        else:  # ReaderError: a character position
            line = data[:max(0, getattr(e, "position", 0))].count(b"\n") + 1
        what = getattr(e, "problem", None) or str(e)
        if isinstance(e, yaml.reader.ReaderError):  # undecodable or non-printable input
            char = e.character
            char = f"0x{char:02x}" if isinstance(char, int) else repr(char)
            what = f"character {char} at byte {e.position}: {e.reason}"
        raise SceneFileError(f"{path}:{line}: YAML syntax: {_printable(what)}") from None
    except RecursionError:  # scene_file_fuzz: thousands of nested [ or {
        raise SceneFileError(f"{path}:1: YAML syntax: nesting too deep") from None
    if root is None:
        raise SceneFileError(f"{path}:1: file: empty scene file")
    top = ctx.mapping(root, "scene", _TOP_KEYS)
    out = SceneFile(path=path)
    base = os.path.dirname(os.path.abspath(path))

    if "numerology" in top:
        out.numerology = ctx.preset_with_overrides(top["numerology"], "numerology",
                                                   params.make_numerology)
    if "geometry" in top:
        out.geometry = ctx.preset_with_overrides(top["geometry"], "geometry",
                                                 params.make_geometry)
    if "beam" in top:
        b = ctx.mapping(top["beam"], "beam", _BEAM_KEYS)
        kw = {}
        if "mode" in b:
            kw["mode"] = ctx.string(b["mode"], "beam.mode")
            if kw["mode"] not in BEAM_MODES:
                ctx.fail(b["mode"], "beam.mode",
                         f"'{kw['mode']}' must be one of {', '.join(sorted(BEAM_MODES))}")
        for k in ("az_aperture_m", "el_aperture_m", "el_center_deg", "cutoff"):
            if k in b:
                kw[k] = ctx.number(b[k], f"beam.{k}")
        try:
            out.beam = make_beam(**kw)
        except ValueError as e:
            ctx.fail(top["beam"], "beam", str(e))

    targets = []
    if "targets" in top:
        for i, tn in enumerate(ctx.sequence(top["targets"], "targets")):
            name = f"targets[{i}]"
            t = ctx.mapping(tn, name, _TARGET_KEYS)
            for k in ("x", "y"):
                if k not in t:
                    ctx.fail(tn, f"{name}.{k}", "missing")
            x, y = ctx.number(t["x"], f"{name}.x"), ctx.number(t["y"], f"{name}.y")
            rcs = ctx.number(t["rcs"], f"{name}.rcs") if "rcs" in t else 1.0
            if rcs < 0:
                ctx.fail(t["rcs"], f"{name}.rcs", f"{rcs} must be >= 0")
            ph = ctx.number(t["phase_deg"], f"{name}.phase_deg") if "phase_deg" in t else 0.0
            targets.append(point_target(x, y, rcs, math.radians(ph)))
    out.points = scene(targets)

    if "maps" in top:
        for i, mn in enumerate(ctx.sequence(top["maps"], "maps")):
            name = f"maps[{i}]"
            m = ctx.mapping(mn, name, _MAP_KEYS)
            for k in ("file", "dx", "dy"):
                if k not in m:
                    ctx.fail(mn, f"{name}.{k}", "missing")
            fname = ctx.string(m["file"], f"{name}.file")
            fpath = fname if os.path.isabs(fname) else os.path.join(base, fname)
            if not os.path.isfile(fpath):
                ctx.fail(m["file"], f"{name}.file", f"no such file '{fpath}'")
            try:
                img = read_image(fpath)
            except (ValueError, OSError) as e:
                ctx.fail(m["file"], f"{name}.file", str(e))
            dx, dy = ctx.number(m["dx"], f"{name}.dx"), ctx.number(m["dy"], f"{name}.dy")
            for k, v in (("dx", dx), ("dy", dy)):
                if v <= 0:
                    ctx.fail(m[k], f"{name}.{k}", f"{v} must be > 0")
            x0 = y0 = 0.0
            if "origin" in m:
                o = ctx.sequence(m["origin"], f"{name}.origin")
                if len(o) != 2:
                    ctx.fail(m["origin"], f"{name}.origin", "must be [x, y]")
                x0 = ctx.number(o[0], f"{name}.origin[0]")
                y0 = ctx.number(o[1], f"{name}.origin[1]")
            kind = ctx.string(m["kind"], f"{name}.kind") if "kind" in m else "power"
            scale = ctx.number(m["scale"], f"{name}.scale") if "scale" in m else 1.0
            speckle = ctx.boolean(m["speckle"], f"{name}.speckle") if "speckle" in m else False
            seed = ctx.integer(m["seed"], f"{name}.seed") if "seed" in m else 0
            try:
                out.maps.append(make_map(img, dx, dy, x0, y0, kind, scale, speckle, seed))
            except ValueError as e:
                ctx.fail(mn, name, str(e))
    if not targets and not out.maps:
        ctx.fail(root, "scene", "needs at least one target or map")
    return out


def bounding_scene(points, maps):
    """Point targets plus the four corners of every map (for extents and scenario checks)."""
    tg = list(points.targets)
    for m in maps:
        for x in (m.x0, m.x0 + (m.nx - 1) * m.dx):
            for y in (m.y0, m.y0 + (m.ny - 1) * m.dy):
                tg.append(point_target(x, y, 1.0))
    return scene(tg)


def ship_and_sea(nx=96, ny=64, dx=0.75, dy=0.75, seed=4):
    """A small synthetic scene: a sea clutter power map (weak, with swell) and a ship (a bright
    hull of a few strong pixels plus a superstructure), for examples/scenes. Returns the power map."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:ny, 0:nx]
    sea = 0.02 * (1.0 + 0.5 * np.sin(2 * np.pi * (xx * 0.7 + yy) / 14.0)) \
        * rng.gamma(4.0, 0.25, size=(ny, nx))
    cx, cy, half_len, half_w = nx * 0.55, ny * 0.5, ny * 0.3, 2.5
    hull = (np.abs(yy - cy) <= half_len) & (np.abs(xx - cx) <= half_w * (1 - ((yy - cy) / half_len) ** 4))
    sea[hull] = 1.0
    sea[(np.abs(yy - cy + 3) <= 4) & (np.abs(xx - cx) <= 1.5)] = 6.0  # superstructure
    return sea.astype(np.float32)


def extended_echo(num, geo, scene_file="", points="", beam=None, snr_db=float("inf"), seed=0,
                  taps=8, oversampling=2.0, path=None):
    """extended_scene_echo from a YAML scene file (its targets, maps and beam; its numerology
    and geometry are ignored here: the block's num and geo rule) and/or point targets
    ('X,Y[,RCS[,PHASE_DEG]];...' or a preset). beam (an antenna_beam) replaces the file's; path:
    the true flight path (a trajectory; None: the ideal line). Used by GRC."""
    from .nrsar_python import extended_scene_echo
    pts, maps, fbeam = [], [], None
    if scene_file:
        sf = load_scene_file(scene_file)
        pts, maps, fbeam = list(sf.points.targets), sf.maps, sf.beam
    if points:
        pts += list(params.make_scene(points).targets)
    return extended_scene_echo(num, geo, scene(pts), maps, beam or fbeam or antenna_beam(),
                               snr_db, seed, taps, oversampling,
                               params.trajectory() if path is None else path)
