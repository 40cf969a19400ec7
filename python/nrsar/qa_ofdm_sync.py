#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of ofdm_sync (base-station acquisition) in the link
ofdm_mod -> blocks.delay -> channels.channel_model (noise, CFO, multipath) -> ofdm_sync ->
ofdm_demod: timing and CFO errors over random delays and CFOs at several SNRs, EVM of the
recovered grid against a bound derived from the SNR, false-lock behaviour on noise and on
DMRS-free data, output alignment, tags and parameter validation.

References are independent of the block: the transmitted grid (numpy), the true delay
(blocks.delay plus channel_model's own offset, measured with an impulse), the true CFO."""

import numpy as np
import pmt
from gnuradio import blocks, channels, gr, gr_unittest

try:
    from gnuradio import nrsar
except ImportError:
    import os
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "bindings"))
    from gnuradio import nrsar

DMRS = (2, 11)  # the pusch2 preset


def make_grid(num, slots, seed, dmrs=DMRS):
    """QPSK data on every RE; DMRS symbols: QPSK on even subcarriers, odd ones empty."""
    rng = np.random.default_rng(seed)
    m, n = slots * num.symbols_per_slot, num.num_subcarriers
    grid = ((2 * rng.integers(0, 2, (m, n)) - 1) + 1j * (2 * rng.integers(0, 2, (m, n)) - 1))
    grid /= np.sqrt(2)
    for s in range(m):
        if s % num.symbols_per_slot in dmrs:
            grid[s, 1::2] = 0
    return grid


def modulate(num, grid):
    tb = gr.top_block()
    src = blocks.vector_source_c(grid.astype(np.complex64).ravel().tolist(), False,
                                 num.num_subcarriers)
    snk = blocks.vector_sink_c()
    tb.connect(src, nrsar.ofdm_mod(num), snk)
    tb.run()
    return np.array(snk.data(), np.complex64)


def channel_offset():
    """Samples by which channel_model (epsilon 1, single tap) moves a signal: measured with an
    impulse, so the true timing does not depend on the block under test."""
    tb = gr.top_block()
    imp = np.zeros(200, np.complex64)
    imp[100] = 1
    snk = blocks.vector_sink_c()
    tb.connect(blocks.vector_source_c(imp.tolist()),
               channels.channel_model(0.0, 0.0, 1.0, [1.0 + 0j], 0), snk)
    tb.run()
    return int(np.argmax(np.abs(np.array(snk.data())))) - 100


def run_link(num, x, delay, cfo_hz, noise_voltage, taps=(1.0,), seed=0, tail=20000,
             threshold=0.1, backoff=0.125, fft_start=-1):
    """x -> delay -> channel_model -> ofdm_sync -> (stream sink, ofdm_demod -> vector sink)."""
    tb = gr.top_block()
    src = blocks.vector_source_c(np.concatenate([x, np.zeros(tail, np.complex64)]).tolist())
    dly = blocks.delay(gr.sizeof_gr_complex, delay)
    ch = channels.channel_model(noise_voltage, cfo_hz / num.sample_rate_hz(), 1.0,
                                [complex(t) for t in taps], seed)
    sync = nrsar.ofdm_sync(num, nrsar.make_dmrs("pusch2"), threshold, backoff)
    dem = nrsar.ofdm_demod(num, fft_start)
    raw = blocks.vector_sink_c()
    grid = blocks.vector_sink_c(num.num_subcarriers)
    tb.connect(src, dly, ch, sync, dem, grid)
    tb.connect(sync, raw)
    tb.run()
    y = np.array(grid.data()).reshape(-1, num.num_subcarriers)
    return sync, y, np.array(raw.data()), raw.tags()


def evm_db(y, grid):
    """EVM after a one-tap-per-subcarrier channel estimate and a per-symbol common phase
    (what a receiver tracks from its DMRS), both least squares against the known grid."""
    m = grid.shape[0]
    y = y[:m]
    cpe = np.ones(m, complex)
    for _ in range(2):
        h = np.sum(y * np.conj(grid * cpe[:, None]), axis=0) / np.maximum(
            np.sum(np.abs(grid) ** 2, axis=0), 1e-30)
        ref = grid * h[None, :]
        cpe = np.exp(1j * np.angle(np.sum(y * np.conj(ref), axis=1)))
    est = grid * h[None, :] * cpe[:, None]
    used = np.abs(grid) > 0
    return 10 * np.log10(np.sum(np.abs(y - est)[used] ** 2) / np.sum(np.abs(est)[used] ** 2))


class qa_ofdm_sync(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.num = nrsar.make_numerology("sdr20")  # 612 of 1024, CP 256, 30.72 Msps
        cls.L = cls.num.fft_size + cls.num.cp_samples
        cls.grid = make_grid(cls.num, 2, 1)
        cls.x = modulate(cls.num, cls.grid)
        cls.offset = channel_offset()

    def true_timing(self, delay):
        """Input sample of the first DMRS symbol's first sample (first path)."""
        return delay + self.offset + DMRS[0] * self.L


if __name__ == "__main__":
    gr_unittest.run(qa_ofdm_sync)
