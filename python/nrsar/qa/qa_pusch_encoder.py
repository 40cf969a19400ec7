#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""pusch_encoder and the DMRS of nr_isac_tx, against independent numpy implementations of
TS 38.211 5.2.1 (Gold sequence), 6.4.1.1.1 (PUSCH DMRS), 6.3.1.1 (scrambling), TS 38.212
5.1 (CRC24A), TS 38.214 5.1.3.2 (TBS), TS 38.321 / 38.322 (MAC and RLC UM headers), and the
UL-SCH built from the step functions of docs/nr_coding.md."""

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


# TS 38.214 Table 5.1.3.2-1: the TBS for N_info <= 3824
TBS_TABLE = [24, 32, 40, 48, 56, 64, 72, 80, 88, 96, 104, 112, 120, 128, 136, 144, 152, 160, 168,
             176, 184, 192, 208, 224, 240, 256, 272, 288, 304, 320, 336, 352, 368, 384, 408, 432,
             456, 480, 504, 528, 552, 576, 608, 640, 672, 704, 736, 768, 808, 848, 888, 928, 984,
             1032, 1064, 1128, 1160, 1192, 1224, 1256, 1288, 1320, 1352, 1416, 1480, 1544, 1608,
             1672, 1736, 1800, 1864, 1928, 2024, 2088, 2152, 2216, 2280, 2408, 2472, 2536, 2600,
             2664, 2728, 2792, 2856, 2976, 3104, 3240, 3368, 3496, 3624, 3752, 3824]

# TS 38.214 Table 5.1.3.1-2 (qam256): MCS -> (Qm, R x 1024)
QAM256_TABLE = dict(enumerate(
    [(2, 120), (2, 193), (2, 308), (2, 449), (2, 602), (4, 378), (4, 434), (4, 490), (4, 553),
     (4, 616), (4, 658), (6, 466), (6, 517), (6, 567), (6, 616), (6, 666), (6, 719), (6, 772),
     (6, 822), (6, 873), (8, 682.5), (8, 711), (8, 754), (8, 797), (8, 841), (8, 885),
     (8, 916.5), (8, 948)]))


def tbs_38214(n_prb, n_dmrs_symbols, qm, r, n_symb=14):
    """TS 38.214 5.1.3.2 steps 1-4, one layer, no xOverhead, written from the text."""
    import math
    n_re_prb = 12 * n_symb - 12 * n_dmrs_symbols
    n_info = min(156, n_re_prb) * n_prb * r * qm
    if n_info <= 3824:
        n = max(3, math.floor(math.log2(n_info)) - 6)
        n_info_q = max(24, 2 ** n * math.floor(n_info / 2 ** n))
        return next(t for t in TBS_TABLE if t >= n_info_q)
    n = math.floor(math.log2(n_info - 24)) - 5
    n_info_q = max(3840, 2 ** n * round((n_info - 24) / 2 ** n))
    if r <= 0.25:
        c = math.ceil((n_info_q + 24) / 3816)
    elif n_info_q > 8424:
        c = math.ceil((n_info_q + 24) / 8424)
    else:
        c = 1
    return 8 * c * math.ceil((n_info_q + 24) / (8 * c)) - 24


def parse_mac_pdu(tb):
    """TS 38.321 6.1.2 subheader (R F LCID L) and TS 38.322 6.2.2.3 UMD header, written from
    the standards' figures: -> dict or 'filler'."""
    lcid = tb[0] & 0x3F
    if lcid == 63:
        return "filler"
    assert tb[0] & 0xC0 == 0x40 and lcid == 4, tb[:4]
    length = int.from_bytes(tb[1:3], "big")
    si, rest = tb[3] >> 6, tb[3] & 0x3F
    hdr = 3 if si >= 2 else 1
    so = int.from_bytes(tb[4:6], "big") if hdr == 3 else 0
    end = 3 + length
    assert end == len(tb) or tb[end] == 0x3F  # padding subheader
    return {"si": si, "sn": rest, "so": so, "data": bytes(tb[3 + hdr:end])}


def pusch_cfg(num, modulation, coding="none", mcs=None, **kw):
    return nrsar.make_pusch_config(num, modulation, "pusch2", coding, "qam256", mcs, **kw)


def run_encoder(cfg, pdus, nbytes):
    enc = nrsar.pusch_encoder(cfg)
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

    def test_uncoded_bits_decode_with_numpy_reference(self):
        # Descramble with a numpy Gold sequence of c_init = n_RNTI 2^15 + n_ID (38.211
        # 6.3.1.1, the same every slot), check CRC24A, the MAC / RLC headers and the padding.
        num = nrsar.make_numerology("tiny")
        g = 12 * 64 * 6
        rng = np.random.default_rng(0)
        big = bytes(rng.integers(0, 256, 1000, dtype=np.uint8))
        small = b"\x00" * 7
        cfg = pusch_cfg(num, "qam64", n_rnti=1000, n_id=321)
        enc, bits = run_encoder(cfg, [backhaul.make_pdu(big), backhaul.make_pdu(small)],
                                g * 5 // 8)
        self.assertEqual(enc.slot_bits(), g)
        tb_bytes = (g - 24) // 8
        self.assertEqual(enc.tbs_bits(), 8 * tb_bytes)
        self.assertEqual(enc.payload_bits_per_slot() // 8, tb_bytes - 4)
        c = gold(1000 * 32768 + 321, g)
        got = []
        for slot in range(len(bits) // g):
            tb = bits[slot * g:(slot + 1) * g] ^ c
            nbits = 8 * tb_bytes + 24
            self.assertEqual(crc24a(tb[:nbits - 24]), list(tb[nbits - 24:nbits]))
            np.testing.assert_array_equal(tb[nbits:], 0)  # padding of G
            got.append(parse_mac_pdu(np.packbits(tb[:nbits - 24]).tobytes()))
        # 1000 bytes: first segment (SI 01, SN 0) of tb_bytes - 4, last (SI 10, SO) with the
        # rest; 7 bytes: a complete SDU (SI 00); then padding-only TBs
        first, last = tb_bytes - 4, 1000 - (tb_bytes - 4)
        self.assertEqual(got[0], {"si": 1, "sn": 0, "so": 0, "data": big[:first]})
        self.assertEqual(got[1], {"si": 2, "sn": 0, "so": first, "data": big[first:]})
        self.assertEqual(got[2], {"si": 0, "sn": 0, "so": 0, "data": small})
        self.assertEqual(got[3:], ["filler"] * (len(got) - 3))
        self.assertEqual(enc.payload_bytes_sent(), len(big) + len(small))
        self.assertEqual(enc.filler_tbs_sent(), enc.tbs_sent() - 3)
        self.assertEqual(len(big[first:]), last)

    def test_coded_bits_are_the_38212_chain(self):
        # pusch_encoder's G bits = the steps of 38.212 6.2 (nrsar.crc_attach, segment,
        # ldpc_encode, rate_match: docs/nr_coding.md), scrambled with c(n) of c_init by hand;
        # TBS from the 38.214 formula written in this test.
        num = nrsar.make_numerology("tiny")
        for modulation, mcs, rv in (("qpsk", 4, 0), ("qam16", 10, 2), ("qam256", 27, 3)):
            qm, r1024 = QAM256_TABLE[mcs]
            cfg = pusch_cfg(num, modulation, "nr-ldpc", mcs, rv=rv, n_rnti=0x4601, n_id=7)
            g = 12 * 64 * qm
            payload = bytes(range(5))
            enc, bits = run_encoder(cfg, [backhaul.make_pdu(payload)], g // 8)
            a = tbs_38214(64 // 12, 2, qm, r1024 / 1024)
            self.assertEqual(enc.tbs_bits(), a, modulation)
            tb = np.zeros(a // 8, np.uint8)
            tb[:9] = [0x44, 0x00, 0x06, 0x00, 0, 1, 2, 3, 4]  # MAC subheader, RLC SI 00, data
            tb[9] = 0x3F  # padding
            bits_a = np.unpackbits(tb)
            crc = "24A" if a > 3824 else "16"
            bg = nrsar.select_base_graph(a, r1024 / 1024)
            tb_crc = nrsar.crc_attach(bits_a, crc)
            seg = nrsar.segment_sizes(len(tb_crc), bg)
            d = np.atleast_2d(nrsar.ldpc_encode(nrsar.segment(tb_crc, bg), bg))
            e = nrsar.code_block_e(g, seg["C"], qm)
            f = np.concatenate([nrsar.rate_match(d[i], e[i], rv, qm, bg)
                                for i in range(seg["C"])])
            ref = f ^ gold(0x4601 * 32768 + 7, g)
            np.testing.assert_array_equal(bits[:g], ref, modulation)
            self.assertEqual(enc.code_blocks(), seg["C"])
            self.assertAlmostEqual(enc.code_rate(), len(tb_crc) / g)

    def test_filler_slots_repeat_under_the_standard_scrambler(self):
        # c_init does not depend on the slot (38.211): padding-only TBs give the same bits
        # every slot (a slot-periodic radar reference; docs/nr_coding.md), the module's
        # per-slot option a fresh half-random sequence.
        num = nrsar.make_numerology("tiny")
        g = 12 * 64 * 2
        for scrambling, same in (("standard", True), ("per-slot", False)):
            cfg = pusch_cfg(num, "qpsk", "nr-ldpc", 4, scrambling=scrambling)
            _, bits = run_encoder(cfg, [], g * 4 // 8)
            slots = bits.reshape(4, g)
            for s in slots:
                self.assertAlmostEqual(s.mean(), 0.5, delta=0.05)
            if same:
                np.testing.assert_array_equal(slots[0], slots[1])
            else:
                self.assertAlmostEqual(np.mean(slots[0] != slots[1]), 0.5, delta=0.05)

    def test_bit_stream_is_continuous(self):
        # QPSK pusch1 on 61 subcarriers: G = 13 * 61 * 2 = 1586 bits, not a multiple of 8.
        num = nrsar.make_numerology("tiny")
        num.num_subcarriers = 61
        cfg = nrsar.make_pusch_config(num, "qpsk", "pusch1", "none")
        g = 13 * 61 * 2
        enc, bits = run_encoder(cfg, [], -(-3 * g // 8))
        self.assertEqual(enc.slot_bits(), g)
        c = gold(0x4601 * 32768, g)
        for slot in range(3):
            tb = bits[slot * g:(slot + 1) * g] ^ c
            self.assertEqual(np.packbits(tb[:8])[0], 0x3F)  # the padding subheader

    def test_first_slot_continues_the_stream(self):
        # An encoder from slot s given the PDUs from slot s's TB on continues the stream of
        # one from slot 0 at bit s G: per-slot scrambling and each repetition's rv at the
        # absolute slot, a TB begun inside its repetitions (s odd), filler past the payload.
        # QPSK pusch1 on 61 subcarriers: G = 1586 bits, slots start off the byte grid.
        num = nrsar.make_numerology("tiny")
        num.num_subcarriers = 61
        cfg = nrsar.make_pusch_config(num, "qpsk", "pusch1", "nr-ldpc", "qam256", 4,
                                      repetitions=2, scrambling="per-slot")
        g, slots = 13 * 61 * 2, 14
        per_tb = nrsar.pusch_encoder(cfg).payload_bits_per_slot() // 8
        rng = np.random.default_rng(3)
        chunks = [bytes(rng.integers(0, 256, per_tb, np.uint8)) for _ in range(4)]
        pdus = [backhaul.make_pdu(c) for c in chunks]
        _, ref = run_encoder(cfg, pdus, -(-slots * g // 8))
        for s in (1, 2, 5, 8, 11):
            with self.subTest(first_slot=s):
                cfg.first_slot = s
                enc, bits = run_encoder(cfg, pdus[s // 2:], -(-(slots - s) * g // 8))
                np.testing.assert_array_equal(bits[:(slots - s) * g], ref[s * g:slots * g])
                self.assertEqual(enc.payload_bytes_sent(), sum(map(len, chunks[s // 2:])))

    def test_queue_bound_drops_counted(self):
        cfg = pusch_cfg(nrsar.make_numerology("tiny"), "qam256", max_queued_bytes=250)
        pdus = ([backhaul.make_pdu(bytes(100))] * 5 + [pmt.intern("junk")]
                + [backhaul.make_pdu(bytes(65536))])
        enc, _ = run_encoder(cfg, pdus, 10)
        self.assertEqual(enc.pdus_dropped(), 3 + 1 + 1)

    def test_getters(self):
        num = nrsar.make_numerology("paper")
        enc = nrsar.pusch_encoder(pusch_cfg(num, "qam256", "nr-ldpc"))
        g = 12 * 3333 * 8
        self.assertEqual(enc.slot_bits(), g)
        a = tbs_38214(3333 // 12, 2, 8, 948 / 1024)  # MCS 27, 277 PRB
        self.assertEqual(enc.tbs_bits(), a)
        self.assertEqual(enc.code_blocks(), -(-(a + 24) // (8448 - 24)))  # 38.212 5.2.2
        self.assertAlmostEqual(enc.code_rate(), (a + 24) / g)
        self.assertEqual(enc.payload_bits_per_slot(), 8 * (a // 8 - 4))
        self.assertAlmostEqual(enc.throughput_bps(),
                               enc.payload_bits_per_slot() / (14 * num.symbol_s()))

    def test_bad_parameters(self):
        num = nrsar.make_numerology("tiny")
        cases = [
            (dict(max_queued_bytes=0), "max_queued_bytes = 0"),
            (dict(mod=nrsar.make_modulation("psk16")), "mod"),
            (dict(mcs=28), "mcs = 28 must be in [0, 27]"),
            (dict(mcs=29, mcs_table="qam64"), "mcs = 29 must be in [0, 28]"),
            (dict(mcs=27), "mcs = 27 of mcs_table qam256 has Qm = 8 but mod has 4"),
            (dict(mcs_table="qam1024"), "mcs_table = 'qam1024'"),
            (dict(rv=4), "rv = 4 must be in [0, 3]"),
            (dict(repetitions=3), "repetitions = 3 must be 1, 2, 4 or 8"),
            (dict(repetitions=2, coding=nrsar.pusch_coding.NONE), "repetitions = 2 needs"),
            (dict(n_rnti=65536), "n_rnti = 65536 must be in [0, 65535]"),
            (dict(n_id=1024), "n_id = 1024 must be in [0, 1023]"),
            (dict(first_slot=2 ** 40 + 1), "first_slot = 1099511627777 must be at most 2^40"),
        ]
        for kw, text in cases:
            args = dict(num=num, mod=nrsar.make_modulation("qam16"), dmrs=nrsar.make_dmrs("pusch2"),
                        mcs=10)
            args.update(kw)
            with self.assertRaises(ValueError) as ctx:
                nrsar.pusch_encoder(nrsar.pusch_config(**args))
            self.assertIn(text, str(ctx.exception))
        with self.assertRaises(ValueError) as ctx:  # SRS symbol on a DMRS symbol
            s = nrsar.srs_config()
            s.start_subcarrier, s.num_rb, s.symbol_in_slot = 0, 2, 2
            nrsar.nr_isac_tx(num, nrsar.make_modulation("qpsk"), nrsar.make_tx_mode("data_srs"),
                             s, 0, nrsar.make_dmrs("pusch2"))
        self.assertIn("srs symbol_in_slot = 2", str(ctx.exception))


if __name__ == "__main__":
    gr_unittest.run(qa_pusch_encoder)
