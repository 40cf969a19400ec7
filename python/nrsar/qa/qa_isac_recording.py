#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""An ISAC flight's recording processed offline (docs/recording.md): nrsar-isac --record
writes the radar receiver's stream with the PUSCH grid's description (nrsar:dmrs,
nrsar:pusch, the payload's SHA-256 and path), nrsar-process regenerates that grid from the
payload file through pusch_encoder -> nr_isac_tx and forms nrsar-isac's image; a payload
file that is not the one sent, or a grid field out of range, is one line naming the field
(exit 2).

The programs run as a user runs them: apps/<program> of this tree with this interpreter."""

import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from gnuradio import gr_unittest

APPS = os.environ.get("NRSAR_APPS_DIR") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps")

# sdr20 (td_echo exact, docs/blocks/td_echo.md), 0.05 s = 1200 symbols = 85 slots; QPSK at
# MCS 4 of the qam256 table: the 20000-byte payload fills 19 slots, padding-only TBs the rest
FLIGHT = ["--preset", "sdr20", "--aperture-s", "0.05", "--target", "300,1", "--snr-db", "5",
          "--modulation", "qpsk"]
PAYLOAD_BYTES = 20000


def run_app(program, args):
    return subprocess.run([sys.executable, os.path.join(APPS, program)] + args,
                          capture_output=True, text=True, timeout=600)


def difference_db(a, b):
    """10 log10 sum |a - b|^2 / sum |a|^2 (-inf: identical)."""
    num = float(np.sum(np.abs(a.astype(np.complex128) - b) ** 2))
    return -np.inf if num == 0 else 10.0 * np.log10(num / float(np.sum(np.abs(a) ** 2)))


class qa_isac_recording(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="qa_isac_recording_")
        rng = np.random.default_rng(7)
        cls.payload = os.path.join(cls.dir, "payload.bin")
        rng.integers(0, 256, PAYLOAD_BYTES, np.uint8).tofile(cls.payload)
        rec = os.path.join(cls.dir, "rec")
        isac = run_app("nrsar-isac", FLIGHT + ["--payload", cls.payload, "--record", rec,
                                               "--json", "--quiet",
                                               "--out", os.path.join(cls.dir, "isac")])
        assert isac.returncode == 0, isac.stderr
        cls.isac = json.loads(isac.stdout)
        cls.meta_path = os.path.join(rec, "flight.sigmf-meta")
        with open(cls.meta_path) as f:
            cls.meta = json.load(f)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def process(self, meta_path, name, *args):
        return run_app("nrsar-process", [meta_path, "--json", "--quiet",
                                         "--out", os.path.join(self.dir, name)] + list(args))

    def test_001_meta(self):
        """The meta names the grid: DMRS, the payload file, its coding as nrsar-isac ran."""
        glob = self.meta["global"]
        self.assertEqual(glob["nrsar:dmrs"], [2, 11])
        self.assertEqual(glob["nrsar:payload_path"], os.path.abspath(self.payload))
        pusch = dict(glob["nrsar:pusch"])
        per_tb = pusch.pop("pdu_bytes")
        self.assertEqual(pusch, {
            "coding": "nr-ldpc", "mcs_table": "qam256", "mcs": 4, "rv": 0, "repetitions": 1,
            "n_rnti": 0x4601, "n_id": 0, "scrambling": "standard", "dmrs_scrambling_id": 0})
        self.assertEqual(self.isac["mcs"], 4)  # the highest QPSK row of the qam256 table
        # one PDU of pdu_bytes per TB (a MAC SDU: the TB's bytes less the headers)
        self.assertLess(per_tb, self.isac["tbs_bits"] // 8)
        self.assertEqual(self.isac["payload_slots"], -(-PAYLOAD_BYTES // per_tb))
        self.assertTrue(self.isac["payload_identical"])

    def test_002_process_gives_the_isac_image(self):
        """nrsar-process on the recording forms nrsar-isac's image: the grid regenerated
        from the payload is the one sent (the same samples, ofdm_demod, filter and
        focuser: the arrays are equal), the NMSE within the issue's 0.1 dB."""
        proc = self.process(self.meta_path, "proc")
        self.assertEqual(proc.returncode, 0, proc.stderr)
        r = json.loads(proc.stdout)
        self.assertLessEqual(abs(r["nmse_db"] - self.isac["nmse_db"]), 0.1)
        a = np.load(os.path.join(self.dir, "isac", "image.npy"))
        b = np.load(r["image_npy"])
        diff = difference_db(a, b)
        print(f"NMSE nrsar-isac {self.isac['nmse_db']:.5f} dB, nrsar-process "
              f"{r['nmse_db']:.5f} dB; image difference {diff} dB of the image energy")
        self.assertEqual(a.shape, b.shape)
        self.assertTrue(np.array_equal(a, b))

    def test_003_the_grid_matters(self):
        """Another grid (the payload scrambled with n_ID 1 instead of 0) gives another image:
        the equality above is the regenerated grid's, not the samples' alone."""
        meta = json.loads(json.dumps(self.meta))
        meta["global"]["nrsar:pusch"]["n_id"] = 1
        path = self.copy("n_id1", meta)
        proc = self.process(path, "n_id1")
        self.assertEqual(proc.returncode, 0, proc.stderr)
        a = np.load(os.path.join(self.dir, "isac", "image.npy"))
        b = np.load(json.loads(proc.stdout)["image_npy"])
        # 19 of 85 slots carry the payload under another scrambling: a large part of the
        # filter's reference is wrong
        self.assertGreater(difference_db(a, b), -10.0)

    def copy(self, name, meta):
        folder = os.path.join(self.dir, name)
        os.makedirs(folder)
        path = os.path.join(folder, "flight.sigmf-meta")
        with open(path, "w") as f:
            json.dump(meta, f)
        os.symlink(self.meta_path[:-len("meta")] + "data",
                   os.path.join(folder, "flight.sigmf-data"))
        return path

    def assert_refused(self, proc, expected):
        where = proc.stderr
        self.assertEqual(proc.returncode, 2, where)
        self.assertNotIn("Traceback", where)
        self.assertEqual(len(where.strip().splitlines()), 1, where)
        self.assertIn(expected, where)
        self.assertEqual(proc.stdout, "", where)

    def test_004_wrong_payload(self):
        """A payload file that is not the one sent (one byte changed, via --payload or at
        nrsar:payload_path) or none at the recorded path: exit 2, naming the field."""
        with open(self.payload, "rb") as f:
            data = bytearray(f.read())
        data[1234] ^= 1
        other = os.path.join(self.dir, "other.bin")
        with open(other, "wb") as f:
            f.write(data)
        proc = self.process(self.meta_path, "bad", "--payload", other)
        self.assert_refused(proc, f"--payload = {other!r}: its SHA-256")
        self.assertIn("nrsar:payload_sha256", proc.stderr)
        meta = json.loads(json.dumps(self.meta))
        meta["global"]["nrsar:payload_path"] = other
        proc = self.process(self.copy("other_path", meta), "bad")
        self.assert_refused(proc, f"global nrsar:payload_path = {other!r}: its SHA-256")
        meta["global"]["nrsar:payload_path"] = os.path.join(self.dir, "gone.bin")
        proc = self.process(self.copy("gone", meta), "bad")
        self.assert_refused(proc, "global nrsar:payload_path = ")
        self.assertIn("cannot be read", proc.stderr)
        # --payload replaces a path that is gone
        proc = self.process(self.copy("gone2", meta), "gone2", "--payload", self.payload,
                            "--images", "none")
        self.assertEqual(proc.returncode, 0, proc.stderr)
        # and has no place in a PRBS grid's recording
        for key in ("nrsar:dmrs", "nrsar:pusch"):
            meta["global"][key] = None
        proc = self.process(self.copy("prbs", meta), "bad", "--payload", self.payload)
        self.assert_refused(proc, f"--payload = {self.payload!r} needs a PUSCH recording")

    def test_005_bad_grid_fields(self):
        """Each nrsar:pusch / nrsar:dmrs defect is one line naming the field, its value and
        the limit."""
        cases = [
            (("nrsar:pusch", "n_id"), 1024, "global nrsar:pusch n_id = 1024 must be within "
                                            "0 .. 1023"),
            (("nrsar:pusch", "coding"), "turbo", "global nrsar:pusch coding = 'turbo' must be "
                                                 "one of nr-ldpc, none"),
            (("nrsar:pusch", "repetitions"), 3, "global nrsar:pusch repetitions = 3 must be "
                                                "one of 1, 2, 4, 8"),
            (("nrsar:pusch", "mcs"), None, "global nrsar:pusch mcs = None must be null with "
                                           "coding none"),
            (("nrsar:pusch", "mcs"), 20, "global nrsar:pusch with nrsar:dmrs [2, 11] and "
                                         "nrsar:modulation 'qpsk' is invalid"),
            (("nrsar:pusch", "pdu_bytes"), 1000, "global nrsar:pusch pdu_bytes = 1000 is not "
                                                 "this pusch_encoder's"),
            (("nrsar:pusch",), None, "global nrsar:pusch = None must be dict"),
            (("nrsar:payload_sha256",), None, "global nrsar:payload_sha256 is null"),
            (("nrsar:dmrs",), [2, 20], "global nrsar:pusch with nrsar:dmrs [2, 20]"),
        ]
        for i, (keys, value, expected) in enumerate(cases):
            meta = json.loads(json.dumps(self.meta))
            obj = meta["global"]
            for k in keys[:-1]:
                obj = obj[k]
            obj[keys[-1]] = value
            with self.subTest(keys=keys, value=value):
                self.assert_refused(self.process(self.copy(f"bad{i}", meta), "bad"), expected)

    def test_006_strip_on_dask(self):
        """--strip-aperture-s on a Dask cluster (local:1): each task regenerates the PUSCH
        grid from its first symbol (pusch_encoder from that symbol's slot with the payload
        from its TB on, nr_isac_tx from the symbol), and the stitched strip equals one graph
        over the whole recording bit for bit."""
        from gnuradio.nrsar import distributed_process as dp, recording
        from gnuradio.nrsar.options import ProcessOptions

        def opts(name, **kw):
            return ProcessOptions(recording=self.meta_path, strip_aperture_s=0.0125,
                                  strip_overlap_s=0.001, out=os.path.join(self.dir, name),
                                  **kw).validate()
        rec = recording.read(self.meta_path)
        one = opts("whole")
        whole = dp.focus_slice(one, self.meta_path, dp.whole(one, rec, dp.layout(one, rec)))
        res = dp.run(opts("dask", dask="local:1"))
        self.assertEqual(res["strip_failed"], [])
        self.assertEqual(res["dask_workers"], 1)
        # 300 lines per aperture: the second task's block starts at symbol 156, inside the
        # payload's slots (19 x 14 symbols) and inside slot 11
        firsts = [first for first, _ in res["strip_slices"]]
        self.assertEqual(firsts, [0, 156, 456, 756])
        self.assertLess(156, self.isac["payload_slots"] * 14)
        np.testing.assert_array_equal(np.load(res["strip_image_npy"]), whole["image"])

    def test_007_repetitions_strip(self):
        """Two slots per TB and per-slot scrambling: nrsar-process gives nrsar-isac's image,
        and the strip's task from symbol 156 (slot 11: the second slot of TB 5) starts its
        encoder inside that TB's repetitions; the strip equals one graph bit for bit."""
        from gnuradio.nrsar import distributed_process as dp, recording
        from gnuradio.nrsar.options import ProcessOptions
        rec_dir = os.path.join(self.dir, "rec_rep")
        isac = run_app("nrsar-isac", FLIGHT + ["--payload", self.payload, "--record", rec_dir,
                                               "--repetitions", "2", "--scrambling",
                                               "per-slot", "--json", "--quiet",
                                               "--out", os.path.join(self.dir, "isac_rep")])
        self.assertEqual(isac.returncode, 0, isac.stderr)
        self.assertEqual(json.loads(isac.stdout)["payload_slots"],
                         2 * self.isac["payload_slots"])
        meta = os.path.join(rec_dir, "flight.sigmf-meta")
        proc = self.process(meta, "proc_rep")
        self.assertEqual(proc.returncode, 0, proc.stderr)
        np.testing.assert_array_equal(np.load(json.loads(proc.stdout)["image_npy"]),
                                      np.load(os.path.join(self.dir, "isac_rep", "image.npy")))
        opts = ProcessOptions(recording=meta, strip_aperture_s=0.0125, strip_overlap_s=0.001,
                              out=os.path.join(self.dir, "strip_rep")).validate()
        rec = recording.read(meta)
        lay = dp.layout(opts, rec)
        self.assertEqual([sl.first for sl in lay.slices], [0, 156, 456, 756])
        res = dp.run(opts)
        np.testing.assert_array_equal(
            np.load(res["strip_image_npy"]),
            dp.focus_slice(opts, meta, dp.whole(opts, rec, lay))["image"])

    def test_008_graph_payload(self):
        """The ISAC graphs' payload and record snippets (examples/gen_isac_grcs.py): the
        file queued by graph_payload into an encoder built as the GRC block builds it (here
        per-slot scrambling and n_ID 5, to catch a field the meta would spell otherwise)
        gives the grid that nrsar-process's build_transmitter makes from graph_pusch's
        meta; the snippets' bad input is a ValueError naming the parameter and the limit."""
        import types
        from gnuradio import blocks, gr, nrsar
        from gnuradio.nrsar import isac_chain
        num = nrsar.make_numerology("sdr20")
        payload = np.random.default_rng(8).integers(0, 256, 5000, np.uint8).tobytes()
        path = os.path.join(self.dir, "graph_payload.bin")
        with open(path, "wb") as f:
            f.write(payload)
        symbols = 4 * num.symbols_per_slot  # 5000 bytes: 3 TBs of 2366, then padding

        def grid(tb, tx):
            sink = blocks.vector_sink_c(num.num_subcarriers)
            tb.connect(tx, blocks.head(gr.sizeof_gr_complex * num.num_subcarriers, symbols),
                       sink)
            tb.run()
            return np.array(sink.data())

        tb = gr.top_block()
        enc = nrsar.pusch_encoder(nrsar.pusch_config(
            num=num, mod=nrsar.make_modulation("qam16"), dmrs=nrsar.make_dmrs("pusch2"),
            coding=nrsar.make_pusch_coding("nr_ldpc"), mcs_table="qam256", mcs=10, rv=0,
            repetitions=1, n_rnti=17921, n_id=5,
            scrambling=nrsar.make_pusch_scrambling("per_slot"), max_queued_bytes=8000,
            first_slot=0))
        tx = nrsar.nr_isac_tx(num, nrsar.make_modulation("qam16"), nrsar.make_tx_mode("data"),
                              nrsar.make_srs(), 0, nrsar.make_dmrs("pusch2"), 0)
        tb.connect(enc, tx)
        self.assertEqual(isac_chain.graph_payload(enc, path, 8000), path)
        pusch = isac_chain.graph_pusch(enc, "sdr20", "qam16", "pusch2", coding="nr-ldpc",
                                       mcs_table="qam256", mcs=10, repetitions=1,
                                       n_rnti=17921, n_id=5, scrambling="per-slot",
                                       dmrs_id=0)
        got = grid(tb, tx)
        self.assertEqual((enc.payload_bytes_sent(), enc.pdus_dropped()), (5000, 0))
        rec = types.SimpleNamespace(pusch=pusch, dmrs=[2, 11], num=num, preset="sdr20",
                                    modulation="qam16", grid_seed=0)
        tb2 = gr.top_block()
        _, tx2, _, chunks = isac_chain.build_transmitter(
            tb2, num, isac_chain.isac_options_of(rec), payload)
        self.assertEqual(len(chunks), 3)
        np.testing.assert_array_equal(got, grid(tb2, tx2))

        self.assertIsNone(isac_chain.graph_payload(enc, isac_chain.STROBE, 8000))
        gone = os.path.join(self.dir, "gone.bin")
        with self.assertRaisesRegex(ValueError, f"payload = {gone!r} cannot be read"):
            isac_chain.graph_payload(enc, gone, 8000)
        with self.assertRaisesRegex(ValueError, "5000 bytes must be at most the encoder's "
                                                "max_queued_bytes = 4999"):
            isac_chain.graph_payload(enc, path, 4999)
        with self.assertRaisesRegex(ValueError, r"the graph's pusch_encoder \(TBS, G, bytes "
                                                r"per TB\) = \(\d+, 29376, 2366\) is not"):
            isac_chain.graph_pusch(enc, "sdr20", "qam16", "pusch2", mcs=9)


if __name__ == "__main__":
    gr_unittest.run(qa_isac_recording)
