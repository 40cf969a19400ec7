#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Every constructor/setter parameter rule of the blocks and shared types: one test per row
of docs/robustness.md. Each row breaks one rule of an otherwise valid call and checks that
Python gets a ValueError whose message names the parameter (and its limit).

`qa_param_rules.py --markdown` prints the table of docs/robustness.md with the messages the
module really gives, so the document cannot drift from the code."""

import sys

import numpy as np

from gnuradio import fft, gr, gr_unittest
from gnuradio import nrsar
from gnuradio.nrsar import (cheby_presum, focuser_config, probe_config, make_filter, make_geometry,
                            make_dmrs, make_modulation, make_numerology, make_scene, make_srs,
                            make_tx_mode, nmse_probe, nr_isac_tx, range_ifft, rd_focuser,
                            scene_echo, tf_filter)

NAN, INF = float("nan"), float("inf")
WIN = fft.window.WIN_RECTANGULAR


def num(**kw):
    n = nrsar.numerology.preset("tiny")
    for key, value in kw.items():
        setattr(n, key, value)
    return n


def pusch(**kw):
    """A valid pusch_config (tiny, 16-QAM, qam256 MCS 10) with fields replaced."""
    args = dict(num=num(), mod=make_modulation("qam16"), dmrs=make_dmrs("pusch2"), mcs=10)
    args.update(kw)
    return nrsar.pusch_config(**args)


def geo(**kw):
    g = nrsar.geometry.preset("short")
    for key, value in kw.items():
        setattr(g, key, value)
    return g


def scn(*targets):
    return nrsar.scene([nrsar.point_target(*t) for t in targets]) if targets \
        else nrsar.scene.preset("paper3")


def srs(**kw):
    s = nrsar.srs_config()
    s.start_subcarrier, s.num_rb = 0, 2
    for key, value in kw.items():
        setattr(s, key, value)
    return s


def cfg(**kw):
    c = focuser_config()
    for key, value in kw.items():
        setattr(c, key, value)
    return c


def points():
    return nrsar.constellation(make_modulation("qpsk")).points()


def tx(**kw):
    a = dict(num=num(), mod=make_modulation("qpsk"), mode=make_tx_mode("data"), srs=srs(),
             seed=0)
    a.update(kw)
    return nr_isac_tx(a["num"], a["mod"], a["mode"], a["srs"], a["seed"])


def echo(n=None, g=None, s=None, snr_db=20.0):
    return scene_echo(n or num(), g or geo(), s or scn(), snr_db, 1)


def rif(n=None, fft_size=0, window=WIN, window_param=-1.0, r_min=0.0, r_max=0.0):
    return range_ifft(n or num(), fft_size, window, window_param, r_min, r_max)


def foc(n=None, g=None, s=None, k=16, first=900.0, rho=0.0, c=None):
    return rd_focuser(n or num(), g or geo(), s or scn(), k, first, rho, c or cfg())


def probe(**kw):
    a = dict(num=num(), geo=geo(), scn=scn(), constellation=points(),
             filter=make_filter("wf"), snr_in_db=10.0, vlen=16)
    a.update({k: v for k, v in kw.items() if k in a})
    return nmse_probe(**a, cfg=probe_config(**{k: v for k, v in kw.items() if k not in a}))


def presum(**kw):
    a = dict(num=nrsar.numerology.preset("paper"), geo=nrsar.geometry.preset("paper"),
             scn=scn(), num_bins=64, first_range_m=1000.0, range_bin_m=1.0)
    c = dict(method=nrsar.presum_method.CHEBY, decim=10, domain=nrsar.presum_domain.RANGE)
    for key, value in kw.items():
        (a if key in a else c)[key] = value
    return cheby_presum(cfg=nrsar.presum_config(**c), **a)


def ext(maps=None, **kw):
    """extended_scene_echo with one 2 x 2 m map around (300, 0)."""
    if maps is None:
        maps = [nrsar.make_map(np.ones((2, 2)), 1.0, 1.0, 300.0, 0.0)]
    return nrsar.extended_scene_echo(num(), geo(), scn((300.0, 0.0)), maps, **kw)


def bad_size_map():
    m = nrsar.reflectivity_map()
    m.nx, m.ny = 3, 3
    m.values = np.ones(4, dtype=np.complex64)
    return m


def connect_mismatch():
    tb = gr.top_block()
    tb.connect(tx(), tf_filter(32))


# (subject, rule, call, fragment that the message must contain)
def bad_beam():
    """An antenna_beam built field by field (make_beam would refuse it already)."""
    b = nrsar.antenna_beam()
    b.mode = nrsar.beam_mode.AZIMUTH
    b.az_aperture_m = -1.0
    return b


RULES = [
    # shared types
    ("numerology", "subcarrier spacing zero", lambda: num(subcarrier_spacing_hz=0.0).validate(),
     "subcarrier_spacing_hz = 0"),
    ("numerology", "subcarrier spacing NaN", lambda: num(subcarrier_spacing_hz=NAN).validate(),
     "subcarrier_spacing_hz = nan"),
    ("numerology", "subcarrier spacing inf", lambda: num(subcarrier_spacing_hz=INF).validate(),
     "subcarrier_spacing_hz = inf"),
    ("numerology", "no subcarriers", lambda: num(num_subcarriers=0).validate(),
     "num_subcarriers = 0"),
    ("numerology", "FFT smaller than N", lambda: num(fft_size=32).validate(),
     "fft_size = 32 must be at least num_subcarriers = 64"),
    ("numerology", "zero symbols per slot", lambda: num(symbols_per_slot=0).validate(),
     "symbols_per_slot = 0"),
    ("numerology", "zero slots per frame", lambda: num(slots_per_frame=0).validate(),
     "slots_per_frame = 0"),
    ("numerology", "unknown preset", lambda: make_numerology("huge"), "huge"),
    ("numerology", "unknown field override", lambda: make_numerology("tiny", nfft=64),
     "no field 'nfft'"),
    ("geometry", "carrier zero", lambda: geo(carrier_hz=0.0).validate(), "carrier_hz = 0"),
    ("geometry", "negative velocity", lambda: geo(velocity_mps=-1.0).validate(),
     "velocity_mps = -1"),
    ("geometry", "height NaN", lambda: geo(height_m=NAN).validate(), "height_m = nan"),
    ("geometry", "track start inf", lambda: geo(track_start_m=INF).validate(),
     "track_start_m = inf"),
    ("geometry", "zero aperture", lambda: geo(aperture_s=0.0).validate(), "aperture_s = 0"),
    ("geometry", "unknown preset", lambda: make_geometry("long"), "long"),
    ("scene", "empty scene", lambda: nrsar.scene([]).validate(), "scene has no targets"),
    ("scene", "target x NaN", lambda: scn((NAN, 0.0)).validate(), "target 0 x_m = nan"),
    ("scene", "target y inf", lambda: scn((300.0, INF)).validate(), "target 0 y_m = inf"),
    ("scene", "target phase NaN", lambda: scn((300.0, 0.0, 1.0, NAN)).validate(),
     "target 0 phase_rad = nan"),
    ("scene", "negative RCS", lambda: scn((300.0, 0.0), (250.0, 0.0, -1.0)).validate(),
     "target 1 rcs = -1"),
    ("scene", "target text not X,Y[,RCS]", lambda: make_scene("300"),
     "target 0 '300': has 1 field; must be X,Y[,RCS[,PHASE_DEG]]"),
    ("scene", "target text not a number", lambda: make_scene("300,abc"),
     "target 0 '300,abc': y_m 'abc' is not a number"),
    ("scene", "unknown preset", lambda: nrsar.scene.preset("paper9"), "paper9"),
    ("srs_config", "comb offset >= comb", lambda: srs(comb_offset=4).validate(num()),
     "srs comb_offset = 4 must be below comb = 4"),
    ("srs_config", "zero comb", lambda: srs(comb=0).validate(num()), "srs comb = 0"),
    ("srs_config", "zero resource blocks", lambda: srs(num_rb=0).validate(num()),
     "srs num_rb = 0"),
    ("srs_config", "zero period", lambda: srs(period_slots=0).validate(num()),
     "srs period_slots = 0"),
    ("srs_config", "symbol beyond the slot", lambda: srs(symbol_in_slot=14).validate(num()),
     "srs symbol_in_slot = 14"),
    ("srs_config", "band beyond the grid", lambda: srs(start_subcarrier=60).validate(num()),
     "does not fit the 64 subcarriers"),
    ("dmrs_config", "symbol beyond the slot", lambda: make_dmrs("2,14", num()),
     "dmrs symbols = 14 must be below symbols_per_slot = 14"),
    ("dmrs_config", "symbols not increasing", lambda: make_dmrs("11,2", num()),
     "dmrs symbols = 2 must be strictly increasing"),
    ("dmrs_config", "scrambling id beyond 16 bits", lambda: make_dmrs("pusch2", num(), 65536),
     "dmrs scrambling_id = 65536"),
    ("make_dmrs", "symbols not integers", lambda: make_dmrs("2,x"), "must be a preset name"),
    ("dmrs_config", "unknown preset", lambda: make_dmrs("pusch3"), "pusch3"),
    ("make_srs", "unknown field", lambda: make_srs(combs=2), "no field 'combs'"),
    ("modulation", "unknown modulation", lambda: make_modulation("qam1024"),
     "modulation 'qam1024' is unknown"),
    ("tx_mode", "unknown mode", lambda: make_tx_mode("srs40"), "tx mode 'srs40' is unknown"),
    ("filter_type", "unknown filter", lambda: make_filter("zf"), "filter 'zf' is unknown"),
    ("check_scenario", "CP too short for the farthest target",
     lambda: nrsar.check_scenario(num(cp_samples=4), geo(), scn()), "cyclic prefix too short"),
    ("check_scenario", "target outside the swath (beyond c / (2 Delta f))",
     lambda: nrsar.check_scenario(num(cp_samples=80), geo(), scn((5500.0, 0.0))),
     "beyond the unambiguous range"),
    ("check_scenario", "normalised Doppler eta >= 0.1",
     lambda: nrsar.check_scenario(num(), geo(velocity_mps=900.0, carrier_hz=30e9), scn()),
     "normalised Doppler eta"),
    ("check_scenario", "zero symbols per pulse",
     lambda: nrsar.check_scenario(num(), geo(), scn(), 0), "symbols_per_pulse = 0"),
    ("graph", "vlen mismatch between connected blocks", connect_mismatch, "itemsize mismatch"),
    # nr_isac_tx
    ("nr_isac_tx", "seed above 31 bits", lambda: tx(seed=2**31), "seed = 2147483648"),
    ("nr_isac_tx", "invalid numerology", lambda: tx(num=num(fft_size=8)), "fft_size = 8"),
    ("nr_isac_tx", "SRS band beyond the grid",
     lambda: tx(mode=make_tx_mode("srs"), srs=srs(start_subcarrier=60)), "does not fit"),
    ("nr_isac_tx", "SRS comb offset >= comb",
     lambda: tx(mode=make_tx_mode("srs"), srs=srs(comb_offset=7)), "srs comb_offset = 7"),
    # scene_echo
    ("scene_echo", "SNR NaN", lambda: echo(snr_db=NAN), "snr_db = nan"),
    ("scene_echo", "SNR -inf", lambda: echo(snr_db=-INF), "snr_db = -inf"),
    ("scene_echo", "set_snr_db NaN", lambda: echo().set_snr_db(NAN), "snr_db = nan"),
    ("scene_echo", "empty scene", lambda: echo(s=nrsar.scene([])), "scene has no targets"),
    ("scene_echo", "set_scene with an empty scene", lambda: echo().set_scene(nrsar.scene([])),
     "scene has no targets"),
    ("scene_echo", "CP too short", lambda: echo(n=num(cp_samples=4)), "cyclic prefix too short"),
    ("scene_echo", "target outside the swath",
     lambda: echo(n=num(cp_samples=80), s=scn((5500.0, 0.0))), "beyond the unambiguous range"),
    ("scene_echo", "threads 0", lambda: echo().set_threads(0), "threads = 0"),
    ("scene_echo", "threads 3", lambda: echo().set_threads(3), "threads = 3"),
    # extended_scene_echo
    ("extended_scene_echo", "odd interpolation taps", lambda: ext(taps=7), "taps = 7"),
    ("extended_scene_echo", "taps above 32", lambda: ext(taps=40), "taps = 40"),
    ("extended_scene_echo", "oversampling below 1.25", lambda: ext(oversampling=1.0),
     "oversampling = 1"),
    ("extended_scene_echo", "SNR NaN", lambda: ext(snr_db=NAN), "snr_db = nan"),
    ("extended_scene_echo", "set_snr_db -inf", lambda: ext().set_snr_db(-INF), "snr_db = -inf"),
    ("extended_scene_echo", "map pixel spacing 0",
     lambda: nrsar.make_map(np.ones((2, 2)), 0.0, 1.0), "map.dx = 0"),
    ("extended_scene_echo", "negative map power",
     lambda: nrsar.make_map(-np.ones((2, 2)), 1.0, 1.0), "power"),
    ("extended_scene_echo", "map value NaN",
     lambda: nrsar.make_map(np.array([[1.0, NAN], [1.0, 1.0]]), 1.0, 1.0, kind="amplitude"),
     "nan"),
    ("extended_scene_echo", "map values not nx * ny", lambda: ext(maps=[bad_size_map()]),
     "map.values.size()"),
    ("extended_scene_echo", "map beyond the cyclic prefix",
     lambda: ext(maps=[nrsar.make_map(np.ones((2, 2)), 1.0, 1.0, 3000.0, 0.0)]),
     "cyclic prefix too short"),
    ("extended_scene_echo", "negative beam aperture",
     lambda: nrsar.make_beam("azimuth", az_aperture_m=-1.0), "beam.az_aperture_m = -1"),
    ("extended_scene_echo", "unknown beam mode", lambda: nrsar.make_beam("sideways"),
     "beam mode = 'sideways'"),
    # tf_filter
    ("tf_filter", "vlen 0", lambda: tf_filter(0), "vlen = 0"),
    ("tf_filter", "SNR NaN", lambda: tf_filter(64, make_filter("wf"), NAN), "snr_db = nan"),
    ("tf_filter", "SNR below -100 dB", lambda: tf_filter(64, make_filter("wf"), -200.0),
     "snr_db = -200"),
    ("tf_filter", "set_snr_db inf", lambda: tf_filter(64).set_snr_db(INF), "snr_db = inf"),
    # range_ifft
    ("range_ifft", "FFT size below N", lambda: rif(fft_size=32), "fft_size = 32"),
    ("range_ifft", "window parameter NaN", lambda: rif(window_param=NAN), "window_param = nan"),
    ("range_ifft", "set_window parameter inf",
     lambda: rif().set_window(WIN, INF), "window_param = inf"),
    ("range_ifft", "negative r_min", lambda: rif(r_min=-1.0), "r_min_m = -1"),
    ("range_ifft", "r_min beyond the unambiguous range", lambda: rif(r_min=6000.0),
     "r_min_m = 6000"),
    ("range_ifft", "r_max NaN", lambda: rif(r_max=NAN), "r_max_m = nan"),
    ("range_ifft", "r_max below r_min", lambda: rif(r_min=1000.0, r_max=900.0),
     "must be at least r_min_m"),
    ("range_ifft", "r_max beyond the unambiguous range", lambda: rif(r_max=6000.0),
     "r_max_m = 6000"),
    ("range_ifft", "crop without a bin", lambda: rif(r_min=1000.0, r_max=1001.0),
     "leaves no range bin"),
    ("range_ifft", "invalid numerology", lambda: rif(n=num(num_subcarriers=0)),
     "num_subcarriers = 0"),
    # rd_focuser
    ("rd_focuser", "no range bins", lambda: foc(k=0), "num_range_bins = 0"),
    ("rd_focuser", "negative first range", lambda: foc(first=-5.0), "first_range_m = -5"),
    ("rd_focuser", "first range NaN", lambda: foc(first=NAN), "first_range_m = nan"),
    ("rd_focuser", "negative range bin", lambda: foc(rho=-1.0), "range_bin_m = -1"),
    ("rd_focuser", "zero symbols per pulse", lambda: foc(c=cfg(symbols_per_pulse=0)),
     "symbols_per_pulse = 0"),
    ("rd_focuser", "overlap below -1", lambda: foc(c=cfg(overlap_lines=-2)),
     "overlap_lines = -2"),
    ("rd_focuser", "band margin NaN", lambda: foc(c=cfg(band_margin_hz=NAN)),
     "band_margin_hz = nan"),
    ("rd_focuser", "estimate threshold outside [1, 60] dB",
     lambda: foc(c=cfg(estimate_threshold_db=0.5)), "estimate_threshold_db = 0.5"),
    ("rd_focuser", "odd RCMC taps", lambda: foc(c=cfg(rcmc_taps=7)), "rcmc_taps = 7"),
    ("rd_focuser", "RCMC skip threshold outside [0, 1]",
     lambda: foc(c=cfg(rcmc_skip_below_bins=2.0)), "rcmc_skip_below_bins = 2"),
    ("rd_focuser", "range centre outside [-1, 1] cycles",
     lambda: foc(c=cfg(range_centre_cycles=1.5)), "range_centre_cycles = 1.5"),
    ("rd_focuser", "aperture shorter than 2 lines", lambda: foc(g=geo(aperture_s=1e-5)),
     "lines_per_aperture"),
    ("rd_focuser", "lines per aperture 1", lambda: foc(c=cfg(lines_per_aperture=1)),
     "lines_per_aperture = 1"),
    ("rd_focuser", "empty scene", lambda: foc(s=nrsar.scene([])), "scene has no targets"),
    ("rd_focuser", "invalid geometry", lambda: foc(g=geo(velocity_mps=0.0)), "velocity_mps = 0"),
    # nmse_probe
    ("nmse_probe", "vlen below 4", lambda: probe(vlen=3), "vlen = 3"),
    ("nmse_probe", "reference target RCS 0",
     lambda: probe(scn=scn((300.0, 0.0, 0.0), (250.0, 0.0))), "reference target rcs = 0"),
    ("nmse_probe", "SNR NaN", lambda: probe(snr_in_db=NAN), "snr_in_db = nan"),
    ("nmse_probe", "set_snr_in_db inf", lambda: probe().set_snr_in_db(INF), "snr_in_db = inf"),
    ("nmse_probe", "empty constellation", lambda: probe(constellation=[]),
     "constellation size"),
    ("nmse_probe", "constellation point 0", lambda: probe(constellation=[0j, 1 + 0j]),
     "constellation point"),
    ("nmse_probe", "negative range resolution", lambda: probe(range_resolution_m=-1.0),
     "range_resolution_m = -1"),
    ("nmse_probe", "azimuth resolution NaN", lambda: probe(azimuth_resolution_m=NAN),
     "azimuth_resolution_m = nan"),
    ("nmse_probe", "negative noise guard", lambda: probe(noise_guard_cells=-1.0),
     "noise_guard_cells = -1"),
    ("nmse_probe", "sidelobe window in (0, 2)", lambda: probe(sidelobe_window_cells=1.0),
     "sidelobe_window_cells = 1"),
    ("nmse_probe", "noise box of 3 values", lambda: probe(noise_box=[0.0, 1.0, 2.0]),
     "noise_box size = 3"),
    ("nmse_probe", "noise box NaN", lambda: probe(noise_box=[0.0, NAN, 0.0, 1.0]),
     "noise_box value = nan"),
    ("nmse_probe", "noise box r_max <= r_min", lambda: probe(noise_box=[5.0, 5.0, 0.0, 1.0]),
     "noise_box r_max = 5"),
    ("nmse_probe", "noise box y_max <= y_min", lambda: probe(noise_box=[0.0, 1.0, 3.0, 2.0]),
     "noise_box y_max = 2"),
    ("nmse_probe", "one aperture above 2^28 pixels",
     lambda: probe(vlen=2**16, lines_per_aperture=2**13), "lines_per_aperture * vlen"),
    ("nmse_probe", "empty scene", lambda: probe(scn=nrsar.scene([])), "scene has no targets"),
    ("nmse_probe", "band NaN", lambda: probe(band_lo_hz=NAN), "band_lo_hz = nan"),
    ("nmse_probe", "band_hi <= band_lo", lambda: probe(band_lo_hz=50.0, band_hi_hz=-50.0),
     "band_hi_hz = -50 must be > band_lo_hz"),
    # cheby_presum
    ("cheby_presum", "D = 0", lambda: presum(decim=0), "decim = 0"),
    ("cheby_presum", "D beyond the eq. (P-36) bound", lambda: presum(decim=100000),
     "decim = 100000"),
    ("cheby_presum", "no range bins", lambda: presum(num_bins=0), "num_bins = 0"),
    ("cheby_presum", "negative first range", lambda: presum(first_range_m=-1.0),
     "first_range_m = -1"),
    ("cheby_presum", "range bin 0", lambda: presum(range_bin_m=0.0), "range_bin_m = 0"),
    ("cheby_presum", "zero symbols per pulse", lambda: presum(symbols_per_pulse=0),
     "symbols_per_pulse = 0"),
    ("cheby_presum", "one tap", lambda: presum(num_taps=1), "num_taps = 1"),
    ("cheby_presum", "stopband weight 0", lambda: presum(stopband_weight=0.0),
     "stopband_weight = 0"),
    ("cheby_presum", "passband NaN", lambda: presum(passband_hz=NAN), "passband_hz = nan"),
    ("cheby_presum", "stopband above PRF / 2", lambda: presum(stopband_hz=1e6),
     "stopband_hz"),
    # fuzz: the scene text (C++ scene::parse) and the YAML scene file (scenes.py)
    ("scene", "target text with 5 fields", lambda: make_scene("1,2,3,4,5"),
     "target 0 '1,2,3,4,5': has 5 fields; must be X,Y[,RCS[,PHASE_DEG]]"),
    ("scene", "target field beyond a double", lambda: make_scene("300,100;1e999,0"),
     "target 1 '1e999,0': x_m '1e999' is out of the range of a double"),
    ("scene", "target phase not a number", lambda: make_scene("300,100,1,east"),
     "target 0 '300,100,1,east': phase_deg 'east' is not a number"),
    ("scene file", "bytes that are not UTF-8",
     lambda: _scene_file(b"targets:\n  - {x: 300, y: \xff}\n"),
     "scene.yaml:2: YAML syntax: character 0xff at byte 25: invalid start byte"),
    ("scene file", "nesting thousands deep", lambda: _scene_file(b"[" * 5000),
     "scene.yaml:1: YAML syntax: nesting too deep"),
    ("scene file", "mapping key that is a list",
     lambda: _scene_file(b"targets:\n  - {[x]: 300, y: 0}\n"),
     "scene.yaml:2: targets[0]: keys must be names"),
    ("scene file", "map seed beyond 64 bits",
     lambda: _scene_file(b"maps:\n  - {file: m.npy, dx: 1, dy: 1, seed: 1e30}\n"),
     "scene.yaml:2: maps[0].seed: 1e30 must be an integer from 0 to 18446744073709551615"),
    ("srs_config", "band end beyond 2^32 (wrapped around before)",
     lambda: make_srs(start_subcarrier=4294967048, num_rb=255).validate(num()),
     "srs band [4294967048, 4294970108) does not fit the 64 subcarriers"),
    # td_echo
    ("td_echo", "odd delay-filter taps", lambda: nrsar.td_echo(num(), geo(), scn(), taps=7),
     "taps = 7"),
    ("td_echo", "delay-filter taps 0", lambda: nrsar.td_echo(num(), geo(), scn(), taps=0),
     "taps = 0"),
    ("td_echo", "delay-filter taps above 256",
     lambda: nrsar.td_echo(num(), geo(), scn(), taps=258), "taps = 258"),
    ("td_echo", "Kaiser beta above 50",
     lambda: nrsar.td_echo(num(), geo(), scn(), kaiser_beta=60.0), "kaiser_beta = 60"),
    ("td_echo", "SNR NaN", lambda: nrsar.td_echo(num(), geo(), scn(), NAN), "snr_db = nan"),
    ("td_echo", "set_snr_db -inf", lambda: nrsar.td_echo(num(), geo(), scn()).set_snr_db(-INF),
     "snr_db = -inf"),
    ("td_echo", "round trip beyond the CP",
     lambda: nrsar.td_echo(num(cp_samples=4), geo(), scn()), "cyclic prefix too short"),
    ("td_echo", "set_scene with an empty scene",
     lambda: nrsar.td_echo(num(), geo(), scn()).set_scene(nrsar.scene([])),
     "scene has no targets"),
    ("td_echo", "negative beam aperture", lambda: nrsar.td_echo(num(), geo(), scn(), beam=bad_beam()),
     "beam.az_aperture_m = -1"),
    # ofdm_mod / ofdm_demod / ofdm_sync
    ("ofdm_mod", "FFT smaller than N", lambda: nrsar.ofdm_mod(num(fft_size=32)),
     "fft_size = 32 must be at least num_subcarriers = 64"),
    ("ofdm_demod", "FFT window beyond the CP", lambda: nrsar.ofdm_demod(num(), 17),
     "fft_start = 17 must be at most cp_samples = 16"),
    ("ofdm_sync", "no DMRS", lambda: nrsar.ofdm_sync(num(), make_dmrs("none")),
     "ofdm_sync needs at least one DMRS symbol"),
    ("ofdm_sync", "threshold 0", lambda: nrsar.ofdm_sync(num(), make_dmrs("pusch2"), 0.0),
     "threshold = 0 must be in (0, 1)"),
    ("ofdm_sync", "threshold 1", lambda: nrsar.ofdm_sync(num(), make_dmrs("pusch2"), 1.0),
     "threshold = 1 must be in (0, 1)"),
    ("ofdm_sync", "threshold NaN", lambda: nrsar.ofdm_sync(num(), make_dmrs("pusch2"), NAN),
     "threshold = nan"),
    ("ofdm_sync", "backoff 1", lambda: nrsar.ofdm_sync(num(), make_dmrs("pusch2"), 0.1, 1.0),
     "backoff = 1 must be in [0, 1)"),
    ("ofdm_sync", "negative backoff",
     lambda: nrsar.ofdm_sync(num(), make_dmrs("pusch2"), 0.1, -0.5), "backoff = -0.5"),
    ("ofdm_sync", "odd FFT size",
     lambda: nrsar.ofdm_sync(num(num_subcarriers=63, fft_size=65), make_dmrs("pusch2")),
     "fft_size = 65 must be even"),
    ("ofdm_sync", "DMRS symbol beyond the slot",
     lambda: nrsar.ofdm_sync(num(), make_dmrs([2, 14])), "dmrs symbols = 14"),
    # pusch_encoder
    ("pusch_encoder", "queue size 0",
     lambda: nrsar.pusch_encoder(pusch(max_queued_bytes=0)), "max_queued_bytes = 0"),
    ("pusch_encoder", "modulation without soft demapper",
     lambda: nrsar.pusch_encoder(pusch(mod=make_modulation("psk8"))),
     "is not decodable by pusch_receiver"),
    ("pusch_encoder", "MCS beyond the qam256 table",
     lambda: nrsar.pusch_encoder(pusch(mcs=28)), "mcs = 28 must be in [0, 27]"),
    ("pusch_encoder", "MCS of another modulation",
     lambda: nrsar.pusch_encoder(pusch(mcs=27)),
     "mcs = 27 of mcs_table qam256 has Qm = 8 but mod has 4 bits per symbol"),
    ("pusch_encoder", "unknown MCS table",
     lambda: nrsar.pusch_encoder(pusch(mcs_table="qam1024")), "mcs_table = 'qam1024'"),
    ("pusch_encoder", "redundancy version 4",
     lambda: nrsar.pusch_encoder(pusch(rv=4)), "rv = 4 must be in [0, 3]"),
    ("pusch_encoder", "3 repetitions",
     lambda: nrsar.pusch_encoder(pusch(repetitions=3)), "repetitions = 3 must be 1, 2, 4 or 8"),
    ("pusch_encoder", "n_RNTI beyond 16 bits",
     lambda: nrsar.pusch_encoder(pusch(n_rnti=65536)), "n_rnti = 65536 must be in [0, 65535]"),
    ("pusch_encoder", "n_ID beyond 1023",
     lambda: nrsar.pusch_encoder(pusch(n_id=1024)), "n_id = 1024 must be in [0, 1023]"),
    ("pusch_encoder", "grid without one PRB",
     lambda: nrsar.pusch_encoder(pusch(num=num(num_subcarriers=8))),
     "num_subcarriers = 8 must hold one PRB (12) for NR_LDPC"),
    ("nr_isac_tx", "SRS symbol on a DMRS symbol",
     lambda: nr_isac_tx(num(), make_modulation("qpsk"), make_tx_mode("data_srs"),
                        srs(symbol_in_slot=2), 0, make_dmrs("pusch2")),
     "srs symbol_in_slot = 2 must not be a DMRS symbol"),
    # pusch_receiver
    ("pusch_receiver", "dmrs none",
     lambda: nrsar.pusch_receiver(pusch(dmrs=make_dmrs("none"))),
     "dmrs symbols = 0 must list at least one DMRS symbol"),
    ("pusch_receiver", "modulation without soft demapper",
     lambda: nrsar.pusch_receiver(pusch(mod=make_modulation("psk16"))), "has no soft demapper"),
    ("pusch_receiver", "even frequency window",
     lambda: nrsar.pusch_receiver(pusch(freq_window=4)), "freq_window = 4 must be odd and >= 1"),
    ("pusch_receiver", "zero LDPC iterations",
     lambda: nrsar.pusch_receiver(pusch(max_iterations=0)), "max_iterations = 0"),
    ("pusch_receiver", "fewer than 6 subcarriers",
     lambda: nrsar.pusch_receiver(pusch(num=num(num_subcarriers=4, fft_size=64),
                                        mod=make_modulation("qpsk"), mcs=4)),
     "num_subcarriers = 4"),
    # image_sink
    ("image_sink", "empty file prefix", lambda: nrsar.image_sink(8, ""), "prefix = ''"),
    ("image_sink", "prefix folder missing",
     lambda: nrsar.image_sink(8, "/nonexistent_nrsar_folder/img"), "does not exist"),
    ("image_sink", "prefix ends with /", lambda: nrsar.image_sink(8, "/tmp/"), "add a file name"),
    ("image_sink", "neither npy nor png",
     lambda: nrsar.image_sink(8, "/tmp/nrsar_rule", write_npy=False, write_png=False),
     "nothing to write"),
    ("image_sink", "dynamic range 0",
     lambda: nrsar.image_sink(8, "/tmp/nrsar_rule", dynamic_range_db=0.0), "dynamic_range_db = 0"),
    ("image_sink", "dynamic range NaN",
     lambda: nrsar.image_sink(8, "/tmp/nrsar_rule", dynamic_range_db=NAN), "dynamic_range_db = nan"),
    ("image_sink", "keep 0 files", lambda: nrsar.image_sink(8, "/tmp/nrsar_rule", keep=0), "keep = 0"),
    ("image_sink", "no range bins", lambda: nrsar.image_sink(0, "/tmp/nrsar_rule"),
     "num_range_bins = 0"),
    # perf
    ("tf_filter", "threads 3", lambda: tf_filter(64).set_threads(3), "threads = 3"),
    ("range_ifft", "threads 0",
     lambda: range_ifft(make_numerology("tiny")).set_threads(0), "threads = 0"),
    # ofdm_demod rx_time alignment (sdr)
    ("ofdm_demod", "TX start time NaN", lambda: nrsar.ofdm_demod(num(), -1, NAN),
     "tx_start_time = nan must be a finite time"),
    ("ofdm_demod", "set_tx_start_time +inf",
     lambda: nrsar.ofdm_demod(num()).set_tx_start_time(INF), "tx_start_time = inf"),
    # guard (rd_focuser guard bins)
    ("rd_focuser", "guard bins half the range bins",
     lambda: foc(k=16, c=focuser_config(guard_bins=8)), "guard_bins = 8 must be below"),
    # a prefix under a regular file (the interpreter): fails for every user, root included
    ("image_sink", "prefix folder is a file",
     lambda: nrsar.image_sink(8, sys.executable + "/img"), "is not a folder"),
    # bp_focuser's GCP gate on e_y (docs/blocks/bp_focuser.md, "Solving e_y")
    ("bp_config", "along-track GCP gate above 1 m",
     lambda: nrsar.bp_config(autofocus_gcp_along_track_se_m=1.5).validate(),
     "autofocus_gcp_along_track_se_m = 1.5 must be in [0, 1]"),
    # and on the along-track speed error d_y ("The along-track speed")
    ("bp_config", "along-track speed GCP gate negative",
     lambda: nrsar.bp_config(autofocus_gcp_speed_se_mps=-0.1).validate(),
     "autofocus_gcp_speed_se_mps = -0.1 must be in [0, 1]"),
]


def _scene_file(data):
    """fuzz: loads data as a YAML scene file next to a 2 x 2 map m.npy."""
    import os
    import tempfile
    from gnuradio.nrsar import scenes
    cwd = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="qa_param_rules_") as folder:
        try:  # a relative path, so the message (docs/robustness.md) does not change
            os.chdir(folder)
            np.save("m.npy", np.ones((2, 2), np.float32))
            with open("scene.yaml", "wb") as f:
                f.write(data)
            return scenes.load_scene_file("scene.yaml")
        finally:
            os.chdir(cwd)


def slug(subject, rule):
    text = f"{subject}_{rule}".lower()
    return "".join(c if c.isalnum() else "_" for c in text).strip("_").replace("__", "_")


def message_of(call):
    try:
        call()
    except Exception as e:  # noqa: BLE001 (the table reports what the user really gets)
        return type(e).__name__, str(e)
    return None, None


class qa_param_rules(gr_unittest.TestCase):
    pass


def _make_test(call, fragment):
    def test(self):
        with self.assertRaises(ValueError) as ctx:
            call()
        self.assertIn(fragment, str(ctx.exception))
    return test


for _i, (_subject, _rule, _call, _fragment) in enumerate(RULES):
    setattr(qa_param_rules, f"test_{_i:03d}_{slug(_subject, _rule)}",
            _make_test(_call, _fragment))


def markdown():
    """The rows of docs/robustness.md's parameter table."""
    lines = ["| # | subject | rule broken | what the user gets | test |",
             "|---|---|---|---|---|"]
    for i, (subject, rule, call, _) in enumerate(RULES):
        kind, text = message_of(call)
        got = f"`{kind}`: {text}" if kind else "(no error)"
        got = got.replace("|", "\\|").replace("\n", " ")
        name = f"test_{i:03d}_{slug(subject, rule)}"
        lines.append(f"| {i} | {subject} | {rule} | {got} | qa_param_rules.py::{name} |")
    return "\n".join(lines)


if __name__ == "__main__":
    if "--markdown" in sys.argv:
        # GNU Radio logs to stdout: off, or a block's warnings land in the table
        gr.logging().set_default_level(gr.log_levels.off)
        print(markdown())
    else:
        gr_unittest.run(qa_param_rules)
