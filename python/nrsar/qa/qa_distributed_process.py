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
samples is reported with its aperture index while the others complete; a client without the
certificate is refused by the scheduler; --dask-make-certs writes a set."""

import contextlib
import faulthandler
import os
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np
from gnuradio import gr_unittest

from gnuradio.nrsar import distributed_process as dp, recording
from gnuradio.nrsar.options import OptionError, ProcessOptions

APPS = os.environ.get("NRSAR_APPS_DIR") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps")

# sdr20, 0.2 s = 4800 symbols = four apertures of 0.05 s (1200 lines each) along 10 m of
# track (2.08 mm per line); the first target at the track's centre y = 5 m focuses on line
# 2400 + 1, at the boundary of apertures 1 and 2 (s = line_shift(), -1 here), the second
# inside aperture 0
FLIGHT = ["--preset", "sdr20", "--aperture-s", "0.2", "--target", "300,5", "--target",
          "290,1.5", "--snr-db", "5"]
M, BOUNDARY = 1200, 2400


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
        return ProcessOptions(recording=meta or cls.meta, strip_aperture_s=0.05,
                              out=os.path.join(cls.dir, name), **kw).validate()

    @classmethod
    def whole(cls, opts):
        """One graph focusing the whole recording (the single-process result)."""
        rec = recording.read(opts.recording)
        return dp.focus_slice(opts, opts.recording,
                              dp.whole(opts, rec, dp.layout(opts, rec)))["image"]

    def test_001_dask_equals_one_process(self):
        res = dp.run(self.opts("dask", dask="local:2"), self.client)
        self.assertEqual((res["strip_apertures"], res["dask_workers"]), (4, 2))
        self.assertEqual(res["strip_failed"], [])
        image = np.load(res["strip_image_npy"])
        self.assertEqual(image.shape[0], 4 * M)
        np.testing.assert_array_equal(image, self.whole_image)
        # the overlap-save blocks reach past the apertures: aperture 3's task starts
        # mid-flight (its history), the others at the flight's start
        firsts = [first for first, _ in res["strip_slices"]]
        self.assertEqual(firsts[:3], [0, 0, 0])
        before, _ = res["strip_overlap_lines"]
        shift = res["strip_line_shift"]
        self.assertEqual(firsts[3], 3 * M + shift - before)
        # the boundary target: its peak on the boundary, its main lobe in both apertures
        mag = np.abs(image)
        line, col = np.unravel_index(np.argmax(mag[M:3 * M]), mag[M:3 * M].shape)
        self.assertLessEqual(abs(M + line + shift - BOUNDARY), 2)  # row r: flight line r + s
        self.assertGreater(mag[BOUNDARY - 1, col], 0.5 * mag[M + line, col])
        self.assertGreater(mag[BOUNDARY, col], 0.5 * mag[M + line, col])
        # each aperture focused alone (no overlap, the paper's circular blocks) splits it:
        # each half holds the pulses of its own aperture only, and loses peak
        alone = np.abs(np.load(dp.run(self.opts("alone", strip_overlap_s=0.0))
                               ["strip_image_npy"]))
        self.assertLess(alone[BOUNDARY - 3:BOUNDARY + 3, col].max(), 0.8 * mag[M + line, col])

    def test_002_corrupt_slice_reported(self):
        # NaNs written into symbol 4500 of a copy of the recording; with 300 lines of
        # overlap only the tasks whose slice reads that symbol fail, the others equal the
        # one-graph strip of the same overlap
        folder = os.path.join(self.dir, "corrupt")
        shutil.copytree(os.path.dirname(self.meta), folder)
        meta = os.path.join(folder, "flight.sigmf-meta")
        rec = recording.read(meta)
        at = rec.hardware_delay_samples + 4500 * rec.symbol_samples
        data = np.memmap(rec.data_path, np.complex64, "r+")
        data[at:at + 10] = np.nan
        data.flush()
        del data
        overlap = 300 * rec.num.symbol_s()
        res = dp.run(self.opts("corrupt_out", meta=meta, dask="local:2",
                               strip_overlap_s=overlap), self.client)
        read = [a for a, (first, n) in enumerate(res["strip_slices"]) if first <= 4500 < first + n]
        self.assertEqual(read, [3])
        self.assertEqual([f["aperture"] for f in res["strip_failed"]], read)
        self.assertRegex(res["strip_failed"][0]["error"], r"aperture 3: \d+ non-finite")
        image = np.load(res["strip_image_npy"])
        clean = self.whole(self.opts("clean", strip_overlap_s=overlap))
        np.testing.assert_array_equal(image[:3 * M], clean[:3 * M])
        self.assertEqual(np.count_nonzero(image[3 * M:]), 0)
        # with 300 lines the tasks 1..3 start mid-flight
        self.assertEqual(res["strip_overlap_lines"], [300, 300])
        self.assertEqual([first for first, _ in res["strip_slices"]],
                         [0] + [a * M + res["strip_line_shift"] - 300 for a in (1, 2, 3)])

    def test_003_worker_killed_costs_a_retry(self):
        opts, client = self.opts("killed"), self.client
        pids = client.run(os.getpid)
        slices = dp.layout(opts, recording.read(self.meta)).slices
        out = {}
        runner = threading.Thread(
            target=lambda: out.update(dp.run_slices(opts, self.meta, slices, client)))
        runner.start()
        deadline = time.monotonic() + 120
        while not any(client.processing().values()) and time.monotonic() < deadline:
            time.sleep(0.05)
        busy = [w for w, tasks in client.processing().items() if tasks]
        self.assertTrue(busy)
        os.kill(pids[busy[0]], signal.SIGKILL)  # its task runs again elsewhere
        runner.join(600)
        self.assertFalse(runner.is_alive())
        image, failed = dp.stitch(slices, out, self.whole_image.shape[1])
        self.assertEqual(failed, [])
        np.testing.assert_array_equal(image, self.whole_image)

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
        with self.assertRaisesRegex(OptionError, "needs --dask-tls-ca"):
            dp.security_of(self.opts("o", dask="tcp://127.0.0.1:8786"))
        for spec in ("local:0", "local:x", "udp://h:1", "tcp://host"):
            with self.assertRaisesRegex(OptionError, "--dask"):
                self.opts("o", dask=spec)
        with self.assertRaisesRegex(OptionError, "needs --strip-aperture-s"):
            ProcessOptions(recording=self.meta, dask="local:2",
                           out=os.path.join(self.dir, "o")).validate()
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
