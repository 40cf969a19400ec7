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
DMRS-free data, re-acquisition of a second burst, output alignment, tags and parameter validation.

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
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bindings"))
    from gnuradio import nrsar

DMRS = (2, 11)  # the pusch2 preset


def make_grid(num, slots, seed, dmrs=DMRS):
    """QPSK data on every RE; DMRS symbols: the 38.211 DMRS of their slot and symbol
    (scrambling id 0) on even subcarriers, odd ones empty (ofdm_sync's lock check tests the
    sequence)."""
    rng = np.random.default_rng(seed)
    m, n = slots * num.symbols_per_slot, num.num_subcarriers
    grid = ((2 * rng.integers(0, 2, (m, n)) - 1) + 1j * (2 * rng.integers(0, 2, (m, n)) - 1))
    grid /= np.sqrt(2)
    for s in range(m):
        slot, l = divmod(s, num.symbols_per_slot)
        if l in dmrs:
            grid[s, 0::2] = nrsar.dmrs_values(0, slot % num.slots_per_frame, l, (n + 1) // 2)
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

    def check_link(self, snr_db, trials, seed, taps=(1.0,)):
        """Random delays and CFOs (|CFO| < 0.9 Delta f) at one SNR: timing errors [samples],
        CFO errors [Delta f], EVMs [dB]."""
        rng = np.random.default_rng(seed)
        df = self.num.subcarrier_spacing_hz
        te, ce, ev = [], [], []
        for t in range(trials):
            delay = int(rng.integers(0, 20000))
            cfo = rng.uniform(-0.9, 0.9) * df
            sync, y, _, _ = run_link(self.num, self.x, delay, cfo, 10 ** (-snr_db / 20), taps,
                                     seed=seed * 100 + t + 1)
            self.assertTrue(sync.locked(), f"SNR {snr_db} dB trial {t}")
            te.append(sync.timing_samples() - self.true_timing(delay))
            ce.append((sync.cfo_hz() - cfo) / df)
            self.assertGreaterEqual(len(y), self.grid.shape[0])
            ev.append(evm_db(y, self.grid))
        return np.array(te), np.array(ce), np.array(ev)

    def evm_bound_db(self, snr_db, margin_db):
        """Per-RE noise s2 = 10^(-SNR/10) (unitary modem) over unit-power REs, plus the noise
        of a least-squares estimate from K = 24 REs per subcarrier: EVM^2 = s2 (1 + 1/K)."""
        return -snr_db + 10 * np.log10(1 + 1 / 24) + margin_db

    def test_001_timing_cfo_evm_statistics(self):
        # Bounds (sdr20, H = 512, DMRS on 306 of 1024 bins: time-domain SNR of the DMRS symbol
        # = per-RE SNR - 5.2 dB). CFO: std about 1 / (pi sqrt(H SNR_td)) Delta f. Timing: the
        # DMRS refinement's std sqrt((n - 1) v^2 / 2 + v) / (n - 1) F / (4 pi) (n = 306,
        # v = 1 / SNR: 0.03, 0.34, 1.06 samples), 4 sigma plus the rounding.
        cases = (  # SNR dB, max |timing error|, max |CFO error| (Delta f), EVM margin dB
            (20, 1, 0.01, 0.3),
            (10, 2, 0.04, 0.3),
            (5, 5, 0.08, 1.0))
        self.stats = {}
        for snr, t_max, c_max, margin in cases:
            te, ce, ev = self.check_link(snr, 8, snr)
            self.assertLessEqual(np.max(np.abs(te)), t_max, f"SNR {snr}: {te}")
            self.assertLess(np.max(np.abs(ce)), c_max, f"SNR {snr}: {ce}")
            self.assertLess(np.max(ev), self.evm_bound_db(snr, margin), f"SNR {snr}: {ev}")
            print(f"SNR {snr} dB: timing error mean {te.mean():+.1f} std {te.std():.1f} "
                  f"max {np.abs(te).max()} samples; CFO error rms {np.sqrt(np.mean(ce**2)):.4f} "
                  f"max {np.abs(ce).max():.4f} Delta f; EVM mean {ev.mean():.2f} dB")
        # The 1 % of Delta f asked at 20 dB holds with margin in RMS.
        te, ce, _ = self.check_link(20, 8, 99)
        self.assertLess(np.sqrt(np.mean(ce ** 2)), 0.005)

    def test_002_multipath_within_cp(self):
        # Taps over 8 samples (a delay spread D = 7 samples, well inside the 256-sample CP),
        # unit energy: the estimate sits near d0 + D/2, the grid comes back at the SNR.
        taps = np.array([0.8, 0, 0, 0.5j, 0, 0, 0, -0.3])
        taps /= np.linalg.norm(taps)
        te, ce, ev = self.check_link(20, 6, 7, taps)
        self.assertTrue(np.all(te >= -2) and np.all(te <= 7 + 2), te)
        self.assertLess(np.max(np.abs(ce)), 0.01)
        self.assertLess(np.max(ev), self.evm_bound_db(20, 0.3), ev)

    def test_003_no_lock_on_noise_or_data_without_dmrs(self):
        rng = np.random.default_rng(3)
        noise = ((rng.normal(size=1_500_000) + 1j * rng.normal(size=1_500_000)) /
                 np.sqrt(2)).astype(np.complex64)
        data = modulate(self.num, make_grid(self.num, 4, 2, dmrs=()))
        for x in (noise, data):
            sync, y, raw, _ = run_link(self.num, x, 0, 1000.0, 0.01)
            self.assertFalse(sync.locked())
            self.assertEqual(sync.timing_samples(), -1)
            self.assertEqual(len(raw), 0)

    def test_004_alignment_and_tags(self):
        delay, b = 5000, round(0.125 * self.num.cp_samples)
        sync, y, raw, tags = run_link(self.num, self.x, delay, 0.0, 0.0)
        start = self.true_timing(delay) - DMRS[0] * self.L - b
        self.assertEqual(sync.start_samples(), start)
        self.assertEqual(sync.timing_samples(), self.true_timing(delay))
        # Output sample k is input sample start + k: the burst begins b samples in.
        np.testing.assert_allclose(raw[b:b + len(self.x)], self.x, atol=1e-4)
        slot_len = self.L * self.num.symbols_per_slot
        got = {}
        for t in tags:
            got.setdefault(pmt.symbol_to_string(t.key), []).append((t.offset, t.value))
        info = got["sync"][0][1]
        self.assertEqual(got["sync"][0][0], 0)
        self.assertEqual(pmt.to_long(pmt.dict_ref(info, pmt.intern("timing"), pmt.PMT_NIL)),
                         sync.timing_samples())
        self.assertEqual(pmt.to_long(pmt.dict_ref(info, pmt.intern("start"), pmt.PMT_NIL)), start)
        self.assertAlmostEqual(
            pmt.to_double(pmt.dict_ref(info, pmt.intern("cfo_hz"), pmt.PMT_NIL)), sync.cfo_hz())
        slots = len(raw) // slot_len + (1 if len(raw) % slot_len else 0)
        self.assertEqual([(o, pmt.to_uint64(v)) for o, v in got["slot"]],
                         [(k * slot_len, k) for k in range(slots)])
        self.assertEqual([(o, pmt.to_uint64(v)) for o, v in got["symbol"]],
                         [(k * slot_len, 14 * k) for k in range(slots)])
        self.assertEqual([(o, pmt.to_uint64(v)) for o, v in got["frame"]], [(0, 0)])
        # The demodulated grid: window b samples early -> linear phase of a b-sample delay.
        n = np.arange(self.num.num_subcarriers) - self.num.dc_subcarrier()
        ramp = np.exp(-2j * np.pi * n * b / self.num.fft_size)
        np.testing.assert_allclose(y[:28], self.grid * ramp, atol=1e-4)

    def test_005_burst_at_stream_start(self):
        # The slot starts 3 samples before the input (channel_model's offset): zeros fill in.
        b = round(0.125 * self.num.cp_samples)
        sync, y, raw, _ = run_link(self.num, self.x, 0, 0.0, 0.0)
        self.assertEqual(sync.start_samples(), self.offset - b)
        lead = b - self.offset
        np.testing.assert_array_equal(raw[:lead], 0)
        self.assertLess(evm_db(y, self.grid), -60)

    def test_006_cfo_beyond_delta_f_aliases(self):
        # Only the fractional CFO is seen: 1.2 Delta f reads as 1.2 - 2 = -0.8 Delta f, which
        # leaves the grid 2 subcarriers off: no DMRS sequence fits, no lock (all rejected).
        df = self.num.subcarrier_spacing_hz
        sync, _, raw, _ = run_link(self.num, self.x, 1234, 1.2 * df, 0.0)
        self.assertFalse(sync.locked())
        self.assertEqual(len(raw), 0)
        sync, _, _, _ = run_link(self.num, self.x, 1234, 0.95 * df, 0.0)
        self.assertAlmostEqual(sync.cfo_hz() / df, 0.95, delta=1e-4)

    def test_007_second_burst_reacquired(self):
        # The first burst ends: two slots without the DMRS plateau lose the lock (lock_losses),
        # the search finds the second burst, whose slots resume on the first one's grid; the
        # first lock's alignment is not moved before that.
        two = np.concatenate([self.x, np.zeros(30000, np.complex64), self.x])
        sync, y, raw, tags = run_link(self.num, two, 2000, 0.0, 0.0)
        self.assertEqual(sync.timing_samples(), self.true_timing(2000) + len(self.x) + 30000)
        self.assertEqual(sync.lock_losses(), 1)  # the tail after the second is too short
        self.assertEqual(sync.reacquisitions(), 1)
        syncs = [t.offset for t in tags if pmt.symbol_to_string(t.key) == "sync"]
        self.assertEqual(len(syncs), 2)
        b = round(0.125 * self.num.cp_samples)
        np.testing.assert_allclose(raw[b:b + len(self.x)], self.x, atol=1e-4)
        np.testing.assert_allclose(raw[syncs[1] + b:syncs[1] + b + len(self.x)], self.x,
                                   atol=1e-4)

    def test_008_nonfinite_input(self):
        # Straight into the block (channel_model's filters would smear a NaN over 16 samples).
        x = np.concatenate([np.zeros(700, np.complex64), self.x, np.zeros(3000, np.complex64)])
        x[len(x) - 100] = np.nan
        tb = gr.top_block()
        sync = nrsar.ofdm_sync(self.num, nrsar.make_dmrs("pusch2"))
        raw = blocks.vector_sink_c()
        tb.connect(blocks.vector_source_c(x.tolist()), sync, raw)
        tb.run()
        out = np.array(raw.data())
        self.assertEqual(sync.timing_samples(), 700 + DMRS[0] * self.L)
        self.assertEqual(sync.nonfinite_count(), 1)
        self.assertTrue(np.all(np.isfinite(out)))
        nf = [t.offset for t in raw.tags() if pmt.symbol_to_string(t.key) == nrsar.tag_keys.nonfinite]
        self.assertEqual(len(nf), 1)
        self.assertLessEqual(nf[0], len(x) - 100 - sync.start_samples())

    def test_011_reset_reacquires(self):
        # One block in two successive flowgraphs: without reset() it keeps tracking the first
        # lock; after reset() it acquires the second burst at its own timing.
        sync = nrsar.ofdm_sync(self.num, nrsar.make_dmrs("pusch2"))

        def run(delay):
            tb = gr.top_block()
            x = np.concatenate([np.zeros(delay, np.complex64), self.x])
            snk = blocks.vector_sink_c()
            tb.connect(blocks.vector_source_c(x.tolist()), sync, snk)
            tb.run()
            return snk.tags()

        run(1000)
        self.assertEqual(sync.timing_samples(), 1000 + DMRS[0] * self.L)
        # Without reset() the lock check loses the old lock while the new burst's first
        # slot goes by (two slots miss) and re-acquires on its second slot.
        run(4321)
        self.assertEqual(sync.lock_losses(), 1)
        self.assertEqual(sync.timing_samples(),
                         4321 + DMRS[0] * self.L + self.num.symbols_per_slot * self.L)
        sync.reset()
        tags = run(4321)
        self.assertTrue(sync.locked())
        self.assertEqual(sync.timing_samples(), 4321 + DMRS[0] * self.L)
        self.assertEqual([t.offset for t in tags if pmt.symbol_to_string(t.key) == "sync"], [0])

    def test_012_drained_slots_are_checked(self):
        # The search takes the whole stream in one chunk (one source write into a buffer that
        # holds it), so every slot after the lock is output from the acquirer's buffer. G
        # samples lost without a tag in slot 1, before its DMRS: slots 1 and 2 start G early,
        # two misses there lose the lock; the new search goes on in the rest of the buffer,
        # finds slot 2's second DMRS symbol and resumes at slot 3 on the old grid moved by G.
        num, G, D = self.num, 1000, 3000
        Ls, b = self.L * num.symbols_per_slot, round(0.125 * num.cp_samples)
        x = modulate(num, make_grid(num, 6, 3))
        cut = np.concatenate([np.zeros(D, np.complex64), x[:Ls + 100], x[Ls + 100 + G:],
                              np.zeros(20000, np.complex64)])
        tb = gr.top_block()
        src = blocks.vector_source_c(cut.tolist())
        src.set_min_output_buffer(len(cut) * 2)
        sync = nrsar.ofdm_sync(num, nrsar.make_dmrs("pusch2"), 0.1, 0.125)
        snk = blocks.vector_sink_c()
        tb.connect(src, sync, snk)
        tb.run()
        raw = np.array(snk.data())
        self.assertEqual((sync.lock_losses(), sync.reacquisitions(), sync.lost_samples()),
                         (1, 1, G))
        # Lost at the end of slot 2's check window (its first DMRS symbol from cp/2 after
        # d0_hat), the symbol completed with zeros; slot 3 follows.
        lost_at = 2 * Ls + DMRS[0] * self.L + b + num.cp_samples // 2 + num.fft_size
        resumed = -(-lost_at // self.L) * self.L
        got = {}
        for t in snk.tags():
            got.setdefault(pmt.symbol_to_string(t.key), []).append((t.offset, t.value))
        self.assertEqual([o for o, _ in got["gap"]], [lost_at])
        self.assertEqual([(o, pmt.to_uint64(v)) for o, v in got["slot"]],
                         [(k * Ls, k) for k in range(3)] +
                         [(o, 3 + k) for k, o in enumerate(range(resumed, len(raw), Ls))])
        np.testing.assert_allclose(raw[b:b + Ls + 100], x[:Ls + 100], atol=1e-4)
        np.testing.assert_array_equal(raw[lost_at:resumed], 0)
        np.testing.assert_allclose(raw[resumed + b:resumed + b + 3 * Ls], x[3 * Ls:],
                                   atol=1e-4)

    def test_009_getters_and_setters(self):
        sync = nrsar.ofdm_sync(self.num, nrsar.make_dmrs("pusch2"))
        self.assertFalse(sync.locked())
        self.assertEqual((sync.threshold(), sync.backoff(), sync.timing_samples()), (0.1, 0.125, -1))
        sync.set_threshold(0.2)
        self.assertEqual(sync.threshold(), 0.2)
        with self.assertRaises(ValueError) as ctx:
            sync.set_threshold(1.5)
        self.assertIn("threshold = 1.5 must be in (0, 1)", str(ctx.exception))
        sync.reset()

    def test_010_invalid_parameters(self):
        pusch2 = nrsar.make_dmrs("pusch2")
        odd = nrsar.numerology.preset("tiny")
        odd.num_subcarriers, odd.fft_size, odd.cp_samples = 63, 65, 16
        cases = ((lambda: nrsar.ofdm_sync(self.num, nrsar.make_dmrs("none")), "dmrs symbols"),
                 (lambda: nrsar.ofdm_sync(self.num, pusch2, 0.0), "threshold = 0"),
                 (lambda: nrsar.ofdm_sync(self.num, pusch2, 1.0), "threshold = 1"),
                 (lambda: nrsar.ofdm_sync(self.num, pusch2, float("nan")), "threshold = nan"),
                 (lambda: nrsar.ofdm_sync(self.num, pusch2, 0.1, 1.0), "backoff = 1"),
                 (lambda: nrsar.ofdm_sync(self.num, pusch2, 0.1, -0.1), "backoff = -0.1"),
                 (lambda: nrsar.ofdm_sync(odd, pusch2), "fft_size = 65 must be even"))
        for call, fragment in cases:
            with self.assertRaises(ValueError) as ctx:
                call()
            self.assertIn(fragment, str(ctx.exception))


if __name__ == "__main__":
    gr_unittest.run(qa_ofdm_sync)
