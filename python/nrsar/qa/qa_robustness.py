#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Run-time robustness of the whole chain (docs/robustness.md, second table).

tx -> echo -> tf_filter -> range_ifft -> rd_focuser -> nmse_probe on the 'tiny' numerology:
non-finite samples injected at every block's input are zeroed, counted and tagged while the
image is still produced; a stream that stops mid-aperture finishes and reports the partial
aperture; a flowgraph stops, waits and restarts; no item is lost or duplicated over a longer
run; the transmitter's tags leave every 1:1 block at their offsets, exactly once."""

import threading

import numpy as np
import pmt

from gnuradio import blocks, fft, gr, gr_unittest
from gnuradio import nrsar

N = 64                      # 'tiny': 64 subcarriers, 64-point FFT, CP 16
APERTURE_S = 0.02           # 480 symbols of 41.7 us
TIMEOUT_S = 120.0           # a hang fails the test instead of blocking ctest


def scenario():
    num = nrsar.make_numerology("tiny")
    geo = nrsar.make_geometry("paper", aperture_s=APERTURE_S)
    scn = nrsar.make_scene("300,0.5")
    return num, geo, scn


def run_with_timeout(tb, timeout=TIMEOUT_S):
    """tb.run() in a thread; True if it finished within timeout (else stops it)."""
    done = threading.Event()

    def target():
        tb.run()
        done.set()

    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    finished = done.wait(timeout)
    if not finished:
        tb.stop()
        thread.join(10)
    return finished


class nonfinite_injector(gr.sync_block):
    """Copies vectors of vlen, replacing the elements at the given (item, index) positions
    with the given non-finite values."""

    def __init__(self, vlen, hits):
        gr.sync_block.__init__(self, "nonfinite_injector", [(np.complex64, vlen)],
                               [(np.complex64, vlen)])
        self.hits = dict(hits)

    def work(self, input_items, output_items):
        inp, out = input_items[0], output_items[0]
        n = len(out)
        out[:] = inp[:n]
        base = self.nitems_written(0)
        for (item, index), value in self.hits.items():
            if base <= item < base + n:
                out[item - base, index] = value
        return n


def tag_list(sink, key):
    return [(t.offset, pmt.to_python(t.value)) for t in sink.tags()
            if pmt.eq(t.key, pmt.intern(key))]


class qa_robustness(gr_unittest.TestCase):

    def chain(self, tb, symbols, inject=None, infinite=False):
        """Connects the chain; inject maps a block name to the hits of an injector in front
        of that block's (first) input. Returns the blocks and a sink after each block."""
        num, geo, scn = scenario()
        inject = inject or {}
        b = {}
        b["tx"] = nrsar.nr_isac_tx(num, nrsar.make_modulation("qpsk"),
                                   nrsar.make_tx_mode("data"), nrsar.srs_config(), 7)
        b["echo"] = nrsar.scene_echo(num, geo, scn, 20.0, 8)
        b["filter"] = nrsar.tf_filter(N, nrsar.make_filter("wf"), 20.0, False)
        b["range_ifft"] = nrsar.range_ifft(num, 0, fft.window.WIN_RECTANGULAR, -1.0, 0.0, 0.0)
        k = b["range_ifft"].num_bins()
        cfg = nrsar.focuser_config()
        cfg.lines_per_aperture = int(geo.symbols_per_aperture(num))
        b["focuser"] = nrsar.rd_focuser(num, geo, scn, k, b["range_ifft"].range_axis_first_m(),
                                        b["range_ifft"].range_bin_m(), cfg)
        b["probe"] = nrsar.nmse_probe(num, geo, scn,
                                      nrsar.constellation(nrsar.make_modulation("qpsk")).points(),
                                      nrsar.make_filter("wf"), 20.0, k)
        sinks = {name: blocks.vector_sink_c(N if name in ("tx", "echo", "filter") else k)
                 for name in ("tx", "echo", "filter", "range_ifft", "focuser")}
        self.injectors = {}

        def entry(name, vlen):
            if name not in inject:
                return b[name]
            inj = nonfinite_injector(vlen, inject[name])
            self.injectors[name] = inj
            tb.connect(inj, b[name])
            return inj

        src = b["tx"]
        if not infinite:
            b["head"] = blocks.head(gr.sizeof_gr_complex * N, symbols)
            tb.connect(b["tx"], b["head"])
            src = b["head"]
        tb.connect(src, entry("echo", N))
        tb.connect(src, (b["filter"], 1))
        if "filter" in inject:
            inj = nonfinite_injector(N, inject["filter"])
            self.injectors["filter"] = inj  # a Python block must outlive the run
            tb.connect((b["echo"], 0), inj, (b["filter"], 0))
        else:
            tb.connect((b["echo"], 0), (b["filter"], 0))
        tb.connect(b["filter"], entry("range_ifft", N))
        tb.connect(b["range_ifft"], entry("focuser", k))
        tb.connect(b["focuser"], entry("probe", k))
        tb.connect((b["echo"], 1), blocks.null_sink(gr.sizeof_gr_complex * N))
        tb.connect(src, sinks["tx"])
        for name in ("echo", "filter", "range_ifft", "focuser"):
            tb.connect(b[name], sinks[name])
        return b, sinks

    def test_001_nonfinite_zeroed_counted_tagged_through_the_chain(self):
        num, geo, _ = scenario()
        m = int(geo.symbols_per_aperture(num))
        nan, inf = complex(float("nan"), 0.0), complex(float("inf"), float("-inf"))
        inject = {"echo": {(3, 5): nan, (10, 0): inf},
                  "filter": {(20, 7): nan},
                  "range_ifft": {(30, 1): inf, (30, 2): nan, (31, 63): nan},
                  "focuser": {(40, 4): nan},
                  "probe": {(50, 3): inf, (51, 3): nan}}
        tb = gr.top_block()
        b, sinks = self.chain(tb, m, inject)
        self.assertTrue(run_with_timeout(tb))
        # Counted: each block counts what arrived at its input, nothing else (the blocks
        # upstream zeroed theirs). tf_filter's data input is the one injected.
        self.assertEqual(b["echo"].nonfinite_count(), 2)
        self.assertEqual(b["filter"].nonfinite_count(), 1)
        self.assertEqual(b["range_ifft"].nonfinite_count(), 3)
        self.assertEqual(b["focuser"].nonfinite_count(), 1)
        self.assertEqual(b["probe"].nonfinite_count(), 2)
        # Tagged: each 1:1 block at the item that carried the samples (value: the count in
        # that item); the tags of the blocks upstream pass through at their offsets.
        key = nrsar.tag_keys.nonfinite
        echo_tags = [(3, 1), (10, 1)]
        filter_tags = sorted(echo_tags + [(20, 1)])
        self.assertEqual(tag_list(sinks["echo"], key), echo_tags)
        self.assertEqual(sorted(tag_list(sinks["filter"], key)), filter_tags)
        self.assertEqual(sorted(tag_list(sinks["range_ifft"], key)),
                         sorted(filter_tags + [(30, 2), (31, 1)]))
        # The focuser reports on the first line of the aperture that held them.
        foc = tag_list(sinks["focuser"], key)
        self.assertEqual(len(foc), 1)
        self.assertEqual(foc[0][1], 1)
        # Zeroed: every output is finite and the image is there (m lines, not all zero),
        # with the probe's metrics of the aperture.
        for name, sink in sinks.items():
            data = np.asarray(sink.data())
            self.assertTrue(np.all(np.isfinite(data)), name)
        image = np.asarray(sinks["focuser"].data()).reshape(-1, b["range_ifft"].num_bins())
        self.assertEqual(image.shape[0], m)
        self.assertGreater(np.max(np.abs(image)), 0.0)
        metrics = b["probe"].metrics()
        self.assertEqual(b["probe"].apertures(), 1)
        self.assertEqual(metrics["nonfinite"], 2.0)
        self.assertTrue(np.isfinite(metrics["peak_power"]))
        self.assertTrue(np.isfinite(metrics["peak_error_m"]))

    def test_002_stream_stopping_mid_aperture_finishes_partial(self):
        num, geo, _ = scenario()
        m = int(geo.symbols_per_aperture(num))
        symbols = m + m // 3
        tb = gr.top_block()
        b, sinks = self.chain(tb, symbols)
        # A second probe whose image stream stops a third into the second aperture.
        k = b["range_ifft"].num_bins()
        cut = blocks.head(gr.sizeof_gr_complex * k, symbols)
        probe2 = nrsar.nmse_probe(*scenario(),
                                  nrsar.constellation(nrsar.make_modulation("qpsk")).points(),
                                  nrsar.make_filter("wf"), 20.0, k)
        tb.connect(b["focuser"], cut, probe2)
        self.assertTrue(run_with_timeout(tb), "the flowgraph hung on a short stream")
        self.assertEqual(len(sinks["range_ifft"].data()), symbols * k)
        # The focuser flushes the pulses of the unfinished aperture, zero padded, as a
        # whole second aperture.
        self.assertEqual(b["focuser"].apertures(), 2)
        self.assertEqual(len(sinks["focuser"].data()), 2 * m * k)
        self.assertEqual(b["probe"].apertures(), 2)
        self.assertEqual(b["probe"].metrics()["partial"], 0.0)
        # The probe whose input stops mid-aperture evaluates what it got, marked partial.
        self.assertEqual(probe2.apertures(), 2)
        metrics = probe2.metrics()
        self.assertEqual(metrics["aperture"], 1.0)
        self.assertEqual(metrics["partial"], 1.0)
        self.assertEqual(metrics["lines"], symbols - m)

    def test_003_stop_wait_restart(self):
        tb = gr.top_block()
        b, sinks = self.chain(tb, 0, infinite=True)
        counts = []
        for _ in range(3):
            tb.start()
            # Wait until items flowed this round (bounded), then stop.
            start = len(sinks["range_ifft"].data())
            for _ in range(600):
                if len(sinks["range_ifft"].data()) > start + 4 * b["range_ifft"].num_bins():
                    break
                threading.Event().wait(0.05)
            tb.stop()
            tb.wait()
            counts.append(len(sinks["range_ifft"].data()))
        # Each round processed items, and stop() really stopped: nothing arrives after wait().
        self.assertGreater(counts[0], 0)
        self.assertGreater(counts[1], counts[0])
        self.assertGreater(counts[2], counts[1])
        threading.Event().wait(0.2)
        self.assertEqual(len(sinks["range_ifft"].data()), counts[2])
        for name in ("tx", "echo", "filter"):
            self.assertTrue(np.all(np.isfinite(np.asarray(sinks[name].data()))), name)

    def test_004_no_item_lost_or_duplicated(self):
        num, geo, _ = scenario()
        m = int(geo.symbols_per_aperture(num))
        symbols = 4 * m + 17
        tb = gr.top_block()
        b, sinks = self.chain(tb, symbols)
        self.assertTrue(run_with_timeout(tb))
        k = b["range_ifft"].num_bins()
        for name, vlen in (("tx", N), ("echo", N), ("filter", N), ("range_ifft", k)):
            self.assertEqual(len(sinks[name].data()), symbols * vlen, name)
        # The transmitter tags the first symbol of every slot with its number: each one once,
        # in order, at its own item, after every 1:1 block.
        spf = num.symbols_per_slot
        for name in ("tx", "echo", "filter", "range_ifft"):
            tags = tag_list(sinks[name], nrsar.tag_keys.symbol)
            self.assertEqual(tags, [(i, i) for i in range(0, symbols, spf)], name)
        # The 1:1 blocks are deterministic functions of their input: the echo of the same
        # grid computed again in one piece equals the streamed one (nothing lost, repeated
        # or reordered at buffer boundaries).
        grid = np.asarray(sinks["tx"].data(), dtype=np.complex64)
        num, geo, scn = scenario()
        tb2 = gr.top_block()
        src = blocks.vector_source_c(grid.tolist(), False, N)
        echo = nrsar.scene_echo(num, geo, scn, 20.0, 8)
        sink = blocks.vector_sink_c(N)
        tb2.connect(src, echo, sink)
        tb2.connect((echo, 1), blocks.null_sink(gr.sizeof_gr_complex * N))
        self.assertTrue(run_with_timeout(tb2))
        self.assertComplexTuplesAlmostEqual(sink.data(), sinks["echo"].data(), 4)
        # The focuser emits whole apertures and one aperture tag per aperture, M lines apart.
        lines = len(sinks["focuser"].data()) // k
        self.assertEqual(lines % m, 0)
        self.assertGreaterEqual(lines, symbols)
        aps = tag_list(sinks["focuser"], nrsar.tag_keys.aperture)
        self.assertEqual(aps, [(i * m, i) for i in range(lines // m)])
        self.assertEqual(b["probe"].apertures(), lines // m)

    def test_005_tags_survive_every_block(self):
        num, geo, _ = scenario()
        m = int(geo.symbols_per_aperture(num))
        symbols = m + 40
        tb = gr.top_block()
        b, sinks = self.chain(tb, symbols)
        self.assertTrue(run_with_timeout(tb))
        spf = num.symbols_per_slot
        expected = {
            nrsar.tag_keys.symbol: [(i, i) for i in range(0, symbols, spf)],
            nrsar.tag_keys.slot: [(i, i // spf) for i in range(0, symbols, spf)],
            nrsar.tag_keys.frame: [(i, i // (spf * num.slots_per_frame))
                                   for i in range(0, symbols, spf * num.slots_per_frame)],
        }
        # Sync blocks: every transmitter tag once, at its offset, with its value (tf_filter
        # has two inputs carrying the same tags and must not double them).
        for name in ("tx", "echo", "filter", "range_ifft"):
            for key, want in expected.items():
                self.assertEqual(tag_list(sinks[name], key), want, f"{name} {key}")
        # range_ifft adds its range axis once, at item 0.
        axis = tag_list(sinks["range_ifft"], nrsar.tag_keys.range_axis)
        self.assertEqual([off for off, _ in axis], [0])
        # The focuser (a rate-changing block) places its own tags on each aperture's first
        # line: aperture index, azimuth axis, range axis.
        k = b["range_ifft"].num_bins()
        lines = len(sinks["focuser"].data()) // k
        for key in (nrsar.tag_keys.aperture, nrsar.tag_keys.azimuth_axis,
                    nrsar.tag_keys.range_axis):
            offsets = [off for off, _ in tag_list(sinks["focuser"], key)]
            self.assertEqual(offsets, list(range(0, lines, m)), key)


if __name__ == "__main__":
    gr_unittest.run(qa_robustness)
