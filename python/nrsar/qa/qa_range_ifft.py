#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of range_ifft: eq. (29) against numpy.fft.ifft (float64) with padding, crop and
windows; a synthetic point target's peak bin and range-axis tag; parameter validation."""

import math

import numpy as np
import pmt
from gnuradio import blocks, fft, gr, gr_unittest

try:
    from gnuradio import nrsar
except ImportError:
    import os
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bindings"))
    from gnuradio import nrsar

C = 299792458.0
WIN = fft.window


def reference(x, nfft, first, count, w=None):
    """(1/sqrt(N)) sum_n w[n] x[n] exp(+j 2 pi n k / nfft), k = first .. first+count-1."""
    x = np.asarray(x, dtype=np.complex128)
    n = x.shape[-1]
    if w is not None:
        x = x * w
    full = np.fft.ifft(x, n=nfft, axis=-1) * nfft / math.sqrt(n)
    return full[..., first:first + count]


class qa_range_ifft(gr_unittest.TestCase):

    def setUp(self):
        self.tb = gr.top_block()
        self.num = nrsar.make_numerology("tiny")  # N = 64, Delta f = 30 kHz

    def tearDown(self):
        self.tb = None

    def run_block(self, blk, x, n, tags=()):
        src = blocks.vector_source_c(np.asarray(x, np.complex64).ravel().tolist(), False, n,
                                     list(tags))
        snk = blocks.vector_sink_c(blk.num_bins())
        self.tb.connect(src, blk, snk)
        self.tb.run()
        return np.array(snk.data()).reshape(-1, blk.num_bins()), snk.tags()

    def noise(self, m, n, seed):
        rng = np.random.default_rng(seed)
        return rng.normal(size=(m, n)) + 1j * rng.normal(size=(m, n))

    def test_001_unpadded_matches_numpy(self):
        x = self.noise(5, 64, 1)
        blk = nrsar.range_ifft(self.num)
        self.assertEqual((blk.fft_size(), blk.first_bin(), blk.num_bins()), (64, 0, 64))
        out, _ = self.run_block(blk, x, 64)
        np.testing.assert_allclose(out, reference(x.astype(np.complex64), 64, 0, 64),
                                   rtol=1e-5, atol=1e-5)

    def test_002_padded_cropped_matches_numpy(self):
        x = self.noise(4, 64, 2)
        bin_m = C / (2 * 100 * 30e3)  # 49.97 m
        blk = nrsar.range_ifft(self.num, 100, WIN.WIN_RECTANGULAR, -1, 1000.0, 2000.0)
        first, last = math.ceil(1000.0 / bin_m), math.floor(2000.0 / bin_m)
        self.assertEqual((blk.first_bin(), blk.num_bins()), (first, last - first + 1))
        self.assertAlmostEqual(blk.range_bin_m(), bin_m, 9)
        self.assertAlmostEqual(blk.range_axis_first_m(), first * bin_m, 9)
        out, _ = self.run_block(blk, x, 64)
        np.testing.assert_allclose(out, reference(x.astype(np.complex64), 100, first,
                                                  last - first + 1), rtol=1e-5, atol=1e-5)

    def test_003_window_matches_numpy(self):
        x = self.noise(3, 64, 3)
        cases = ((WIN.WIN_HAMMING, -1, np.hamming(64)),
                 (WIN.WIN_BLACKMAN, -1, np.blackman(64)),
                 (WIN.WIN_KAISER, 6.0, np.kaiser(64, 6.0)))
        for win, param, w in cases:
            self.tb = gr.top_block()
            blk = nrsar.range_ifft(self.num, 128, win, param)
            self.assertAlmostEqual(blk.coherent_gain(), np.mean(w), 5)
            out, _ = self.run_block(blk, x, 64)
            np.testing.assert_allclose(out, reference(x.astype(np.complex64), 128, 0, 128, w),
                                       rtol=1e-4, atol=2e-5)

    def test_004_point_target_peak_and_axis_tag(self):
        # Paper numerology, target at R: x[n] = exp(-j 4 pi n Delta f R / c), eq. (27).
        num = nrsar.make_numerology("paper")
        n, df = num.num_subcarriers, num.subcarrier_spacing_hz
        for nfft, win in ((0, WIN.WIN_RECTANGULAR), (nrsar.fast_fft_size(n), WIN.WIN_HANN),
                          (4096, WIN.WIN_HAMMING)):
            for r in (1044.0, 1031.37):
                self.tb = gr.top_block()
                x = np.exp(-4j * np.pi * np.arange(n) * df * r / C)
                blk = nrsar.range_ifft(num, nfft, win, -1, 900.0, 1200.0)
                out, tags = self.run_block(blk, np.tile(x, (2, 1)), n)
                size = blk.fft_size()
                peak = int(np.argmax(np.abs(out[0])))
                self.assertEqual(blk.first_bin() + peak, round(2 * r * size * df / C))
                axis = [t for t in tags if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.range_axis))]
                self.assertEqual(len(axis), 1)
                self.assertEqual(axis[0].offset, 0)
                first_m = pmt.to_double(pmt.tuple_ref(axis[0].value, 0))
                step_m = pmt.to_double(pmt.tuple_ref(axis[0].value, 1))
                k = pmt.to_uint64(pmt.tuple_ref(axis[0].value, 2))
                self.assertEqual(k, blk.num_bins())
                self.assertAlmostEqual(step_m, C / (2 * size * df), 9)
                self.assertLessEqual(abs(first_m + peak * step_m - r), step_m / 2)
                if nfft == 0:
                    # Unwindowed, unpadded, on-bin or not: the peak never exceeds sqrt(N).
                    self.assertLessEqual(np.abs(out[0, peak]), math.sqrt(n) * (1 + 1e-4))

    def test_005_full_band_peak_is_sqrt_n_times_coherent_gain(self):
        num = self.num
        x = np.exp(-2j * np.pi * np.arange(64) * 5 / 64)  # on bin 5 of 64
        for pad in (1, 2, 4):
            for win in (WIN.WIN_RECTANGULAR, WIN.WIN_HANN):
                self.tb = gr.top_block()
                blk = nrsar.range_ifft(num, 64 * pad, win)
                out, _ = self.run_block(blk, x, 64)
                w = np.ones(64) if win == WIN.WIN_RECTANGULAR else np.hanning(64)
                self.assertAlmostEqual(abs(out[0, 5 * pad]), 8.0 * np.mean(w), 4)

    def test_006_tags_propagate_and_window_setter_retags(self):
        x = self.noise(6, 64, 6)
        tag = gr.tag_utils.python_to_tag((2, pmt.intern(nrsar.tag_keys.symbol),
                                          pmt.from_uint64(7), pmt.PMT_F))
        blk = nrsar.range_ifft(self.num)
        src = blocks.vector_source_c(x.astype(np.complex64).ravel().tolist(), False, 64, [tag])
        snk = blocks.vector_sink_c(64)
        self.tb.connect(src, blk, snk)
        self.tb.run()
        blk.set_window(WIN.WIN_HANN, -1)
        self.assertEqual(blk.window(), WIN.WIN_HANN)
        src.rewind()
        self.tb.run()
        out = np.array(snk.data()).reshape(12, 64)
        np.testing.assert_allclose(out[6:], reference(x.astype(np.complex64), 64, 0, 64,
                                                      np.hanning(64)), rtol=1e-4, atol=2e-5)
        tags = snk.tags()
        sym = [(t.offset, pmt.to_uint64(t.value)) for t in tags
               if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.symbol))]
        # (vector_source re-emits its tags at their original offsets after rewind.)
        self.assertEqual(sym[0], (2, 7))
        axis = [t.offset for t in tags if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.range_axis))]
        # A new run restarts the item counters at 0 and the block re-tags its axis there
        # (start() and set_window() both re-arm the tag).
        self.assertEqual(axis, [0, 0])

    def test_007_nonfinite_zeroed_counted_tagged(self):
        x = self.noise(4, 64, 7)
        x[1, 10] = np.nan
        blk = nrsar.range_ifft(self.num)
        out, tags = self.run_block(blk, x, 64)
        self.assertEqual(blk.nonfinite_count(), 1)
        self.assertTrue(np.all(np.isfinite(out)))
        x[1, 10] = 0
        np.testing.assert_allclose(out, reference(x.astype(np.complex64), 64, 0, 64),
                                   rtol=1e-5, atol=1e-5)
        nf = [t.offset for t in tags if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.nonfinite))]
        self.assertEqual(nf, [1])

    def test_008_fast_fft_size(self):
        def smooth(m):
            for p in (2, 3, 5, 7):
                while m % p == 0:
                    m //= p
            return m == 1
        for n in (3333, 3276, 612, 1000, 4097):
            f = nrsar.fast_fft_size(n)
            self.assertEqual(f, next(m for m in range(n, 2 * n + 1) if smooth(m)))
            self.assertEqual(nrsar.range_ifft.fast_fft_size(n), f)
        self.assertEqual(nrsar.fast_fft_size(3333), 3360)

    # One test per invalid-parameter rule.
    def test_010_fft_size_below_n(self):
        with self.assertRaisesRegex(ValueError, r"fft_size = 32 must be 0 \(no padding\) or at "
                                    r"least num_subcarriers = 64"):
            nrsar.range_ifft(self.num, 32)

    def test_011_crop_empty(self):
        # bins of 78.07 m: [100, 150] m holds none
        with self.assertRaisesRegex(ValueError, r"r_max_m = 150 leaves no range bin"):
            nrsar.range_ifft(self.num, 0, WIN.WIN_RECTANGULAR, -1, 100.0, 150.0)

    def test_012_r_max_below_r_min(self):
        with self.assertRaisesRegex(ValueError, r"r_max_m = 500 must be at least r_min_m"):
            nrsar.range_ifft(self.num, 0, WIN.WIN_RECTANGULAR, -1, 1000.0, 500.0)

    def test_013_r_min_beyond_unambiguous_range(self):
        with self.assertRaisesRegex(ValueError, r"r_min_m = 6000 must be in \[0, 4996.54"):
            nrsar.range_ifft(self.num, 0, WIN.WIN_RECTANGULAR, -1, 6000.0, 0.0)

    def test_014_r_min_negative(self):
        with self.assertRaisesRegex(ValueError, r"r_min_m = -1 must be in \[0, "):
            nrsar.range_ifft(self.num, 0, WIN.WIN_RECTANGULAR, -1, -1.0, 0.0)

    def test_015_r_max_beyond_unambiguous_range(self):
        with self.assertRaisesRegex(ValueError, r"r_max_m = 6000 must be at most the "
                                    r"unambiguous range"):
            nrsar.range_ifft(self.num, 0, WIN.WIN_RECTANGULAR, -1, 0.0, 6000.0)

    def test_016_nan_parameters(self):
        nan = float("nan")
        with self.assertRaisesRegex(ValueError, r"r_min_m = nan must be finite"):
            nrsar.range_ifft(self.num, 0, WIN.WIN_RECTANGULAR, -1, nan, 0.0)
        with self.assertRaisesRegex(ValueError, r"r_max_m = nan must be finite"):
            nrsar.range_ifft(self.num, 0, WIN.WIN_RECTANGULAR, -1, 0.0, nan)
        with self.assertRaisesRegex(ValueError, r"window_param = nan must be finite"):
            nrsar.range_ifft(self.num, 0, WIN.WIN_KAISER, nan)
        blk = nrsar.range_ifft(self.num)
        with self.assertRaisesRegex(ValueError, r"window_param = nan must be finite"):
            blk.set_window(WIN.WIN_KAISER, nan)

    def test_017_window_param_missing(self):
        with self.assertRaisesRegex(ValueError, r"window_param = -1 is invalid: .*kaiser"):
            nrsar.range_ifft(self.num, 0, WIN.WIN_KAISER, -1)
        with self.assertRaisesRegex(ValueError, r"window_param = 2 is invalid: .*tukey"):
            nrsar.range_ifft(self.num, 0, WIN.WIN_TUKEY, 2.0)

    def test_018_invalid_numerology(self):
        num = nrsar.make_numerology("tiny")
        num.subcarrier_spacing_hz = -1.0
        with self.assertRaisesRegex(ValueError, r"subcarrier_spacing_hz = -1"):
            nrsar.range_ifft(num)

    def test_019_two_threads_same_output(self):
        # set_threads(2): second half of each work() call on another thread with its own
        # plan: eq. (29) in float64 as with one thread, non-finite tags at the same items.
        x = self.noise(700, 64, 19)
        x[500, 3] = np.nan
        outs = []
        for threads in (1, 2):
            self.tb = gr.top_block()
            blk = nrsar.range_ifft(self.num, 100, WIN.WIN_HANN, -1, 1000.0, 2000.0)
            blk.set_threads(threads)
            self.assertEqual(blk.threads(), threads)
            out, tags = self.run_block(blk, x, 64)
            self.assertEqual(blk.nonfinite_count(), 1)
            nf = [t.offset for t in tags
                  if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.nonfinite))]
            self.assertEqual(nf, [500])
            outs.append(out)
        x[500, 3] = 0
        w = np.asarray(WIN.build(WIN.WIN_HANN, 64, -1, False))
        np.testing.assert_allclose(outs[1], reference(x.astype(np.complex64), 100,
                                                      blk.first_bin(), blk.num_bins(), w),
                                   rtol=1e-5, atol=1e-5)
        np.testing.assert_array_equal(outs[0], outs[1])

    def test_020_invalid_threads(self):
        blk = nrsar.range_ifft(self.num)
        with self.assertRaisesRegex(ValueError, r"threads = 0 must be in"):
            blk.set_threads(0)
        self.assertEqual(blk.threads(), 1)


if __name__ == "__main__":
    gr_unittest.run(qa_range_ifft)
