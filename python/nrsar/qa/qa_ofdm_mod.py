#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of ofdm_mod: samples against a slow numpy CP-OFDM modulator (subcarrier n at FFT bin
(n - k0) mod fft_size, unitary scaling), the round trip through ofdm_demod, tag placement,
non-finite input and parameter validation."""

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


def numpy_mod(grid, num):
    """Slow reference: one np.fft.ifft per symbol, float64."""
    n, f, cp = num.num_subcarriers, num.fft_size, num.cp_samples
    k0 = (n // 2) & ~1
    out = []
    for s in np.asarray(grid, np.complex128):
        bins = np.zeros(f, np.complex128)
        for k in range(n):
            bins[(k - k0) % f] = s[k]
        body = np.fft.ifft(bins) * f / np.sqrt(f)
        out.append(np.concatenate([body[f - cp:], body]))
    return np.concatenate(out)


def random_grid(m, n, seed):
    rng = np.random.default_rng(seed)
    return (rng.normal(size=(m, n)) + 1j * rng.normal(size=(m, n))) / np.sqrt(2)


class qa_ofdm_mod(gr_unittest.TestCase):

    def setUp(self):
        self.tb = gr.top_block()

    def tearDown(self):
        self.tb = None

    def run_mod(self, grid, num, tags=()):
        n = num.num_subcarriers
        src = blocks.vector_source_c(np.asarray(grid, np.complex64).ravel().tolist(), False, n,
                                     list(tags))
        mod = nrsar.ofdm_mod(num)
        snk = blocks.vector_sink_c()
        self.tb.connect(src, mod, snk)
        self.tb.run()
        return mod, np.array(snk.data()), snk.tags()

    def test_001_matches_numpy_modulator(self):
        for preset in ("tiny", "sdr20", "small"):
            num = nrsar.make_numerology(preset)
            grid = random_grid(5, num.num_subcarriers, 1)
            self.tb = gr.top_block()
            mod, x, _ = self.run_mod(grid, num)
            ref = numpy_mod(grid, num)
            self.assertEqual(len(x), 5 * (num.fft_size + num.cp_samples))
            self.assertEqual(mod.symbol_length(), num.fft_size + num.cp_samples)
            err = np.max(np.abs(x - ref)) / np.sqrt(np.mean(np.abs(ref) ** 2))
            self.assertLess(err, 1e-5, preset)

    def test_002_odd_subcarrier_count_and_dc(self):
        # N = 51 of 64: k0 = 24 (even); a lone subcarrier k0 is the DC term.
        num = nrsar.make_numerology("tiny", num_subcarriers=51)
        grid = np.zeros((1, 51), complex)
        grid[0, 24] = 1.0
        _, x, _ = self.run_mod(grid, num)
        np.testing.assert_allclose(x, np.full(80, 1 / 8), atol=1e-6)

    def test_003_unitary_noise_power(self):
        # White per-RE grid on all bins: per-sample power = N / fft_size times RE power.
        num = nrsar.make_numerology("sdr20")
        grid = random_grid(40, num.num_subcarriers, 2)
        _, x, _ = self.run_mod(grid, num)
        body = x.reshape(40, -1)[:, num.cp_samples:]
        ratio = np.mean(np.abs(body) ** 2) / (num.num_subcarriers / num.fft_size)
        self.assertAlmostEqual(ratio, np.mean(np.abs(grid) ** 2), delta=0.01)

    def test_004_round_trip_through_demod(self):
        for preset in ("tiny", "sdr20", "paper"):
            num = nrsar.make_numerology(preset)
            grid = random_grid(4, num.num_subcarriers, 3)
            tb = gr.top_block()
            src = blocks.vector_source_c(grid.astype(np.complex64).ravel().tolist(), False,
                                         num.num_subcarriers)
            snk = blocks.vector_sink_c(num.num_subcarriers)
            tb.connect(src, nrsar.ofdm_mod(num), nrsar.ofdm_demod(num), snk)
            tb.run()
            y = np.array(snk.data()).reshape(grid.shape)
            rel = np.max(np.abs(y - grid)) / np.max(np.abs(grid))
            self.assertLess(rel, 1e-5, preset)

    def test_005_tags_move_to_symbol_start(self):
        num = nrsar.make_numerology("tiny")
        L = num.fft_size + num.cp_samples
        tags = [gr.tag_utils.python_to_tag((i, pmt.intern(key), pmt.from_uint64(v)))
                for i, key, v in ((0, nrsar.tag_keys.symbol, 0), (0, nrsar.tag_keys.slot, 0),
                                  (3, "user", 7), (5, nrsar.tag_keys.symbol, 14))]
        _, x, out_tags = self.run_mod(random_grid(6, 64, 4), num, tags)
        got = sorted((t.offset, pmt.symbol_to_string(t.key), pmt.to_uint64(t.value))
                     for t in out_tags)
        self.assertEqual(got, sorted([(0, "symbol", 0), (0, "slot", 0), (3 * L, "user", 7),
                                      (5 * L, "symbol", 14)]))

    def test_006_nonfinite_zeroed_and_tagged(self):
        num = nrsar.make_numerology("tiny")
        L = num.fft_size + num.cp_samples
        grid = random_grid(3, 64, 5)
        bad = grid.copy()
        bad[1, 7] = np.nan
        bad[1, 9] = np.inf
        mod, x, out_tags = self.run_mod(bad, num)
        clean = grid.copy()
        clean[1, 7] = clean[1, 9] = 0
        np.testing.assert_allclose(x, numpy_mod(clean, num), atol=1e-5)
        self.assertEqual(mod.nonfinite_count(), 2)
        nf = [(t.offset, pmt.to_uint64(t.value)) for t in out_tags
              if pmt.symbol_to_string(t.key) == nrsar.tag_keys.nonfinite]
        self.assertEqual(nf, [(L, 2)])

    def test_007_invalid_numerology(self):
        num = nrsar.numerology.preset("tiny")
        num.fft_size = 32
        with self.assertRaises(ValueError) as ctx:
            nrsar.ofdm_mod(num)
        self.assertIn("fft_size = 32", str(ctx.exception))


if __name__ == "__main__":
    gr_unittest.run(qa_ofdm_mod)
