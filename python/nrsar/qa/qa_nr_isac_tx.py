#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nr_isac_tx against numpy float64 references: the TS 38.211 5.1 formulas of SPEC 2, a
bit-by-bit Gold sequence (38.211 5.2.1), the Zadoff-Chu SRS formula (38.211 5.2.2)."""

import numpy as np
import pmt

from gnuradio import blocks, gr, gr_unittest
from gnuradio import nrsar


# ---------------------------------------------------------------- independent references

def gold_bits(c_init, n):
    """c(0..n-1) of 38.211 5.2.1, one register value at a time."""
    nc = 1600
    x1 = [0] * (n + nc + 31)
    x2 = [0] * (n + nc + 31)
    x1[0] = 1
    for i in range(31):
        x2[i] = (c_init >> i) & 1
    for k in range(n + nc):
        x1[k + 31] = (x1[k + 3] + x1[k]) % 2
        x2[k + 31] = (x2[k + 3] + x2[k + 2] + x2[k + 1] + x2[k]) % 2
    return np.array([(x1[k + nc] + x2[k + nc]) % 2 for k in range(n)], dtype=np.int64)


BITS = {"qpsk": 2, "qam16": 4, "qam64": 6, "qam256": 8, "psk8": 3, "psk16": 4}


def spec_map(bits, name):
    """SPEC section 2 formulas (QAM) / Gray M-PSK, float64; bits: flat 0/1 array."""
    k = BITS[name]
    b = np.asarray(bits[: len(bits) // k * k], dtype=np.float64).reshape(-1, k)
    s = 1.0 - 2.0 * b
    if name == "qpsk":
        return (s[:, 0] + 1j * s[:, 1]) / np.sqrt(2)
    if name == "qam16":
        return (s[:, 0] * (2 - s[:, 2]) + 1j * s[:, 1] * (2 - s[:, 3])) / np.sqrt(10)
    if name == "qam64":
        return (s[:, 0] * (4 - s[:, 2] * (2 - s[:, 4]))
                + 1j * s[:, 1] * (4 - s[:, 3] * (2 - s[:, 5]))) / np.sqrt(42)
    if name == "qam256":
        return (s[:, 0] * (8 - s[:, 2] * (4 - s[:, 4] * (2 - s[:, 6])))
                + 1j * s[:, 1] * (8 - s[:, 3] * (4 - s[:, 5] * (2 - s[:, 7])))) / np.sqrt(170)
    m = 1 << k
    index = b.astype(np.int64) @ (1 << np.arange(k - 1, -1, -1))
    gray_to_point = np.zeros(m, dtype=np.int64)
    for point in range(m):
        gray_to_point[point ^ (point >> 1)] = point
    return np.exp(2j * np.pi * gray_to_point[index] / m)


def zc_pilot(length, u=0, v=0):
    """38.211 5.2.2.1 for length >= 36: N_ZC the largest prime below length."""
    nzc = next(p for p in range(length - 1, 1, -1) if all(p % d for d in range(2, int(p ** 0.5) + 1)))
    qbar = nzc * (u + 1) / 31.0
    q = np.floor(qbar + 0.5) + v * (-1) ** np.floor(2 * qbar)
    mm = np.arange(length) % nzc
    return np.exp(-1j * np.pi * q * mm * (mm + 1) / nzc)


def unpack(data):
    return np.unpackbits(np.asarray(data, dtype=np.uint8)).astype(np.int64)


def srs_positions(srs):
    return np.arange(srs.start_subcarrier + srs.comb_offset,
                     srs.start_subcarrier + 12 * srs.num_rb, srs.comb)


def is_srs_symbol(m, num, srs):
    return m % num.symbols_per_slot == srs.symbol_in_slot and \
        (m // num.symbols_per_slot) % srs.period_slots == 0


class qa_nr_isac_tx(gr_unittest.TestCase):

    def setUp(self):
        self.tb = gr.top_block()

    def tearDown(self):
        self.tb = None

    # ------------------------------------------------------------ helpers
    def run_prbs(self, num, mod, mode, srs, seed, nsym):
        blk = nrsar.nr_isac_tx(num, nrsar.make_modulation(mod), mode, srs, seed)
        head = blocks.head(gr.sizeof_gr_complex * num.num_subcarriers, nsym)
        sink = blocks.vector_sink_c(num.num_subcarriers)
        self.tb.connect(blk, head, sink)
        self.tb.run()
        out = np.array(sink.data()).reshape(-1, num.num_subcarriers)
        return blk, out, sink

    def run_stream(self, num, mod, payload, mode=nrsar.tx_mode.DATA, srs=None):
        blk = nrsar.nr_isac_tx(num, nrsar.make_modulation(mod), mode,
                               srs or nrsar.srs_config(), 1)
        src = blocks.vector_source_b(list(payload))
        sink = blocks.vector_sink_c(num.num_subcarriers)
        self.tb.connect(src, blk, sink)
        self.tb.run()
        return blk, np.array(sink.data()).reshape(-1, num.num_subcarriers)

    # ------------------------------------------------------------ mapping
    def test_stream_payload_maps_by_spec_formula(self):
        # 61 subcarriers: 61 k bits per symbol is not a multiple of 8 for k = 2, 6, 3
        num = nrsar.make_numerology("tiny", num_subcarriers=61)
        rng = np.random.default_rng(5)
        payload = rng.integers(0, 256, 700, dtype=np.uint8)
        for name, k in BITS.items():
            with self.subTest(mod=name):
                self.tb = gr.top_block()
                blk, out = self.run_stream(num, name, payload)
                nsym = (8 * len(payload)) // (61 * k)
                self.assertEqual(out.shape[0], nsym)
                ref = spec_map(unpack(payload)[: nsym * 61 * k], name).reshape(nsym, 61)
                np.testing.assert_allclose(out, ref, atol=1e-6)
                # bytes taken: just enough for the symbols made
                self.assertEqual(blk.payload_bytes_sent(), -(-nsym * 61 * k // 8))
                self.assertEqual(blk.prbs_symbols(), 0)

    def test_prbs_is_gold_sequence_of_seed(self):
        num = nrsar.make_numerology("tiny", num_subcarriers=61)
        seed = 0x1234567
        for name in ("qam64", "qam256", "psk8"):
            with self.subTest(mod=name):
                self.tb = gr.top_block()
                nsym = 9
                blk, out, _ = self.run_prbs(num, name, nrsar.tx_mode.DATA, nrsar.srs_config(),
                                            seed, nsym)
                k = BITS[name]
                ref = spec_map(gold_bits(seed, nsym * 61 * k), name).reshape(nsym, 61)
                np.testing.assert_allclose(out, ref, atol=1e-6)
                self.assertEqual(blk.prbs_symbols(), blk.nitems_written(0))
                self.assertEqual(blk.payload_bytes_sent(), 0)

    def test_unit_average_power(self):
        num = nrsar.make_numerology("small")
        for name in BITS:
            with self.subTest(mod=name):
                self.tb = gr.top_block()
                _, out, _ = self.run_prbs(num, name, nrsar.tx_mode.DATA, nrsar.srs_config(), 3, 40)
                # 20480 REs of pseudo-random data: the mean power is 1 within 2 %
                self.assertAlmostEqual(np.mean(np.abs(out.astype(np.complex128)) ** 2), 1.0,
                                       delta=0.02)

    # ------------------------------------------------------------ SRS
    def small_srs(self):
        return nrsar.make_srs(start_subcarrier=100, num_rb=12, comb=4, comb_offset=1,
                              period_slots=2, symbol_in_slot=13)

    def test_srs_mode_positions_periodicity_zeros(self):
        num = nrsar.make_numerology("small")
        srs = self.small_srs()
        nsym = 14 * 7
        _, out, _ = self.run_prbs(num, "qam256", nrsar.tx_mode.SRS, srs, 0, nsym)
        pos = srs_positions(srs)
        self.assertEqual(len(pos), 36)
        pilot = zc_pilot(len(pos))
        n_srs = 0
        for m in range(nsym):
            if is_srs_symbol(m, num, srs):
                n_srs += 1
                np.testing.assert_allclose(out[m, pos], pilot, atol=2e-6)
                rest = np.delete(out[m], pos)
                self.assertTrue(np.all(rest == 0), f"symbol {m}")
            else:
                self.assertTrue(np.all(out[m] == 0), f"symbol {m}")
        self.assertEqual(n_srs, 4)  # slots 0, 2, 4, 6
        np.testing.assert_allclose(np.abs(pilot), 1.0)

    def test_data_srs_pilots_and_data_elsewhere(self):
        num = nrsar.make_numerology("small")
        srs = self.small_srs()
        seed = 99
        nsym = 14 * 3
        _, out, _ = self.run_prbs(num, "qam16", nrsar.tx_mode.DATA_SRS, srs, seed, nsym)
        pos = srs_positions(srs)
        mask = np.zeros((nsym, 512), dtype=bool)  # True where data
        for m in range(nsym):
            mask[m] = True
            if is_srs_symbol(m, num, srs):
                mask[m, pos] = False
        ndata = int(mask.sum())
        data = spec_map(gold_bits(seed, 4 * ndata), "qam16")
        np.testing.assert_allclose(out[mask], data, atol=1e-6)
        for m in range(nsym):
            if is_srs_symbol(m, num, srs):
                np.testing.assert_allclose(out[m, pos], zc_pilot(len(pos)), atol=2e-6)
        self.assertEqual(int((~mask).sum()), 2 * 36)  # SRS in slots 0 and 2

    # ------------------------------------------------------------ tags
    def test_tags_at_slot_and_frame_starts(self):
        num = nrsar.make_numerology("tiny")  # 14 symbols/slot, 20 slots/frame
        nsym = 14 * 20 * 2 + 30
        _, _, sink = self.run_prbs(num, "qpsk", nrsar.tx_mode.DATA, nrsar.srs_config(), 0, nsym)
        got = {}
        for t in sink.tags():
            got.setdefault(pmt.symbol_to_string(t.key), {})[t.offset] = pmt.to_uint64(t.value)
        slot_starts = list(range(0, nsym, 14))
        sym = got[nrsar.tag_keys.symbol]
        slot = got[nrsar.tag_keys.slot]
        frame = got[nrsar.tag_keys.frame]
        self.assertEqual(sym, {m: m for m in slot_starts})
        self.assertEqual(slot, {m: m // 14 for m in slot_starts})
        self.assertEqual(frame, {m: m // 280 for m in range(0, nsym, 280)})

    # ------------------------------------------------------------ start_symbol
    def grid_from(self, start, nsym, mode, srs, dmrs, pdu=None):
        """nsym symbols (and their tags, offset: value) of nr_isac_tx(start_symbol=start)."""
        num = nrsar.make_numerology("tiny", num_subcarriers=61)  # 61 k bits: not whole bytes
        tb = gr.top_block()
        blk = nrsar.nr_isac_tx(num, nrsar.modulation.QAM64, mode, srs, 0x2b1d, dmrs, start)
        if pdu is not None:
            blk.to_basic_block()._post(pmt.intern("pdus"),
                                       pmt.cons(pmt.PMT_NIL, pmt.init_u8vector(len(pdu), pdu)))
        head = blocks.head(gr.sizeof_gr_complex * 61, nsym)
        sink = blocks.vector_sink_c(61)
        tb.connect(blk, head, sink)
        tb.run()
        tags = sorted((t.offset, pmt.symbol_to_string(t.key), pmt.to_uint64(t.value))
                      for t in sink.tags())
        return blk, np.array(sink.data(), np.complex64).reshape(-1, 61), tags

    def test_start_symbol_is_the_tail_of_the_stream_from_0(self):
        # Inside a slot, at a slot and SRS-period boundary, in the third frame (DMRS of
        # other slots of the frame); 61 x 6 bits per symbol: starts off the byte grid.
        srs = nrsar.make_srs(start_subcarrier=5, num_rb=3, comb=4, comb_offset=2,
                             period_slots=3, symbol_in_slot=13)
        total = 2 * 280 + 60
        for mode in (nrsar.tx_mode.DATA, nrsar.tx_mode.DATA_SRS):
            for dmrs in ("none", "pusch2"):
                _, ref, ref_tags = self.grid_from(0, total, mode, srs, nrsar.make_dmrs(dmrs))
                for start in (0, 5, 42, 575):
                    with self.subTest(mode=mode, dmrs=dmrs, start=start):
                        _, out, tags = self.grid_from(start, total - start, mode, srs,
                                                      nrsar.make_dmrs(dmrs))
                        np.testing.assert_array_equal(out.view(np.uint64),
                                                      ref[start:].view(np.uint64))
                        self.assertEqual(tags, [(o - start, k, v) for o, k, v in ref_tags
                                                if o >= start])

    def test_start_symbol_far_is_a_jump_of_the_near_one(self):
        # 10^6 symbols (61 M values) from 0 is too long for a test: a far start must equal
        # the tail of a start 40 symbols before it, and differ from a start at 0.
        srs = nrsar.srs_config()
        far = 10 ** 6 + 3
        _, near, _ = self.grid_from(far - 40, 60, nrsar.tx_mode.DATA, srs, nrsar.dmrs_config())
        _, out, tags = self.grid_from(far, 20, nrsar.tx_mode.DATA, srs, nrsar.dmrs_config())
        np.testing.assert_array_equal(out.view(np.uint64), near[40:].view(np.uint64))
        first = -far % 14  # the first slot start at or after `far`
        self.assertEqual(tags[:2], [(first, nrsar.tag_keys.slot, (far + first) // 14),
                                    (first, nrsar.tag_keys.symbol, far + first)])

    def test_start_symbol_drops_pdus(self):
        blk, out, _ = self.grid_from(5, 10, nrsar.tx_mode.DATA, nrsar.srs_config(),
                                     nrsar.dmrs_config(), pdu=[1, 2, 3])
        _, ref, _ = self.grid_from(0, 15, nrsar.tx_mode.DATA, nrsar.srs_config(),
                                   nrsar.dmrs_config())
        self.assertEqual(blk.pdus_dropped(), 1)
        np.testing.assert_array_equal(out.view(np.uint64), ref[5:].view(np.uint64))

    def test_start_symbol_with_a_stream_is_the_tail(self):
        # Input 0 from the first data bit of start_symbol's slot (what pusch_encoder with
        # first_slot gives): the grid is the tail of the one from symbol 0 fed the whole
        # stream. QAM64 on 61 subcarriers, DMRS {2, 11}: 366 bits per data symbol, so the
        # symbols skipped inside the start slot end off the byte grid.
        num = nrsar.make_numerology("tiny", num_subcarriers=61)
        per_slot = 12 * 61 * 6
        total = 4 * 14
        bits = np.random.default_rng(5).integers(0, 2, total * 61 * 6, np.uint8)

        def grid(start, stream_bits):
            tb = gr.top_block()
            blk = nrsar.nr_isac_tx(num, nrsar.modulation.QAM64, nrsar.tx_mode.DATA,
                                   nrsar.srs_config(), 0, nrsar.make_dmrs("pusch2"), start)
            sink = blocks.vector_sink_c(61)
            tb.connect(blocks.vector_source_b(np.packbits(stream_bits).tolist()), blk,
                       blocks.head(gr.sizeof_gr_complex * 61, total - start), sink)
            tb.run()
            return np.array(sink.data(), np.complex64).reshape(-1, 61)

        ref = grid(0, bits)
        for start in (1, 3, 14, 17, 40):
            with self.subTest(start=start):
                out = grid(start, bits[start // 14 * per_slot:])
                np.testing.assert_array_equal(out.view(np.uint64), ref[start:].view(np.uint64))

    # ------------------------------------------------------------ payload round trips
    def demap_bytes(self, symbols, name):
        cons = nrsar.constellation(nrsar.make_modulation(name))
        k = BITS[name]
        idx = np.array(cons.demap(list(symbols)), dtype=np.int64)
        bits = ((idx[:, None] >> np.arange(k - 1, -1, -1)) & 1).ravel()
        return np.packbits(bits[: len(bits) // 8 * 8].astype(np.uint8))

    def test_stream_round_trip_through_demapper(self):
        num = nrsar.make_numerology("tiny")
        rng = np.random.default_rng(8)
        payload = rng.integers(0, 256, 1000, dtype=np.uint8)
        for name in ("qam64", "psk16"):
            with self.subTest(mod=name):
                self.tb = gr.top_block()
                _, out = self.run_stream(num, name, payload)
                got = self.demap_bytes(out.ravel(), name)
                n = len(got)
                self.assertGreater(n, 900)
                np.testing.assert_array_equal(got, payload[:n])

    def test_stream_round_trip_data_srs_skips_pilots(self):
        num = nrsar.make_numerology("small")
        srs = self.small_srs()
        srs.period_slots = 1
        srs.symbol_in_slot = 2
        payload = np.random.default_rng(9).integers(0, 256, 8000, dtype=np.uint8)
        _, out = self.run_stream(num, "qam256", payload, nrsar.tx_mode.DATA_SRS, srs)
        pos = srs_positions(srs)
        data = [np.delete(out[m], pos) if is_srs_symbol(m, num, srs) else out[m]
                for m in range(out.shape[0])]
        got = self.demap_bytes(np.concatenate(data), "qam256")
        self.assertEqual(len(got), sum(len(d) for d in data))
        np.testing.assert_array_equal(got, payload[: len(got)])

    def test_pdu_round_trip_then_prbs(self):
        num = nrsar.make_numerology("tiny")
        seed = 4242
        blk = nrsar.nr_isac_tx(num, nrsar.modulation.QAM16, nrsar.tx_mode.DATA,
                               nrsar.srs_config(), seed)
        rng = np.random.default_rng(10)
        pdus = [rng.integers(0, 256, n, dtype=np.uint8) for n in (50, 1, 77)]
        for p in pdus:
            blk.to_basic_block()._post(pmt.intern("pdus"),
                                       pmt.cons(pmt.PMT_NIL, pmt.init_u8vector(len(p), list(p))))
        nsym = 12
        head = blocks.head(gr.sizeof_gr_complex * 64, nsym)
        sink = blocks.vector_sink_c(64)
        self.tb.connect(blk, head, sink)
        self.tb.run()
        out = np.array(sink.data())
        payload = np.concatenate(pdus)  # 128 bytes = 256 16-QAM symbols = 4 symbols
        got = self.demap_bytes(out, "qam16")
        np.testing.assert_array_equal(got[: len(payload)], payload)
        # after the payload: the Gold sequence from its start
        ref = spec_map(gold_bits(seed, 4 * (out.size - 256)), "qam16")
        np.testing.assert_allclose(out[256:], ref, atol=1e-6)
        self.assertEqual(blk.payload_bytes_sent(), len(payload))
        # the source runs ahead of head(): every symbol after the 4 payload ones drew PRBS bits
        self.assertEqual(blk.prbs_symbols(), blk.nitems_written(0) - 4)
        self.assertEqual(blk.pdus_dropped(), 0)

    def test_pdu_queue_bound_drops_newest(self):
        num = nrsar.make_numerology("tiny")
        blk = nrsar.nr_isac_tx(num, nrsar.modulation.QPSK, nrsar.tx_mode.DATA,
                               nrsar.srs_config(), 0)
        # 70 PDUs of 16 bytes (one QPSK symbol of 64 REs each) before the graph runs
        for i in range(70):
            blk.to_basic_block()._post(pmt.intern("pdus"),
                                       pmt.cons(pmt.PMT_NIL, pmt.init_u8vector(16, [i] * 16)))
        blk.to_basic_block()._post(pmt.intern("pdus"), pmt.intern("not a pdu"))
        head = blocks.head(gr.sizeof_gr_complex * 64, 80)
        sink = blocks.vector_sink_c(64)
        self.tb.connect(blk, head, sink)
        self.tb.run()
        self.assertEqual(blk.pdus_dropped(), 70 - nrsar.nr_isac_tx.max_queued_pdus + 1)
        got = self.demap_bytes(np.array(sink.data()), "qpsk")
        np.testing.assert_array_equal(got[: 64 * 16], np.repeat(np.arange(64), 16))
        self.assertEqual(blk.payload_bytes_sent(), 64 * 16)

    # ------------------------------------------------------------ invalid parameters
    def make(self, num=None, mod=nrsar.modulation.QAM256, mode=nrsar.tx_mode.DATA, srs=None,
             seed=0):
        return nrsar.nr_isac_tx(num or nrsar.make_numerology("small"), mod, mode,
                                srs or self.small_srs(), seed)

    def test_invalid_numerology(self):
        num = nrsar.numerology.preset("small")
        num.num_subcarriers = 0
        with self.assertRaisesRegex(ValueError, "num_subcarriers = 0 must be at least 1"):
            self.make(num=num)

    def test_invalid_seed(self):
        with self.assertRaisesRegex(ValueError, r"seed = 2147483648 must be in \[0, 2147483647\]"):
            self.make(seed=2 ** 31)
        self.make(seed=2 ** 31 - 1)  # the largest c_init is fine

    def test_invalid_start_symbol(self):
        num = nrsar.make_numerology("small")
        with self.assertRaisesRegex(ValueError, r"start_symbol = 1099511627777 must be in"):
            nrsar.nr_isac_tx(num, start_symbol=2 ** 40 + 1)
        nrsar.nr_isac_tx(num, start_symbol=2 ** 40)

    def test_invalid_srs_band_outside_grid(self):
        srs = nrsar.make_srs()  # 1667 + 288 > 512
        with self.assertRaisesRegex(ValueError, r"srs band \[1667, 1955\) does not fit the 512"):
            self.make(mode=nrsar.tx_mode.SRS, srs=srs)
        self.make(mode=nrsar.tx_mode.DATA, srs=srs)  # DATA does not use the SRS layout

    def test_invalid_srs_comb_offset(self):
        srs = self.small_srs()
        srs.comb_offset = 4
        with self.assertRaisesRegex(ValueError, "srs comb_offset = 4 must be below comb = 4"):
            self.make(mode=nrsar.tx_mode.DATA_SRS, srs=srs)

    def test_invalid_srs_comb_offset_outside_band(self):
        srs = self.small_srs()
        srs.num_rb = 1
        srs.comb = 16
        srs.comb_offset = 12
        with self.assertRaisesRegex(ValueError,
                                    "srs comb_offset = 12 must be below the band width num_rb"):
            self.make(mode=nrsar.tx_mode.SRS, srs=srs)

    def test_invalid_srs_symbol_in_slot(self):
        srs = self.small_srs()
        srs.symbol_in_slot = 14
        with self.assertRaisesRegex(ValueError,
                                    "srs symbol_in_slot = 14 must be below symbols_per_slot = 14"):
            self.make(mode=nrsar.tx_mode.SRS, srs=srs)

    def test_invalid_srs_period(self):
        srs = self.small_srs()
        srs.period_slots = 0
        with self.assertRaisesRegex(ValueError, "srs period_slots = 0 must be at least 1"):
            self.make(mode=nrsar.tx_mode.SRS, srs=srs)

    def test_invalid_srs_comb(self):
        srs = self.small_srs()
        srs.comb = 0
        with self.assertRaisesRegex(ValueError, "srs comb = 0 must be at least 1"):
            self.make(mode=nrsar.tx_mode.SRS, srs=srs)

    def test_invalid_srs_num_rb(self):
        srs = self.small_srs()
        srs.num_rb = 0
        with self.assertRaisesRegex(ValueError, "srs num_rb = 0 must be at least 1"):
            self.make(mode=nrsar.tx_mode.SRS, srs=srs)


if __name__ == '__main__':
    gr_unittest.run(qa_nr_isac_tx)
