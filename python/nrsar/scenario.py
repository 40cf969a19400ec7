#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The scenario an options object describes: numerology, geometry, scene and pulse grid.

    scn = scenario.of(opts)     # Scenario(num, geo, scene, ...), checked (check_scenario)

`Scenario.trajectory` is the true flight path (what the echo generators fly) and
`Scenario.navigation` what the UAV believes (what every processing block uses); both are
trajectory objects, the geometry's ideal line by default (docs/flight.md).
`range_grid_warnings(sc, fft_size)` says, before the run, when the navigation's sway spreads
the range spectrum beyond the range grid's headroom.

Every failure is a ValueError that names the flag it came from (`--preset = 'huge': ...`),
raised before any block is built.
"""

import dataclasses
import math
import os
import sys
import typing

import numpy as np

from . import params
from .nrsar_python import range_ifft, srs_config
from .options import MODES, OptionError

# A point-target scene file costs one complex rotation per target, subcarrier and symbol;
# above this many targets nrsar-sim says what it is about to do.
MANY_TARGETS = 10000


@dataclasses.dataclass
class Scenario:
    num: object          # numerology
    geo: object          # geometry
    scene: object        # point targets (a scene file's extent for maps)
    scene_file: typing.Any  # scenes.SceneFile of --scene FILE, or None
    tx_mode: str         # "data" or "srs"
    srs: object          # SRS layout of the grid
    pulse_symbols: int   # symbols per slow-time sample (1 for data)
    symbols: int         # symbols per aperture M
    warnings: list
    trajectory: typing.Any = None  # true path (echo generators); None: the ideal line
    navigation: typing.Any = None  # believed path (processing blocks); None: the ideal line
    # a strip's task (distributed_process): the focuser's (lines per aperture, first
    # aperture, apertures, overlap lines) of the flight; None: one aperture of `symbols`
    strip: typing.Any = None

    def __post_init__(self):
        ideal = None
        for name in ("trajectory", "navigation"):
            if getattr(self, name) is None:
                ideal = ideal or params.make_trajectory("ideal", self.geo)
                setattr(self, name, ideal)


def grid_of_mode(mode_arg, num):
    """(tx mode name, SRS layout, symbols per pulse) of a --mode value. The SRS band is
    the paper's (subcarriers 1667..1954) where it fits, else centred."""
    mode, period = MODES[mode_arg]
    srs = srs_config()
    if period:
        srs.period_slots = period
    if mode != "data" and srs.num_subcarriers() > num.num_subcarriers:
        raise OptionError(f"--mode = {mode_arg!r} needs its SRS band's {srs.num_subcarriers()} "
                          f"subcarriers, more than the numerology's {num.num_subcarriers} "
                          f"(choose a wider --preset)")
    if mode != "data" and srs.start_subcarrier + srs.num_subcarriers() > num.num_subcarriers:
        srs.start_subcarrier = (num.num_subcarriers - srs.num_subcarriers()) // 2
    return mode, srs, params.symbols_per_pulse(mode, num, srs)


def fft_size_of(opts, num_subcarriers):
    """The range IFFT size of --fft-size."""
    text = opts.fft_size.strip().lower()
    if text == "exact":
        return num_subcarriers
    if text == "fast":
        return range_ifft.fast_fft_size(num_subcarriers)
    size = int(text)
    if size < num_subcarriers:
        raise OptionError(f"--fft-size = {size} must be at least the {num_subcarriers} "
                          f"subcarriers of --preset {opts.preset}")
    return size


def sway_spread_hz(sc, dt_s=1e-3, window=None):
    """(spread [Hz], target) of the worst scene target (a scene file: its points and its
    maps' corners): max - min over the aperture [0, geo.aperture_s], or the flight's time
    window (t0, t1) [s] (a strip's task, distributed_process), on a dt_s grid, of
    s(t) = fc (dr/dR0 - dr_line/dR0), the shift of a pulse's range wavenumber on the ideal
    line's slant grid when the antenna flies the NAVIGATION (what the processing uses; a real
    processor has no truth) instead of the line. r and r_line share the path's y (the look
    angle's change, not the along-track one's); targets on the ground at ground range g:
    dr/dR0 = (g - x) / r * R0 / g (a target at nadir, g = 0, where R0 has no slope, is left
    out). (0, None) on the ideal line (docs/blocks/rd_focuser.md, "Range grid under a large
    sway")."""
    targets = [tg for tg in sc.scene.targets if tg.x_m != 0.0]
    if sc.navigation.is_ideal() or not targets:
        return 0.0, None
    geo = sc.geo
    t0, t1 = window or (0.0, geo.aperture_s)
    t = np.linspace(t0, t1, int(math.ceil((t1 - t0) / dt_s)) + 1)
    x, y, z = (c[:, None] for c in np.array(sc.navigation.positions(list(t))).T)
    g = np.array([tg.x_m for tg in targets])
    dy = y - np.array([tg.y_m for tg in targets])
    h = geo.height_m
    r = np.sqrt((g - x) ** 2 + dy * dy + z * z)
    r_line = np.sqrt(g * g + dy * dy + h * h)
    s = geo.carrier_hz * np.sqrt(g * g + h * h) / g * ((g - x) / r - g / r_line)
    spread = s.max(axis=0) - s.min(axis=0)
    worst = int(np.argmax(spread))
    return float(spread[worst]), targets[worst]


# The spread a range grid absorbs beyond its headroom, in B: measured (docs/flight.md, "The
# range-grid headroom check"), 0.06-0.08 B past it moved a peak by 0.08-0.09 m (1 % of the
# resolution), 0.19-0.21 B by 1.9-2.3 m.
RANGE_SPREAD_TOLERANCE_B = 0.1


def range_grid_warnings(sc, fft_size):
    """[the warning] when the sway's spread of the range spectrum (sway_spread_hz) exceeds
    the range grid's headroom (fft_size - N) Delta f, the band the IFFT holds beyond the
    occupied B = N Delta f, by more than RANGE_SPREAD_TOLERANCE_B: the range cut then
    aliases, and its peak and IRW err (metres on the ALFA flight, docs/flight.md), else [].
    A warning, not a refusal: the image is made."""
    return range_spread_warnings(sc.num, fft_size, *sway_spread_hz(sc))


def range_spread_warnings(num, fft_size, spread, target, where="the aperture"):
    """range_grid_warnings' text of a spread [Hz] at a target over `where` (a strip names
    its worst aperture), or [] within the headroom and the tolerance."""
    n, df = num.num_subcarriers, num.subcarrier_spacing_hz
    headroom = (fft_size - n) * df
    band = n * df
    if spread <= headroom + RANGE_SPREAD_TOLERANCE_B * band:
        return []
    need = range_ifft.fast_fft_size(n + int(math.ceil(spread / df)))
    return [f"the navigation's sway spreads the range spectrum by {spread / 1e6:.3f} MHz "
            f"({spread / band:.3f} B, B = {band / 1e6:.3f} MHz) over {where} at the "
            f"target x = {target.x_m:g} m, y = {target.y_m:g} m, beyond the range grid's "
            f"headroom of {headroom / 1e6:.3f} MHz (--fft-size {fft_size}, {n} subcarriers): "
            f"the range cut aliases the excess, its peak and IRW err the more the larger it "
            f"is (2.5 m at 0.37 B, docs/flight.md); --fft-size {need} holds it "
            f"(docs/blocks/rd_focuser.md, 'Range grid under a large sway')"]


def _flagged(flag, value, func, *args, **kwargs):
    """func(...) with a ValueError's message prefixed by the flag and its value."""
    try:
        return func(*args, **kwargs)
    except OptionError:
        raise
    except ValueError as err:
        raise OptionError(f"{flag} = {value!r}: {err}") from None


def load_scene(opts):
    """(scene, scene file or None) of --target / --scene. A --scene value is a scene file if
    such a file exists, else a preset or target text; a value that is none of these names
    all three."""
    if opts.target:
        return _flagged("--target", opts.target, params.make_scene, opts.target), None
    if os.path.isfile(opts.scene):
        from . import scenes
        sf = _flagged("--scene", opts.scene, scenes.load_scene_file, opts.scene)
        sf.extent_scene = scenes.bounding_scene(sf.points, sf.maps)
        return sf.extent_scene, sf
    try:
        return params.make_scene(opts.scene), None
    except ValueError as err:
        looks_like_path = (os.sep in opts.scene or opts.scene.endswith((".yaml", ".yml"))
                           or not any(c.isdigit() for c in opts.scene))
        if looks_like_path:
            raise OptionError(f"--scene = {opts.scene!r} is no file that exists, no preset "
                              f"(paper3, single) and no target text 'X,Y[,RCS[,PHASE_DEG]];"
                              f"...'") from None
        raise OptionError(f"--scene = {opts.scene!r}: {err}") from None


def flight_of(opts, geo):
    """(trajectory, navigation) of --trajectory / --motion / --motion-seed and --nav /
    --nav-error (navigation error seeded with motion seed + 1), over the aperture."""
    if opts.trajectory is not None:
        truth = _flagged("--trajectory", opts.trajectory, params.make_trajectory,
                         opts.trajectory, geo)
    else:
        truth = _flagged("--motion", opts.motion, params.make_trajectory, opts.motion, geo,
                         seed=opts.motion_seed)
    if opts.nav is not None:
        nav = _flagged("--nav", opts.nav, params.make_navigation, truth, opts.nav, geo=geo)
    else:
        nav = _flagged("--nav-error", opts.nav_error, params.make_navigation, truth,
                       opts.nav_error, seed=opts.motion_seed + 1, geo=geo)
    return truth, nav


def of(opts):
    """The Scenario of validated options; check_scenario's warnings travel with it."""
    num = _flagged("--preset", opts.preset, params.make_numerology, opts.preset)
    overrides = {} if opts.aperture_s is None else {"aperture_s": opts.aperture_s}
    geo = _flagged("--geometry", opts.geometry, params.make_geometry, opts.geometry,
                   **overrides)
    scn, sf = load_scene(opts)
    warnings = []
    if sf is not None:  # the scene file's numerology and geometry replace the presets
        num = sf.numerology or num
        if sf.geometry is not None:
            fields = ("carrier_hz", "velocity_mps", "height_m", "track_start_m", "aperture_s")
            geo = params.make_geometry("paper", **{**{k: getattr(sf.geometry, k)
                                                      for k in fields}, **overrides})
        n_points = len(sf.points.targets) if sf.points is not None else 0
        if n_points > MANY_TARGETS:
            text = (f"the scene file has {n_points} point targets: the echo costs one "
                    f"rotation per target, subcarrier and symbol; a reflectivity map (maps:) "
                    f"is far cheaper for dense scenes")
            print(f"warning: {text}", file=sys.stderr)  # before the long run, not after it
            warnings.append(text)
    fft_size = fft_size_of(opts, num.num_subcarriers)  # refused here, before any block is built
    mode, srs, pulse_symbols = grid_of_mode(opts.mode, num)
    warnings = list(params.check_scenario(num, geo, scn, pulse_symbols)) + warnings
    truth, nav = flight_of(opts, geo)
    if not truth.is_ideal():  # targets in front of the antenna, round trips in the CP
        flag, value = (("--trajectory", opts.trajectory) if opts.trajectory is not None
                       else ("--motion", opts.motion))
        _flagged(flag, value, params.check_scenario, num, geo, scn, truth, pulse_symbols)
    symbols = int(geo.symbols_per_aperture(num))
    sc = Scenario(num=num, geo=geo, scene=scn, scene_file=sf, tx_mode=mode, srs=srs,
                  pulse_symbols=pulse_symbols, symbols=symbols, warnings=warnings,
                  trajectory=truth, navigation=nav)
    sc.warnings += range_grid_warnings(sc, fft_size)
    return sc
