#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-process --strip-aperture-s / --dask (distributed_process.py): a recording of four
apertures, a target on the boundary between two, processed as a strip on a local Dask cluster
over TLS equals one graph focusing the whole recording (each task reads its aperture and the
focuser's overlap by offset); a worker killed mid-run costs a retry; a slice with non-finite
samples is reported with its aperture index while the others complete; with --estimate-snr
each task starts its SNR estimator from the history a pre-pass gives and the strip still
equals one graph (a recording whose SNR falls along the track); with --band full the strip
warns that the full band's reference reaches past the overlap and names the overlap that makes
every block linear; a navigation that sways within one aperture warns that the range grid's
headroom falls short there, naming that aperture; a client without the certificate is refused
by the scheduler; --dask-make-certs writes a set."""

import contextlib
import dataclasses
import faulthandler
import gc
import math
import os
import re
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import threading
import time
from unittest import mock

import numpy as np
from gnuradio import gr, gr_unittest

from gnuradio.nrsar import distributed_process as dp, params, recording
from gnuradio.nrsar.options import OptionError, ProcessOptions

APPS = os.environ.get("NRSAR_APPS_DIR") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps")

# sdr20 imaging on its SRS pulses (srs2: one pulse every 28 symbols, 857 Hz), 0.5 s = 428
# lines along 25 m of track (5.8 cm per line), cut into four apertures of 0.125 s (107 lines).
# Image row r is the flight's line r + s (s = line_shift(), -56 lines for this scene), so the
# first target, at y = 15.5 m = line 265.7, lies on row 321.7, the boundary of apertures 2 and
# 3, with an azimuth IRW of about 28 rows (1.6 m); the second in aperture 1. Each aperture's
# overlap-save block (402 lines of history, 516 of look-ahead) reaches past the recording.
FLIGHT = ["--preset", "sdr20", "--mode", "srs2", "--aperture-s", "0.5", "--target",
          "300,15.5", "--target", "290,3", "--snr-db", "5"]
M, BOUNDARY, STEP = 107, 321, 28  # lines per aperture, the first row of aperture 3, symbols per line


class qa_distributed_process(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        # a cluster that hangs fails the test with every thread's traceback, bounded
        faulthandler.dump_traceback_later(1500, exit=True)
        cls.dir = tempfile.mkdtemp(prefix="qa_distributed_process_")
        rec = os.path.join(cls.dir, "rec")
        sim = subprocess.run([sys.executable, os.path.join(APPS, "nrsar-sim")] + FLIGHT +
                             ["--record", rec, "--images", "none", "--quiet",
                              "--out", os.path.join(cls.dir, "sim")],
                             capture_output=True, text=True, timeout=900)
        assert sim.returncode == 0, sim.stderr
        cls.meta = os.path.join(rec, "flight.sigmf-meta")
        cls.whole_image = cls.whole(cls.opts("whole"))
        # one local cluster (TLS, 2 workers) for the class, made as nrsar-process --dask
        # local:2 makes it
        cls.stack = contextlib.ExitStack()
        cls.client = cls.stack.enter_context(dp.connect(cls.opts("c", dask="local:2")))

    @classmethod
    def tearDownClass(cls):
        cls.stack.close()
        faulthandler.cancel_dump_traceback_later()
        shutil.rmtree(cls.dir, ignore_errors=True)

    @classmethod
    def opts(cls, name, meta=None, **kw):
        return ProcessOptions(recording=meta or cls.meta, strip_aperture_s=0.125,
                              out=os.path.join(cls.dir, name), **kw).validate()

    @classmethod
    def whole(cls, opts):
        """One graph focusing the whole recording (the single-process result)."""
        rec = recording.read(opts.recording)
        return dp.focus_slice(opts, opts.recording,
                              dp.whole(opts, rec, dp.layout(opts, rec)))["image"]

    def _corrupted(self, name, symbol):
        """A copy of the recording (its meta) with 10 NaN samples in the symbol."""
        folder = os.path.join(self.dir, name)
        shutil.copytree(os.path.dirname(self.meta), folder)
        meta = os.path.join(folder, "flight.sigmf-meta")
        rec = recording.read(meta)
        at = rec.hardware_delay_samples + symbol * rec.symbol_samples
        data = np.memmap(rec.data_path, np.complex64, "r+")
        data[at:at + 10] = np.nan
        data.flush()
        return meta

    def _assert_fails_alone(self, res, symbol, aperture):
        """Only the aperture's task reads the bad symbol, and only it failed, by index."""
        read = [a for a, (first, n) in enumerate(res["strip_slices"])
                if first <= symbol < first + n]
        self.assertEqual(read, [aperture])
        self.assertEqual([f["aperture"] for f in res["strip_failed"]], read)
        self.assertRegex(res["strip_failed"][0]["error"], rf"aperture {aperture}: \d+ non-finite")

    def test_001_dask_equals_one_process(self):
        # two tasks submitted and not yet written at once, a strip of four: the client
        # streams each aperture into the file in order, holding at most two
        res = dp.run(self.opts("dask", dask="local:2", strip_window=2), self.client)
        self.assertEqual((res["strip_apertures"], res["dask_workers"]), (4, 2))
        self.assertEqual(res["strip_held_peak"], 2)
        self.assertEqual(res["strip_failed"], [])
        # the straight line: no sway, no range-grid warning (test_003i)
        self.assertEqual((res["strip_range_spread_b"], res["warnings"]), ([0.0] * 4, []))
        self.assertEqual(os.listdir(os.path.dirname(res["strip_image_npy"])),
                         ["strip_image.npy"])  # the temporary renamed
        image = np.load(res["strip_image_npy"])
        self.assertEqual(image.shape[0], 4 * M)
        np.testing.assert_array_equal(image, self.whole_image)
        # each task reads from the first line of its aperture's overlap-save block (the
        # scene band's extent reaches back past the flight's start here: every task from 0)
        before, _ = res["strip_overlap_lines"]
        shift = res["strip_line_shift"]
        self.assertEqual(shift, -56)
        self.assertEqual([first for first, _ in res["strip_slices"]],
                         [0] + [STEP * max(0, a * M + shift - before) for a in (1, 2, 3)])
        # the boundary target: its peak on the boundary, its main lobe in both apertures
        mag = np.abs(image)
        col = int(np.argmax(mag[BOUNDARY]))
        line = int(np.argmax(mag[2 * M:, col]))
        peak = mag[2 * M + line, col]
        self.assertLessEqual(abs(2 * M + line - BOUNDARY), 2)
        self.assertGreater(mag[BOUNDARY - 1, col], 0.9 * peak)
        self.assertGreater(mag[BOUNDARY, col], 0.9 * peak)
        # each aperture focused alone (no overlap, the paper's circular blocks) cuts it:
        # each aperture holds a quarter of the pulses that see it, and loses peak
        alone = np.abs(np.load(dp.run(self.opts("alone", strip_overlap_s=0.0))
                               ["strip_image_npy"]))
        self.assertLess(alone[BOUNDARY - 3:BOUNDARY + 3, col].max(), 0.8 * peak)

    def test_002_corrupt_slice_reported(self):
        # NaNs written into a copy of the recording just past what task 2 reads; with 50
        # lines of overlap only task 3 reads them and fails, the others equal the one-graph
        # strip of the same overlap
        rec = recording.read(self.meta)
        overlap = 50 * STEP * rec.num.symbol_s()
        task2 = dp.layout(self.opts("l", strip_overlap_s=overlap), rec).slices[2]
        bad = task2.first + task2.symbols + 10
        res = dp.run(self.opts("corrupt_out", meta=self._corrupted("corrupt", bad),
                               dask="local:2", strip_overlap_s=overlap), self.client)
        self._assert_fails_alone(res, bad, 3)
        image = np.load(res["strip_image_npy"])
        clean = self.whole(self.opts("clean", strip_overlap_s=overlap))
        np.testing.assert_array_equal(image[:3 * M], clean[:3 * M])
        self.assertEqual(np.count_nonzero(image[3 * M:]), 0)
        # with 50 lines the tasks 1..3 start mid-flight
        self.assertEqual(res["strip_overlap_lines"], [50, 50])
        self.assertEqual([first for first, _ in res["strip_slices"]],
                         [0] + [STEP * (a * M + res["strip_line_shift"] - 50) for a in (1, 2, 3)])

    def test_002b_corrupt_symbols_in_the_prepass(self):
        # --estimate-snr: NaNs in symbols that only task 2 reads and that the pre-pass
        # replays for task 3's SNR history. Task 2 fails, named; the pre-pass skips them as
        # the estimator of one graph does (the nonfinite guard), so tasks 0, 1 and 3 equal
        # the clean recording's one graph with --estimate-snr bit for bit (task 3's filter
        # weights, so its estimate, included)
        rec = recording.read(self.meta)
        overlap = 50 * STEP * rec.num.symbol_s()
        opts = self.opts("l", strip_overlap_s=overlap, estimate_snr=True)
        lay = dp.layout(opts, rec)
        s1, s2, s3 = lay.slices[1:]
        self.assertLess(s1.first + s1.symbols, s3.first)  # symbols that only task 2 reads
        bad = (s1.first + s1.symbols + s3.first) // 2
        self.assertLess(bad, dp.prepass_symbols(opts, rec, lay))
        res = dp.run(self.opts("corrupt_prepass_out", meta=self._corrupted("corrupt_prepass", bad),
                               dask="local:2", strip_overlap_s=overlap, estimate_snr=True),
                     self.client)
        self._assert_fails_alone(res, bad, 2)
        image = np.load(res["strip_image_npy"])
        clean = self.whole(self.opts("clean_snr", strip_overlap_s=overlap, estimate_snr=True))
        for a in (0, 1, 3):
            np.testing.assert_array_equal(image[a * M:(a + 1) * M], clean[a * M:(a + 1) * M])
        self.assertEqual(np.count_nonzero(image[2 * M:3 * M]), 0)
        self.assertIsNone(res["strip_snr_db"][2])
        self.assertTrue(all(np.isfinite(res["strip_snr_db"][a]) for a in (0, 1, 3)))

    def test_002c_abutting_apertures(self):
        # --strip-overlap-s 0: each task reads its aperture's own lines, the blocks abut with
        # neither gap nor overlap (read factor 1), and the strip equals one graph focusing
        # the whole recording with the same (zero) overlap
        opts = self.opts("abut", dask="local:2", strip_overlap_s=0.0)
        res = dp.run(opts, self.client)
        slices = res["strip_slices"]
        self.assertEqual(slices[0][0], 0)
        for (first, n), (after, _) in zip(slices, slices[1:]):
            self.assertEqual(first + n, after)
        self.assertEqual([n for _, n in slices], [STEP * M] * 4)
        self.assertEqual(res["strip_read_factor"], 1.0)
        np.testing.assert_array_equal(np.load(res["strip_image_npy"]), self.whole(opts))

    def test_002d_a_task_frees_its_blocks(self):
        # a worker runs task after task: each task's graph (its chain's blocks, kernels and
        # FFT objects) is freed when it ends (GNU Radio keeps a hier block with a message
        # connection to its own port, imaging_chain's "metrics", unless released)
        opts = self.opts("free")
        rec = recording.read(self.meta)
        sl = dp.layout(opts, rec).slices[1]
        gc.collect()
        blocks = gr.basic_block_ncurrently_allocated()
        for _ in range(2):
            dp.focus_slice(opts, self.meta, sl)
            gc.collect()
            self.assertEqual(gr.basic_block_ncurrently_allocated(), blocks)

    def test_003_worker_killed_costs_a_retry(self):
        opts, client = self.opts("killed"), self.client
        pids = client.run(os.getpid)
        lay = dp.layout(opts, recording.read(self.meta))
        path = os.path.join(self.dir, "killed.npy")
        out = []
        runner = threading.Thread(target=lambda: out.append(dp.write_strip(
            path, lay, dp.in_order(opts, self.meta, lay.slices, client))))
        runner.start()
        deadline = time.monotonic() + 120
        while not any(client.processing().values()) and time.monotonic() < deadline:
            time.sleep(0.05)
        busy = [w for w, tasks in client.processing().items() if tasks]
        self.assertTrue(busy)
        os.kill(pids[busy[0]], signal.SIGKILL)  # its task runs again elsewhere
        runner.join(600)
        self.assertFalse(runner.is_alive())
        failed, _, held, _ = out[0]
        self.assertEqual((failed, held), ([], 4))  # the default window: twice the workers
        np.testing.assert_array_equal(np.load(path), self.whole_image)

    def test_003b_back_projection_strip(self):
        # bp_focuser images each aperture from its own pulses: a task reads its aperture
        # alone (reading factor 1) and the strip, in one process, is one graph's
        opts = self.opts("bp", focuser="bp")
        res = dp.run(opts)
        self.assertEqual(res["strip_read_factor"], 1.0)
        self.assertEqual([s for s in res["strip_slices"]],
                         [[a * M * STEP, M * STEP] for a in range(4)])
        np.testing.assert_array_equal(np.load(res["strip_image_npy"]), self.whole(opts))

    def test_003c_presummed_strip(self):
        # behind a presummer (D = 2: 54 lines of 56 symbols per aperture) with 25 lines of
        # overlap: task 2 starts mid-flight, at the presummer's window of its first line
        # (line g needs pulses from g D - a, a = (L - 1) / 2 = 3 for cheby's L = 4 D taps, 0
        # for boxcar's sum of g D .. g D + D - 1), task 1's window reaches back to pulse 0;
        # the strip is one graph's
        overlap = 25 * 2 * STEP * recording.read(self.meta).num.symbol_s()
        for presum, a in (("cheby", 3), ("boxcar", 0)):
            opts = self.opts("presum_" + presum, presum=presum, decim=2, strip_overlap_s=overlap)
            res = dp.run(opts)
            m, shift = res["strip_aperture_lines"], res["strip_line_shift"]
            self.assertEqual((m, res["strip_overlap_lines"]), (54, [25, 25]))
            self.assertEqual([first for first, _ in res["strip_slices"]],
                             [0] + [STEP * max(0, 2 * (i * m + shift - 25) - a)
                                    for i in (1, 2)])
            self.assertEqual(res["strip_failed"], [])
            image = np.load(res["strip_image_npy"])
            self.assertEqual(image.shape[0], 3 * m)
            np.testing.assert_array_equal(image, self.whole(opts))
            self.assertGreater(np.abs(image).max(), 0)

    def _recording(self, name, extra):
        rec = os.path.join(self.dir, name)
        sim = subprocess.run([sys.executable, os.path.join(APPS, "nrsar-sim")] + FLIGHT + extra +
                             ["--record", rec, "--images", "none", "--quiet",
                              "--out", os.path.join(self.dir, name + "_sim")],
                             capture_output=True, text=True, timeout=900)
        self.assertEqual(sim.returncode, 0, sim.stderr)
        return os.path.join(rec, "flight.sigmf-meta")

    def test_003d_recording_with_gaps(self):
        # two overflows: 3000 samples from 500 before task 2's first symbol (3024, with 50
        # lines of overlap), so task 2 starts inside the gap, and 20000 samples 200 symbols
        # later, inside tasks 2 and 3: each task zero-fills the symbols a gap touched where
        # one graph over the whole recording does (ofdm_demod's rx_time alignment)
        sym = 1280  # samples per symbol at sdr20
        start = STEP * (2 * M - 56 - 50)
        meta = self._recording("gaps", ["--record-gap", f"{start * sym - 500}:3000",
                                        "--record-gap", f"{(start + 200) * sym}:20000"])
        opts = self.opts("gaps_out", meta=meta, strip_overlap_s=50 * STEP * 1280 / 30.72e6)
        res = dp.run(opts)
        self.assertEqual(res["strip_slices"][2][0], start)
        self.assertEqual((res["overflows"], res["lost_samples"]), (2, 23000))
        self.assertEqual(res["strip_failed"], [])
        image = np.load(res["strip_image_npy"])
        np.testing.assert_array_equal(image, self.whole(opts))
        # a part from task 2's first symbol: its data from the first gap's end, the 2500
        # samples it lost in the part stamped at its first sample; the second gap clipped at
        # the part's end (10 of its symbols lost inside a part of 210)
        rec = recording.read(meta)
        gap_end = rec.hardware_delay_samples + start * sym - 500  # the first overflow's index
        second = gap_end + 200 * sym + 500 - 3000  # the second's: less the 3000 lost before
        self.assertEqual(rec.gaps, [(gap_end, 3000), (second, 20000)])
        for symbols, gaps in ((100, [(gap_end, 2500)]),
                              (210, [(gap_end, 2500), (second, 10 * sym)]),
                              (1000, [(gap_end, 2500), (second, 20000)])):
            part = dp.part_of(rec, start, symbols)
            self.assertEqual((part.hardware_delay_samples, part.gaps), (gap_end, gaps))
        # a part after both: the file that much shorter before it
        self.assertEqual(dp.part_of(rec, start + 300, 10).hardware_delay_samples,
                         rec.hardware_delay_samples + (start + 300) * sym - 23000)

    def test_003e_flown_path(self):
        # a gusty flight imaged along an RTK navigation (nrsar:trajectory, nrsar:navigation):
        # rd_focuser's motion compensation and bp_focuser's positions take the flight's slow
        # time from the task's first aperture, cheby's compensation along the navigation its
        # phase segments from the flight's blocks of 64 pulses: the strip is one graph's
        meta = self._recording("flown", ["--motion", "gusty", "--nav-error", "rtk"])
        for focuser, presum in (("rd", {}), ("bp", {}), ("rd", dict(presum="cheby", decim=2))):
            opts = self.opts("flown_" + focuser, meta=meta, focuser=focuser,
                             strip_overlap_s=25 * 2 * STEP * 1280 / 30.72e6, **presum)
            res = dp.run(opts)
            self.assertEqual(res["strip_failed"], [])
            self.assertGreater(res["strip_slices"][2][0], 0)
            np.testing.assert_array_equal(np.load(res["strip_image_npy"]), self.whole(opts))
            # gusty's sway per task: inside the range grid's tolerance, no warning (test_003i)
            self.assertEqual(res["warnings"], [])
            self.assertTrue(0.0 < max(res["strip_range_spread_b"]) < 0.1,
                            res["strip_range_spread_b"])
        print(f"flown path: range spread per task {res['strip_range_spread_b']} B")

    def test_003f_estimated_snr(self):
        # --estimate-snr: the Wiener filter's SNR estimate at a symbol sums the estimator's
        # window before it (2^24 REs, pooled in buckets of 2^18 from the stream's start), so
        # a pre-pass takes the estimator's sums of every symbol before the last task's block
        # and each task starts from the history one graph has at its first symbol: its
        # estimate, and image, equal one graph's bit for bit. paper (3333 REs: a window of
        # 5034 symbols, 0.21 s; buckets of 79 symbols), srs2, 0.4 s = 9600 symbols cut into 6
        # apertures of 56 lines (1568 symbols), 10 lines of overlap (a task reads from line
        # 56 a - 13 - 10): tasks 4 and 5 start past the first window, at symbols 5628 and
        # 7196. The SNR falls along the track (noise added to the recording from symbol 4000
        # on, rising to 4x the recording's power), so where a task's window starts matters.
        meta = self._recording("snr", ["--preset", "paper", "--aperture-s", "0.4"])
        rec = recording.read(meta)
        sym = rec.symbol_samples
        data = np.memmap(rec.data_path, np.complex64, "r+")
        power = float(np.mean(np.abs(data[:1 << 20]) ** 2))
        rng = np.random.default_rng(7)
        first = rec.hardware_delay_samples + 4000 * sym
        chunk = 1 << 20
        for at in range(first, len(data), chunk):
            end = min(len(data), at + chunk)
            sigma = np.sqrt(4 * power * (at - first) / (len(data) - first) / 2)
            noise = rng.standard_normal((end - at, 2), np.float32) * np.float32(sigma)
            data[at:end] += noise.view(np.complex64)[:, 0]
        data.flush()
        del data
        step = 28 * rec.num.symbol_s()
        opts = ProcessOptions(recording=meta, strip_aperture_s=56 * step,
                              strip_overlap_s=10 * step, estimate_snr=True,
                              out=os.path.join(self.dir, "snr_out")).validate()
        lay = dp.layout(opts, rec)
        whole = self.whole(opts)
        self.assertEqual([sl.first for sl in lay.slices],
                         [0] + [28 * (56 * a - 13 - 10) for a in range(1, 6)])
        self.assertEqual(dp.prepass_symbols(opts, rec, lay), lay.slices[-1].first)
        # each history's window: whole buckets of 79 symbols (263307 REs) from the stream's
        # start and the symbols since the last, the fewest newest that cover 2^24 REs
        slices, _ = dp.prepass(opts, rec, lay)
        for sl in slices:
            h = np.asarray(sl.history)
            full, partial = h[9::5], h[4]
            self.assertTrue(np.all(full == 79 * 3333))
            self.assertEqual(partial, (sl.first % 79) * 3333)
            res_kept = full.sum() + partial
            if sl.first * 3333 >= 1 << 24:
                self.assertGreaterEqual(res_kept, 1 << 24)
                self.assertLess(res_kept - full[0], 1 << 24)
            else:
                self.assertEqual(res_kept, sl.first * 3333)
        # cut into 3 parts (boundaries 2399 and 4798, inside buckets: the replay takes each
        # symbol's sums in stream order) the histories are the same; the task at symbol 0
        # is handed out before any part runs, the others as the parts before them return;
        # a block that reads nothing (before the flight: a long geometry's) passes as it is
        parts, real = [], dp.prepass_sums
        empty = dp.Slice(0, 1, lay.lines, 0, 0)
        with mock.patch.object(dp, "prepass_sums",
                               lambda *a: parts.append(a[2:]) or real(*a)):
            streamed = dp.histories(opts, rec, dataclasses.replace(
                lay, slices=[empty] + lay.slices), parts=3)
            self.assertEqual(next(streamed), empty)
            self.assertEqual(next(streamed), slices[0])
            self.assertEqual(parts, [])
            self.assertEqual(next(streamed), slices[1])
            self.assertEqual(parts, [(0, 2399)])
            self.assertEqual(list(streamed), slices[2:])
            self.assertEqual(parts, [(0, 2399), (2399, 2399), (4798, 2398)])
        # one part per worker only where each takes at least 2^21 REs: this strip's
        # 7196 symbols of 3333 REs make 11; bench_dask's 3056 of 612 one
        self.assertEqual(dp.prepass_parts(7196, 3333, 2), [(0, 3598), (3598, 3598)])
        self.assertEqual(len(dp.prepass_parts(7196, 3333, 16)), 11)
        self.assertEqual(dp.prepass_parts(3056, 612, 4), [(0, 3056)])
        for client in (None, self.client):
            res = dp.run(opts.replace(out=os.path.join(self.dir, f"snr_{client is None}")),
                         client)
            self.assertEqual(res["strip_failed"], [])
            np.testing.assert_array_equal(np.load(res["strip_image_npy"]), whole)
            self.assertEqual(res["strip_prepass_symbols"], 7196)
        # each task's last estimate: the recorded 5 dB at the start (measured 4.89), falling
        # along the track with the added noise (measured 4.85, 4.72, 4.05, 2.61, 1.00 dB)
        snr = res["strip_snr_db"]
        self.assertAlmostEqual(snr[0], 5.0, delta=0.25)
        self.assertTrue(all(a > b for a, b in zip(snr[1:], snr[2:])), snr)
        self.assertLess(snr[-1], snr[0] - 3.0)
        # without the history the last task differs from one graph (what the pre-pass is
        # for): measured 25 % of the image's peak at most, the estimate -0.57 dB
        cold = dp.focus_slice(opts, meta, lay.slices[-1])
        rows = slice(5 * lay.lines, 6 * lay.lines)
        self.assertGreater(np.abs(cold["image"] - whole[rows]).max(), 0.05 * np.abs(whole).max())
        self.assertLess(cold["snr_db"], snr[-1] - 1.0)
        # a presummer in the TF domain (cheby, D = 2), and bp_focuser's tasks (each its
        # own aperture): one graph's strip too
        for kw in (dict(presum="cheby", decim=2, presum_domain="tf"), dict(focuser="bp")):
            o = opts.replace(out=os.path.join(self.dir, "snr_" + kw.get("presum", "bp")), **kw)
            res = dp.run(o)
            self.assertEqual(res["strip_failed"], [])
            self.assertGreater(res["strip_prepass_symbols"], 5000)
            np.testing.assert_array_equal(np.load(res["strip_image_npy"]), self.whole(o))

    def test_003g_estimated_snr_fused(self):
        # the same with --rx-fuse on (range_compress filters and range-compresses in one
        # block: it takes the history): paper, every symbol a pulse, 0.3 s cut into 6
        # apertures of 1200 lines, 60 lines of overlap (line shift +831): tasks 4 and 5
        # start past the first window (5034 symbols)
        meta = self._recording("fused", ["--preset", "paper", "--mode", "data",
                                         "--aperture-s", "0.3"])
        rec = recording.read(meta)
        opts = ProcessOptions(recording=meta, strip_aperture_s=1200 * rec.num.symbol_s(),
                              strip_overlap_s=60 * rec.num.symbol_s(), estimate_snr=True,
                              rx_fuse="on", out=os.path.join(self.dir, "fused_out")).validate()
        lay = dp.layout(opts, rec)
        self.assertEqual([sl.first > 5034 for sl in lay.slices], [False] * 4 + [True] * 2)
        res = dp.run(opts)
        self.assertEqual(res["strip_failed"], [])
        np.testing.assert_array_equal(np.load(res["strip_image_npy"]), self.whole(opts))

    def test_003h_full_band(self):
        # --band full: the azimuth reference of the full pulse rate (857 Hz) reaches about
        # 7900 lines each way, 18 flights of 428 lines, far past the scene band's overlap
        # (402 / 516), so every block wraps the Doppler bins outside the scene band and the
        # strip's noise there is not that of one block over the flight (nrsar-sim's, here
        # the strip of one aperture): the strip warns, naming the overlap that makes every
        # block linear; inside the scene band the two agree as the scene band's strips do
        rec = recording.read(self.meta)
        opts = self.opts("full", band="full")
        res = dp.run(opts)
        self.assertEqual(res["strip_failed"], [])
        need = max(res["strip_full_band_reach_lines"])
        self.assertGreater(min(res["strip_full_band_reach_lines"]), 10 * 516)
        self.assertEqual(len(res["warnings"]), 1)
        flag = re.search(r"--strip-overlap-s (\S+) \((\d+) lines\)", res["warnings"][0])
        self.assertEqual(int(flag.group(2)), need)
        one = opts.replace(out=os.path.join(self.dir, "full_one"), strip_aperture_s=0.499)
        ref = self.whole(one)  # lines per aperture: the flight's 428
        diff = np.fft.fft(np.load(res["strip_image_npy"]) - ref, axis=0)
        # the scene band with the focuser's margin (10 % of it and 2 / Ta each side)
        ext = params.compute_extent(rec.geo, rec.scene)
        margin = 0.1 * (ext.max_doppler_hz - ext.min_doppler_hz) + 2.0 / rec.geo.aperture_s
        f = np.fft.fftfreq(len(ref), STEP * rec.num.symbol_s())
        inside = (f >= ext.min_doppler_hz - margin) & (f <= ext.max_doppler_hz + margin)
        energy = np.sum(np.abs(ref) ** 2) * len(ref)  # Parseval: the unnormalised FFT
        split = [10 * np.log10(np.sum(np.abs(d) ** 2) / energy)
                 for d in (diff[inside], diff[~inside])]
        self.assertLess(split[0], -40.0)
        self.assertGreater(split[1], -20.0)
        # with the warning's overlap every block is linear: the cut no longer matters
        linear = opts.replace(out=os.path.join(self.dir, "full_linear"),
                              strip_overlap_s=float(flag.group(1)))
        res = dp.run(linear)
        self.assertEqual((res["warnings"], res["strip_failed"]), ([], []))
        ref = self.whole(linear.replace(strip_aperture_s=0.499))
        err = np.sum(np.abs(np.load(res["strip_image_npy"]) - ref) ** 2) / np.sum(np.abs(ref) ** 2)
        self.assertLess(10 * np.log10(err), -60.0)
        print(f"--band full: reach {need} lines; the strip against one block over the flight "
              f"{split[0]:.1f} dB inside the scene band, {split[1]:.1f} dB outside; with "
              f"--strip-overlap-s {flag.group(1)}: {10 * np.log10(err):.1f} dB")

    def test_003i_range_grid_check(self):
        # the range-grid headroom check per task (scenario.range_grid_warnings): a --nav
        # drifting across track at up to 3.2 m/s (a Gaussian of 70 ms around t = 0.31 s, 39
        # m/s^2 at most), 0.32 m within aperture 2 (no overlap: each task reads its
        # aperture's own pulses), at this steep look (1 km up, 300 m out) about 0.58 B per
        # metre: aperture 2's spread exceeds the 625-point grid's 0.021 B of headroom by more
        # than 0.1 B, the others' do not. The test's own float64 s(t) per window: dr/dR0 by
        # a central difference in R0 (the target moved along the ground), on the analytic path
        fc, h, df, n_sub, ts = 3.5e9, 1000.0, 30e3, 612, 1280 / 30.72e6
        erf = np.frompyfunc(math.erf, 1, 1)

        def drift(t):  # the integral of 3.2 exp(-((t - 0.31) / 0.07)^2) m/s from 0
            return (3.2 * 0.07 * math.sqrt(math.pi) / 2
                    * (erf((t - 0.31) / 0.07) - math.erf(-0.31 / 0.07))).astype(float)
        t = np.arange(501) / 1000.0
        path = os.path.join(self.dir, "drift.csv")
        with open(path, "w") as f:
            f.write("t_s,x_m,y_m,z_m\n" + "".join(f"{a!r},{b!r},{50.0 * a!r},{h!r}\n"
                                                   for a, b in zip(t.tolist(), drift(t).tolist())))
        spreads, worst = [], []
        for a in range(4):
            t0, t1 = a * M * STEP * ts, (a + 1) * M * STEP * ts
            tw = np.linspace(t0, t1, int(np.ceil((t1 - t0) / 1e-3)) + 1)
            x, y = drift(tw), 50.0 * tw
            by = {}
            for g, y_t in ((300.0, 15.5), (290.0, 3.0)):
                def ds(x0, e=1e-3):  # fc (r(R0 + e) - r(R0 - e)) / 2e, ground point g(R0)
                    r = [np.sqrt((x0 - np.sqrt(r0 * r0 - h * h)) ** 2 + (y - y_t) ** 2 + h * h)
                         for r0 in (np.hypot(g, h) + e, np.hypot(g, h) - e)]
                    return fc * (r[0] - r[1]) / (2 * e)
                s = ds(x) - ds(0.0)
                by[g] = s.max() - s.min()
            spreads.append(max(by.values()))
            worst.append(max(by, key=by.get))
        a = int(np.argmax(spreads))
        band = n_sub * df
        res = dp.run(self.opts("grid", nav=path, strip_overlap_s=0.0))
        np.testing.assert_allclose(res["strip_range_spread_b"], np.array(spreads) / band,
                                   rtol=0, atol=1e-5)
        self.assertEqual(len(res["warnings"]), 1, res["warnings"])
        text = res["warnings"][0]
        m = re.search(r"by ([\d.]+) MHz \(([\d.]+) B, B = ([\d.]+) MHz\) over aperture (\d) "
                      r".*x = (\d+) m.*headroom of ([\d.]+) MHz \(--fft-size (\d+).*"
                      r"--fft-size (\d+) holds", text)
        self.assertIsNotNone(m, text)
        self.assertAlmostEqual(float(m[1]), spreads[a] / 1e6, delta=6e-4)  # printed to 1 kHz
        self.assertAlmostEqual(float(m[2]), spreads[a] / band, delta=6e-4)
        self.assertEqual((float(m[3]), int(m[4]), int(m[5])), (18.36, a, worst[a]))
        self.assertEqual((float(m[6]), int(m[7])), (0.39, 625))  # 13 subcarriers of headroom
        # 612 + ceil(3.502 MHz / 30 kHz) = 729 = 3^6, itself a fast size
        self.assertEqual((n_sub + math.ceil(spreads[a] / df), int(m[8])), (729, 729))
        limit = 0.39e6 + 0.1 * band
        self.assertEqual([sp > limit for sp in spreads], [False, False, True, False])
        print(f"range grid per aperture: {[round(sp / band, 4) for sp in spreads]} B, "
              f"aperture {a} warned: {text}")

    def test_004_tls_refuses_a_client_without_certificate(self):
        import distributed
        from distributed.security import Security
        address = self.client.scheduler.address
        self.assertTrue(address.startswith("tls://127.0.0.1:"))
        # no certificate (the client cannot even speak TLS), and a certificate of another
        # CA: the scheduler's handshake refuses it (the client times out)
        ca = self.client.security.tls_ca_file
        other = Security.temporary()
        for security in (None, Security(tls_ca_file=ca, tls_client_cert=other.tls_client_cert,
                                        tls_client_key=other.tls_client_key,
                                        require_encryption=True)):
            with self.assertRaises((OSError, TypeError)):
                distributed.Client(address, security=security, timeout="5s")
            # the refused Client is half built: collect it here, in this thread. Left to a
            # later collection, its __del__ can run inside the next Client's IO-loop thread
            # start and wait for the loop lock that start holds (a deadlock seen under load:
            # distributed/utils.py LoopRunner.stop against _start_unlocked)
            gc.collect()
        with self.assertRaisesRegex(OptionError, "needs --dask-tls-ca"):
            dp.security_of(self.opts("o", dask="tcp://127.0.0.1:8786"))
        for spec in ("local:0", "local:x", "udp://h:1", "tcp://host"):
            with self.assertRaisesRegex(OptionError, "--dask"):
                self.opts("o", dask=spec)
        with self.assertRaisesRegex(OptionError, "needs --strip-aperture-s"):
            ProcessOptions(recording=self.meta, dask="local:2",
                           out=os.path.join(self.dir, "o")).validate()
        rec = recording.read(self.meta)
        with self.assertRaisesRegex(OptionError, "--presum = 'lms' with --strip-aperture-s: "
                                    "its filter adapts from the flight's first pulse"):
            dp.layout(self.opts("o", presum="lms", decim=2), rec)
        for aperture_s in (0.001, 0.6):
            with self.assertRaisesRegex(OptionError, "--strip-aperture-s = .* at most the "
                                        "recording's 428 lines"):
                dp.layout(self.opts("o").replace(strip_aperture_s=aperture_s), rec)
        with self.assertRaisesRegex(OptionError, "--strip-overlap-s = 0.1 needs"):
            ProcessOptions(recording=self.meta, strip_overlap_s=0.1,
                           out=os.path.join(self.dir, "o")).validate()

    def test_005_make_certificates(self):
        folder = os.path.join(self.dir, "certs")
        app = [sys.executable, os.path.join(APPS, "nrsar-process"), "--out",
               os.path.join(self.dir, "certs_out")]
        done = subprocess.run(app + ["--dask-make-certs", folder, "--json"],
                              capture_output=True, text=True, timeout=120)
        self.assertEqual(done.returncode, 0, done.stderr)
        for name in dp.CERTIFICATES:
            mode = stat.S_IMODE(os.stat(os.path.join(folder, name)).st_mode)
            self.assertEqual(mode, 0o600, name)
        self.assertEqual(sorted(os.listdir(folder)), sorted(dp.CERTIFICATES))  # no temp left
        # a scheduler with the set takes a client with it
        import distributed
        from distributed.security import Security
        sec = Security(tls_ca_file=os.path.join(folder, "ca.pem"),
                       tls_client_cert=os.path.join(folder, "cert.pem"),
                       tls_client_key=os.path.join(folder, "key.pem"),
                       tls_scheduler_cert=os.path.join(folder, "cert.pem"),
                       tls_scheduler_key=os.path.join(folder, "key.pem"),
                       tls_worker_cert=os.path.join(folder, "cert.pem"),
                       tls_worker_key=os.path.join(folder, "key.pem"),
                       require_encryption=True)
        with dp.local_cluster(1, sec) as cluster, \
                distributed.Client(cluster, security=sec, timeout="30s") as client:
            self.assertEqual(client.submit(sum, [1, 2]).result(), 3)
        # never overwritten; given with a recording or --dask: refused, one line, exit 2
        for extra in ([], [self.meta], ["--dask", "local:1"]):
            bad = subprocess.run(app + ["--dask-make-certs", folder] + extra,
                                 capture_output=True, text=True, timeout=120)
            self.assertEqual(bad.returncode, 2)
            self.assertEqual(len(bad.stderr.strip().splitlines()), 1, bad.stderr)
            self.assertIn("--dask-make-certs", bad.stderr)
        self.assertIn("already holds ca.pem, cert.pem, key.pem", bad.stderr)


if __name__ == "__main__":
    gr_unittest.run(qa_distributed_process)
