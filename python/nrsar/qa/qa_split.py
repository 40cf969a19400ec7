#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-sim --split zmq (split.py, link.py): the UAV and the ground as two processes over
gr-zeromq on loopback. The split image equals the one-graph image; the framing's counts
(lost, rejected, replayed, junk) against frames built here; a ground killed mid-aperture and
restarted; a stranger's lines rejected with the image unchanged; a UAV without a ground
that does not block."""

import multiprocessing
import os
import shutil
import signal
import socket
import tempfile
import time

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest

from gnuradio.nrsar import chain, link, split
from gnuradio.nrsar.options import OptionError, SimOptions

# sdr20, 0.05 s = 1200 symbols, one target: 298 presummed lines (D = 4), 1200 at the IFFT
FLIGHT = dict(preset="sdr20", aperture_s=0.05, target=["300,1"], snr_db=5.0)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def load(result, name):
    return np.load(result[name])


class qa_split(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="qa_split_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def opts(self, name, **kw):
        return SimOptions(**dict(FLIGHT, out=os.path.join(self.dir, name), **kw)).validate()

    def test_001_deframer_counts(self):
        # frames built here: lines 0..9 with 3 and 4 lost, 6 sent twice (a replay), a
        # stranger's frame (other key), junk bytes between frames, then the end frame
        bins, key = 8, link.new_key()
        rng = np.random.default_rng(3)
        lines = (rng.standard_normal((10, bins)) +
                 1j * rng.standard_normal((10, bins))).astype(np.complex64)
        axis = pmt.make_tuple(pmt.from_double(100.0), pmt.from_double(2.0), pmt.from_long(bins))
        stream = b""
        for seq in (0, 1, 2, 5, 6, 6, 7, 8, 9):
            stream += link.encode_frame(key, 7, seq, lines[seq], {"range_axis": axis})
            if seq == 5:
                stream += b"junk!" + link.encode_frame(link.new_key(), 7, 6, lines[6] * 0, {})
        stream += link.encode_frame(key, 8, 9, lines[9], {})  # another session
        stream += link.encode_frame(key, 7, 10, np.zeros(bins, np.complex64), {},
                                    link.FLAG_END)
        tb = gr.top_block()
        src = blocks.vector_source_b(list(stream), False)
        deframer = link.line_deframer(bins, key, 0, 5.0)
        sink = blocks.vector_sink_c(bins)
        tb.connect(src, deframer, sink)
        tb.run()
        out = np.array(sink.data(), np.complex64).reshape(-1, bins)
        expect = lines.copy()
        expect[3:5] = 0
        np.testing.assert_array_equal(out, expect)
        rep = deframer.report()
        # a rejected frame's magic is skipped and its rest counted as junk (a stranger's
        # frame may be short: the search for the next magic finds ours)
        rest = link.frame_bytes(bins) - len(link.MAGIC)
        self.assertEqual((rep["lines_received"], rep["lines_lost"], rep["frames_rejected"],
                          rep["frames_replayed"], rep["frames_other_session"],
                          rep["junk_bytes"], rep["gaps"], rep["end_frame"]),
                         (8, 2, 1, 1, 1, 5 + rest, [[3, 2]], True))
        tags = [(t.offset, pmt.symbol_to_string(t.key)) for t in sink.tags()]
        self.assertEqual(tags, [(0, "range_axis")])  # once: the value never changed

    def test_002_split_equals_one_graph(self):
        for at, extra in (("presum", dict(presum="cheby", decim=4)), ("range", {})):
            with self.subTest(at=at):
                one = chain.simulate(self.opts("one_" + at, **extra))
                two = split.simulate(self.opts("two_" + at, split="zmq", split_at=at, **extra))
                np.testing.assert_array_equal(load(two, "image_npy"), load(one, "image_npy"))
                self.assertEqual(two["nmse_db"], one["nmse_db"])
                self.assertEqual(two["split_ground"]["lines_lost"], 0)
                self.assertEqual(two["split_ground"]["lines_received"],
                                 two["split_uav"]["lines"])
                # 1200 pulses; behind the presummer (16 taps = 4 D, centred between a = 7
                # pulses before and b = 8 after) one line per 4 pulses less the last
                # ceil(b / D) = 2, whose window would reach past the end
                self.assertEqual(two["split_uav"]["lines"], 298 if at == "presum" else 1200)

    def test_003_ground_killed_and_restarted(self):
        # 1200 lines at 400 lines/s: 3 s of flight; the first ground (up before the UAV)
        # is killed after about 1 s, the second starts 0.5 s later and zero-fills what it
        # missed; the UAV keeps its link open for --split-idle-s after its last line
        opts = self.opts("restart", split="zmq", split_at="range", split_line_rate=400.0,
                         split_idle_s=20.0,
                         split_address=f"tcp://127.0.0.1:{free_port()}")
        one = chain.simulate(self.opts("restart_one"))
        key = link.new_key()
        ground1 = split.start_ground(opts, key, opts.split_address)
        uav, address = split.start_uav(opts, key)
        time.sleep(1.0)
        os.kill(ground1.proc.pid, signal.SIGKILL)
        ground1.proc.join(10)
        time.sleep(0.5)
        ground2 = split.start_ground(opts, key, address)
        uav_report, msg = split.finish(uav, ground2)
        rep, res = msg["report"], msg["result"]
        lines = uav_report["lines"]
        self.assertEqual(rep["lines_received"] + rep["lines_lost"], lines)
        self.assertEqual(rep["lines_out"], lines)
        self.assertGreater(rep["first_seq"], 100)  # the first ground had taken these
        self.assertLess(rep["first_seq"], lines - 100)  # mid-aperture
        # what came through is bit-exact, what was lost is zero (the gaps reported)
        got, ref = load(res, "range_compressed_npy"), load(one, "range_compressed_npy")
        lost = np.all(got == 0, axis=1)
        self.assertEqual(int(lost.sum()), rep["lines_lost"])
        np.testing.assert_array_equal(got[~lost], ref[~lost])
        zeros = sum(count for _, count in rep["gaps"])
        self.assertEqual(zeros, rep["lines_lost"])
        # image quality: a point target's compressed peak is the coherent sum over the
        # pulses that hold it; every pulse does here (no beam), so the peak keeps the
        # fraction of lines received (within the band's edge effects, 5 %)
        peak = np.abs(load(res, "image_npy")).max() / np.abs(load(one, "image_npy")).max()
        self.assertAlmostEqual(peak, rep["lines_received"] / lines, delta=0.05)

    def test_004_stranger_rejected(self):
        # a stranger binds the port before the UAV: its frames (signed with another key)
        # and its junk reach the ground, which rejects and counts them; the image is the
        # one-graph image
        import zmq
        port = free_port()
        opts = self.opts("stranger", split="zmq", split_address=f"tcp://127.0.0.1:{port}",
                         presum="cheby", decim=4)
        one = chain.simulate(self.opts("stranger_one", presum="cheby", decim=4))
        key = link.new_key()
        ground = split.start_ground(opts, key, opts.split_address)
        ctx = zmq.Context()
        sock = ctx.socket(zmq.PUSH)
        sock.setsockopt(zmq.LINGER, 5000)
        sock.bind(opts.split_address)
        bins = chain.layout(opts).range_bins
        forged = np.ones(bins, np.complex64)
        for seq in range(20):
            sock.send(link.encode_frame(link.new_key(), 1, seq, forged, {}))
        sock.send(b"\x00" * 100)
        sock.close()  # lingers until delivered
        ctx.term()
        uav, _ = split.start_uav(opts, key)
        uav_report, msg = split.finish(uav, ground)
        rep = msg["report"]
        self.assertEqual(rep["frames_rejected"], 20)
        self.assertEqual(rep["junk_bytes"], 100 + 20 * (link.frame_bytes(bins) -
                                                        len(link.MAGIC)))
        self.assertEqual((rep["lines_lost"], rep["lines_received"]), (0, uav_report["lines"]))
        np.testing.assert_array_equal(load(msg["result"], "image_npy"),
                                      load(one, "image_npy"))

    def test_005_uav_without_ground_does_not_block(self):
        # no ground ever: the radio path runs to its end, the queue drops and counts
        opts = self.opts("alone", split="zmq", split_at="range", split_queue_lines=8,
                         split_line_rate=4000.0, split_idle_s=2.0, images="none")
        uav, _ = split.start_uav(opts, link.new_key())
        try:
            rep = uav.receive("report")["report"]
        finally:
            uav.stop()
        self.assertEqual(rep["lines_framed"], rep["lines"])
        self.assertGreater(rep["lines_dropped"], 0)
        self.assertLessEqual(rep["queue_peak"], 8 + 1)  # + the end frame, always queued
        # every line framed was dropped, handed to the link or is still queued
        self.assertEqual(rep["lines_framed"] - rep["lines_dropped"] + 1,
                         rep["frames_sent"] + rep["frames_unsent"])

    def test_006_options_and_key(self):
        for addr in ("tcp://*:5757", "tcp://0.0.0.0:5757", "tcp://[::]:5757"):
            with self.assertRaisesRegex(OptionError, "every interface"):
                self.opts("o", split="zmq", split_address=addr)
        self.opts("o", split="zmq", split_address="tcp://0.0.0.0:5757", split_bind_any=True)
        for addr in ("udp://127.0.0.1:5", "tcp://127.0.0.1:70000", "tcp://127.0.0.1"):
            with self.assertRaisesRegex(OptionError, "--split-address"):
                self.opts("o", split="zmq", split_address=addr)
        path = os.path.join(self.dir, "key")
        link.write_key(path)
        self.assertEqual(len(link.read_key(path)), link.KEY_MIN_BYTES)
        os.chmod(path, 0o644)
        with self.assertRaisesRegex(ValueError, "--split-key .* mode 644"):
            self.opts("o", split="zmq", split_key=path)
        short = os.path.join(self.dir, "short")
        with open(os.open(short, os.O_WRONLY | os.O_CREAT, 0o600), "wb") as f:
            f.write(b"x" * 31)
        with self.assertRaisesRegex(ValueError, "31 bytes, fewer than 32"):
            self.opts("o", split="zmq", split_key=short)

    def test_007_autofocus_on_the_ground(self):
        # the ground graph's autofocus is the one graph's: same image, same estimate
        extra = dict(presum="cheby", decim=4, autofocus="pga")
        one = chain.simulate(self.opts("af_one", **extra))
        two = split.simulate(self.opts("af_two", split="zmq", **extra))
        self.assertIsNotNone(one["autofocus_phase_rms_rad"])
        self.assertEqual(two["autofocus_phase_rms_rad"], one["autofocus_phase_rms_rad"])
        np.testing.assert_array_equal(load(two, "image_npy"), load(one, "image_npy"))
        self.assertEqual(two["nmse_db"], one["nmse_db"])
        # and it acts on the image: without it the focuser's image is another array
        plain = chain.simulate(self.opts("af_plain", presum="cheby", decim=4))
        self.assertFalse(np.array_equal(load(plain, "image_npy"), load(one, "image_npy")))

    def test_008_pub_sub_two_grounds(self):
        # one UAV publishing (PUB), two grounds subscribed before its radio starts (ZMQ's
        # slow joiner: a subscription takes a moment to reach the PUB socket); at 1000
        # lines per second neither falls behind, so both get every line and the one-graph
        # image
        extra = dict(presum="cheby", decim=4)
        one = chain.simulate(self.opts("pub_one", **extra))
        cut = dict(split="zmq", split_pattern="pub", split_line_rate=1000.0, **extra)
        key = link.new_key()
        go = multiprocessing.get_context("spawn").Event()
        uav, address = split.start_uav(self.opts("pub_uav", **cut), key, go)
        halves = [uav]
        try:
            for i in range(2):
                halves.append(split.start_ground(self.opts(f"pub_g{i}", **cut), key, address))
            time.sleep(1.0)
            go.set()
            lines = uav.receive("report")["report"]["lines"]
            msgs = [g.receive("images") for g in halves[1:]]
        finally:
            for half in halves:
                half.stop()
        self.assertEqual(lines, 298)
        for msg in msgs:
            rep = msg["report"]
            self.assertEqual((rep["lines_received"], rep["lines_lost"]), (lines, 0))
            np.testing.assert_array_equal(load(msg["result"], "image_npy"),
                                          load(one, "image_npy"))

    def test_009_pub_sub_late_joiner(self):
        # a ground that subscribes after the UAV started misses the lines published before
        # (PUB does not keep them): it counts them lost, zero-fills them, and its lines
        # received + lost are the UAV's
        opts = self.opts("late", split="zmq", split_pattern="pub", split_at="range",
                         split_line_rate=400.0, split_idle_s=20.0)
        one = chain.simulate(self.opts("late_one"))
        key = link.new_key()
        uav, address = split.start_uav(opts, key)
        try:
            time.sleep(1.0)  # about 400 of the 1200 lines are gone
            ground = split.start_ground(opts, key, address)
            uav_report, msg = split.finish(uav, ground)
        finally:
            uav.stop()
        rep, lines = msg["report"], uav_report["lines"]
        self.assertEqual(rep["lines_received"] + rep["lines_lost"], lines)
        self.assertGreater(rep["lines_lost"], 100)
        self.assertLess(rep["lines_lost"], lines - 100)
        self.assertEqual(rep["gaps"][0][0], 0)  # the lines before its first one
        got = load(msg["result"], "range_compressed_npy")
        ref = load(one, "range_compressed_npy")
        lost = np.all(got == 0, axis=1)
        self.assertEqual(int(lost.sum()), rep["lines_lost"])
        np.testing.assert_array_equal(got[~lost], ref[~lost])


if __name__ == "__main__":
    gr_unittest.run(qa_split)
