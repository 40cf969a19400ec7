#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of tf_filter: eq. (25) against numpy float64, chi statistics against theory.py,
the SNR_in estimator against the true SNR, run-time setters, empty REs, non-finite
inputs, tags and parameter validation."""

import math
import os
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest

try:
    from gnuradio import nrsar
    from gnuradio.nrsar import theory
except ImportError:
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bindings"))
    from gnuradio import nrsar
    from gnuradio.nrsar import theory

FILTERS = {"rf": nrsar.filter_type.RF, "mf": nrsar.filter_type.MF, "wf": nrsar.filter_type.WF}


def qam256(rng, n):
    """Random 256-QAM symbols written out from SPEC 2 (not from theory.py)."""
    b = rng.integers(0, 2, size=(n, 8)).astype(float)
    a = 1 - 2 * b
    re = a[:, 0] * (8 - a[:, 2] * (4 - a[:, 4] * (2 - a[:, 6])))
    im = a[:, 1] * (8 - a[:, 3] * (4 - a[:, 5] * (2 - a[:, 7])))
    return (re + 1j * im) / math.sqrt(170)


def snr_estimate_std_db(snr_db, n):
    """Standard deviation [dB] of the estimate 10 log10(P^/sigma^2^) from n REs of y = h s + z
    (|h| = 1, s uniform 256-QAM, z ~ CN(0, sigma^2)): the least-squares line |y|^2 = P u +
    sigma^2 (u = |s|^2) with residual variance sigma^4 + 2 P sigma^2 u given u, covariance
    M^-1 S M^-1 / n, through the gradient of the dB ratio (as tests/test_tf_filter.cc)."""
    lv = np.arange(-15, 16, 2.0)
    u = ((lv[:, None] ** 2 + lv[None, :] ** 2) / 170.0).ravel()
    s2 = 10.0 ** (-snr_db / 10.0)
    x = np.stack([np.ones_like(u), u], 1)
    m = x.T @ x / u.size
    sv = (x * (s2 * s2 + 2.0 * s2 * u)[:, None]).T @ x / u.size
    mi = np.linalg.inv(m)
    grad = 10.0 / math.log(10.0) * np.array([-1.0 / s2, 1.0])
    return math.sqrt(grad @ (mi @ sv @ mi / n) @ grad)


def ref_filter(name, y, s, snr_db):
    """eq. (25) in float64, empty REs (s = 0) -> 0."""
    y = y.astype(np.complex128)
    s = s.astype(np.complex128)
    m = np.abs(s) ** 2
    if name == "rf":
        g = np.where(m > 0, np.conj(s) / np.where(m > 0, m, 1.0), 0.0)
    elif name == "mf":
        g = np.conj(s)
    else:
        g = np.conj(s) / (m + 10 ** (-snr_db / 10))
    return y * g


class qa_tf_filter(gr_unittest.TestCase):

    def setUp(self):
        self.tb = gr.top_block()

    def tearDown(self):
        self.tb = None

    def connect(self, blk, y, s, vlen, y_tags=()):
        """vector sources of y (with tags) and s -> blk -> vector sink."""
        src_y = blocks.vector_source_c(y.astype(np.complex64).ravel().tolist(), False, vlen,
                                       list(y_tags))
        src_s = blocks.vector_source_c(s.astype(np.complex64).ravel().tolist(), False, vlen)
        snk = blocks.vector_sink_c(vlen)
        self.tb.connect(src_y, (blk, 0))
        self.tb.connect(src_s, (blk, 1))
        self.tb.connect(blk, snk)
        return src_y, src_s, snk

    def run_block(self, blk, y, s, vlen, y_tags=()):
        _, _, snk = self.connect(blk, y, s, vlen, y_tags)
        self.tb.run()
        return np.array(snk.data()).reshape(-1, vlen), snk.tags()

    def test_001_filters_match_numpy(self):
        rng = np.random.default_rng(1)
        vlen, m = 97, 20
        for name, ftype in FILTERS.items():
            for snr_db in (-20.0, 5.0, 20.0):
                s = qam256(rng, vlen * m).reshape(m, vlen)
                s[:, ::5] = 0  # empty REs
                y = (rng.normal(size=(m, vlen)) + 1j * rng.normal(size=(m, vlen)))
                self.tb = gr.top_block()
                blk = nrsar.tf_filter(vlen, ftype, snr_db, False)
                out, _ = self.run_block(blk, y, s, vlen)
                ref = ref_filter(name, y, s.astype(np.complex64), snr_db)
                np.testing.assert_allclose(out, ref, rtol=2e-5, atol=2e-6,
                                           err_msg=f"{name} at {snr_db} dB")
                self.assertTrue(np.all(out[:, ::5] == 0))
                self.assertEqual(blk.empty_re_count(), m * len(range(0, vlen, 5)))

    def test_002_chi_statistics_match_theory(self):
        # y = s (H = 1, no noise) makes the output chi = s g; y = 1 makes it g. Every
        # constellation point appears equally often, so means are exact expectations.
        for mod in ("qam256", "qam16", "psk8"):
            pts = theory.constellation(mod)
            s = np.tile(pts, 4).reshape(4, -1)
            vlen = s.shape[1]
            for name, ftype in FILTERS.items():
                for snr_db in (-20.0, 5.0, 20.0):
                    th = theory.filter_moments(mod, name, snr_db)
                    self.tb = gr.top_block()
                    chi, _ = self.run_block(nrsar.tf_filter(vlen, ftype, snr_db), s, s, vlen)
                    self.tb = gr.top_block()
                    g, _ = self.run_block(nrsar.tf_filter(vlen, ftype, snr_db),
                                          np.ones_like(s), s, vlen)
                    msg = f"{mod} {name} {snr_db} dB"
                    self.assertLess(np.max(np.abs(chi.imag)), 1e-5 * max(1, th["E_chi"]), msg)
                    self.assertAlmostEqual(np.mean(chi.real) / th["E_chi"], 1.0, 5, msg)
                    self.assertAlmostEqual(np.var(chi.real), th["Var_chi"],
                                           delta=1e-5 * (th["Var_chi"] + th["E_chi"] ** 2))
                    self.assertAlmostEqual(np.mean(np.abs(g) ** 2) / th["E_g2"], 1.0, 5, msg)

    def test_003_theory_reproduces_spec_table(self):
        # SPEC 8: 256-QAM at -20 / 5 / 20 dB.
        spec = {"rf": (25.4, 0.4, -14.6), "mf": (20.0, -1.5, -3.9), "wf": (20.0, -3.3, -15.6)}
        for name, values in spec.items():
            for snr_db, expected in zip((-20.0, 5.0, 20.0), values):
                self.assertAlmostEqual(theory.nmse_theory_db("qam256", name, snr_db),
                                       expected, delta=0.1)
        # Unit-power constellations, constant modulus for PSK/QPSK (Var chi = 0 for MF).
        for mod in theory.MODULATIONS:
            self.assertAlmostEqual(np.mean(np.abs(theory.constellation(mod)) ** 2), 1.0, 12)
        self.assertAlmostEqual(theory.filter_moments("qpsk", "mf", 0)["Var_chi"], 0.0, 12)

    def test_004_snr_estimate_within_four_sigma(self):
        # Echo of one target, y = H s + z, |H| = 1 with a random phase per RE. At -20 dB
        # the estimator needs its full window (2^24 REs, 0.17 dB standard deviation);
        # 2^22 REs above (0.012 dB at 5 dB, 0.045 dB at 20 dB). The data go through files: lists of 16 M samples would
        # not fit the QA's memory budget.
        vlen = 2048
        for snr_db, n_re in ((-20.0, 1 << 24), (5.0, 1 << 22), (20.0, 1 << 22)):
            rng = np.random.default_rng(int(snr_db) + 100)
            sigma = math.sqrt(10 ** (-snr_db / 10) / 2)
            with tempfile.TemporaryDirectory() as tmp:
                fy, fs = os.path.join(tmp, "y.c64"), os.path.join(tmp, "s.c64")
                with open(fy, "wb") as out_y, open(fs, "wb") as out_s:
                    chunk = 1 << 21
                    for _ in range(n_re // chunk):
                        s = qam256(rng, chunk)
                        h = np.exp(2j * np.pi * rng.random(chunk))
                        z = sigma * (rng.normal(size=chunk) + 1j * rng.normal(size=chunk))
                        (h * s + z).astype(np.complex64).tofile(out_y)
                        s.astype(np.complex64).tofile(out_s)
                self.tb = gr.top_block()
                blk = nrsar.tf_filter(vlen, nrsar.filter_type.WF, 0.0, True)
                src_y = blocks.file_source(gr.sizeof_gr_complex * vlen, fy, False)
                src_s = blocks.file_source(gr.sizeof_gr_complex * vlen, fs, False)
                tail = blocks.keep_m_in_n(gr.sizeof_gr_complex * vlen, 1, n_re // vlen,
                                          n_re // vlen - 1)
                snk = blocks.vector_sink_c(vlen)
                self.tb.connect(src_y, (blk, 0))
                self.tb.connect(src_s, (blk, 1))
                self.tb.connect(blk, tail, snk)
                self.tb.run()
                y_last = np.fromfile(fy, np.complex64)[-vlen:]
                s_last = np.fromfile(fs, np.complex64)[-vlen:]
            est = blk.estimated_snr_db()
            # 4 standard deviations of the estimator: a Gaussian error beyond has p = 6e-5
            tol = 4.0 * snr_estimate_std_db(snr_db, n_re)
            self.assertLess(abs(est - snr_db), tol, f"estimate {est} dB at {snr_db} dB")
            # The last item was filtered with the estimate, not the given 0 dB.
            out = np.array(snk.data())
            ref = ref_filter("wf", y_last, s_last, est)
            np.testing.assert_allclose(out, ref, rtol=1e-3, atol=1e-4 * np.abs(ref).max())

    def test_005_constant_modulus_keeps_given_snr(self):
        rng = np.random.default_rng(5)
        vlen, m = 64, 50
        s = np.exp(1j * np.pi / 2 * rng.integers(0, 4, size=(m, vlen)) + 1j * np.pi / 4)
        y = s + 0.3 * rng.normal(size=(m, vlen))
        blk = nrsar.tf_filter(vlen, nrsar.filter_type.WF, 7.0, True)
        out, _ = self.run_block(blk, y, s, vlen)
        self.assertTrue(math.isnan(blk.estimated_snr_db()))
        np.testing.assert_allclose(out, ref_filter("wf", y, s.astype(np.complex64), 7.0),
                                   rtol=2e-5, atol=2e-6)

    def test_006_setters_between_runs(self):
        rng = np.random.default_rng(6)
        vlen, m = 32, 10
        s = qam256(rng, vlen * m).reshape(m, vlen)
        y = rng.normal(size=(m, vlen)) + 1j * rng.normal(size=(m, vlen))
        blk = nrsar.tf_filter(vlen, nrsar.filter_type.MF, 0.0, False)
        src_y, src_s, snk = self.connect(blk, y, s, vlen)
        self.tb.run()
        runs = [("mf", 0.0)]
        for name, snr_db in (("wf", -3.0), ("rf", 0.0), ("wf", 12.0)):
            blk.set_filter_type(FILTERS[name])
            blk.set_snr_db(snr_db)
            self.assertEqual(blk.filter_type(), FILTERS[name])
            self.assertEqual(blk.snr_db(), snr_db)
            src_y.rewind()
            src_s.rewind()
            self.tb.run()
            runs.append((name, snr_db))
        out = np.array(snk.data()).reshape(len(runs), m, vlen)
        for i, (name, snr_db) in enumerate(runs):
            np.testing.assert_allclose(out[i], ref_filter(name, y, s.astype(np.complex64),
                                                          snr_db), rtol=2e-5, atol=2e-6)
        blk.set_estimate_snr(True)
        self.assertTrue(blk.estimate_snr())

    def test_007_nonfinite_zeroed_counted_tagged(self):
        rng = np.random.default_rng(7)
        vlen, m = 16, 6
        s = qam256(rng, vlen * m).reshape(m, vlen)
        y = rng.normal(size=(m, vlen)) + 0j
        y[2, 3] = np.nan
        y[4, 0] = np.inf
        s[4, 7] = complex(np.nan, 0)
        blk = nrsar.tf_filter(vlen, nrsar.filter_type.RF)
        out, tags = self.run_block(blk, y, s, vlen)
        self.assertEqual(blk.nonfinite_count(), 3)
        self.assertTrue(np.all(np.isfinite(out)))
        self.assertEqual(out[2, 3], 0)
        self.assertEqual(out[4, 0], 0)
        self.assertEqual(out[4, 7], 0)
        nf = [(t.offset, pmt.to_uint64(t.value)) for t in tags
              if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.nonfinite))]
        self.assertEqual(nf, [(2, 1), (4, 2)])

    def test_008_input_tags_propagate(self):
        vlen, m = 8, 5
        s = np.ones((m, vlen), dtype=complex)
        tag = gr.tag_utils.python_to_tag((3, pmt.intern(nrsar.tag_keys.symbol),
                                          pmt.from_uint64(42), pmt.PMT_F))
        _, tags = self.run_block(nrsar.tf_filter(vlen, nrsar.filter_type.MF), s, s, vlen,
                                 [tag])
        sym = [(t.offset, pmt.to_uint64(t.value)) for t in tags
               if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.symbol))]
        self.assertEqual(sym, [(3, 42)])

    def test_009_invalid_vlen(self):
        with self.assertRaisesRegex(ValueError, r"vlen = 0 must be at least 1"):
            nrsar.tf_filter(0, nrsar.filter_type.RF)

    def test_010_invalid_snr_db(self):
        with self.assertRaisesRegex(ValueError, r"snr_db = nan must be in \[-100, 200\]"):
            nrsar.tf_filter(8, nrsar.filter_type.WF, float("nan"))
        with self.assertRaisesRegex(ValueError, r"snr_db = 300 must be in \[-100, 200\]"):
            nrsar.tf_filter(8, nrsar.filter_type.WF, 300.0)

    def test_011_invalid_snr_db_setter(self):
        blk = nrsar.tf_filter(8, nrsar.filter_type.WF, 10.0)
        with self.assertRaisesRegex(ValueError, r"snr_db = inf must be in"):
            blk.set_snr_db(float("inf"))
        self.assertEqual(blk.snr_db(), 10.0)

    def test_012_constant_modulus_shortcut(self):
        # QPSK and 8-PSK references (every non-empty RE the same |s|^2, some empty REs):
        # the shortcut must give eq. (25) in float64 and the general path's output within
        # float rounding; a 256-QAM symbol in the stream takes the general path.
        rng = np.random.default_rng(12)
        vlen, m = 101, 12
        for name, ftype in FILTERS.items():
            ph = rng.integers(0, 8, size=(m, vlen)) * np.pi / 4 + 0.1
            s = 0.8 * np.exp(1j * ph)
            s[5] = qam256(rng, vlen)  # one non-constant-modulus symbol
            s[:, ::7] = 0
            y = rng.normal(size=(m, vlen)) + 1j * rng.normal(size=(m, vlen))
            outs = []
            for on in (True, False):
                self.tb = gr.top_block()
                blk = nrsar.tf_filter(vlen, ftype, -20.0, False)
                blk.set_constant_modulus_path(on)
                self.assertEqual(blk.constant_modulus_path(), on)
                out, _ = self.run_block(blk, y, s, vlen)
                # MF is conj(s) already: it never takes (or needs) the shortcut
                self.assertEqual(blk.constant_modulus_items(),
                                 m - 1 if on and name != "mf" else 0)
                outs.append(out)
            ref = ref_filter(name, y, s.astype(np.complex64), -20.0)
            np.testing.assert_allclose(outs[0], ref, rtol=2e-6, atol=1e-7, err_msg=name)
            np.testing.assert_allclose(outs[0], outs[1], rtol=2e-6, atol=1e-7, err_msg=name)
            self.assertTrue(np.all(outs[0][:, ::7] == 0))

    def test_013_two_threads_same_output(self):
        # set_threads(2) filters the second half of each work() call on another thread:
        # same output as eq. (25) in float64 and as one thread; tags and counts kept.
        rng = np.random.default_rng(13)
        vlen, m = 67, 600
        s = qam256(rng, vlen * m).reshape(m, vlen)
        s[:, ::9] = 0
        y = rng.normal(size=(m, vlen)) + 1j * rng.normal(size=(m, vlen))
        y[100, 3] = np.nan
        outs = []
        for threads in (1, 2):
            self.tb = gr.top_block()
            blk = nrsar.tf_filter(vlen, nrsar.filter_type.WF, 3.0, False)
            blk.set_threads(threads)
            self.assertEqual(blk.threads(), threads)
            out, tags = self.run_block(blk, y, s, vlen)
            self.assertEqual(blk.empty_re_count(), m * len(range(0, vlen, 9)))
            self.assertEqual(blk.nonfinite_count(), 1)
            self.assertEqual([t.offset for t in tags
                              if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.nonfinite))], [100])
            outs.append(out)
        y0 = y.copy()
        y0[100, 3] = 0
        np.testing.assert_allclose(outs[1], ref_filter("wf", y0, s.astype(np.complex64), 3.0),
                                   rtol=2e-5, atol=2e-6)
        np.testing.assert_array_equal(outs[0], outs[1])

    def test_014_invalid_threads(self):
        blk = nrsar.tf_filter(8)
        with self.assertRaisesRegex(ValueError, r"threads = 3 must be in"):
            blk.set_threads(3)
        self.assertEqual(blk.threads(), 1)

    def test_015_prepass_history_continues_the_stream(self):
        # A strip's pre-pass (docs/scale.md): each item's estimator sums against numpy
        # float64; a block started at item t0 from the history those sums give filters
        # items t0.. as the block that saw the whole stream did, bit for bit (the SNR
        # falling along the stream, every 8th RE empty); without it, it differs.
        rng = np.random.default_rng(15)
        vlen, m, t0 = 64, 300, 170
        s = qam256(rng, vlen * m).reshape(m, vlen)
        s[:, ::8] = 0
        sigma = np.linspace(0.1, 1.0, m)[:, None]
        y = (np.exp(2j * np.pi * rng.random((m, vlen))) * s +
             sigma * (rng.normal(size=(m, vlen)) + 1j * rng.normal(size=(m, vlen))))
        wf = nrsar.filter_type.WF
        whole = nrsar.tf_filter(vlen, wf, 0.0, True)
        out_whole, _ = self.run_block(whole, y, s, vlen)
        self.tb = gr.top_block()
        pre = nrsar.tf_filter(vlen, wf, 0.0, True)
        pre.set_snr_prepass(True)
        out_pre, _ = self.run_block(pre, y, s, vlen)
        self.assertTrue(np.all(out_pre == 0))
        self.assertTrue(math.isnan(pre.estimated_snr_db()))  # it does not estimate
        y2 = np.abs(y.astype(np.complex64).astype(complex)) ** 2
        s2 = np.abs(s.astype(np.complex64).astype(complex)) ** 2
        ref = np.stack([y2.sum(1), s2.sum(1), (s2 ** 2).sum(1), (y2 * s2).sum(1)], 1)
        sums = pre.snr_sums()
        np.testing.assert_allclose(np.reshape(sums, (m, 4)), ref, rtol=1e-5)
        hist = nrsar.tf_filter.snr_histories(vlen, sums, [t0, m])
        self.assertEqual(hist[1], whole.snr_history())
        outs = []
        for history in (hist[0], None):
            self.tb = gr.top_block()
            task = nrsar.tf_filter(vlen, wf, 0.0, True)
            if history:
                task.set_snr_history(history)
            outs.append(self.run_block(task, y[t0:], s[t0:], vlen)[0])
            if history:
                self.assertEqual(task.estimated_snr_db(), whole.estimated_snr_db())
        np.testing.assert_array_equal(outs[0], out_whole[t0:])
        self.assertFalse(np.array_equal(outs[1], out_whole[t0:]))
        with self.assertRaisesRegex(ValueError, r"history: 8 values"):
            task.set_snr_history([0.0] * 8)
        with self.assertRaisesRegex(ValueError, r"sums: 7 values"):
            nrsar.tf_filter.snr_histories(vlen, [0.0] * 7, [0])
        with self.assertRaisesRegex(ValueError, r"items: 2 out of order or past"):
            nrsar.tf_filter.snr_histories(vlen, [0.0] * 4, [2])


if __name__ == "__main__":
    gr_unittest.run(qa_tf_filter)
