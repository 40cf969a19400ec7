#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-process --strip-aperture-s / --dask (distributed_process.py): a recording of two
apertures processed as a strip on a local Dask cluster over TLS equals the one-process
strip; a worker killed mid-run costs a retry; a slice with non-finite samples is reported
with its aperture index while the other completes; a client without the certificate is
refused by the scheduler."""

import contextlib
import faulthandler
import os
import shutil
import signal
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

# sdr20, 0.1 s = 2400 symbols = two apertures of 0.05 s (1200 lines each), two targets
FLIGHT = ["--preset", "sdr20", "--aperture-s", "0.1", "--target", "300,1", "--target",
          "290,-2", "--snr-db", "5"]


class qa_distributed_process(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        # a cluster that hangs fails the test with every thread's traceback, bounded
        faulthandler.dump_traceback_later(900, exit=True)
        cls.dir = tempfile.mkdtemp(prefix="qa_distributed_process_")
        rec = os.path.join(cls.dir, "rec")
        sim = subprocess.run([sys.executable, os.path.join(APPS, "nrsar-sim")] + FLIGHT +
                             ["--record", rec, "--images", "none", "--quiet",
                              "--out", os.path.join(cls.dir, "sim")],
                             capture_output=True, text=True, timeout=600)
        assert sim.returncode == 0, sim.stderr
        cls.meta = os.path.join(rec, "flight.sigmf-meta")
        cls.serial = dp.run(cls.opts("serial"))
        cls.serial_image = np.load(cls.serial["strip_image_npy"])
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

    def test_001_dask_equals_one_process(self):
        self.assertEqual(self.serial["strip_apertures"], 2)
        self.assertEqual(self.serial_image.shape[0], 2400)
        self.assertEqual(self.serial["strip_slices"], [[0, 1200], [1200, 1200]])
        res = dp.run(self.opts("dask", dask="local:2"), self.client)
        self.assertEqual(res["dask_workers"], 2)
        self.assertEqual(res["strip_failed"], [])
        np.testing.assert_array_equal(np.load(res["strip_image_npy"]), self.serial_image)
        # both apertures were focused (a point target echoes on every pulse: no beam)
        for a in range(2):
            self.assertGreater(np.abs(self.serial_image[1200 * a:1200 * (a + 1)]).max(), 0)

    def test_002_corrupt_slice_reported(self):
        # NaNs written into aperture 1's samples of a copy of the recording
        folder = os.path.join(self.dir, "corrupt")
        shutil.copytree(os.path.dirname(self.meta), folder)
        meta = os.path.join(folder, "flight.sigmf-meta")
        rec = recording.read(meta)
        at = rec.hardware_delay_samples + 1500 * rec.symbol_samples
        data = np.memmap(rec.data_path, np.complex64, "r+")
        data[at:at + 10] = np.nan
        data.flush()
        del data
        res = dp.run(self.opts("corrupt_out", meta=meta, dask="local:2"), self.client)
        self.assertEqual([f["aperture"] for f in res["strip_failed"]], [1])
        self.assertRegex(res["strip_failed"][0]["error"], r"aperture 1: \d+ non-finite")
        image = np.load(res["strip_image_npy"])
        np.testing.assert_array_equal(image[:1200], self.serial_image[:1200])
        self.assertEqual(np.count_nonzero(image[1200:]), 0)

    def test_003_worker_killed_costs_a_retry(self):
        opts, client = self.opts("killed"), self.client
        pids = client.run(os.getpid)
        slices = dp.layout(opts, recording.read(self.meta))
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
        runner.join(300)
        self.assertFalse(runner.is_alive())
        image, failed = dp.stitch(slices, out, self.serial_image.shape[1])
        self.assertEqual(failed, [])
        np.testing.assert_array_equal(image, self.serial_image)

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


if __name__ == "__main__":
    gr_unittest.run(qa_distributed_process)
