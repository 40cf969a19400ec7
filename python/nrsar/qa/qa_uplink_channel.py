#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of uplink_channel (nrsar-isac's base-station channel): samples against a float64 numpy
evaluation of y[n] = exp(j 2 pi cfo n) sum_l h[l] x[n - D - l] (+ noise), the noise power,
call-size invariance, tags moved by the delay, and parameter validation."""

import re

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

TAPS = [1, 0, 0, 0.3 + 0.2j, 0, 0, 0, 0, -0.1j]  # nrsar-isac's default taps


def numpy_channel(x, delay, taps, cfo):
    """float64 reference without noise: delay, FIR, CFO phase counted from output 0."""
    xd = np.concatenate([np.zeros(delay), np.asarray(x, np.complex128)])
    y = np.convolve(xd, np.asarray(taps, np.complex128))[:xd.size]
    return y * np.exp(2j * np.pi * cfo * np.arange(xd.size))


class qa_uplink_channel(gr_unittest.TestCase):

    def run_channel(self, x, cfg, limit=0, tags=()):
        tb = gr.top_block()
        src = blocks.vector_source_c(list(x), False, 1, list(tags))
        cp = blocks.copy(gr.sizeof_gr_complex)
        if limit:
            cp.set_max_noutput_items(limit)
        chan = nrsar.uplink_channel(cfg)
        if limit:
            chan.set_max_noutput_items(limit + 2)
        sink = blocks.vector_sink_c()
        tb.connect(src, cp, chan, sink)
        tb.run()
        self.assertEqual(chan.samples(), len(sink.data()))
        return np.asarray(sink.data()), sink.tags()

    def test_001_against_numpy(self):
        rng = np.random.default_rng(1)
        x = (rng.normal(size=20000) + 1j * rng.normal(size=20000)).astype(np.complex64)
        cfo = 9000.0 / 122.88e6 * 50  # a few turns over the test
        cfg = nrsar.uplink_channel_config(delay_samples=1234, taps=TAPS, cfo=cfo)
        y, _ = self.run_channel(x, cfg)
        ref = numpy_channel(x, 1234, TAPS, cfo)
        self.assertEqual(y.size, x.size + 1234)  # every input sample arrives
        self.assertTrue(np.all(y[:1234] == 0))
        err = np.abs(y - ref).max() / np.sqrt(np.mean(np.abs(ref) ** 2))
        self.assertLess(err, 1e-5)  # float rounding of O(1) products

    def test_002_noise_power_and_call_sizes(self):
        sigma = 0.1
        x = np.exp(2j * np.pi * 0.01 * np.arange(50000)).astype(np.complex64)
        cfg = nrsar.uplink_channel_config(delay_samples=77, taps=TAPS, cfo=1e-4,
                                          noise_voltage=sigma, seed=9)
        y, _ = self.run_channel(x, cfg)
        noise = y - numpy_channel(x, 77, TAPS, 1e-4)
        # E|n|^2 = sigma^2; 50077 samples estimate it to 0.45 % (one standard deviation)
        self.assertAlmostEqual(np.mean(np.abs(noise) ** 2) / sigma ** 2, 1.0, delta=0.025)
        cut, _ = self.run_channel(x, cfg, limit=3)
        self.assertTrue(np.array_equal(cut, y))  # a function of the stream, not of the calls

    def test_003_tags_move_by_the_delay(self):
        tag = gr.tag_utils.python_to_tag((5, pmt.intern("burst"), pmt.PMT_T))
        _, tags = self.run_channel(np.ones(100, np.complex64),
                                   nrsar.uplink_channel_config(delay_samples=40), tags=[tag])
        self.assertEqual([(t.offset, pmt.symbol_to_string(t.key)) for t in tags],
                         [(45, "burst")])

    def test_004_bad_parameters(self):
        for kw, name in ((dict(cfo=0.5), "cfo"), (dict(noise_voltage=-1.0), "noise_voltage"),
                         (dict(taps=[]), "taps"), (dict(taps=[complex("nan")]), "taps[0]")):
            with self.assertRaisesRegex(ValueError, re.escape(name)):
                nrsar.uplink_channel(nrsar.uplink_channel_config(**kw))


if __name__ == "__main__":
    gr_unittest.run(qa_uplink_channel)
