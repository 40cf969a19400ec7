#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of ofdm_demod: against np.fft on random samples for several FFT window starts, the
linear phase of an early window, the TF model of an echo delayed by 0 .. CP, tag mapping,
non-finite input and parameter validation."""

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest

try:
    from gnuradio import nrsar
except ImportError:
    import os
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "bindings"))
    from gnuradio import nrsar


def numpy_demod(x, num, fft_start):
    n, f, cp = num.num_subcarriers, num.fft_size, num.cp_samples
    k0 = (n // 2) & ~1
    sym = np.asarray(x, np.complex128).reshape(-1, f + cp)
    bins = np.fft.fft(sym[:, fft_start:fft_start + f], axis=1) / np.sqrt(f)
    return bins[:, (np.arange(n) - k0) % f]


def numpy_mod(grid, num):
    n, f, cp = num.num_subcarriers, num.fft_size, num.cp_samples
    k0 = (n // 2) & ~1
    bins = np.zeros((grid.shape[0], f), np.complex128)
    bins[:, (np.arange(n) - k0) % f] = grid
    body = np.fft.ifft(bins, axis=1) * np.sqrt(f)
    return np.concatenate([body[:, f - cp:], body], axis=1).ravel()


class qa_ofdm_demod(gr_unittest.TestCase):

    def setUp(self):
        self.tb = gr.top_block()
        self.rng = np.random.default_rng(11)

    def tearDown(self):
        self.tb = None

    def run_demod(self, x, num, fft_start=-1, tags=()):
        src = blocks.vector_source_c(np.asarray(x, np.complex64).tolist(), False, 1, list(tags))
        dem = nrsar.ofdm_demod(num, fft_start)
        snk = blocks.vector_sink_c(num.num_subcarriers)
        self.tb = gr.top_block()
        self.tb.connect(src, dem, snk)
        self.tb.run()
        return dem, np.array(snk.data()).reshape(-1, num.num_subcarriers), snk.tags()

    def noise(self, n):
        return self.rng.normal(size=n) + 1j * self.rng.normal(size=n)

    def test_001_matches_numpy_fft(self):
        for preset in ("tiny", "sdr20"):
            num = nrsar.make_numerology(preset)
            L = num.fft_size + num.cp_samples
            x = self.noise(4 * L)
            for start in (num.cp_samples, num.cp_samples // 2, 0):
                dem, y, _ = self.run_demod(x, num, start)
                self.assertEqual(dem.fft_start(), start)
                np.testing.assert_allclose(y, numpy_demod(x, num, start), atol=2e-5)
        self.assertEqual(nrsar.ofdm_demod(num).fft_start(), num.cp_samples)

    def test_002_early_window_linear_phase(self):
        num = nrsar.make_numerology("sdr20")
        n, f, cp = num.num_subcarriers, num.fft_size, num.cp_samples
        k0 = num.dc_subcarrier()
        grid = (self.noise(3 * n) / np.sqrt(2)).reshape(3, n)
        x = numpy_mod(grid, num)
        for start in (cp, 100, 0):
            _, y, _ = self.run_demod(x, num, start)
            ramp = np.exp(-2j * np.pi * (np.arange(n) - k0) * (cp - start) / f)
            np.testing.assert_allclose(y, grid * ramp, atol=1e-5)

    def test_003_echo_within_cp_is_tf_model(self):
        # A delay tau <= CP: Y = S exp(-j 2 pi (n - k0) tau / fft_size), SPEC section 3.
        num = nrsar.make_numerology("tiny")
        n, f, cp = num.num_subcarriers, num.fft_size, num.cp_samples
        grid = (self.noise(6 * n) / np.sqrt(2)).reshape(6, n)
        x = numpy_mod(grid, num)
        for tau in (0, 1, 7, cp):
            xd = np.concatenate([np.zeros(tau), x])[:len(x)]
            _, y, _ = self.run_demod(xd, num)
            ramp = np.exp(-2j * np.pi * (np.arange(n) - num.dc_subcarrier()) * tau / f)
            np.testing.assert_allclose(y, grid * ramp, atol=1e-5, err_msg=f"tau {tau}")

    def test_004_tags_map_to_their_symbol(self):
        num = nrsar.make_numerology("tiny")
        L = num.fft_size + num.cp_samples
        offsets = (0, L - 1, L, 2 * L + 5, 3 * L + num.cp_samples)
        tags = [gr.tag_utils.python_to_tag((o, pmt.intern("k"), pmt.from_long(o))) for o in offsets]
        _, y, out_tags = self.run_demod(self.noise(4 * L), num, tags=tags)
        got = sorted((t.offset, pmt.to_long(t.value)) for t in out_tags)
        self.assertEqual(got, [(0, 0), (0, L - 1), (1, L), (2, 2 * L + 5), (3, 3 * L + 16)])

    def test_005_nonfinite_zeroed_and_tagged(self):
        num = nrsar.make_numerology("tiny")
        L = num.fft_size + num.cp_samples
        x = self.noise(3 * L)
        bad = x.copy()
        bad[L + 20] = np.nan
        dem, y, out_tags = self.run_demod(bad, num)
        clean = x.copy()
        clean[L + 20] = 0
        np.testing.assert_allclose(y, numpy_demod(clean, num, num.cp_samples), atol=2e-5)
        self.assertEqual(dem.nonfinite_count(), 1)
        nf = [t.offset for t in out_tags if pmt.symbol_to_string(t.key) == nrsar.tag_keys.nonfinite]
        self.assertEqual(nf, [1])

    def test_006_window_beyond_cp_rejected(self):
        num = nrsar.make_numerology("tiny")
        with self.assertRaises(ValueError) as ctx:
            nrsar.ofdm_demod(num, num.cp_samples + 1)
        self.assertIn("fft_start = 17 must be at most cp_samples = 16", str(ctx.exception))


if __name__ == "__main__":
    gr_unittest.run(qa_ofdm_demod)
