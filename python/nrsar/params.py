#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Build and validate the shared parameter types from presets, strings and dicts.

The one place where GRC `make:` lines, the apps and scripts turn user input into
`numerology`, `geometry`, `scene` and enum values; the numbers are checked by the C++
`validate()` / `check_scenario()` so every front end gets the same errors.
"""

from .nrsar_python import (numerology, geometry, scene, point_target, srs_config, dmrs_config,
                           modulation, tx_mode, filter_type, presum_method, presum_domain,
                           doppler_band, beam_mode, image_colormap, check_scenario,
                           compute_extent, trajectory, motion_model, nav_error_model,
                           moco_order, pusch_coding, pusch_scrambling, pusch_config, mcs as nr_mcs,
                           autofocus_method)


def _names(enum):
    """{'qam256': modulation.QAM256, ...}: the bound enum's members by lower-case name, in
    the C++ declaration order; the one table of names the apps, scripts and GRC accept."""
    return {name.lower(): member for name, member in enum.__members__.items()}


MODULATIONS = _names(modulation)
TX_MODES = _names(tx_mode)
FILTERS = _names(filter_type)
PRESUM_METHODS = _names(presum_method)
PRESUM_DOMAINS = _names(presum_domain)
DOPPLER_BANDS = _names(doppler_band)
BEAM_MODES = _names(beam_mode)
COLORMAPS = _names(image_colormap)

MOTIONS = _names(motion_model)
NAV_ERRORS = _names(nav_error_model)
MOCO_ORDERS = _names(moco_order)

PUSCH_CODINGS = _names(pusch_coding)
PUSCH_SCRAMBLINGS = _names(pusch_scrambling)
MCS_TABLES = ("qam64", "qam256")
# bits per symbol of the square QAMs pusch_receiver demaps
QAM_BITS = {"qpsk": 2, "qam16": 4, "qam64": 6, "qam256": 8}

AUTOFOCUS_METHODS = _names(autofocus_method)


def _lookup(table, kind, name):
    if not isinstance(name, str):
        return name
    try:
        return table[name.lower()]
    except KeyError:
        raise ValueError(f"{kind} '{name}' is unknown; choose one of {sorted(table)}") from None


def _builder(table, kind):
    """make_X(name): a name of table (any case) -> its enum member; members pass through;
    ValueError names the kind, the name and the choices."""
    def make(name):
        return _lookup(table, kind, name)
    first = next(iter(table))
    make.__doc__ = f"'{first}' -> {table[first]!r} (enum values pass through)."
    return make


make_modulation = _builder(MODULATIONS, "modulation")
make_tx_mode = _builder(TX_MODES, "tx mode")
make_filter = _builder(FILTERS, "filter")
make_presum_method = _builder(PRESUM_METHODS, "presum method")
make_presum_domain = _builder(PRESUM_DOMAINS, "presum domain")
make_doppler_band = _builder(DOPPLER_BANDS, "doppler band")
make_colormap = _builder(COLORMAPS, "colormap")
make_moco_order = _builder(MOCO_ORDERS, "moco order")
_coding = _builder(PUSCH_CODINGS, "coding")
_scrambling = _builder(PUSCH_SCRAMBLINGS, "scrambling")


def make_pusch_coding(name):
    """'nr_ldpc' or 'nr-ldpc' (the command line's spelling), 'none' -> pusch_coding."""
    return _coding(name.replace("-", "_") if isinstance(name, str) else name)


def make_pusch_scrambling(name):
    """'standard', 'per_slot' or 'per-slot' -> pusch_scrambling."""
    return _scrambling(name.replace("-", "_") if isinstance(name, str) else name)


def highest_mcs(mcs_table, modulation):
    """The highest MCS of a 38.214 table (qam64: rows 0-28, qam256: 0-27) whose Qm is the
    modulation's: qam256 -> 27 (R 948/1024), qam64 in the qam64 table -> 28."""
    qm = QAM_BITS[str(modulation).lower()]
    rows = range(28 if mcs_table == "qam256" else 29)
    return max(m for m in rows if nr_mcs(mcs_table, m)[0] == qm)


def make_pusch_config(num, modulation="qam256", dmrs="pusch2", coding="nr-ldpc",
                      mcs_table="qam256", mcs=None, **fields):
    """A pusch_config (pusch_encoder / pusch_receiver) from names, validated; mcs None =
    highest_mcs(mcs_table, modulation). fields: rv, repetitions, n_rnti, n_id, scrambling
    ('standard' / 'per-slot'), freq_window, max_iterations, max_queued_bytes."""
    if mcs is None and make_pusch_coding(coding) == pusch_coding.NR_LDPC:
        mcs = highest_mcs(mcs_table, modulation)
    cfg = pusch_config(num=num, mod=make_modulation(modulation), dmrs=make_dmrs(dmrs, num),
                       coding=make_pusch_coding(coding), mcs_table=mcs_table,
                       mcs=0 if mcs is None else mcs)
    if "scrambling" in fields:
        fields["scrambling"] = make_pusch_scrambling(fields["scrambling"])
    _with_overrides(cfg, fields, "pusch_config")
    cfg.validate()
    return cfg

make_autofocus_method = _builder(AUTOFOCUS_METHODS, "autofocus method")


def _with_overrides(obj, overrides, kind):
    for key, value in (overrides or {}).items():
        if not hasattr(obj, key):
            raise ValueError(f"{kind} has no field '{key}'")
        setattr(obj, key, value)
    return obj


def make_numerology(preset="paper", **overrides):
    """A numerology preset with fields overridden, validated."""
    num = _with_overrides(numerology.preset(preset), overrides, "numerology")
    num.validate()
    return num


def make_geometry(preset="paper", **overrides):
    geo = _with_overrides(geometry.preset(preset), overrides, "geometry")
    geo.validate()
    return geo


def make_srs(**overrides):
    return _with_overrides(srs_config(), overrides, "srs_config")


def make_dmrs(spec="none", num=None, scrambling_id=0):
    """A DMRS layout from a preset name ('none', 'pusch1', 'pusch2', 'pusch4'), a
    comma-separated list of symbol positions ('2,11') or a list of ints; validated against
    num when given."""
    if isinstance(spec, dmrs_config):
        dmrs = spec
    elif isinstance(spec, str) and not spec.strip()[:1].isdigit():
        dmrs = dmrs_config.preset(spec.strip().lower())
    else:
        text = spec.split(",") if isinstance(spec, str) else spec
        try:
            symbols = [int(s) for s in text]
        except (TypeError, ValueError):
            raise ValueError(f"dmrs symbols '{spec}' must be a preset name or integers "
                             "like '2,11'") from None
        dmrs = dmrs_config()
        dmrs.symbols = symbols
    if scrambling_id:
        dmrs.scrambling_id = int(scrambling_id)
    if num is not None:
        dmrs.validate(num)
    return dmrs


def parse_target(text, index=0):
    """'X,Y[,RCS[,PHASE_DEG]]' (metres, linear RCS power, degrees) -> point_target.

    The grammar is C++'s point_target::parse (the same for GRC, the apps and scripts);
    ValueError names the target index, the field and the text."""
    return point_target.parse(str(text), index)


def make_scene(spec="paper3"):
    """A scene from a preset name, 'X,Y[,RCS[,PHASE_DEG]];X,Y...' (C++ scene::parse), a list
    of such strings (one target each), a list of (x, y[, rcs[, phase_rad]]) tuples, or a
    scene. Validated."""
    if isinstance(spec, scene):
        scn = spec
    elif isinstance(spec, str):
        scn = scene.parse(spec)
    else:
        targets = []
        for i, t in enumerate(spec):
            if isinstance(t, point_target):
                targets.append(t)
            elif isinstance(t, str):
                targets.append(parse_target(t, i))
            else:
                targets.append(point_target(*[float(v) for v in t]))
        scn = scene(targets)
    scn.validate()
    return scn


def symbols_per_pulse(mode, num, srs=None):
    """Slow-time sampling interval in symbols: 1 for data, one SRS symbol per SRS slot."""
    if make_tx_mode(mode) == tx_mode.SRS:
        srs = srs or srs_config()
        return num.symbols_per_slot * srs.period_slots
    return 1


def make_trajectory(spec="ideal", geo=None, duration_s=None, seed=0, rate_hz=100.0,
                    lever_arm_m=(0.0, 0.0, 0.0)):
    """The true flight path: 'ideal' (geo's straight line), a motion model 'calm' / 'gusty'
    added to it (seeded, sampled at rate_hz over [0, duration_s], default geo.aperture_s),
    or a CSV file t_s,x_m,y_m,z_m[,roll_rad,pitch_rad,yaw_rad] that must cover
    [0, duration_s]. A trajectory passes through unchanged. lever_arm_m: the antenna phase
    centre's offset from the CSV's navigated point, body frame (CSV files only: the line and
    the models are the phase centre's path)."""
    name = str(spec).strip()
    if any(float(v) != 0.0 for v in lever_arm_m) and (
            isinstance(spec, trajectory) or name.lower() in ("ideal", "none", *MOTIONS)):
        raise ValueError(f"lever_arm_m = {tuple(lever_arm_m)} needs a CSV file of the navigated "
                         f"point, not {name!r} (the phase centre's own path)")
    if isinstance(spec, trajectory):
        return spec
    geo = make_geometry() if geo is None else geo
    span = geo.aperture_s if duration_s is None else float(duration_s)
    if name.lower() in ("ideal", "none"):
        return trajectory.ideal(geo)
    if name.lower() in MOTIONS:
        return trajectory.motion(geo, MOTIONS[name.lower()], int(seed), span, float(rate_hz))
    return trajectory.from_csv(name, span, tuple(float(v) for v in lever_arm_m))


def make_navigation(truth, error="none", seed=0, duration_s=None, rate_hz=100.0, geo=None):
    """What the platform believes: truth plus the error model 'none' / 'rtk' / 'gnss'
    (seeded, over [0, duration_s], default geo.aperture_s), or a second CSV file."""
    name = str(error).strip()
    if name.lower() not in NAV_ERRORS:
        return make_trajectory(name, geo, duration_s)
    geo = make_geometry() if geo is None else geo
    span = geo.aperture_s if duration_s is None else float(duration_s)
    return trajectory.navigation(truth, NAV_ERRORS[name.lower()], int(seed), span,
                                 float(rate_hz))
