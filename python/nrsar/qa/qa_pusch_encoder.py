#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""pusch_encoder and the DMRS of nr_isac_tx, against independent numpy implementations of
TS 38.211 5.2.1 (Gold sequence), 6.4.1.1.1 (PUSCH DMRS), 6.3.1.1 (scrambling) and TS 38.212
5.1 (CRC24A)."""

import numpy as np
import pmt

from gnuradio import blocks, gr, gr_unittest
from gnuradio import nrsar
from gnuradio.nrsar import backhaul


def gold(c_init, n):
    """c(0..n-1) of TS 38.211 5.2.1, bit by bit."""
    nc = 1600
    x1 = np.zeros(n + nc + 31, np.uint8)
    x2 = np.zeros(n + nc + 31, np.uint8)
    x1[0] = 1
    x2[:31] = [(c_init >> i) & 1 for i in range(31)]
    for i in range(n + nc):
        x1[i + 31] = x1[i + 3] ^ x1[i]
        x2[i + 31] = x2[i + 3] ^ x2[i + 2] ^ x2[i + 1] ^ x2[i]
    return x1[nc:nc + n] ^ x2[nc:nc + n]


def dmrs_ref(nid, slot, symbol, count):
    """TS 38.211 6.4.1.1.1.1: r(i) = ((1 - 2c(2i)) + j(1 - 2c(2i+1))) / sqrt(2),
    c_init = (2^17 (14 n_s + l + 1)(2 N_ID + 1) + 2 N_ID) mod 2^31."""
    c_init = (2 ** 17 * (14 * slot + symbol + 1) * (2 * nid + 1) + 2 * nid) % 2 ** 31
    c = gold(c_init, 2 * count).astype(float)
    return ((1 - 2 * c[0::2]) + 1j * (1 - 2 * c[1::2])) / np.sqrt(2)


def crc24a(bits):
    """TS 38.212 5.1 CRC24A by long division, bits in, 24 parity bits out."""
    poly = [int(b) for b in bin(0x1864CFB)[2:]]  # D^24 + ... + 1
    reg = list(bits) + [0] * 24
    for i in range(len(bits)):
        if reg[i]:
            for j in range(25):
                reg[i + j] ^= poly[j]
    return reg[-24:]


def scrambling_c_init(scrambling_id, slot):
    return (((scrambling_id << 15) + slot % 32768) * 0x9E3779B1 + 0x2545F491) % 2 ** 31


def run_encoder(num, mod, dmrs, pdus, nbytes, max_queued=1 << 20, scrambling_id=0):
    enc = nrsar.pusch_encoder(num, mod, dmrs, "", scrambling_id, max_queued)
    head = blocks.head(gr.sizeof_char, nbytes)
    snk = blocks.vector_sink_b()
    tb = gr.top_block()
    tb.connect(enc, head, snk)
    for p in pdus:
        enc.to_basic_block()._post(pmt.intern("pdus"), p)
    tb.run()
    return enc, np.unpackbits(np.array(snk.data(), np.uint8))


class qa_pusch_encoder(gr_unittest.TestCase):

    def test_dmrs_in_grid_matches_38211(self):
        num = nrsar.make_numerology("tiny")
        for preset, nid in (("pusch2", 0), ("pusch4", 1234), ("pusch1", 65535)):
            dmrs = nrsar.make_dmrs(preset, scrambling_id=nid)
            tx = nrsar.nr_isac_tx(num, nrsar.make_modulation("qam16"), nrsar.make_tx_mode("data"),
                                  nrsar.srs_config(), 3, dmrs)
            nsym = 14 * 21  # slot 20 wraps to slot_in_frame 0
            head = blocks.head(gr.sizeof_gr_complex * 64, nsym)
            snk = blocks.vector_sink_c(64)
            tb = gr.top_block()
            tb.connect(tx, head, snk)
            tb.run()
            grid = np.array(snk.data()).reshape(nsym, 64)
            for m in range(nsym):
                slot, l = divmod(m, 14)
                if l in dmrs.symbols:
                    ref = dmrs_ref(nid, slot % 20, l, 32)
                    np.testing.assert_allclose(grid[m, 0::2], ref, atol=1e-6)
                    np.testing.assert_array_equal(grid[m, 1::2], 0)
                else:
                    self.assertTrue(np.all(np.abs(grid[m]) > 0.1))
            np.testing.assert_allclose(nrsar.dmrs_values(nid, 7, 2, 32), dmrs_ref(nid, 7, 2, 32),
                                       atol=1e-6)

    def test_no_dmrs_grid_unchanged(self):
        num = nrsar.make_numerology("tiny")
        out = []
        for extra in ((), (nrsar.make_dmrs("none"),)):
            tx = nrsar.nr_isac_tx(num, nrsar.make_modulation("qam256"), nrsar.make_tx_mode("data"),
                                  nrsar.srs_config(), 9, *extra)
            head = blocks.head(gr.sizeof_gr_complex * 64, 30)
            snk = blocks.vector_sink_c(64)
            tb = gr.top_block()
            tb.connect(tx, head, snk)
            tb.run()
            out.append(np.array(snk.data()))
        np.testing.assert_array_equal(out[0], out[1])

    def test_bits_decode_with_numpy_reference(self):
        # Descramble with a numpy Gold sequence, check header, payload and CRC24A.
        num, mod, dmrs = (nrsar.make_numerology("tiny"), nrsar.make_modulation("qam64"),
                          nrsar.make_dmrs("pusch2"))
        g = 12 * 64 * 6
        rng = np.random.default_rng(0)
        big = bytes(rng.integers(0, 256, 1000, dtype=np.uint8))
        small = b"\x00" * 7
        enc, bits = run_encoder(num, mod, dmrs,
                                [backhaul.make_pdu(big), backhaul.make_pdu(small)],
                                g * 6 // 8, scrambling_id=321)
        self.assertEqual(enc.slot_bits(), g)
        cap = enc.payload_bits_per_slot() // 8
        self.assertEqual(cap, (g - 24) // 8 - 5)
        chunks = [big[i:i + cap] for i in range(0, len(big), cap)] + [small]
        for slot in range(len(bits) // g):
            c = gold(scrambling_c_init(321, slot), g)
            tb = bits[slot * g:(slot + 1) * g] ^ c
            nbits = 8 * (5 + cap) + 24
            self.assertEqual(crc24a(tb[:nbits - 24]), list(tb[nbits - 24:nbits]))
            np.testing.assert_array_equal(tb[nbits:], 0)  # padding
            raw = np.packbits(tb[:nbits - 24]).tobytes()
            length, seq, flags = int.from_bytes(raw[0:2], "big"), int.from_bytes(raw[2:4], "big"), raw[4]
            self.assertEqual(seq, slot)
            if slot < len(chunks):
                self.assertEqual(raw[5:5 + length], chunks[slot])
                self.assertEqual(flags & 1, 0)
                self.assertEqual(bool(flags & 2), slot in (0, len(chunks) - 1))
                self.assertEqual(bool(flags & 4), slot >= len(chunks) - 2)
            else:
                self.assertEqual((length, flags), (0, 1))  # filler
        self.assertEqual(enc.payload_bytes_sent(), len(big) + len(small))
        self.assertEqual(enc.filler_tbs_sent(), enc.tbs_sent() - len(chunks))

    def test_filler_scrambled_and_random(self):
        num, mod, dmrs = (nrsar.make_numerology("tiny"), nrsar.make_modulation("qpsk"),
                          nrsar.make_dmrs("pusch2"))
        g = 12 * 64 * 2
        _, bits = run_encoder(num, mod, dmrs, [], g * 4 // 8)
        slots = bits.reshape(4, g)
        for s in slots:
            self.assertAlmostEqual(s.mean(), 0.5, delta=0.05)
        self.assertAlmostEqual(np.mean(slots[0] != slots[1]), 0.5, delta=0.05)

    def test_bit_stream_is_continuous(self):
        # QPSK pusch1 on 61 subcarriers: G = 13 * 61 * 2 = 1586 bits, not a multiple of 8.
        num = nrsar.make_numerology("tiny")
        num.num_subcarriers = 61
        mod, dmrs = nrsar.make_modulation("qpsk"), nrsar.make_dmrs("pusch1")
        g = 13 * 61 * 2
        enc, bits = run_encoder(num, mod, dmrs, [], -(-3 * g // 8))
        self.assertEqual(enc.slot_bits(), g)
        for slot in range(3):
            tb = bits[slot * g:(slot + 1) * g] ^ gold(scrambling_c_init(0, slot), g)
            raw = np.packbits(tb[:40]).tobytes()
            self.assertEqual(int.from_bytes(raw[2:4], "big"), slot)

    def test_queue_bound_drops_counted(self):
        num, mod, dmrs = (nrsar.make_numerology("tiny"), nrsar.make_modulation("qam256"),
                          nrsar.make_dmrs("pusch2"))
        pdus = [backhaul.make_pdu(bytes(100))] * 5 + [pmt.intern("junk")]
        enc, _ = run_encoder(num, mod, dmrs, pdus, 10, max_queued=250)
        self.assertEqual(enc.pdus_dropped(), 3 + 1)

    def test_getters(self):
        num = nrsar.make_numerology("paper")
        enc = nrsar.pusch_encoder(num, nrsar.make_modulation("qam256"), nrsar.make_dmrs("pusch2"),
                                  backhaul.DEFAULT_ALIST, 0, 1000)
        g = 12 * 3333 * 8
        self.assertEqual(enc.slot_bits(), g)
        self.assertAlmostEqual(enc.code_rate(), 902 / 1800)
        cw = g // 1800
        self.assertEqual(enc.payload_bits_per_slot(), 8 * ((cw * 902 - 24) // 8 - 5))
        self.assertAlmostEqual(enc.throughput_bps(),
                               enc.payload_bits_per_slot() / (14 * num.symbol_s()))

    def test_bad_parameters(self):
        num = nrsar.make_numerology("tiny")
        cases = [
            (dict(max_queued_bytes=0), "max_queued_bytes = 0"),
            (dict(mod=nrsar.make_modulation("psk16")), "mod"),
            (dict(ldpc_alist="/nonexistent.alist"), "ldpc_alist"),
            (dict(scrambling_id=65536), "scrambling_id = 65536"),
        ]
        for kw, text in cases:
            args = dict(num=num, mod=nrsar.make_modulation("qam16"), dmrs=nrsar.make_dmrs("pusch2"))
            args.update(kw)
            with self.assertRaises(ValueError) as ctx:
                nrsar.pusch_encoder(**args)
            self.assertIn(text, str(ctx.exception))
        with self.assertRaises(ValueError) as ctx:  # SRS symbol on a DMRS symbol
            s = nrsar.srs_config()
            s.start_subcarrier, s.num_rb, s.symbol_in_slot = 0, 2, 2
            nrsar.nr_isac_tx(num, nrsar.make_modulation("qpsk"), nrsar.make_tx_mode("data_srs"),
                             s, 0, nrsar.make_dmrs("pusch2"))
        self.assertIn("srs symbol_in_slot = 2", str(ctx.exception))


if __name__ == "__main__":
    gr_unittest.run(qa_pusch_encoder)
