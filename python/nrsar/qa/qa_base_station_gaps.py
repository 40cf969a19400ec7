#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The base station's receive path through gaps (radio overflows): pusch_encoder ->
nr_isac_tx -> ofdm_mod (numpy: delay, CFO, noise, samples removed) -> rx_time_stamper (the
radio's rx_time tags, python/nrsar/recording.py) -> ofdm_sync -> ofdm_demod -> pusch_receiver.

References computed here, not by the blocks: the slots a gap cuts are those whose samples
[D - b + k L, D - b + (k + 1) L) (D: the burst's delay, b: ofdm_sync's backoff, L: the slot
length, numerology formulas) meet the removed samples [p, p + G); those TBs are reported lost,
every other TB decodes to the payload queued for it, and ofdm_sync's lost_samples is G."""

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest
from gnuradio import nrsar
from gnuradio.nrsar import backhaul, recording

NSLOTS = 16
DELAY = 3000
CFO_HZ = 4000.0
DMRS = (2, 11)  # the pusch2 preset


class qa_base_station_gaps(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        num = nrsar.make_numerology("sdr20")
        cls.num = num
        cls.cfg = nrsar.make_pusch_config(num, "qpsk", "pusch2", "nr-ldpc", n_id=5)
        per_tb = nrsar.pusch_encoder(cls.cfg).payload_bits_per_slot() // 8
        rng = np.random.default_rng(15)
        cls.chunks = [rng.integers(0, 256, per_tb, dtype=np.uint8).tobytes()
                      for _ in range(NSLOTS)]
        cls.L = num.symbols_per_slot * (num.cp_samples + num.fft_size)
        cls.b = int(round(0.125 * num.cp_samples))  # ofdm_sync's default backoff
        cls.x = cls.received(cls.cfg, cls.chunks, NSLOTS, rng)

    @classmethod
    def received(cls, cfg, chunks, nslots, rng, num=None):
        """The burst of nslots slots carrying chunks as the base station receives it: after
        DELAY zeros, CFO_HZ, 30 dB per RE, half a slot of noise after it."""
        num = cls.num if num is None else num
        grid, _ = backhaul.transmit_grid(cfg, chunks, nslots)
        tb = gr.top_block()
        src = blocks.vector_source_c(grid.ravel().tolist(), False, num.num_subcarriers)
        snk = blocks.vector_sink_c()
        tb.connect(src, nrsar.ofdm_mod(num), snk)
        tb.run()
        burst = np.array(snk.data(), np.complex64)
        x = np.concatenate([np.zeros(DELAY, np.complex64), burst,
                            np.zeros(len(burst) // nslots // 2, np.complex64)])
        n = np.arange(len(x))
        x = x * np.exp(2j * np.pi * CFO_HZ / num.sample_rate_hz() * n)
        sigma = 10.0 ** (-30.0 / 20.0) / np.sqrt(2.0)  # 30 dB per RE (unitary OFDM)
        x = x + sigma * (rng.standard_normal(len(x)) + 1j * rng.standard_normal(len(x)))
        return x.astype(np.complex64)

    def cut_slots(self, p, g):
        """Slots of the burst with a sample in [p, p + g) (input sample indices)."""
        first = (p - (DELAY - self.b)) // self.L
        last = (p + g - 1 - (DELAY - self.b)) // self.L
        return list(range(first, last + 1))

    def run_gap(self, p, g, stamped=True):
        return self.run_gaps([(p, g)], stamped)

    def run_gaps(self, gaps, stamped=True, x=None, cfg=None, fields=("slot", "crc_ok", "lost"),
                 num=None):
        """gaps: [(first lost sample of the burst's stream, samples lost)], in order."""
        x = self.x if x is None else x
        cfg = self.cfg if cfg is None else cfg
        num = self.num if num is None else num
        keep = np.ones(len(x), bool)
        for p, g in gaps:
            keep[p:p + g] = False
        x = x[keep]
        # rx_time_stamper's gaps: (received index of the first sample after, lost)
        stamps, before = [], 0
        for p, g in gaps:
            stamps.append((p - before, g))
            before += g
        tb = gr.top_block()
        src = blocks.vector_source_c(x.tolist())
        sync = nrsar.ofdm_sync(num, nrsar.make_dmrs("pusch2"))
        dem = nrsar.ofdm_demod(num)
        rx = nrsar.pusch_receiver(cfg)
        store = blocks.message_debug()
        if stamped:
            stamper = recording.rx_time_stamper(num.sample_rate_hz(), stamps)
            tb.connect(src, stamper, sync)
        else:
            tb.connect(src, sync)
        tb.connect(sync, dem, rx)
        tb.msg_connect((rx, "pdus"), (store, "store"))
        tb.run()
        if fields is None:  # the PDUs as they came
            return sync, rx, [backhaul.pdu_fields(store.get_message(i), ("slot", "crc_ok", "lost",
                                                                         "transmissions"))
                              for i in range(store.num_messages())]
        pdus = {}
        for i in range(store.num_messages()):
            meta, data = backhaul.pdu_fields(store.get_message(i), fields)
            pdus[int(meta["slot"])] = (bool(meta["crc_ok"]), bool(meta["lost"]), data())
        return sync, rx, pdus

    def check_stamped(self, p, g):
        sync, rx, pdus = self.run_gap(p, g)
        cut = self.cut_slots(p, g)
        self.assertEqual(sync.lost_samples(), g)
        self.assertEqual(sync.rx_time_gaps(), 1)
        self.assertEqual(sync.reacquisitions(), 1)
        self.assertEqual(sync.lock_losses(), 0)
        self.assertEqual(sync.skipped_slots(), len(cut))
        sym = self.num.cp_samples + self.num.fft_size
        cut_symbol = (p - (DELAY - self.b)) // sym
        self.assertEqual(sync.skipped_symbols(), (cut[-1] + 1) * self.num.symbols_per_slot
                         - cut_symbol)
        self.assertEqual(rx.blocks_lost(), len(cut))
        for s in range(NSLOTS):
            crc_ok, lost, data = pdus[s]
            if s in cut:
                self.assertTrue(lost and not crc_ok, s)
            else:
                self.assertTrue(crc_ok and not lost, s)
                self.assertEqual(data, self.chunks[s], s)
        self.assertEqual(rx.blocks_ok(), NSLOTS - len(cut))
        return cut

    def test_001_one_sample(self):
        self.assertEqual(self.check_stamped(DELAY + 3 * self.L + 5000, 1), [3])

    def test_002_hundred_samples(self):
        self.assertEqual(self.check_stamped(DELAY + 3 * self.L + 5000, 100), [3])

    def test_003_ten_thousand_samples_across_a_slot_boundary(self):
        self.assertEqual(self.check_stamped(DELAY + 3 * self.L + 12000, 10000), [3, 4])

    def test_004_more_than_a_slot(self):
        g = self.L + 12000  # ends 1080 samples into slot 4
        self.assertEqual(self.check_stamped(DELAY + 2 * self.L + 7000, g), [2, 3, 4])

    def test_005_gap_on_the_grid_boundaries(self):
        # starts on a slot boundary and ends on one: exactly the two slots inside
        p = DELAY - self.b + 2 * self.L
        self.assertEqual(self.check_stamped(p, 2 * self.L), [2, 3])

    def test_007_gap_in_a_slots_last_symbol(self):
        # the zeros that complete the cut symbol complete the slot too: its gap tag marks it
        p = DELAY - self.b + 4 * self.L - 500
        self.assertEqual(self.check_stamped(p, 100), [3])

    def test_008_gaps_close_together(self):
        # as a radio overflowing every few thousand samples: gaps inside the samples dropped
        # after the last one, in consecutive slots, in the same symbol's zeros
        base = DELAY - self.b + 2 * self.L
        gaps = [(base + 4000, 50), (base + 4100, 300), (base + 5000, 7),
                (base + 2 * self.L - 600, 20), (base + 2 * self.L - 100, 10),
                (base + 2 * self.L + 15000, 4000)]
        sync, rx, pdus = self.run_gaps(gaps)
        cut = sorted(set(k for p, g in gaps for k in self.cut_slots(p, g)))
        self.assertEqual(cut, [2, 3, 4, 5])
        self.assertEqual(sync.lost_samples(), sum(g for _, g in gaps))
        self.assertEqual(sync.rx_time_gaps(), len(gaps))
        self.assertEqual(sync.skipped_slots(), len(cut))
        self.assertEqual(rx.blocks_lost(), len(cut))
        for s in range(NSLOTS):
            crc_ok, lost, data = pdus[s]
            self.assertEqual((crc_ok, lost), (s not in cut, s in cut), s)
            if s not in cut:
                self.assertEqual(data, self.chunks[s], s)

    def test_009_receiver_slot_number_jumps(self):
        # pusch_receiver alone: slot tags 0, 4 (3 lost), 5 + 4097 (a new burst: none lost)
        n, sps = self.num.num_subcarriers, self.num.symbols_per_slot
        grid, _ = backhaul.transmit_grid(self.cfg, self.chunks[:3], 3)
        def tag(item, slot):
            t = gr.tag_t()
            t.offset, t.key, t.value = item, pmt.intern("slot"), pmt.from_uint64(slot)
            return t
        tb = gr.top_block()
        src = blocks.vector_source_c(grid.ravel().tolist(), False, n,
                                     [tag(0, 0), tag(sps, 4), tag(2 * sps, 5 + 4097)])
        rx = nrsar.pusch_receiver(self.cfg)
        store = blocks.message_debug()
        tb.connect(src, rx)
        tb.msg_connect((rx, "pdus"), (store, "store"))
        tb.run()
        lost = [backhaul.pdu_fields(store.get_message(i), ("slot", "lost"))[0]
                for i in range(store.num_messages())]
        self.assertEqual([int(m["slot"]) for m in lost if m["lost"]], [1, 2, 3])
        self.assertEqual(rx.blocks_lost(), 3)

    def test_006_no_rx_time_the_dmrs_check(self):
        # 150 samples lost without a tag: the DMRS arrives 150 samples early; the check's
        # mean offset over three slots passes the backoff (32) in the first slot after the
        # gap (-50) and the second (-100): two misses, the third re-acquires modulo a slot.
        p, g = DELAY + 3 * self.L + 5000, 150
        sync, rx, pdus = self.run_gap(p, g, stamped=False)
        self.assertEqual(sync.rx_time_gaps(), 0)
        self.assertEqual(sync.lock_losses(), 1)
        self.assertEqual(sync.reacquisitions(), 1)
        self.assertLessEqual(abs(int(sync.lost_samples()) - g), 2)
        bad = [s for s in range(NSLOTS) if not pdus.get(s, (False,))[0]]
        # the cut slot 3 fails, slot 4 is decoded with its FFT windows 150 - 32 samples
        # late (QPSK at rate 0.2 may survive that), slot 5 is cut by the lost lock (its
        # check, the second miss, comes after its first DMRS symbol), slot 6 re-acquired
        self.assertIn(3, bad)
        self.assertIn(5, bad)
        self.assertLessEqual(set(bad), {3, 4, 5})
        self.assertEqual(sync.skipped_slots(), 1)
        self.assertTrue(pdus[5][1])  # the slot the lost lock cut: lost
        for s in range(NSLOTS):
            if s not in bad:
                self.assertEqual(pdus[s][2], self.chunks[s], s)

    def untagged_expectation(self, p, g):
        """(first slot not decoded, first slot decoded again) for g samples lost at p
        without a tag, from the documented rules (docs/blocks/ofdm_sync.md): slot k's check
        window is fft_size samples from cp/2 after its first DMRS symbol's start (received
        samples, old grid); the first window after p misses, so does the next one and the
        lock is lost at its end; the search from there (after the gap: g samples later in
        the burst) finds the next DMRS symbol; output resumes at its slot, or at the next
        slot if it is the slot's second DMRS symbol."""
        num, L, b = self.num, self.L, self.b
        sym = num.cp_samples + num.fft_size
        o = DELAY - b  # grid sample 0 in the burst's stream
        win = b + DMRS[0] * sym + num.cp_samples // 2
        k1 = next(k for k in range(NSLOTS) if o + k * L + win >= p)
        search = o + (k1 + 1) * L + win + num.fft_size + g  # in the burst's samples
        starts = sorted((o + k * L + b + l * sym, k, l) for k in range(NSLOTS) for l in DMRS)
        d, k, l = next(t for t in starts if t[0] >= search)
        # the search starts clear of any DMRS symbol (the expectation's premise)
        self.assertGreater(d - search, 600)
        self.assertTrue(all(search >= e + sym + 100 for e, _, _ in starts if e < search))
        return self.cut_slots(p, g)[0], k if l == DMRS[0] else k + 1

    def check_untagged(self, p, g):
        first, resume = self.untagged_expectation(p, g)
        sync, rx, pdus = self.run_gap(p, g, stamped=False)
        self.assertEqual(sync.rx_time_gaps(), 0)
        self.assertEqual(sync.lock_losses(), 1)
        self.assertEqual(sync.reacquisitions(), 1)
        # the re-acquisition's DMRS sequence tells its slot: whole slots counted
        self.assertLessEqual(abs(int(sync.lost_samples()) - g), 1)
        # one PDU per slot, in order; the slots from the cut one to the resumed one are
        # not decoded (cut, numbered on the old grid, or cut by the lost lock), every
        # other slot decodes its own payload
        self.assertEqual(sorted(pdus), list(range(NSLOTS)))
        for s in range(NSLOTS):
            crc_ok, lost, data = pdus[s]
            self.assertEqual(crc_ok, not first <= s < resume, s)
            if crc_ok:
                self.assertEqual(data, self.chunks[s], s)
        self.assertEqual(rx.blocks_ok(), NSLOTS - (resume - first))
        return first, resume

    def test_010_untagged_gaps_longer_than_half_a_slot(self):
        # 0.66, 1.5 and 3.7 slots lost in slot 3 (5000 samples in, after its check window)
        for frac, expect in ((0.66, (3, 6)), (1.5, (3, 7)), (3.7, (3, 9))):
            with self.subTest(slots=frac):
                g = int(round(frac * self.L))
                self.assertEqual(self.check_untagged(DELAY - self.b + 3 * self.L + 5000, g),
                                 expect)

    def test_011_untagged_gap_of_several_slots(self):
        g = int(round(9.3 * self.L))
        self.assertEqual(self.check_untagged(DELAY - self.b + self.L + 5000, g), (1, 13))

    def test_012_lost_tbs_with_repetitions(self):
        # repetitions 2: TB t in slots 2t (rv 0) and 2t + 1 (rv 2). Documented
        # (docs/blocks/pusch_receiver.md): a TB is reported once, at the slot where it decoded
        # or at its last repetition; lost when a gap cut one of its transmissions and the
        # others did not decode it. Gaps: TB 1's second repetition (it decoded from the
        # first: ok, not reported again), both of TB 3's (lost, not decoded), TB 5's first
        # (its second, rv 2 alone, is decoded and not combined with the cut one:
        # transmissions 1; rv 2 alone misses most systematic bits at this rate: lost).
        cfg = nrsar.make_pusch_config(self.num, "qpsk", "pusch2", "nr-ldpc", n_id=5,
                                      repetitions=2)
        ntb = NSLOTS // 2
        per_tb = nrsar.pusch_encoder(cfg).payload_bits_per_slot() // 8
        rng = np.random.default_rng(16)
        chunks = [rng.integers(0, 256, per_tb, dtype=np.uint8).tobytes() for _ in range(ntb)]
        x = self.received(cfg, chunks, NSLOTS, rng)
        o = DELAY - self.b
        gaps = [(o + 3 * self.L + 5000, 100), (o + 6 * self.L + 5000, self.L),
                (o + 10 * self.L + 5000, 100)]
        self.assertEqual([self.cut_slots(p, g) for p, g in gaps], [[3], [6, 7], [10]])
        sync, rx, msgs = self.run_gaps(gaps, x=x, cfg=cfg, fields=None)
        self.assertEqual(sync.skipped_slots(), 4)
        # one PDU per TB, in order, slot = the TB's first slot
        self.assertEqual([int(m["slot"]) for m, _ in msgs], [2 * t for t in range(ntb)])
        for t, (m, data) in enumerate(msgs):
            lost = t in (3, 5)
            self.assertEqual((bool(m["lost"]), bool(m["crc_ok"])), (lost, not lost), t)
            if not lost:
                self.assertEqual(data(), chunks[t], t)
        # TB 1 decoded at its first slot; TB 3 never decoded; TB 5 from its second alone
        self.assertEqual([int(m["transmissions"]) for m, _ in msgs],
                         [1, 1, 1, 0, 1, 1, 1, 1])
        self.assertEqual((rx.blocks_lost(), rx.blocks_failed(), rx.blocks_ok()), (2, 2, ntb - 2))
    def test_013_first_lock_numbers_its_slot_by_the_dmrs(self):
        # A base station that starts inside the burst: the first lock's slot number is the
        # one its DMRS sequence carries. Slot 0 silent: the lock is in slot 1 (its first DMRS
        # symbol), numbered 1. The stream starting 5 symbols into slot 2: the lock is on slot
        # 2's second DMRS symbol, whose slot began before the stream: output starts at slot 3.
        sym = self.num.cp_samples + self.num.fft_size
        o = DELAY - self.b
        silent = self.x.copy()
        silent[:o + self.L] = 0
        for x, first in ((silent, 1), (self.x[o + 2 * self.L + 5 * sym:], 3)):
            with self.subTest(first=first):
                sync, rx, pdus = self.run_gaps([], stamped=False, x=x)
                self.assertEqual((sync.lock_losses(), sync.reacquisitions()), (0, 0))
                self.assertEqual(sorted(pdus), list(range(first, NSLOTS)))
                for s in range(first, NSLOTS):
                    crc_ok, lost, data = pdus[s]
                    self.assertTrue(crc_ok and not lost, s)
                    self.assertEqual(data, self.chunks[s], s)

    def test_014_tiny_noise_before_the_burst(self):
        # tiny (F = 64, H = 32): noise and data cross the default threshold 0.1 with
        # probability exp(-0.1 H) = 4% per position, so the 3000 noise samples before the
        # burst hold many crossings. Each fits no DMRS sequence and is rejected (it used to
        # lock, and its noise CFO stayed through every re-acquisition): the lock is the first
        # DMRS symbol of slot 0, exactly, and every TB decodes (256-QAM, as
        # bench.base_station_realtime --preset tiny).
        num = nrsar.make_numerology("tiny")
        cfg = nrsar.make_pusch_config(num, "qam256", "pusch2", "nr-ldpc")
        per_tb = nrsar.pusch_encoder(cfg).payload_bits_per_slot() // 8
        rng = np.random.default_rng(14)
        chunks = [rng.integers(0, 256, per_tb, dtype=np.uint8).tobytes() for _ in range(4)]
        x = self.received(cfg, chunks, 4, rng, num)
        sync, rx, pdus = self.run_gaps([], stamped=False, x=x, cfg=cfg, num=num)
        self.assertEqual(sync.timing_samples(),
                         DELAY + DMRS[0] * (num.cp_samples + num.fft_size))
        self.assertAlmostEqual(sync.cfo_hz(), CFO_HZ, delta=0.01 * num.subcarrier_spacing_hz)
        self.assertEqual(sync.lock_losses(), 0)
        self.assertEqual(pdus, {s: (True, False, chunks[s]) for s in range(4)})


if __name__ == "__main__":
    gr_unittest.run(qa_base_station_gaps)
