#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of nrsar.scene_echo against eqs. (7)-(8) evaluated in numpy float64."""

import math

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest

try:
    from gnuradio import nrsar
except ImportError:
    import os
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bindings"))
    from gnuradio import nrsar

C = 299792458.0


def qam256(rng, shape):
    """Random 256-QAM symbols (38.211 levels, unit mean power)."""
    levels = np.arange(-15, 16, 2) / np.sqrt(170.0)
    return (rng.choice(levels, shape) + 1j * rng.choice(levels, shape)).astype(np.complex64)


def echo_reference(num, geo, targets, s, m0=0):
    """eq. (7) without noise, exact range (8), float64: s is (M, N), symbols m0 .. m0+M-1."""
    M, N = s.shape
    tsym = 1.0 / num.subcarrier_spacing_hz + num.cp_samples / (num.fft_size * num.subcarrier_spacing_hz)
    m = m0 + np.arange(M, dtype=np.float64)
    yp = geo.track_start_m + geo.velocity_mps * m * tsym
    f = geo.carrier_hz + np.arange(N) * num.subcarrier_spacing_hz
    y = np.zeros((M, N), dtype=np.complex128)
    for (x, yq, rcs, phase) in targets:
        R = np.sqrt(x**2 + geo.height_m**2 + (yp - yq) ** 2)
        alpha = np.sqrt(rcs) * np.exp(1j * phase)
        y += alpha * np.exp(-1j * 4.0 * np.pi * np.outer(R, f) / C)
    return s.astype(np.complex128) * y


def rel_error_db(got, ref):
    return 10.0 * np.log10(np.sum(np.abs(got - ref) ** 2) / np.sum(np.abs(ref) ** 2))


PAPER3 = [(300.0, 100.0, 1.0, 0.0), (250.0, 100.0, 1.0, 0.0), (300.0, 140.0, 1.0, 0.0)]


class qa_scene_echo(gr_unittest.TestCase):

    def setUp(self):
        self.tb = gr.top_block()
        self.num = nrsar.make_numerology("small")
        self.geo = nrsar.make_geometry("paper")
        self.N = self.num.num_subcarriers

    def tearDown(self):
        self.tb = None

    def run_block(self, blk, s, tags=(), with_reference=False):
        """Streams s (M x N) through blk; returns (out0, out1 or None, out0 tags)."""
        src = blocks.vector_source_c(s.ravel().tolist(), False, self.N, list(tags))
        snk0 = blocks.vector_sink_c(self.N)
        self.tb.connect(src, blk, snk0)
        snk1 = None
        if with_reference:
            snk1 = blocks.vector_sink_c(self.N)
            self.tb.connect((blk, 1), snk1)
        self.tb.run()
        out0 = np.array(snk0.data(), dtype=np.complex64).reshape(-1, self.N)
        out1 = np.array(snk1.data(), dtype=np.complex64).reshape(-1, self.N) if snk1 else None
        return out0, out1, snk0.tags()

    def test_001_phase_history_matches_eq7(self):
        rng = np.random.default_rng(1)
        s = qam256(rng, (300, self.N))
        blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"))
        y, h, _ = self.run_block(blk, s, with_reference=True)
        err = rel_error_db(y, echo_reference(self.num, self.geo, PAPER3, s))
        self.assertLess(err, -80.0)
        # Output 1 is H: the echo of S = 1 without noise.
        err_h = rel_error_db(h, echo_reference(self.num, self.geo, PAPER3, np.ones_like(s)))
        self.assertLess(err_h, -80.0)

    def test_002_rcs_and_phase_of_targets(self):
        rng = np.random.default_rng(2)
        s = qam256(rng, (50, self.N))
        targets = [(300.0, 100.0, 2.0, 0.7), (260.0, 120.0, 0.25, -1.9)]
        scn = nrsar.scene([nrsar.point_target(*t) for t in targets])
        y, _, _ = self.run_block(nrsar.scene_echo(self.num, self.geo, scn), s)
        self.assertLess(rel_error_db(y, echo_reference(self.num, self.geo, targets, s)), -80.0)

    def test_003_long_stream_keeps_moving(self):
        # tiny numerology, 48 010 symbols: the last ones are past the end of the 2 s
        # aperture; the slow time is the absolute item index.
        num = nrsar.make_numerology("tiny")
        self.N = num.num_subcarriers
        M = 48010
        s = np.ones((M, self.N), dtype=np.complex64)
        blk = nrsar.scene_echo(num, self.geo, nrsar.make_scene("paper3"))
        y, _, _ = self.run_block(blk, s)
        tail = slice(M - 20, M)
        ref = echo_reference(num, self.geo, PAPER3, s[tail], m0=M - 20)
        self.assertLess(rel_error_db(y[tail], ref), -80.0)

    def test_004_noise_variance(self):
        rng = np.random.default_rng(4)
        s = qam256(rng, (400, self.N))
        snr_db = 3.0
        blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"), snr_db, 11)
        sigma2 = 3.0 / 10 ** (snr_db / 10.0)  # SNR per RE = sum of RCS / sigma^2
        self.assertAlmostEqual(blk.noise_variance(), sigma2, places=12)
        y, h, _ = self.run_block(blk, s, with_reference=True)
        z = y.astype(np.complex128) - echo_reference(self.num, self.geo, PAPER3, s)
        n = z.size
        # |z|^2 exponential: relative standard error 1/sqrt(n); bounds at 5 standard errors.
        self.assertAlmostEqual(np.mean(np.abs(z) ** 2) / sigma2, 1.0, delta=5.0 / math.sqrt(n))
        self.assertLess(abs(np.mean(z)), 5.0 * math.sqrt(sigma2 / n))
        self.assertLess(abs(np.mean(z * z)) / sigma2, 5.0 / math.sqrt(n))  # circular
        # The reference output carries no noise.
        self.assertLess(rel_error_db(h, echo_reference(self.num, self.geo, PAPER3, np.ones_like(s))), -80.0)

    def test_005_set_snr_db_takes_effect(self):
        rng = np.random.default_rng(5)
        s = qam256(rng, (200, self.N))
        blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"), 40.0, 3)
        blk.set_snr_db(0.0)
        self.assertEqual(blk.snr_db(), 0.0)
        self.assertAlmostEqual(blk.noise_variance(), 3.0, places=12)
        y, _, _ = self.run_block(blk, s)
        z = y.astype(np.complex128) - echo_reference(self.num, self.geo, PAPER3, s)
        self.assertAlmostEqual(np.mean(np.abs(z) ** 2) / 3.0, 1.0, delta=5.0 / math.sqrt(z.size))
        # +inf turns the noise off.
        blk.set_snr_db(float("inf"))
        self.assertEqual(blk.noise_variance(), 0.0)
        self.tb = gr.top_block()
        y, _, _ = self.run_block(blk, s)  # a new flowgraph counts items from 0 again
        ref = echo_reference(self.num, self.geo, PAPER3, s)
        self.assertLess(rel_error_db(y, ref), -80.0)

    def test_006_deterministic_per_seed(self):
        rng = np.random.default_rng(6)
        s = qam256(rng, (20, self.N))
        outs = []
        for seed in (7, 7, 8):
            self.tb = gr.top_block()
            blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"), 0.0, seed)
            outs.append(self.run_block(blk, s)[0])
        np.testing.assert_array_equal(outs[0], outs[1])
        self.assertGreater(np.mean(outs[0] != outs[2]), 0.99)

    def test_007_set_scene(self):
        rng = np.random.default_rng(7)
        s = qam256(rng, (30, self.N))
        blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"), 10.0)
        blk.set_scene(nrsar.make_scene("300,100,2"))
        self.assertEqual(len(blk.get_scene().targets), 1)
        self.assertAlmostEqual(blk.noise_variance(), 2.0 / 10.0, places=12)  # follows the RCS
        blk.set_snr_db(float("inf"))
        y, _, _ = self.run_block(blk, s)
        ref = echo_reference(self.num, self.geo, [(300.0, 100.0, 2.0, 0.0)], s)
        self.assertLess(rel_error_db(y, ref), -80.0)

    def test_008_nonfinite_input_zeroed_counted_tagged(self):
        rng = np.random.default_rng(8)
        s = qam256(rng, (10, self.N))
        s[3, 5] = np.nan
        s[3, 9] = complex(1.0, np.inf)
        s[7, 0] = -np.inf
        blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"))
        y, _, tags = self.run_block(blk, s)
        self.assertTrue(np.all(np.isfinite(y)))
        clean = np.where(np.isfinite(s), s, 0)
        self.assertLess(rel_error_db(y, echo_reference(self.num, self.geo, PAPER3, clean)), -80.0)
        self.assertEqual(y[3, 5], 0)
        self.assertEqual(blk.nonfinite_count(), 3)
        found = [(t.offset, pmt.to_uint64(t.value), pmt.symbol_to_string(t.srcid)) for t in tags
                 if pmt.eq(t.key, pmt.intern("nonfinite"))]
        self.assertEqual(found, [(3, 2, blk.alias()), (7, 1, blk.alias())])

    def test_009_tags_propagate(self):
        s = np.ones((5, self.N), dtype=np.complex64)
        tag = gr.tag_utils.python_to_tag((2, pmt.intern("marker"), pmt.from_long(42)))
        blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"))
        _, _, tags = self.run_block(blk, s, tags=[tag])
        marks = [t.offset for t in tags if pmt.eq(t.key, pmt.intern("marker"))]
        self.assertEqual(marks, [2])

    def test_018_two_threads_same_output(self):
        # The second thread takes half of every work() call; noise is a function of
        # (seed, m), so the output is the same as with one thread.
        rng = np.random.default_rng(18)
        s = qam256(rng, (300, self.N))
        s[150, 7] = np.nan
        outs = []
        for threads in (1, 2):
            self.tb = gr.top_block()
            blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"), 5.0, 21)
            blk.set_threads(threads)
            blk.set_min_output_buffer(64)  # work() calls of many symbols, so both threads work
            self.assertEqual(blk.threads(), threads)
            y, h, tags = self.run_block(blk, s, with_reference=True)
            outs.append((y, h, [(t.offset, pmt.to_uint64(t.value)) for t in tags
                                if pmt.eq(t.key, pmt.intern("nonfinite"))], blk.nonfinite_count()))
        np.testing.assert_array_equal(outs[0][0], outs[1][0])
        np.testing.assert_array_equal(outs[0][1], outs[1][1])
        self.assertEqual(outs[1][2], [(150, 1)])
        self.assertEqual(outs[0][2:], outs[1][2:])

    def test_020_reference_only(self):
        # out0 of a reference-only block is H: eq. (7) with S = 1 and no noise whatever
        # the input (NaN included: not read, not counted), the input's tags on it, and
        # bit for bit the reference output of the block computing both (1 and 2 threads).
        rng = np.random.default_rng(20)
        s = qam256(rng, (300, self.N))
        s[40, 3] = np.nan
        tag = gr.tag_utils.python_to_tag((7, pmt.intern("marker"), pmt.from_long(1)))
        both = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"), 5.0, 3)
        _, h_both, _ = self.run_block(both, s, with_reference=True)
        for threads in (1, 2):
            self.tb = gr.top_block()
            blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"), 5.0, 3)
            blk.set_reference_only(True)
            blk.set_threads(threads)
            blk.set_min_output_buffer(64)
            self.assertTrue(blk.reference_only())
            h, _, tags = self.run_block(blk, s, tags=[tag])
            ref = echo_reference(self.num, self.geo, PAPER3, np.ones_like(s))
            self.assertLess(rel_error_db(h, ref), -80.0)
            np.testing.assert_array_equal(h, h_both)
            self.assertEqual(blk.nonfinite_count(), 0)
            self.assertEqual([t.offset for t in tags if pmt.eq(t.key, pmt.intern("marker"))], [7])

    def test_021_reference_only_refuses_a_second_output(self):
        blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"))
        blk.set_reference_only(True)
        s = np.ones((4, self.N), dtype=np.complex64)
        with self.assertRaises(Exception) as ctx:
            self.run_block(blk, s, with_reference=True)
        self.assertIn("noutputs", str(ctx.exception))

    # One test per invalid-parameter rule.
    def assert_refused(self, text, make):
        with self.assertRaises(ValueError) as ctx:
            make()
        self.assertIn(text, str(ctx.exception))
        return str(ctx.exception)

    def test_010_cp_too_short(self):
        msg = self.assert_refused("cyclic prefix too short", lambda: nrsar.scene_echo(
            nrsar.make_numerology("nr273"), self.geo, nrsar.make_scene("paper3")))
        self.assertIn("288 samples", msg)

    def test_011_snr_nan(self):
        self.assert_refused("snr_db = nan", lambda: nrsar.scene_echo(
            self.num, self.geo, nrsar.make_scene("paper3"), float("nan")))
        blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"), 5.0)
        self.assert_refused("snr_db = nan", lambda: blk.set_snr_db(float("nan")))
        self.assertEqual(blk.snr_db(), 5.0)

    def test_012_snr_minus_inf(self):
        self.assert_refused("snr_db = -inf", lambda: nrsar.scene_echo(
            self.num, self.geo, nrsar.make_scene("paper3"), float("-inf")))

    def test_013_invalid_numerology(self):
        num = nrsar.make_numerology("small")
        num.subcarrier_spacing_hz = 0.0
        self.assert_refused("subcarrier_spacing_hz = 0", lambda: nrsar.scene_echo(
            num, self.geo, nrsar.make_scene("paper3")))

    def test_014_invalid_geometry(self):
        geo = nrsar.make_geometry("paper")
        geo.height_m = -5.0
        self.assert_refused("height_m = -5", lambda: nrsar.scene_echo(
            self.num, geo, nrsar.make_scene("paper3")))

    def test_015_eta_too_large(self):
        geo = nrsar.make_geometry("paper")
        geo.carrier_hz = 10e9  # eta = 2 v fc / (c Delta f) = 0.111
        self.assert_refused("normalised Doppler", lambda: nrsar.scene_echo(
            self.num, geo, nrsar.make_scene("paper3")))

    def test_016_invalid_scene(self):
        bad = nrsar.scene([nrsar.point_target(float("nan"), 100.0)])
        self.assert_refused("target 0 x_m = nan", lambda: nrsar.scene_echo(self.num, self.geo, bad))
        self.assert_refused("no targets", lambda: nrsar.scene_echo(self.num, self.geo, nrsar.scene([])))
        negative = nrsar.scene([nrsar.point_target(300.0, 100.0, -1.0)])
        self.assert_refused("rcs = -1", lambda: nrsar.scene_echo(self.num, self.geo, negative))

    def test_019_threads_range(self):
        blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"))
        self.assert_refused("threads = 3 must be in [1, 2]", lambda: blk.set_threads(3))
        self.assert_refused("threads = 0 must be in [1, 2]", lambda: blk.set_threads(0))
        self.assertEqual(blk.threads(), 1)

    def test_017_set_scene_refuses_and_keeps_old(self):
        blk = nrsar.scene_echo(self.num, self.geo, nrsar.make_scene("paper3"))
        far = nrsar.scene([nrsar.point_target(3000.0, 100.0)])  # beyond the CP of 'small'
        self.assert_refused("cyclic prefix too short", lambda: blk.set_scene(far))
        self.assertEqual(len(blk.get_scene().targets), 3)


if __name__ == "__main__":
    gr_unittest.run(qa_scene_echo)
