#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of rd_focuser: range-Doppler focusing of synthetic range-compressed point targets.

The input is the exact range-compressed echo of eqs. (8), (29), evaluated in numpy float64
(no other block of the chain is used); the references are the SPEC's formulas: the true
target position, the sinc figures of SPEC 8 (IRW 0.886 cells, PSLR -13.26 dB, ISLR -9.68 dB),
the stationary-phase peak sqrt(N) sqrt(M_t B_t T) of the unitary chain, and the band
fraction for white noise.
"""

import math

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest

try:
    from gnuradio import nrsar
except ImportError:
    import os
    import sys
    dirname, filename = os.path.split(os.path.abspath(__file__))
    sys.path.append(os.path.join(dirname, "..", "bindings"))
    from gnuradio import nrsar

from gnuradio.nrsar import chain
from gnuradio.nrsar.focus_scenario import (LAM, V, H, N_SUB, NFFT, RHO, K, R_FIRST, SPP,
                                          NUM, T, geometry, echo)


def doppler(x, y, yp):
    r = np.sqrt(x * x + H * H + (y - yp) ** 2)
    return 2 * V * (y - yp) / (LAM * r)


def upsample_abs(cut, factor):
    """|cut| interpolated by zero padding its spectrum in the gap of the occupied band (the
    range spectrum of eq. (29) is not centred at 0, so the padding goes where it is empty)."""
    n = len(cut)
    spec = np.fft.fft(cut)
    p = np.abs(spec) ** 2
    w = max(1, n // 16)
    smooth = np.convolve(np.concatenate([p, p[:w]]), np.ones(w), "valid")[:n]
    gap = (int(np.argmin(smooth)) + w // 2) % n
    spec = np.roll(spec, -gap - 1)  # the emptiest bin last
    padded = np.concatenate([spec, np.zeros(n * (factor - 1))])
    return np.abs(np.fft.ifft(padded)) * factor


def cut_metrics(cut, factor=32):
    """Peak position [samples], IRW [samples], PSLR [dB], ISLR [dB] of a (circular) cut."""
    a = upsample_abs(cut, factor)
    n = len(a)
    i0 = int(np.argmax(a))
    a = np.roll(a, n // 2 - i0)  # peak in the middle
    c = n // 2
    p2 = a ** 2
    half = p2[c] / 2
    lo = c
    while p2[lo - 1] > half:
        lo -= 1
    hi = c
    while p2[hi + 1] > half:
        hi += 1
    # linear interpolation of the -3 dB crossings
    x_lo = lo - (p2[lo] - half) / (p2[lo] - p2[lo - 1])
    x_hi = hi + (p2[hi] - half) / (p2[hi] - p2[hi + 1])
    irw = (x_hi - x_lo) / factor
    # first nulls
    nl = c
    while a[nl - 1] < a[nl]:
        nl -= 1
    nr = c
    while a[nr + 1] < a[nr]:
        nr += 1
    main = p2[nl:nr + 1].sum()
    side = p2.sum() - main
    pslr = 10 * np.log10(max(p2[:nl].max(), p2[nr + 1:].max()) / p2[c])
    islr = 10 * np.log10(side / main)
    # sub-sample peak by a parabola through the upsampled maximum
    y0, y1, y2 = a[c - 1], a[c], a[c + 1]
    frac = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
    peak = ((i0 + frac) / factor) % len(cut)
    return peak, irw, pslr, islr


def run_block(data, num=NUM, geo=None, scn=None, cfg=None, tags=(), first_range=R_FIRST,
              range_bin=RHO):
    cfg = cfg or nrsar.focuser_config()
    blk = nrsar.rd_focuser(num, geo, scn, K, first_range, range_bin, cfg)
    src = blocks.vector_source_c(np.asarray(data, np.complex64).ravel().tolist(), False, K,
                                 list(tags))
    snk = blocks.vector_sink_c(K)
    tb = gr.top_block()
    tb.connect(src, blk, snk)
    tb.run()
    img = np.array(snk.data(), complex).reshape(-1, K)
    return blk, img, snk.tags()


def first_line_y(tags):
    """Along-track position [m] of output line 0, from the first azimuth_axis tag."""
    for t in tags:
        if pmt.symbol_to_string(t.key) == nrsar.tag_keys.azimuth_axis and t.offset == 0:
            return pmt.to_double(pmt.tuple_ref(t.value, 0))
    raise AssertionError("no azimuth_axis tag on line 0")


def tag_map(tags):
    out = {}
    for t in tags:
        out.setdefault(pmt.symbol_to_string(t.key), []).append((t.offset, t.value))
    return out


def predicted_peak(x, y, yp0, yp1):
    """Stationary-phase peak of a unit target illuminated from yp0 to yp1 (unitary chain):
    sqrt(N) sqrt(M_t B_t T), B_t its Doppler bandwidth."""
    m_t = (yp1 - yp0) / (V * T)
    b_t = abs(doppler(x, y, yp0) - doppler(x, y, yp1))
    return math.sqrt(N_SUB) * math.sqrt(m_t * b_t * T)


class qa_rd_focuser(gr_unittest.TestCase):

    def cfg(self, **kw):
        c = nrsar.focuser_config()
        c.symbols_per_pulse = SPP
        for k, v in kw.items():
            setattr(c, k, v)
        return c

    def centred_case(self):
        """480 lines (60 m), unit target at R0 = 1000 m (on bin 30) abeam of the middle."""
        m = 480
        y = V * T * m / 2
        return (m, y, geometry(m * T), nrsar.make_scene([(800.0, y)]),
                echo([(800.0, y, 1.0)], m))

    # -- position, scaling, RCMC ------------------------------------------------------
    def test_001_position_off_grid_and_off_centre_band(self):
        # Target ahead of the track (like the paper: band [8, 41] Hz, not centred at 0),
        # off the range grid; it focuses 80 lines after the last pulse (zero-Doppler line
        # 560 of the pulses), inside the aperture's window shifted by line_shift().
        m = 480
        x = math.sqrt((R_FIRST + 30.37 * RHO) ** 2 - H * H)
        y = 70.13
        data = echo([(x, y, 1.0)], m)
        geo = geometry(m * T)
        scn = nrsar.make_scene([(x, y)])
        blk, img, tags = run_block(data, geo=geo, scn=scn, cfg=self.cfg())
        self.assertGreater(blk.band_lo_hz(), 0.0)  # band not centred at 0
        self.assertEqual(img.shape[0], m)  # the pulses of one aperture: one aperture out
        self.assertGreater(blk.line_shift(), 100)
        y0 = first_line_y(tags)
        self.assertAlmostEqual(y0, blk.line_shift() * V * T)
        i, k = np.unravel_index(np.argmax(np.abs(img)), img.shape)
        az, _, _, _ = cut_metrics(img[:, k])
        rg, _, _, _ = cut_metrics(img[i, :])
        true_line = (y - y0) / (V * T)
        true_bin = (math.hypot(x, H) - R_FIRST) / RHO
        res_az = V / abs(doppler(x, y, 0) - doppler(x, y, V * m * T)) / (V * T)  # lines
        res_rg = NFFT / N_SUB  # bins
        self.assertLess(abs(az - true_line), 0.25 * res_az)
        self.assertLess(abs(rg - true_bin), 0.25 * res_rg)

    def test_002_rcmc_straightens_migration_and_peak_scaling(self):
        # R0 = 1000 m, 200 m aperture centred on the target: 3.3 bins of migration.
        m = 1600
        y = 100.0
        geo = geometry(m * T)
        scn = nrsar.make_scene([(800.0, y)])
        data = echo([(800.0, y, 1.0)], m)
        blk, img, tags = run_block(data, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0))
        self.assertTrue(blk.rcmc_applied())
        mig = 1000.0 * (1 / math.sqrt(1 - (LAM * doppler(800, y, 0) / (2 * V)) ** 2) - 1) / RHO
        self.assertGreater(mig, 3.0)
        self.assertGreater(blk.max_migration_bins(), mig)
        peak = np.abs(img).max()
        pred = predicted_peak(800.0, y, 0.0, V * m * T)
        self.assertAlmostEqual(20 * math.log10(peak / pred), 0.0, delta=0.5)
        i, k = np.unravel_index(np.argmax(np.abs(img)), img.shape)
        self.assertEqual(k, 30)
        self.assertLess(abs(i - (y - first_line_y(tags)) / (V * T)), 1.0)
        # Without RCMC the migrated energy is lost from the target's range bin.
        _, img2, _ = run_block(data, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0, rcmc=False))
        self.assertLess(20 * math.log10(np.abs(img2).max() / peak), -1.0)

    # -- impulse response ---------------------------------------------------------------
    def test_003_irw_pslr_islr_match_sinc(self):
        # Unweighted chain, short aperture (band +-35 Hz) so that Ka is constant over the
        # range sidelobes; one circular aperture, target in the middle, on a range bin.
        m, y, geo, scn, data = self.centred_case()
        _, img, _ = run_block(data, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0))
        i, k = np.unravel_index(np.argmax(np.abs(img)), img.shape)
        _, irw_a, pslr_a, islr_a = cut_metrics(img[:, k])
        _, irw_r, pslr_r, islr_r = cut_metrics(img[i, :])
        b_t = doppler(800.0, y, 0.0) - doppler(800.0, y, V * m * T)
        cell_a = 1.0 / (b_t * T)   # lines per azimuth resolution cell v / B_t
        cell_r = NFFT / N_SUB      # bins per range resolution cell c / (2 B)
        for name, got, ref in [("IRW az", irw_a / cell_a, 0.886), ("IRW rg", irw_r / cell_r, 0.886),
                               ("PSLR az", pslr_a, -13.26), ("PSLR rg", pslr_r, -13.26),
                               ("ISLR az", islr_a, -9.68), ("ISLR rg", islr_r, -9.68)]:
            self.assertLess(abs(got / ref - 1.0), 0.05, f"{name}: {got:.3f} vs {ref}")

    def test_003b_rcmc_skipped_below_threshold(self):
        # Band +-45 Hz at R0 = 1000 m: at most about 0.6 bins of migration.
        m, y, geo, scn, data = self.centred_case()
        blk, img, _ = run_block(data, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0))
        self.assertTrue(blk.rcmc_applied())
        self.assertLess(blk.max_migration_bins(), 1.0)
        blk2, img2, _ = run_block(data, geo=geo, scn=scn,
                                  cfg=self.cfg(overlap_lines=0, rcmc_skip_below_bins=1.0))
        self.assertFalse(blk2.rcmc_applied())
        self.assertAlmostEqual(20 * math.log10(np.abs(img2).max() / np.abs(img).max()), 0.0,
                               delta=0.3)

    # -- band restriction ------------------------------------------------------------
    def test_004_scene_band_same_peak_less_noise(self):
        m, y, geo, scn, data = self.centred_case()
        blk_s, img_s, _ = run_block(data, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0))
        _, img_f, _ = run_block(data, geo=geo, scn=scn,
                                cfg=self.cfg(overlap_lines=0, band=nrsar.doppler_band.FULL))
        self.assertAlmostEqual(20 * math.log10(np.abs(img_s).max() / np.abs(img_f).max()),
                               0.0, delta=0.1)
        # White noise alone (RCMC off so that nothing leaves the range window): the image
        # power is the input power times the processed fraction of the Doppler bins.
        rng = np.random.default_rng(5)
        noise = (rng.standard_normal((m, K)) + 1j * rng.standard_normal((m, K))) / math.sqrt(2)
        blk_n, img_ns, _ = run_block(noise, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0, rcmc=False))
        _, img_nf, _ = run_block(noise, geo=geo, scn=scn,
                                 cfg=self.cfg(overlap_lines=0, rcmc=False,
                                              band=nrsar.doppler_band.FULL))
        fraction = (blk_n.band_hi_hz() - blk_n.band_lo_hz()) * T  # band / PRF
        ratio_db = 10 * math.log10(np.mean(np.abs(img_ns) ** 2) / np.mean(np.abs(img_nf) ** 2))
        self.assertLess(ratio_db, -3.0)
        self.assertAlmostEqual(ratio_db, 10 * math.log10(fraction), delta=0.5)
        self.assertAlmostEqual(np.mean(np.abs(img_nf) ** 2), 1.0, delta=0.05)  # unitary

    def test_005_estimated_band(self):
        m, y, geo, scn, data = self.centred_case()
        rng = np.random.default_rng(9)
        data += 0.3 * (rng.standard_normal(data.shape) + 1j * rng.standard_normal(data.shape))
        blk, img_e, _ = run_block(data, geo=geo, scn=scn,
                                  cfg=self.cfg(overlap_lines=0, band=nrsar.doppler_band.ESTIMATE))
        f0, f1 = doppler(800.0, y, V * m * T), doppler(800.0, y, 0.0)
        b = f1 - f0
        self.assertLess(blk.band_lo_hz(), f0 + 0.05 * b)
        self.assertGreater(blk.band_hi_hz(), f1 - 0.05 * b)
        self.assertLess(blk.band_hi_hz() - blk.band_lo_hz(), 2.0 * b)
        _, img_s, _ = run_block(data, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0))
        self.assertAlmostEqual(20 * math.log10(np.abs(img_e).max() / np.abs(img_s).max()),
                               0.0, delta=0.2)

    # -- tags and streaming ------------------------------------------------------------
    def test_006_tags_and_axis_from_tags(self):
        m = 200
        t_tag = 2.0e-3  # a presummer's new pulse interval overrides num.symbol_s() * SPP
        r_tag = R_FIRST - 3 * RHO
        y = 10.0  # line 100 of the first aperture; illuminated over lines 50..150 only
        data = echo([(800.0, y, 1.0)], 2 * m, t_pulse=t_tag, illum=5.0)
        # The generator's bins are referenced to R_FIRST; shift them into the tagged axis.
        data = np.roll(data, 3, axis=1)
        geo = geometry(m * t_tag)
        scn = nrsar.make_scene([(800.0, y)])
        tags = [gr.tag_utils.python_to_tag((0, pmt.intern(nrsar.tag_keys.pulse_interval),
                                            pmt.from_double(t_tag))),
                gr.tag_utils.python_to_tag((0, pmt.intern(nrsar.tag_keys.range_axis),
                                            pmt.make_tuple(pmt.from_double(r_tag),
                                                           pmt.from_double(RHO),
                                                           pmt.from_uint64(K))))]
        blk, img, out_tags = run_block(data, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0),
                                       tags=tags)
        self.assertEqual(blk.lines_per_aperture(), m)
        self.assertAlmostEqual(blk.pulse_interval_s(), t_tag)
        self.assertEqual(img.shape[0], 2 * m)
        tm = tag_map(out_tags)
        self.assertEqual([o for o, _ in tm[nrsar.tag_keys.aperture]], [0, m])
        self.assertEqual([pmt.to_uint64(v) for _, v in tm[nrsar.tag_keys.aperture]], [0, 1])
        y0 = first_line_y(out_tags)
        self.assertAlmostEqual(y0, blk.line_shift() * V * t_tag)
        for idx, (off, val) in enumerate(tm[nrsar.tag_keys.azimuth_axis]):
            self.assertEqual(off, idx * m)
            self.assertAlmostEqual(pmt.to_double(pmt.tuple_ref(val, 0)), y0 + idx * m * V * t_tag)
            self.assertAlmostEqual(pmt.to_double(pmt.tuple_ref(val, 1)), V * t_tag)
            self.assertEqual(pmt.to_uint64(pmt.tuple_ref(val, 2)), m)
        for off, val in tm[nrsar.tag_keys.range_axis]:
            self.assertAlmostEqual(pmt.to_double(pmt.tuple_ref(val, 0)), r_tag)
            self.assertAlmostEqual(pmt.to_double(pmt.tuple_ref(val, 1)), RHO)
            self.assertEqual(pmt.to_uint64(pmt.tuple_ref(val, 2)), K)
        i, k = np.unravel_index(np.argmax(np.abs(img)), img.shape)
        self.assertEqual(k, 33)  # 1000 m on the tagged axis
        self.assertLess(abs(i - (y - y0) / (V * t_tag)), 1.0)

    def test_006b_tags_at_start_with_overlap_and_shift(self):
        # Off-centre band (target ahead of the track), automatic overlap, the pulse interval
        # from a tag on item 0: the framing follows the tagged interval.
        m = 300
        t_tag = 2.0e-3
        x = math.sqrt((R_FIRST + 30.0 * RHO) ** 2 - H * H)
        y = 45.0
        data = echo([(x, y, 1.0)], m, t_pulse=t_tag)
        geo = geometry(m * t_tag)
        scn = nrsar.make_scene([(x, y)])
        tags = [gr.tag_utils.python_to_tag((0, pmt.intern(nrsar.tag_keys.pulse_interval),
                                            pmt.from_double(t_tag)))]
        blk, img, out_tags = run_block(data, geo=geo, scn=scn, cfg=self.cfg(), tags=tags)
        self.assertGreater(blk.line_shift(), 50)
        self.assertGreater(blk.overlap_before(), 0)
        self.assertEqual(img.shape[0], m)
        y0 = first_line_y(out_tags)
        self.assertAlmostEqual(y0, blk.line_shift() * V * t_tag)
        i, k = np.unravel_index(np.argmax(np.abs(img)), img.shape)
        self.assertEqual(k, 30)
        self.assertLess(abs(i - (y - y0) / (V * t_tag)), 1.0)
        pred = math.sqrt(N_SUB) * math.sqrt(
            m * abs(doppler(x, y, 0) - doppler(x, y, V * m * t_tag)) * t_tag)
        self.assertAlmostEqual(20 * math.log10(np.abs(img).max() / pred), 0.0, delta=0.5)

    def test_006c_bad_axis_tags_are_ignored(self):
        # A range_axis tuple for another K, a malformed one and a negative pulse interval:
        # warnings, the constructor's axis stays, nothing crashes.
        m = 100
        geo = geometry(m * T)
        scn = nrsar.make_scene([(800.0, 6.0)])
        data = echo([(800.0, 6.0, 1.0)], m)
        key_r = pmt.intern(nrsar.tag_keys.range_axis)
        tags = [gr.tag_utils.python_to_tag((0, key_r, pmt.make_tuple(
                    pmt.from_double(1.0), pmt.from_double(2.0), pmt.from_uint64(K + 1)))),
                gr.tag_utils.python_to_tag((0, key_r, pmt.make_tuple(
                    pmt.intern("x"), pmt.from_double(2.0), pmt.from_uint64(K)))),
                gr.tag_utils.python_to_tag((0, pmt.intern(nrsar.tag_keys.pulse_interval),
                                            pmt.from_double(-1.0)))]
        blk, img, out_tags = run_block(data, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0),
                                       tags=tags)
        self.assertEqual(img.shape[0], m)
        self.assertAlmostEqual(blk.first_range_m(), R_FIRST)
        self.assertAlmostEqual(blk.pulse_interval_s(), T)
        val = tag_map(out_tags)[nrsar.tag_keys.range_axis][0][1]
        self.assertAlmostEqual(pmt.to_double(pmt.tuple_ref(val, 0)), R_FIRST)

    def test_007_streaming_two_and_a_half_apertures(self):
        # Targets illuminated over the whole strip; one straddles the first aperture
        # boundary and one sits in the half aperture the flush emits (lines relative to
        # the first output line, y0 = line_shift() v T).
        m = 400
        n_lines = 1000
        strip = V * T * n_lines
        geo = geometry(n_lines * T)  # the scene band over the whole strip
        ys_probe = [20.0, 62.5, 100.0]
        probe = nrsar.rd_focuser(NUM, geo, nrsar.make_scene([(800.0, y) for y in ys_probe]), K,
                                 R_FIRST, RHO, self.cfg(lines_per_aperture=m))
        y0 = probe.line_shift() * V * T
        ys = [y0 + 30.0 * V * T, y0 + 399.6 * V * T, y0 + 900.2 * V * T]
        targets = [(800.0, y, 1.0) for y in ys]
        data = echo(targets, n_lines)
        scn = nrsar.make_scene([(800.0, y) for y in ys_probe])
        blk, img, out_tags = run_block(data, geo=geo, scn=scn,
                                       cfg=self.cfg(lines_per_aperture=m))
        self.assertAlmostEqual(first_line_y(out_tags), y0)
        self.assertGreater(blk.overlap_before(), 0)
        self.assertEqual(img.shape[0], 3 * m)  # apertures whose pulses arrived
        tm = tag_map(out_tags)
        self.assertEqual([o for o, _ in tm[nrsar.tag_keys.aperture]],
                         list(range(0, img.shape[0], m)))
        col = img[:, 30]
        for y in ys:
            line = (y - y0) / (V * T)
            lo = int(line) - 20
            seg = np.abs(col[lo:lo + 41])
            got = lo + int(np.argmax(seg))
            self.assertLess(abs(got - line), 1.0)
            pred = predicted_peak(800.0, y, 0.0, strip)
            self.assertAlmostEqual(20 * math.log10(seg.max() / pred), 0.0, delta=0.6,
                                   msg=f"target at line {line}")

    def test_007c_range_doppler_map_port(self):
        # The optional rd_map port: per aperture band_bins() lines in ascending Doppler, after
        # RCMC (a target is a straight line at its closest-approach range bin), tagged; the
        # image is the same whether the port is connected or not.
        m = 400
        n_lines = 1000
        geo = geometry(n_lines * T)
        ys = [40.0, 100.0]
        scn = nrsar.make_scene([(800.0, y) for y in ys])
        data = echo([(800.0, y, 1.0) for y in ys], n_lines)
        cfg = self.cfg(lines_per_aperture=m, rcmc_skip_below_bins=0.0)
        _, img_alone, _ = run_block(data, geo=geo, scn=scn, cfg=cfg)
        blk = nrsar.rd_focuser(NUM, geo, scn, K, R_FIRST, RHO, cfg)
        src = blocks.vector_source_c(np.asarray(data, np.complex64).ravel().tolist(), False, K)
        snk = blocks.vector_sink_c(K)
        rd = blocks.vector_sink_c(K)
        tb = gr.top_block()
        tb.connect(src, blk, snk)
        tb.connect((blk, 1), rd)
        tb.run()
        img = np.array(snk.data(), complex).reshape(-1, K)
        np.testing.assert_array_equal(img, img_alone)
        rdm = np.array(rd.data(), complex).reshape(-1, K)
        b = blk.band_bins()
        self.assertEqual(rdm.shape[0], 3 * b)  # one map per aperture
        tm = tag_map(rd.tags())
        self.assertEqual([o for o, _ in tm[nrsar.tag_keys.aperture]], [0, b, 2 * b])
        self.assertEqual([pmt.to_uint64(v) for _, v in tm[nrsar.tag_keys.aperture]], [0, 1, 2])
        f0, df, nb = pmt.to_python(tm[nrsar.tag_keys.doppler_axis][0][1])
        self.assertEqual(nb, b)
        self.assertAlmostEqual(df, 1.0 / (blk.fft_size() * T))
        # The lines cover the processed band in ascending Doppler.
        self.assertAlmostEqual(f0, blk.band_lo_hz(), delta=df)
        self.assertLessEqual(f0 + (b - 1) * df, blk.band_hi_hz() + df)
        # Straight after RCMC: every strong Doppler line peaks at the targets' range bin
        # (closest approach sqrt(x^2 + H^2) = 1000 m = bin 30).
        k_true = (math.sqrt(800.0 ** 2 + H ** 2) - R_FIRST) / RHO
        a = np.abs(rdm[b:2 * b])
        strong = a.max(axis=1) > 0.3 * a.max()
        self.assertGreater(strong.sum(), b // 4)
        self.assertLessEqual(np.abs(a[strong].argmax(axis=1) - k_true).max(), 1.0)

    def test_007d_memory_estimate_counts_the_kernels_doppler_bins(self):
        # chain.memory_estimate_bytes before the run (no kernel built yet) takes as many band
        # bins as the kernel processes in it, and these are the FFT bins j / (nfft T) inside
        # [lo, hi] (every bin for FULL; at least one). The band edges' old Python count,
        # ceil((hi - lo) nfft T) + 1, said 246, 173 and 3 for the first three.
        m = 480
        y = V * T * m / 2
        rif = type("range_bins", (), {"num_bins": staticmethod(lambda: K)})
        for target, kw in (((800.0, y), {}), ((800.0, y), {"band_margin_hz": 0.0}),
                           ((800.0, 10000.0), {"band_margin_hz": 0.0}),  # 1.6 bins wide
                           ((800.0, y), {"band": nrsar.doppler_band.FULL})):
            scn = nrsar.make_scene([target])
            blk = nrsar.rd_focuser(NUM, geometry(m * T), scn, K, R_FIRST, RHO, self.cfg(**kw))
            before = chain.memory_estimate_bytes(rif, blk, m, False)
            tb = gr.top_block()
            data = np.asarray(echo([(*target, 1.0)], m), np.complex64).ravel()
            tb.connect(blocks.vector_source_c(data.tolist(), False, K), blk,
                       blocks.null_sink(gr.sizeof_gr_complex * K))
            tb.run()
            bins = blk.band_bins()  # the kernel's, after its blocks
            lines = blk.overlap_before() + 2 * m + blk.overlap_after()
            self.assertEqual(before, int(8 * 2 * K * (lines + 2.5 * bins)), (target, kw))
            nfft, lo, hi = blk.fft_size(), blk.band_lo_hz(), blk.band_hi_hz()
            df = 1.0 / (nfft * T)
            inside = max(1, math.floor(hi / df) - math.ceil(lo / df) + 1)
            self.assertEqual(bins, nfft if "band" in kw else inside, (target, kw))
        self.assertEqual(bins, nfft)

    def test_007b_pulse_interval_change_mid_stream(self):
        # A pulse_interval tag in the middle of aperture 1 applies from aperture 2.
        m = 100
        t2 = 2 * T
        geo = geometry(m * T)
        scn = nrsar.make_scene([(800.0, 5.0)])
        data = echo([(800.0, 5.0, 1.0)], 3 * m)
        tags = [gr.tag_utils.python_to_tag((150, pmt.intern(nrsar.tag_keys.pulse_interval),
                                            pmt.from_double(t2)))]
        blk, img, out_tags = run_block(data, geo=geo, scn=scn,
                                       cfg=self.cfg(overlap_lines=0, lines_per_aperture=m),
                                       tags=tags)
        self.assertEqual(img.shape[0], 3 * m)
        axes = [(off, pmt.to_double(pmt.tuple_ref(v, 0)), pmt.to_double(pmt.tuple_ref(v, 1)))
                for off, v in tag_map(out_tags)[nrsar.tag_keys.azimuth_axis]]
        base = axes[0][1]
        expected = [(0, base, V * T), (m, base + m * V * T, V * T),
                    (2 * m, base + 2 * m * V * T, V * t2)]
        self.assertEqual(len(axes), 3)
        for (off, y0, dy), (eoff, ey0, edy) in zip(axes, expected):
            self.assertEqual(off, eoff)
            self.assertAlmostEqual(y0, ey0, places=9)
            self.assertAlmostEqual(dy, edy, places=9)
        self.assertAlmostEqual(blk.pulse_interval_s(), t2)

    def test_008_nonfinite_input(self):
        m = 200
        geo = geometry(m * T)
        scn = nrsar.make_scene([(800.0, 25.0)])
        data = echo([(800.0, 25.0, 1.0)], m)
        data[10, 5] = np.nan
        data[11, 6] = np.inf
        blk, img, out_tags = run_block(data, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0))
        self.assertEqual(blk.nonfinite_count(), 2)
        self.assertTrue(np.all(np.isfinite(img)))
        tm = tag_map(out_tags)
        self.assertEqual(pmt.to_uint64(tm[nrsar.tag_keys.nonfinite][0][1]), 2)

    def test_009_short_stream_flushes(self):
        # 1.3 apertures without overlap: the partial aperture comes out zero padded.
        m = 200
        geo = geometry(m * T)
        scn = nrsar.make_scene([(800.0, 25.0)])
        data = echo([(800.0, 25.0, 1.0)], 260)
        blk, img, _ = run_block(data, geo=geo, scn=scn, cfg=self.cfg(overlap_lines=0))
        self.assertEqual(img.shape[0], 2 * m)
        self.assertEqual(blk.apertures(), 2)

    # -- invalid parameters --------------------------------------------------------------
    def make(self, k=K, first=R_FIRST, rho=RHO, geo=None, **kw):
        geo = geo or geometry(1.0)
        return nrsar.rd_focuser(NUM, geo, nrsar.make_scene([(800.0, 25.0)]), k, first, rho,
                                self.cfg(**kw))

    def assert_invalid(self, text, **kw):
        with self.assertRaises(ValueError) as ctx:
            self.make(**kw)
        self.assertIn(text, str(ctx.exception))

    def test_010_invalid_num_range_bins(self):
        self.assert_invalid("num_range_bins = 0 must be at least 1", k=0)

    def test_011_invalid_first_range(self):
        self.assert_invalid("first_range_m = -5 must be finite and >= 0", first=-5.0)

    def test_012_invalid_range_bin(self):
        self.assert_invalid("range_bin_m = -1 must be finite and > 0", rho=-1.0)

    def test_013_invalid_symbols_per_pulse(self):
        self.assert_invalid("symbols_per_pulse = 0 must be at least 1", symbols_per_pulse=0)

    def test_014_invalid_overlap(self):
        self.assert_invalid("overlap_lines = -2 must be at least -1", overlap_lines=-2)

    def test_015_invalid_taps(self):
        self.assert_invalid("rcmc_taps = 7 must be even and in [2, 64]", rcmc_taps=7)
        self.assert_invalid("rcmc_taps = 66 must be even and in [2, 64]", rcmc_taps=66)

    def test_016_invalid_window(self):
        from gnuradio.fft import window
        self.assert_invalid("rcmc_window", rcmc_window=window.WIN_FLATTOP)

    def test_017_invalid_kaiser_beta(self):
        self.assert_invalid("rcmc_window_param = 60 must be in [0, 50]", rcmc_window_param=60.0)

    def test_018_invalid_threshold(self):
        self.assert_invalid("estimate_threshold_db = 0.5 must be in [1, 60]",
                            estimate_threshold_db=0.5)

    def test_019_invalid_skip(self):
        self.assert_invalid("rcmc_skip_below_bins = 2 must be in [0, 1]", rcmc_skip_below_bins=2.0)

    def test_020_invalid_margin(self):
        self.assert_invalid("band_margin_hz = nan must be finite", band_margin_hz=float("nan"))

    def test_021_invalid_range_centre(self):
        self.assert_invalid("range_centre_cycles = 2 must be in [-1, 1]", range_centre_cycles=2.0)

    def test_022_invalid_lines_per_aperture(self):
        self.assert_invalid("lines_per_aperture = 1 must be at least 2", lines_per_aperture=1)

    def test_023_invalid_geometry(self):
        geo = geometry(1.0)
        geo.velocity_mps = 0.0
        self.assert_invalid("velocity_mps = 0 must be finite and > 0", geo=geo)


    # -- guard bins (docs/blocks/rd_focuser.md, guard) ---------------------------------
    def test_024_guard_bins_give_edge_columns_the_interior_noise(self):
        # White noise over the full band (PRF 400 Hz): the RCMC of bin k reads up to
        # Delta k = R0 (1 / D(f) - 1) / rho bins beyond it (about 9.9 bins at 1050 m,
        # f = 200 Hz) plus taps / 2 = 8. Without guard bins the last columns read zeros
        # beyond the window and carry less noise; with g guard bins the K - 2 g output
        # columns all carry the interior's noise power.
        m = 480
        u = LAM * 200.0 / (2 * V)
        r_far = R_FIRST + (K - 1) * RHO
        g = int(math.ceil(r_far * (1 / math.sqrt(1 - u * u) - 1) / RHO)) + 8
        rng = np.random.default_rng(24)
        noise = (rng.standard_normal((m, K)) + 1j * rng.standard_normal((m, K))) / math.sqrt(2)
        geo, scn = geometry(m * T), nrsar.make_scene([(800.0, V * T * m / 2)])
        cfg = dict(overlap_lines=0, band=nrsar.doppler_band.FULL)
        _, plain, _ = run_block(noise, geo=geo, scn=scn, cfg=self.cfg(**cfg))
        blk = nrsar.rd_focuser(NUM, geo, scn, K, R_FIRST, RHO, self.cfg(guard_bins=g, **cfg))
        self.assertEqual(blk.num_output_bins(), K - 2 * g)
        src = blocks.vector_source_c(noise.astype(np.complex64).ravel().tolist(), False, K)
        snk = blocks.vector_sink_c(K - 2 * g)
        tb = gr.top_block()
        tb.connect(src, blk, snk)
        tb.run()
        guarded = np.array(snk.data(), complex).reshape(-1, K - 2 * g)
        # The output is the plain image's inner window, and the range axis says so.
        np.testing.assert_allclose(guarded, plain[:, g:K - g], atol=1e-5)
        axis = tag_map(snk.tags())["range_axis"][0][1]
        self.assertAlmostEqual(pmt.to_double(pmt.tuple_ref(axis, 0)), R_FIRST + g * RHO, 9)
        self.assertEqual(pmt.to_uint64(pmt.tuple_ref(axis, 2)), K - 2 * g)

        def power(img, cols):
            return np.mean(np.abs(img[:, cols]) ** 2)
        interior = power(plain, slice(K // 2 - 4, K // 2 + 4))
        # Without guard: the last 4 columns lose more than 1 dB of noise power.
        self.assertLess(10 * math.log10(power(plain, slice(K - 4, K)) / interior), -1.0)
        # With guard: both edges within 0.4 dB of the interior (1920 samples: 0.1 dB std).
        for cols in (slice(0, 4), slice(K - 2 * g - 4, K - 2 * g)):
            self.assertAlmostEqual(10 * math.log10(power(guarded, cols) / interior), 0.0,
                                   delta=0.4)

    def test_025_invalid_guard_bins(self):
        self.assert_invalid("guard_bins = 32 must be below num_range_bins / 2 (64 / 2)",
                            guard_bins=32)

if __name__ == '__main__':
    gr_unittest.run(qa_rd_focuser)
