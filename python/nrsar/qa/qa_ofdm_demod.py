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
from gnuradio.nrsar.theory import ofdm_demodulate as numpy_demod
from gnuradio.nrsar.theory import ofdm_modulate as numpy_mod

try:
    from gnuradio import nrsar
except ImportError:
    import os
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bindings"))
    from gnuradio import nrsar


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


    # rx_time alignment (tx_start_time): symbols from a numpy modulator behind junk samples,
    # stamped the way a USRP source stamps its first sample and the first after an overflow.

    def stamp(self, offset, full, frac):
        return gr.tag_utils.python_to_tag(
            (offset, pmt.intern("rx_time"),
             pmt.make_tuple(pmt.from_uint64(full), pmt.from_double(frac))))

    def run_aligned(self, x, num, t0, tags):
        src = blocks.vector_source_c(np.asarray(x, np.complex64).tolist(), False, 1, list(tags))
        dem = nrsar.ofdm_demod(num, -1, t0)
        snk = blocks.vector_sink_c(num.num_subcarriers)
        self.tb = gr.top_block()
        self.tb.connect(src, dem, snk)
        self.tb.run()
        return dem, np.array(snk.data()).reshape(-1, num.num_subcarriers), snk.tags()

    def tag_values(self, tags, key):
        return sorted((t.offset, pmt.to_uint64(t.value)) for t in tags
                      if pmt.symbol_to_string(t.key) == key)

    def test_007_rx_time_aligns_symbol_zero(self):
        # TX at 1e6 + 0.5 s; the receiver's first sample is stamped 1234 samples earlier:
        # rx_time = (1000000, 0.5 - 1234 / fs), fractions in double.
        num = nrsar.make_numerology("tiny")
        n, fs = num.num_subcarriers, num.sample_rate_hz()
        grid = (self.noise(30 * n) / np.sqrt(2)).reshape(30, n)
        pre = 1234
        x = np.concatenate([self.noise(pre), numpy_mod(grid, num)])
        dem, y, tags = self.run_aligned(x, num, 1e6 + 0.5,
                                        [self.stamp(0, 1000000, 0.5 - pre / fs)])
        np.testing.assert_allclose(y, grid, atol=1e-5)
        self.assertTrue(dem.aligned())
        self.assertEqual(dem.dropped_samples(), pre)
        self.assertEqual(dem.lost_symbols(), 0)
        self.assertEqual(dem.next_symbol(), 30)
        self.assertEqual(self.tag_values(tags, nrsar.tag_keys.symbol), [(0, 0), (14, 14), (28, 28)])
        self.assertEqual(self.tag_values(tags, nrsar.tag_keys.slot), [(0, 0), (14, 1), (28, 2)])
        # The stamp itself moves to the first symbol.
        self.assertEqual([t.offset for t in tags if pmt.symbol_to_string(t.key) == "rx_time"], [0])

    def test_008_stamp_in_an_earlier_second(self):
        # TX at 1e6 + 0.00002 s, RX stamped at 999999.99999 s: 3e-5 s = 57.6 -> 58 samples.
        num = nrsar.make_numerology("tiny")
        n, fs = num.num_subcarriers, num.sample_rate_hz()
        pre = int(round(3e-5 * fs))
        grid = (self.noise(4 * n) / np.sqrt(2)).reshape(4, n)
        x = np.concatenate([self.noise(pre), numpy_mod(grid, num)])
        dem, y, _ = self.run_aligned(x, num, 1e6 + 0.00002, [self.stamp(0, 999999, 0.99999)])
        self.assertEqual(dem.dropped_samples(), pre)
        np.testing.assert_allclose(y, grid, atol=1e-5)

    def test_009_late_start_and_overflow_counted(self):
        num = nrsar.make_numerology("tiny")
        n, fs = num.num_subcarriers, num.sample_rate_hz()
        L = num.fft_size + num.cp_samples
        nsym = 40
        grid = (self.noise(nsym * n) / np.sqrt(2)).reshape(nsym, n)
        tx = numpy_mod(grid, num)
        t0 = 1e6 + 0.5
        # Late start: the receiver starts 2 L + 30 samples after the TX start, so symbols
        # 0..2 are incomplete; then an overflow loses TX samples 10 L + 5 .. 16 L + 40 - 1.
        a, gap0, gap1 = 2 * L + 30, 10 * L + 5, 16 * L + 40
        rx = np.concatenate([tx[a:gap0], tx[gap1:]])
        tags = [self.stamp(0, 1000000, 0.5 + a / fs),
                self.stamp(gap0 - a, 1000000, 0.5 + gap1 / fs)]
        dem, y, out_tags = self.run_aligned(rx, num, t0, tags)
        # received whole: 3 .. 9 (before the gap) and 17 .. 39; the lost symbols 0..2 and
        # 10..16 (symbol 10 is partial) come out as zeros in their places
        lost = list(range(0, 3)) + list(range(10, 17))
        want = grid.copy()
        want[lost] = 0
        np.testing.assert_allclose(y, want, atol=1e-5)
        self.assertEqual(dem.lost_symbols(), len(lost))
        self.assertEqual(dem.next_symbol(), nsym)
        # dropped: head of symbol 3, tail before the gap (symbol 10 partial), head of 17
        self.assertEqual(dem.dropped_samples(), (3 * L - a) + (gap0 - 10 * L) + (17 * L - gap1))
        self.assertEqual(dem.rx_time_tags(), 2)
        # output item k is symbol k: tagged at each stamp's first (zero) symbol, at the
        # first received symbol after the zeros and at the slot starts
        sym = self.tag_values(out_tags, nrsar.tag_keys.symbol)
        self.assertEqual(sym, [(0, 0), (3, 3), (10, 10), (14, 14), (17, 17), (28, 28)])
        self.assertEqual(self.tag_values(out_tags, nrsar.tag_keys.slot),
                         [(0, 0), (14, 1), (28, 2)])

    def test_010_consistent_stamp_changes_nothing_and_no_stamp_drops(self):
        num = nrsar.make_numerology("tiny")
        n, fs = num.num_subcarriers, num.sample_rate_hz()
        L = num.fft_size + num.cp_samples
        grid = (self.noise(6 * n) / np.sqrt(2)).reshape(6, n)
        x = numpy_mod(grid, num)
        # a second stamp in the middle of symbol 2 that agrees with the first: no loss
        tags = [self.stamp(0, 7, 0.25), self.stamp(2 * L + 11, 7, 0.25 + (2 * L + 11) / fs)]
        dem, y, _ = self.run_aligned(x, num, 7.25, tags)
        np.testing.assert_allclose(y, grid, atol=1e-5)
        self.assertEqual((dem.lost_symbols(), dem.dropped_samples()), (0, 0))
        # alignment on, no stamp: nothing is output, every sample counted as dropped
        dem, y, _ = self.run_aligned(x, num, 7.25, [])
        self.assertEqual(len(y), 0)
        self.assertEqual(dem.dropped_samples(), len(x))
        self.assertFalse(dem.aligned())
        # off (default): plain demodulation, the stamp moves like any tag
        dem, y, _ = self.run_aligned(x, num, -1.0, tags)
        np.testing.assert_allclose(y, grid, atol=1e-5)
        self.assertEqual(dem.tx_start_time(), -1.0)

    def test_011_invalid_tx_start_time(self):
        num = nrsar.make_numerology("tiny")
        with self.assertRaises(ValueError) as ctx:
            nrsar.ofdm_demod(num, -1, float("nan"))
        self.assertIn("tx_start_time = nan must be a finite time", str(ctx.exception))


if __name__ == "__main__":
    gr_unittest.run(qa_ofdm_demod)
