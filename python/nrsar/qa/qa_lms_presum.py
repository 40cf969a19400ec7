#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""cheby_presum's LMS method, the second paper's adaptive baseline [P-3.1]: the block against
a float64 numpy line enhancer, its single-pulse gain at D = 12 against the normalised-LMS
misadjustment theory and the paper, and the option / GRC names."""

import math

import numpy as np
from gnuradio import blocks, gr, gr_unittest

from gnuradio import nrsar
from gnuradio.nrsar import options, params
from gnuradio.nrsar.figures import presum_compare


def ale_numpy(x, taps, mu):
    """Adaptive line enhancer of every column of x (pulses x elements) in float64: predict
    pulse m from pulses m-1 .. m-L by w^H x, then w += mu conj(e) x / ||x||^2."""
    m, k = x.shape
    w = np.zeros((taps, k), complex)
    hist = np.zeros((taps, k), complex)
    y = np.zeros((m, k), complex)
    for i in range(m):
        y[i] = np.einsum("lk,lk->k", w.conj(), hist)
        nrm = (np.abs(hist) ** 2).sum(0)
        g = np.where(nrm > 0, mu / np.where(nrm > 0, nrm, 1.0), 0.0) * np.conj(x[i] - y[i])
        w += g[None, :] * hist
        hist = np.roll(hist, 1, axis=0)
        hist[0] = x[i]
    return y


class qa_lms_presum(gr_unittest.TestCase):

    def make(self, k, d, **kw):
        return nrsar.cheby_presum(params.make_numerology("small"),
                                  params.make_geometry("paper"), params.make_scene("paper3"),
                                  k, 1000.0, 9.7, nrsar.presum_config(
                                      method=nrsar.presum_method.LMS, decim=d, **kw))

    def test_001_block_matches_numpy_ale(self):
        k, d, taps, mu, pulses = 6, 4, 10, 0.25, 2400
        rng = np.random.default_rng(5)
        x = (rng.standard_normal((pulses, k)) + 1j * rng.standard_normal((pulses, k))) / 2
        x[:, 1] += np.exp(2j * np.pi * 0.03 * np.arange(pulses))  # a tone in element 1
        x = x.astype(np.complex64)
        blk = self.make(k, d, num_taps=taps, lms_step=mu)
        self.assertEqual(blk.num_taps(), taps)
        self.assertEqual(blk.centre_offset(), 0.0)
        src = blocks.vector_source_c(x.ravel().tolist(), False, k)
        snk = blocks.vector_sink_c(k)
        tb = gr.top_block()
        tb.connect(src, blk, snk)
        tb.run()
        out = np.array(snk.data()).reshape(-1, k)
        ref = d * ale_numpy(x.astype(complex), taps, mu)[::d]
        self.assertEqual(out.shape, ref.shape)  # one output per D, the first at pulse 0
        err = np.linalg.norm(out - ref) / np.linalg.norm(ref)
        self.assertLess(err, 1e-4)

    def test_002_single_pulse_gain_at_d12(self):
        # Chain TX -> echo -> MF -> range IFFT, 0 dB pulses as in the paper, D = 12.
        # Expectations independent of the code: boxcar 10 log10 D; a FIR of taps h
        # D^2 / sum h^2; LMS (2 - mu) / mu (L rho / (1 + L rho))^2 (misadjustment of
        # normalised LMS), within 0.6 dB: the floor is estimated from ~100 bins but the
        # signal from one bin over ~500 outputs (0.1 dB), and the misadjustment formula
        # is a small-step, large-L approximation (0.3 dB off at mu = 1/3, numpy). The paper:
        # LMS about 7 dB, the proposed method about 9 dB and above LMS.
        rows, _, _ = presum_compare.fig6_rows("small", 0.5, 12)
        by = {r["method"]: r for r in rows}
        # nominal 0 dB per pulse (SNR_in - 10 log10 N); measured about -2 dB
        self.assertAlmostEqual(by["none"]["pulse_snr_db"], 0.0, delta=3.0)
        self.assertAlmostEqual(by["boxcar"]["gain_db"], 10 * math.log10(12), delta=0.4)
        self.assertAlmostEqual(by["drop"]["gain_db"], 0.0, delta=0.4)
        self.assertAlmostEqual(by["cheby"]["gain_db"], by["cheby"]["theory_gain_db"], delta=0.4)
        for r in rows:
            if r["method"].startswith("lms"):
                self.assertAlmostEqual(r["gain_db"], r["theory_gain_db"], delta=0.6,
                                       msg=r["method"])
        # the paper's 7 dB LMS: its step is not given; mu = 1/3 (misadjustment 20 %) gives it
        self.assertAlmostEqual(by["lms mu=0.333"]["gain_db"], 7.0, delta=1.0)
        self.assertLess(by["lms"]["gain_db"], by["cheby"]["gain_db"])
        self.assertGreater(by["lms"]["gain_db"], by["drop"]["gain_db"] + 5.0)

    def test_003_option_and_grc_names(self):
        self.assertIn("lms", options.PRESUM)
        opts = options.SimOptions(presum="lms", decim=12).validate()
        self.assertEqual(opts.presum_factor(), 12)
        self.assertEqual(nrsar.presum_config().lms_step, 0.2)

    def test_004_rejects_bad_step(self):
        for mu in (0.0, 2.0, -1.0, float("nan")):
            with self.assertRaisesRegex(ValueError, "lms_step"):
                self.make(8, 12, lms_step=mu)


if __name__ == "__main__":
    gr_unittest.run(qa_lms_presum)
