#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of range_compress (tf_filter and range_ifft fused): eq. (25) then eq. (29) against a
float64 numpy reference for the three filters, windows, padding and crop; the same output
as the separate blocks (fixed and estimated SNR_in); tags; non-finite input; parameter
validation."""

import math
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, fft, gr, gr_unittest
from qa_tf_filter import ref_filter  # eq. (25) in float64, empty REs -> 0

try:
    from gnuradio import nrsar
except ImportError:
    import os
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bindings"))
    from gnuradio import nrsar

C = 299792458.0
WIN = fft.window
N = 64  # the "tiny" numerology's subcarriers


def qam256(rng, shape):
    """256-QAM points: odd levels -15..15 on both axes over sqrt(170) (SPEC 2)."""
    lv = 2 * rng.integers(0, 16, size=shape + (2,)) - 15
    return (lv[..., 0] + 1j * lv[..., 1]) / math.sqrt(170)


def reference(y, s, name, snr_db, nfft, first, count, w=None):
    """float64: g of eq. (17) / (20) / (23) (0 on an empty RE), then
    (1/sqrt(N)) sum_n w[n] y[n] g(s[n]) exp(+j 2 pi n k / nfft), k = first .. + count - 1."""
    x = ref_filter(name, y, s, snr_db) * (1.0 if w is None else w)
    n = x.shape[-1]
    return (np.fft.ifft(x, n=nfft, axis=-1) * nfft / math.sqrt(n))[..., first:first + count]


FILTERS = {"rf": nrsar.filter_type.RF, "mf": nrsar.filter_type.MF, "wf": nrsar.filter_type.WF}


class qa_range_compress(gr_unittest.TestCase):

    def setUp(self):
        self.tb = gr.top_block()
        self.num = nrsar.make_numerology("tiny")  # N = 64, Delta f = 30 kHz

    def tearDown(self):
        self.tb = None

    def grid(self, m, seed, every_empty=0):
        rng = np.random.default_rng(seed)
        y = rng.normal(size=(m, N)) + 1j * rng.normal(size=(m, N))
        s = qam256(rng, (m, N))
        if every_empty:
            s[:, ::every_empty] = 0
        return y.astype(np.complex64), s.astype(np.complex64)

    def run_block(self, blk, y, s, y_tags=(), s_tags=()):
        src_y = blocks.vector_source_c(y.ravel().tolist(), False, N, list(y_tags))
        src_s = blocks.vector_source_c(s.ravel().tolist(), False, N, list(s_tags))
        snk = blocks.vector_sink_c(blk.num_bins())
        self.tb.connect(src_y, (blk, 0))
        self.tb.connect(src_s, (blk, 1))
        self.tb.connect(blk, snk)
        self.tb.run()
        return np.array(snk.data()).reshape(-1, blk.num_bins()), snk.tags()

    def test_001_matches_float64_reference(self):
        y, s = self.grid(5, 1, every_empty=9)
        bin_m = C / (2 * 100 * 30e3)
        first, last = math.ceil(1000.0 / bin_m), math.floor(2500.0 / bin_m)
        for name, ftype in FILTERS.items():
            for win, w in ((WIN.WIN_RECTANGULAR, None), (WIN.WIN_HANN, np.hanning(N))):
                self.tb = gr.top_block()
                cfg = nrsar.range_compress_config(filter=ftype, snr_db=-5.0, fft_size=100,
                                                  window=win, r_min_m=1000.0, r_max_m=2500.0)
                blk = nrsar.range_compress(self.num, cfg)
                self.assertEqual((blk.fft_size(), blk.first_bin(), blk.num_bins()),
                                 (100, first, last - first + 1))
                out, _ = self.run_block(blk, y, s)
                ref = reference(y, s, name, -5.0, 100, first, last - first + 1, w)
                # float rounding of a 64-term sum: 1e-5 of the profile's rms is far above it
                rms = np.sqrt(np.mean(np.abs(ref) ** 2))
                np.testing.assert_allclose(out, ref, rtol=0, atol=1e-5 * rms,
                                           err_msg=f"{name} {win}")
                self.assertEqual(blk.empty_re_count(), 5 * len(range(0, N, 9)))

    def test_002_equals_separate_blocks(self):
        # tf_filter -> range_ifft with the same parameters, fixed and estimated SNR_in
        # (the estimator's window of 2^24 REs: every vector updates it).
        y, s = self.grid(40, 2)
        for estimate in (False, True):
            self.tb = gr.top_block()
            cfg = nrsar.range_compress_config(filter=nrsar.filter_type.WF, snr_db=3.0,
                                              estimate_snr=estimate, fft_size=80,
                                              window=WIN.WIN_KAISER, window_param=6.0,
                                              r_min_m=500.0, r_max_m=3000.0)
            fused = nrsar.range_compress(self.num, cfg)
            out, _ = self.run_block(fused, y, s)
            tb = gr.top_block()
            tff = nrsar.tf_filter(N, nrsar.filter_type.WF, 3.0, estimate)
            rif = nrsar.range_ifft(self.num, 80, WIN.WIN_KAISER, 6.0, 500.0, 3000.0)
            snk = blocks.vector_sink_c(rif.num_bins())
            tb.connect(blocks.vector_source_c(y.ravel().tolist(), False, N), (tff, 0))
            tb.connect(blocks.vector_source_c(s.ravel().tolist(), False, N), (tff, 1))
            tb.connect(tff, rif, snk)
            tb.run()
            sep = np.array(snk.data()).reshape(out.shape)
            np.testing.assert_allclose(out, sep, rtol=0, atol=1e-6 * np.abs(sep).max())
            self.assertAlmostEqual(fused.coherent_gain(), np.mean(np.kaiser(N, 6.0)), 5)
            if estimate:
                self.assertTrue(math.isfinite(fused.estimated_snr_db()))
                self.assertAlmostEqual(fused.estimated_snr_db(), tff.estimated_snr_db(), 9)

    def test_002b_snr_history_from_prepass(self):
        # a strip task's start (docs/scale.md): range_compress started at vector 25 from the
        # history tf_filter's pre-pass gives equals the block that saw all 40 vectors, bit
        # for bit, from vector 25 on (its estimate too); a malformed history is refused
        y, s = self.grid(40, 3, every_empty=5)
        cfg = nrsar.range_compress_config(filter=nrsar.filter_type.WF, snr_db=3.0,
                                          estimate_snr=True, fft_size=80)
        whole = nrsar.range_compress(self.num, cfg)
        out, _ = self.run_block(whole, y, s)
        self.tb = gr.top_block()
        pre = nrsar.tf_filter(N, nrsar.filter_type.WF, 3.0, True)
        pre.set_snr_prepass(True)
        self.tb.connect(blocks.vector_source_c(y.ravel().tolist(), False, N), (pre, 0))
        self.tb.connect(blocks.vector_source_c(s.ravel().tolist(), False, N), (pre, 1))
        self.tb.connect(pre, blocks.null_sink(gr.sizeof_gr_complex * N))
        self.tb.run()
        history = nrsar.tf_filter.snr_histories(N, pre.snr_sums(), [25])[0]
        self.tb = gr.top_block()
        task = nrsar.range_compress(self.num, cfg)
        task.set_snr_history(history)
        self.assertEqual(task.snr_history(), history)
        part, _ = self.run_block(task, y[25:], s[25:])
        np.testing.assert_array_equal(part, out[25:])
        self.assertEqual(task.estimated_snr_db(), whole.estimated_snr_db())
        with self.assertRaisesRegex(ValueError, r"history: 3 values"):
            task.set_snr_history([1.0, 2.0, 3.0])

    def test_003_tags_and_window_setter(self):
        y, s = self.grid(6, 3)

        def tag(offset, value):
            return gr.tag_utils.python_to_tag((offset, pmt.intern(nrsar.tag_keys.symbol),
                                               pmt.from_uint64(value), pmt.PMT_F))
        blk = nrsar.range_compress(self.num, nrsar.range_compress_config(
            filter=nrsar.filter_type.MF))
        out, tags = self.run_block(blk, y, s, [tag(2, 7)], [tag(3, 8)])
        sym = [(t.offset, pmt.to_uint64(t.value)) for t in tags
               if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.symbol))]
        self.assertEqual(sym, [(2, 7)])  # the echo's tags only
        axis = [t for t in tags if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.range_axis))]
        self.assertEqual([t.offset for t in axis], [0])
        self.assertAlmostEqual(pmt.to_double(pmt.tuple_ref(axis[0].value, 1)),
                               C / (2 * N * 30e3), 9)
        self.assertEqual(pmt.to_uint64(pmt.tuple_ref(axis[0].value, 2)), N)
        blk.set_window(WIN.WIN_HAMMING, -1)
        self.assertEqual(blk.window(), WIN.WIN_HAMMING)
        self.tb = gr.top_block()
        out, tags = self.run_block(blk, y, s)
        np.testing.assert_allclose(out, reference(y, s, "mf", 0, N, 0, N, np.hamming(N)),
                                   rtol=0, atol=1e-5 * np.abs(out).max())
        axis = [t.offset for t in tags if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.range_axis))]
        self.assertEqual(axis, [0])

    def test_004_nonfinite_zeroed_counted_tagged(self):
        y, s = self.grid(4, 4)
        y[1, 10] = np.nan
        s[2, 20] = np.inf
        blk = nrsar.range_compress(self.num, nrsar.range_compress_config(snr_db=0.0))
        out, tags = self.run_block(blk, y, s)
        self.assertEqual(blk.nonfinite_count(), 2)
        self.assertTrue(np.all(np.isfinite(out)))
        y[1, 10] = 0
        s[2, 20] = 0
        ref = reference(y, s, "wf", 0.0, N, 0, N)
        np.testing.assert_allclose(out, ref, rtol=0, atol=1e-5 * np.abs(ref).max())
        nf = [t.offset for t in tags if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.nonfinite))]
        self.assertEqual(nf, [1, 2])

    def test_005_constant_modulus_items_counted(self):
        rng = np.random.default_rng(5)
        s = (np.exp(1j * np.pi / 2 * rng.integers(0, 4, size=(3, N)) + 1j * np.pi / 4)
             ).astype(np.complex64)
        y = (rng.normal(size=(3, N)) + 1j * rng.normal(size=(3, N))).astype(np.complex64)
        blk = nrsar.range_compress(self.num, nrsar.range_compress_config(
            filter=nrsar.filter_type.RF))
        out, _ = self.run_block(blk, y, s)
        self.assertEqual(blk.constant_modulus_items(), 3)
        ref = reference(y, s, "rf", 0, N, 0, N)
        np.testing.assert_allclose(out, ref, rtol=0, atol=1e-5 * np.abs(ref).max())

    def check_error(self, names, **kw):
        with self.assertRaises(ValueError) as ctx:
            nrsar.range_compress(self.num, nrsar.range_compress_config(**kw))
        for name in names:
            self.assertIn(name, str(ctx.exception))

    def test_006_invalid_parameters(self):
        self.check_error(["fft_size = 32", "64"], fft_size=32)
        self.check_error(["r_max_m", "leaves no range bin"], r_min_m=100.0, r_max_m=110.0)
        self.check_error(["snr_db = 300", "200"], snr_db=300.0)
        self.check_error(["window_param"], window=WIN.WIN_KAISER, window_param=float("nan"))
        blk = nrsar.range_compress(self.num)
        with self.assertRaises(ValueError):
            blk.set_snr_db(float("nan"))

    def test_009_unit_grid_is_the_all_ones_reference(self):
        # unit_grid: one input, S = 1: bit for bit the block fed an all-ones grid (every
        # filter, constant-modulus path on and off), the float64 reference within rounding,
        # the echo's tags kept.
        y, _ = self.grid(30, 9)
        ones = np.ones_like(y)
        tag = gr.tag_utils.python_to_tag((4, pmt.intern("marker"), pmt.from_long(4)))
        bin_m = C / (2 * 80 * 30e3)
        first, last = math.ceil(500.0 / bin_m), math.floor(3000.0 / bin_m)
        for name, ftype in FILTERS.items():
            for cm in (True, False):
                cfg = nrsar.range_compress_config(filter=ftype, snr_db=-20.0, fft_size=80,
                                                  r_min_m=500.0, r_max_m=3000.0)
                self.tb = gr.top_block()
                two = nrsar.range_compress(self.num, cfg)
                two.set_constant_modulus_path(cm)
                want, _ = self.run_block(two, y, ones)
                cfg.unit_grid = True
                one = nrsar.range_compress(self.num, cfg)
                one.set_constant_modulus_path(cm)
                self.assertEqual(one.input_signature().max_streams(), 1)
                self.tb = gr.top_block()
                snk = blocks.vector_sink_c(one.num_bins())
                self.tb.connect(blocks.vector_source_c(y.ravel().tolist(), False, N, [tag]),
                                one, snk)
                self.tb.run()
                got = np.array(snk.data()).reshape(-1, one.num_bins())
                np.testing.assert_array_equal(got, want, err_msg=f"{name} cm {cm}")
                ref = reference(y, ones, name, -20.0, 80, first, last - first + 1)
                rms = np.sqrt(np.mean(np.abs(ref) ** 2))
                np.testing.assert_allclose(got, ref, rtol=0, atol=1e-5 * rms)
                self.assertEqual([t.offset for t in snk.tags()
                                  if pmt.eq(t.key, pmt.intern("marker"))], [4])

    def test_007_chain_rx_fuse_same_image(self):
        # nrsar-sim's chain with --rx-fuse on (range_compress in both branches) against the
        # separate blocks: the same range-compressed data and image within float rounding,
        # the same metrics, and the receive times under the fused block's own name.
        from gnuradio.nrsar import chain
        from gnuradio.nrsar.options import SimOptions
        runs = {}
        for fuse in ("off", "on"):
            out = tempfile.mkdtemp(prefix="qa_range_compress_")
            runs[fuse] = chain.simulate(SimOptions.parse(
                ["--preset", "small", "--aperture-s", "0.2", "--target", "300,5",
                 "--snr-db", "-10", "--presum", "cheby", "--decim", "4", "--rx-fuse", fuse,
                 "--out", out]))
        a, b = runs["off"], runs["on"]
        for key in ("image_npy", "range_compressed_npy"):
            x, y = np.load(a[key]), np.load(b[key])
            self.assertEqual(x.shape, y.shape)
            np.testing.assert_allclose(y, x, rtol=0, atol=1e-5 * np.abs(x).max())
        for key in ("nmse_db", "snr_out_db", "pel_db"):
            self.assertAlmostEqual(a[key], b[key], 3)
        self.assertEqual(set(a["rx_block_s"]), {"filter", "range_ifft", "presum", "focuser",
                                                "probe"})
        self.assertEqual(set(b["rx_block_s"]), {"range_compress", "presum", "focuser",
                                                "probe"})

    def test_008_isac_rx_fuse_names_the_block_once(self):
        # nrsar-isac with --rx-fuse on: the same radar image metrics, and block_cpu_s names
        # the fused block once (not under the filter's and the range IFFT's keys both)
        from gnuradio.nrsar import isac_chain
        from gnuradio.nrsar.options import IsacOptions
        runs = {}
        for fuse in ("off", "on"):
            out = tempfile.mkdtemp(prefix="qa_range_compress_isac_")
            runs[fuse] = isac_chain.run(IsacOptions.parse(
                ["--preset", "tiny", "--aperture-s", "0.05", "--rx-fuse", fuse,
                 "--images", "none", "--out", out]))
        a, b = runs["off"], runs["on"]
        self.assertAlmostEqual(a["nmse_db"], b["nmse_db"], 3)
        radar = {f: {k for k in r["block_cpu_s"] if k.startswith("radar_")}
                 for f, r in runs.items()}
        self.assertEqual(radar["off"] - radar["on"], {"radar_filter", "radar_range_ifft"})
        self.assertEqual(radar["on"] - radar["off"], {"radar_range_compress"})


if __name__ == "__main__":
    gr_unittest.run(qa_range_compress)
