#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of cheby_presum, the azimuth presummer of the second paper (SPEC 6).

References: the filter's response measured with numpy on its taps; eqs. (P-25..P-27)
evaluated in numpy float64; the exact range-compressed echo of eqs. (8), (29) in numpy,
focused at full rate by rd_focuser (the full-rate image is the reference of the presummed
one); DROP against slicing; BOXCAR against a numpy sum.
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

# The tiny geometry and the exact range-compressed echo shared with qa_rd_focuser.
from gnuradio.nrsar.focus_scenario import C, FC, H, K, NFFT, NUM, N_SUB, R_FIRST, RHO, V
from gnuradio.nrsar.focus_scenario import echo as rc_echo

SPP = 488       # symbols per pulse: PRF about 3.2 kHz
T = NUM.symbol_s() * SPP
PAPER = nrsar.make_numerology("paper")


def geometry(aperture_s):
    return nrsar.make_geometry("paper", carrier_hz=FC, velocity_mps=V, height_m=H,
                               aperture_s=aperture_s)


def echo(targets, n_lines):
    """Exact range-compressed echo (eqs. 8, 29) at this file's pulse interval."""
    return rc_echo(targets, n_lines, t_pulse=T)


def run_presum(data, blk, tags=()):
    k = blk.num_bins()
    src = blocks.vector_source_c(np.asarray(data, np.complex64).ravel().tolist(), False, k,
                                 list(tags))
    snk = blocks.vector_sink_c(k)
    tb = gr.top_block()
    tb.connect(src, blk, snk)
    tb.run()
    return np.array(snk.data(), complex).reshape(-1, k), snk.tags()


def focus(data, geo, scn, presum=None):
    """rd_focuser image of data, optionally presummed first (the focuser learns T D from
    the presummer's pulse_interval tag)."""
    cfg = nrsar.focuser_config()
    cfg.symbols_per_pulse = SPP
    foc = nrsar.rd_focuser(NUM, geo, scn, K, R_FIRST, RHO, cfg)
    src = blocks.vector_source_c(np.asarray(data, np.complex64).ravel().tolist(), False, K)
    snk = blocks.vector_sink_c(K)
    tb = gr.top_block()
    if presum is None:
        tb.connect(src, foc, snk)
    else:
        tb.connect(src, presum, foc, snk)
    tb.run()
    return np.array(snk.data(), complex).reshape(-1, K)


def peak_and_irw(img, factor=16):
    """Sub-cell peak position (line, bin) and 3 dB widths [cells] from cuts through the
    peak, spectra zero padded (the cuts are band-limited)."""
    m0, k0 = np.unravel_index(np.argmax(np.abs(img)), img.shape)
    out = []
    for cut, c0 in ((img[:, k0], m0), (img[m0, :], k0)):
        n = len(cut)
        spec = np.fft.fft(np.roll(cut, n // 2 - c0))
        p = np.abs(spec) ** 2
        gap = int(np.argmin(np.convolve(np.concatenate([p, p[:8]]), np.ones(8), "valid")[:n]))
        spec = np.roll(spec, -gap - 5)
        a = np.abs(np.fft.ifft(np.concatenate([spec, np.zeros(n * (factor - 1))]))) ** 2
        i = int(np.argmax(a))
        half = a[i] / 2
        lo, hi = i, i
        while a[lo - 1] > half:
            lo -= 1
        while a[(hi + 1) % len(a)] > half:
            hi += 1
        x_lo = lo - (a[lo] - half) / (a[lo] - a[lo - 1])
        x_hi = hi + (a[hi] - half) / (a[hi] - a[(hi + 1) % len(a)])
        out.append((c0 - n // 2 + i / factor, (x_hi - x_lo) / factor))
    return out


class qa_cheby_presum(gr_unittest.TestCase):

    def test_001_filter_meets_design_numpy(self):
        """Paper preset, D = 12: passband ripple and stopband attenuation measured with
        numpy on the taps; equiripple ratio delta_p / delta_s = stopband weight."""
        geo = nrsar.make_geometry("paper")
        scn = nrsar.make_scene("paper3")
        d = 12
        blk = nrsar.cheby_presum(PAPER, geo, scn, 256, 1000.0, 1.5,
            nrsar.presum_config(method=nrsar.CHEBY, decim=d, domain=nrsar.RANGE))
        h = np.array(blk.prototype())
        self.assertEqual(len(h), 4 * d)
        self.assertTrue(blk.equiripple())
        prf = PAPER.prf_hz()
        nf = 1 << 17
        hf = np.abs(np.fft.fft(h, nf))[: nf // 2 + 1]
        f = np.arange(nf // 2 + 1) * prf / nf
        fp, fs = blk.passband_hz(), blk.stopband_hz()
        self.assertAlmostEqual(fs, prf / (2 * d), delta=1e-6)
        pas, stop = hf[f <= fp], hf[f >= fs]
        ripple_db = 20 * np.log10(pas.max() / pas.min())
        atten_db = 20 * np.log10(d / stop.max())
        self.assertLess(ripple_db, 0.5)
        self.assertGreater(atten_db, 30.0)
        self.assertAlmostEqual(ripple_db, blk.passband_ripple_db(), delta=0.02)
        self.assertAlmostEqual(atten_db, blk.stopband_atten_db(), delta=0.05)
        self.assertGreater(atten_db, 40.0)
        # Parks-McClellan: the stopband error is equiripple (all its local maxima equal).
        s = stop / d
        peaks = s[1:-1][(s[1:-1] >= s[:-2]) & (s[1:-1] >= s[2:])]
        self.assertGreater(len(peaks), 10)
        self.assertLess(20 * np.log10(peaks.max() / peaks.min()), 0.5)
        # Passband covers the residual band after compensation (paper3: targets 40 m
        # apart along track: 2 v 20 / (lambda R) about 22 Hz) and stays below fs.
        self.assertGreater(fp, 22.0)
        self.assertLess(fp, fs)

    def test_002_compensation_table_eq25_27(self):
        geo = geometry(1.0)
        scn = nrsar.make_scene([(800.0, 20.0), (800.0, 30.0)])
        blk = nrsar.cheby_presum(NUM, geo, scn, K, R_FIRST, RHO,
            nrsar.presum_config(method=nrsar.CHEBY, decim=8, domain=nrsar.RANGE,
                                symbols_per_pulse=SPP))
        f = FC + 0.5 * (N_SUB - 1) * NUM.subcarrier_spacing_hz
        self.assertAlmostEqual(blk.phase_frequency_hz(3), f, delta=1e-3)
        yc = 25.0
        for n in (0, 17, 63):
            r0 = R_FIRST + n * RHO
            for m in (0, 1000, 3100):
                for dm in (1, 7, 31):
                    a = V * m * T - yc
                    b = V * (m + dm) * T - yc
                    d_r = math.sqrt(r0 ** 2 + b ** 2) - math.sqrt(r0 ** 2 + a ** 2)  # eq. 26
                    want = 4 * math.pi * f * d_r / C                                 # eq. 27
                    self.assertAlmostEqual(blk.compensation_phase(n, m * T, dm), want, delta=1e-9)
        # Data path: the reference history exp(-j 4 pi f R(n, t) / c) is summed coherently:
        # output g = D exp(-j 4 pi f R(n, t_g) / c), t_g = (g D + centre) T.
        d, pulses = 8, 800
        t = np.arange(pulses) * T
        r0 = R_FIRST + np.arange(K) * RHO
        phase = lambda tt: 4 * np.pi * f * np.sqrt(r0[None, :] ** 2 +
                                                  (V * tt[:, None] - yc) ** 2) / C
        data = np.exp(-1j * np.mod(phase(t), 2 * np.pi))
        out, _ = run_presum(data, blk)
        g = np.arange(len(out))
        want = d * np.exp(-1j * np.mod(phase((g * d + blk.centre_offset()) * T), 2 * np.pi))
        g0 = -(-blk.num_taps() // d)
        err = np.abs(out[g0:] - want[g0:]).max() / d
        self.assertLess(err, 2e-3)

    def test_003_drop_is_every_dth_pulse_and_tags(self):
        geo = geometry(1.0)
        scn = nrsar.make_scene([(800.0, 20.0)])
        d, pulses, k = 6, 61, 5
        rng = np.random.default_rng(3)
        data = (rng.standard_normal((pulses, k)) + 1j * rng.standard_normal((pulses, k)))
        key = pmt.intern("marker")
        tags = [gr.tag_utils.python_to_tag((p, key, pmt.from_long(p), pmt.PMT_F))
                for p in (0, 2 * d, 2 * d + 1, 5 * d)]
        blk = nrsar.cheby_presum(NUM, geo, scn, k, 900.0, 2.0,
            nrsar.presum_config(method=nrsar.DROP, decim=d, domain=nrsar.RANGE,
                                symbols_per_pulse=SPP))
        out, otags = run_presum(data, blk, tags)
        np.testing.assert_array_equal(out.astype(np.complex64),
                                      data[::d].astype(np.complex64))
        got = {}
        for t in otags:
            got.setdefault(pmt.symbol_to_string(t.key), []).append((t.offset, t.value))
        self.assertEqual([(o, pmt.to_long(v)) for o, v in got["marker"]],
                         [(0, 0), (2, 2 * d), (5, 5 * d)])
        (o, v), = got[nrsar.tag_keys.pulse_interval]
        self.assertEqual(o, 0)
        self.assertAlmostEqual(pmt.to_double(v), NUM.symbol_s() * SPP * d, delta=1e-15)
        (o, v), = got[nrsar.tag_keys.range_axis]
        self.assertEqual(o, 0)
        self.assertEqual(pmt.to_double(pmt.tuple_ref(v, 0)), 900.0)
        self.assertEqual(pmt.to_uint64(pmt.tuple_ref(v, 2)), k)

    def test_004_boxcar_is_plain_sum(self):
        geo = geometry(1.0)
        scn = nrsar.make_scene([(800.0, 20.0)])
        d, pulses, k = 4, 40, 3
        rng = np.random.default_rng(4)
        data = (rng.standard_normal((pulses, k)) + 1j * rng.standard_normal((pulses, k)))
        blk = nrsar.cheby_presum(NUM, geo, scn, k, 900.0, 2.0,
            nrsar.presum_config(method=nrsar.BOXCAR, decim=d, domain=nrsar.RANGE,
                                symbols_per_pulse=SPP))
        out, _ = run_presum(data, blk)
        want = data.reshape(-1, d, k).sum(1)
        np.testing.assert_allclose(out, want, atol=1e-5)

    def test_005_presummed_target_focuses_where_full_rate_does(self):
        """Noise-free target off the scene centre: CHEBY at D = 10 focused by rd_focuser
        lands within a quarter cell of the full-rate image, with the same IRW (5 %)."""
        ta = 2.0
        geo = geometry(ta)
        scn = nrsar.make_scene([(800.0, 50.0), (800.0, 62.0)])
        pulses = int(round(ta / T))
        data = echo([(800.0, 50.0, 1.0)], pulses)  # the first target only
        full = focus(data, geo, scn)
        d = 10
        blk = nrsar.cheby_presum(NUM, geo, scn, K, R_FIRST, RHO,
            nrsar.presum_config(method=nrsar.CHEBY, decim=d, domain=nrsar.RANGE,
                                symbols_per_pulse=SPP))
        pres = focus(data, geo, scn, blk)
        self.assertLessEqual(abs(pres.shape[0] * d - full.shape[0]), d)
        (az_f, irw_af), (rg_f, irw_rf) = peak_and_irw(full)
        (az_p, irw_ap), (rg_p, irw_rp) = peak_and_irw(pres)
        # azimuth cell of the full-rate image: IRW in lines; compare in metres
        cell_az = irw_af * V * T
        self.assertLess(abs(az_p * d * V * T - az_f * V * T), 0.25 * cell_az)
        self.assertLess(abs(rg_p - rg_f), 0.25 * irw_rf)
        self.assertAlmostEqual(irw_ap * d / irw_af, 1.0, delta=0.05)
        self.assertAlmostEqual(irw_rp / irw_rf, 1.0, delta=0.05)

    def test_006_tf_domain_equals_range_domain_after_ifft(self):
        """Presumming the TF echo (before the IFFT) and then compressing gives the
        range-domain presum of the compressed echo on the target's bins."""
        geo = geometry(0.5)
        x, y = 800.0, 12.5
        scn = nrsar.make_scene([(x, y)])
        pulses = 400
        yp = V * np.arange(pulses) * T
        r = np.sqrt(x * x + H * H + (yp - y) ** 2)
        n = np.arange(N_SUB)
        fn = FC + n * NUM.subcarrier_spacing_hz
        tf = np.exp(-4j * np.pi * np.mod(np.outer(r, fn) / C, 1.0))
        rc = np.fft.ifft(tf, NFFT, axis=1) * NFFT / np.sqrt(N_SUB)  # eq. (29), all bins
        d = 8
        b_tf = nrsar.cheby_presum(NUM, geo, scn, N_SUB,
            cfg=nrsar.presum_config(method=nrsar.CHEBY, decim=d, domain=nrsar.TF,
                                symbols_per_pulse=SPP))
        first = 10 * NFFT * RHO  # 960 m: IFFT bin k is at first + k RHO (range period 96 m)
        b_rc = nrsar.cheby_presum(NUM, geo, scn, NFFT, first, RHO,
            nrsar.presum_config(method=nrsar.CHEBY, decim=d, domain=nrsar.RANGE,
                                symbols_per_pulse=SPP))
        o_tf, _ = run_presum(tf, b_tf)
        o_rc, _ = run_presum(rc, b_rc)
        o_tf = np.fft.ifft(o_tf, NFFT, axis=1) * NFFT / np.sqrt(N_SUB)
        kq = int(round((math.sqrt(x * x + H * H) - first) / RHO))
        g0 = -(-b_tf.num_taps() // d)
        a, b = o_tf[g0:, kq], o_rc[g0:, kq]
        self.assertLess(np.abs(a - b).max() / np.abs(b).max(), 0.02)
        self.assertGreater(np.abs(b).min(), 0.5 * d * math.sqrt(N_SUB) * 0.5)

    def test_007_warns_when_output_prf_below_band(self):
        geo = nrsar.make_geometry("paper")
        scn = nrsar.make_scene("paper3")
        blk = nrsar.cheby_presum(PAPER, geo, scn, 8, 1000.0, 1.5,
            nrsar.presum_config(method=nrsar.CHEBY, decim=200, domain=nrsar.RANGE))
        self.assertTrue(any("output PRF 120" in w for w in blk.warnings()), blk.warnings())
        blk = nrsar.cheby_presum(PAPER, geo, scn, 8, 1000.0, 1.5,
            nrsar.presum_config(method=nrsar.CHEBY, decim=10, domain=nrsar.RANGE))
        self.assertEqual(blk.warnings(), [])

    def test_008_large_vectors_do_not_stall(self):
        """4096-sample pulses (buffers of a few items): every output whose window is
        complete comes out, D at a time."""
        geo = nrsar.make_geometry("paper")
        scn = nrsar.make_scene("paper3")
        d, pulses, k = 10, 95, 4096
        blk = nrsar.cheby_presum(PAPER, geo, scn, k, 0.0, 1.5,
            nrsar.presum_config(method=nrsar.CHEBY, decim=d, domain=nrsar.RANGE))
        data = np.ones((pulses, k), np.complex64)
        out, _ = run_presum(data, blk)
        self.assertEqual(len(out), (pulses - 1 - blk.lookahead()) // d + 1)

    def test_009_nrsar_sim_presum_option(self):
        """nrsar-sim --presum cheby --decim 10: the focuser gets M / 10 lines at PRF / 10,
        the JSON names presum and decim, SNR_out stays with the full-rate chain while
        --presum drop loses about 10 log10(10) dB."""
        import tempfile
        from gnuradio.nrsar import chain
        from gnuradio.nrsar.options import SimOptions
        res = {}
        with tempfile.TemporaryDirectory() as out:
            for p in ("none", "cheby", "drop"):
                decim = [] if p == "none" else ["--decim", "10"]
                args = SimOptions.parse(
                    ["--preset", "small", "--aperture-s", "0.5", "--scene", "300,12.5",
                     "--presum", p, "--out", out] + decim)
                res[p] = chain.simulate(args)
        self.assertEqual((res["none"]["presum"], res["none"]["decim"]), ("none", 1))
        self.assertEqual((res["cheby"]["presum"], res["cheby"]["decim"]), ("cheby", 10))
        self.assertEqual(res["cheby"]["azimuth_lines"] * 10, res["none"]["azimuth_lines"])
        self.assertLess(abs(res["cheby"]["snr_out_db"] - res["none"]["snr_out_db"]), 0.5)
        # Dropping 9 of 10 pulses keeps 1/10 of the coherent gain: SNR_out falls by
        # 10 log10(10) dB. The estimate's spread: SNR_out divides by the mean noise power of
        # the image, which holds N_eff = (image length / azimuth cell) x (range cells)
        # independent noise cells (the cells are wider than the pixels: 86 lines and one bin
        # per cell here), so each run's noise power has a relative std 1 / sqrt(N_eff); the
        # dropped run's in-band noise is mostly the other bands' folded in, independent of the
        # full-rate one's: std of the difference 10 log10(e) sqrt(2 / N_eff) (0.29 dB for
        # N_eff = 447; 12 seeds measured 0.34 dB). Tolerance: 4 of it.
        r = res["drop"]
        length_m = r["azimuth_lines"] * r["azimuth_axis_m"][1]
        az_cell_m = r["irw_azimuth_m"] / 0.886
        n_eff = length_m / az_cell_m * r["range_bins"]  # range: one bin per cell, c / (2 N df)
        self.assertAlmostEqual(r["range_axis_m"][1], 299792458.0 / (2 * r["subcarriers"] * 30e3),
                               6)
        sigma_db = 10 * math.log10(math.e) * math.sqrt(2.0 / n_eff)
        self.assertAlmostEqual(res["none"]["snr_out_db"] - res["drop"]["snr_out_db"],
                               10 * math.log10(10), delta=4 * sigma_db)

    # invalid parameters: one test per rule
    def bad(self, text, **kw):
        args = dict(num=PAPER, geo=nrsar.make_geometry("paper"), scn=nrsar.make_scene("paper3"),
                    num_bins=8, first_range_m=1000.0, range_bin_m=1.5)
        cfg = dict(method=nrsar.CHEBY, decim=10, domain=nrsar.RANGE)
        for key, value in kw.items():
            (args if key in args else cfg)[key] = value
        with self.assertRaises(ValueError) as ctx:
            nrsar.cheby_presum(cfg=nrsar.presum_config(**cfg), **args)
        self.assertIn(text, str(ctx.exception))

    def test_100_decim_zero(self):
        self.bad("decim = 0 must be at least 1", decim=0)

    def test_101_decim_above_qpe_bound(self):
        geo, scn = nrsar.make_geometry("paper"), nrsar.make_scene("paper3")
        prf, lam = PAPER.prf_hz(), geo.wavelength_m()
        r0 = math.sqrt(250.0 ** 2 + 1000.0 ** 2)  # nearest target, T2
        dmax = int(math.floor(prf / (2 * V) * math.sqrt(lam * r0 / 2)))  # eq. (P-36)
        self.assertEqual(nrsar.cheby_presum.max_decim(PAPER, geo, scn), dmax)
        self.bad(f"decim = {dmax + 1} exceeds the quadratic-phase-error bound of eq. (P-36), "
                 f"D_max = {dmax}", decim=dmax + 1)
        self.bad(f"D_max = {dmax}", decim=dmax + 1, method=nrsar.BOXCAR)

    def test_102_tf_domain_needs_n_bins(self):
        self.bad("num_bins = 8 must equal num_subcarriers = 3333", domain=nrsar.TF)

    def test_103_passband_above_stopband(self):
        self.bad("passband_hz = 2000 must be below the stopband edge", passband_hz=2000.0)

    def test_104_stopband_above_nyquist(self):
        self.bad("stopband_hz = 13000 must be below PRF / 2", stopband_hz=13000.0)

    def test_105_stopband_weight(self):
        self.bad("stopband_weight = 0 must be finite and > 0", stopband_weight=0.0)

    def test_106_num_taps_one(self):
        self.bad("num_taps = 1 must be 0 (4 D) or at least 2", num_taps=1)

    def test_107_range_bin(self):
        self.bad("range_bin_m = 0 must be finite and > 0", range_bin_m=0.0)

    def test_108_num_bins_zero(self):
        self.bad("num_bins = 0 must be at least 1", num_bins=0)

    def test_109_symbols_per_pulse_zero(self):
        self.bad("symbols_per_pulse = 0 must be at least 1", symbols_per_pulse=0)


if __name__ == "__main__":
    gr_unittest.run(qa_cheby_presum)
