#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""pusch_receiver: frequency-domain loopback pusch_encoder -> nr_isac_tx(dmrs) -> numpy
channel + AWGN on the grid -> pusch_receiver. References: the PDUs sent, the transmitted
grid itself (uncoded BER), and the exact min-distance BER of the mapping computed here."""

import math
import time

import numpy as np
import pmt

from gnuradio import blocks, gr, gr_unittest
from gnuradio import nrsar
from gnuradio.nrsar import backhaul



def cfg_of(modulation, coding="nr-ldpc", dmrs="pusch2", num="tiny", **kw):
    """The PUSCH of the tests: the qam256 table's highest MCS of the modulation."""
    return nrsar.make_pusch_config(nrsar.make_numerology(num), modulation, dmrs, coding,
                                   n_id=5, **kw)


def qam_points(order):
    """38.211 5.1 points indexed by b(0) b(1) ... (b(0) = MSB), from the SPEC formulas."""
    k = int(np.log2(order))
    pts = np.zeros(order, complex)
    for idx in range(order):
        b = [(idx >> (k - 1 - j)) & 1 for j in range(k)]
        def axis(bits):
            v = 0.0
            for lvl, bit in enumerate(reversed(bits)):
                v = (1 - 2 * bit) * ((1 << lvl) - v) if lvl else (1 - 2 * bit)
            return v
        re, im = axis(b[0::2]), axis(b[1::2])
        pts[idx] = re + 1j * im
    return pts / np.sqrt(np.mean(np.abs(pts) ** 2))


def qfunc(x):
    return 0.5 * math.erfc(x / math.sqrt(2.0))


def ber_min_distance(order, esn0_db, kappa=0.0):
    """Exact BER of min-distance detection of the test's 38.211 square-QAM mapping in AWGN
    (Es = 1, N0 = 10^(-Es/N0 / 10)): per point and axis, the probability of each decision
    interval (thresholds midway between the levels) times the bits that decision flips.
    kappa: a channel estimate h^ = h + e with Var(e) = kappa N0 adds |s|^2 kappa N0 to the
    noise of the equalised point s (first order in e; Gaussian, as e is)."""
    pts = qam_points(order)
    k = int(np.log2(order))
    n0 = 10.0 ** (-esn0_db / 10.0)
    total = 0.0
    for idx, pt in enumerate(pts):
        sd = math.sqrt(n0 * (1.0 + kappa * abs(pt) ** 2) / 2.0)
        for axis, first in ((np.real, 0), (np.imag, 1)):
            bits = {}  # level -> that axis' bits
            for j, q in enumerate(pts):
                bits[round(float(axis(q)), 12)] = [(j >> (k - 1 - b)) & 1 for b in range(first, k, 2)]
            levels = sorted(bits)
            edges = [-math.inf] + [(a + b) / 2 for a, b in zip(levels, levels[1:])] + [math.inf]
            a = float(axis(pt))
            mine = bits[round(a, 12)]
            for lvl, lo, hi in zip(levels, edges, edges[1:]):
                p = qfunc((lo - a) / sd) - qfunc((hi - a) / sd)
                total += p * sum(x != y for x, y in zip(bits[lvl], mine))
    return total / (order * k)


def transmit(cfg, pdus, nslots):
    return backhaul.transmit_grid(cfg, pdus, nslots)


def channel(grid, num, esn0_db, seed, selective=True, drift=0.0):
    """Per-subcarrier complex channel (two paths, constant over the run), a slow common
    phase drift per symbol and AWGN of variance 10^(-Es/N0 / 10) on every RE (Es = 1)."""
    rng = np.random.default_rng(seed)
    n = grid.shape[1]
    f = np.arange(n) / n
    if selective:
        h = 0.9 * np.exp(-2j * np.pi * 0.4 * f) + 0.35 * np.exp(-2j * np.pi * 1.1 * f + 1.0j)
    else:
        h = np.full(n, np.exp(0.7j))
    phase = np.exp(1j * drift * np.arange(grid.shape[0]))[:, None]
    n0 = 10.0 ** (-esn0_db / 10.0)
    noise = np.sqrt(n0 / 2) * (rng.standard_normal(grid.shape) + 1j * rng.standard_normal(grid.shape))
    return (grid * h[None, :] * phase + noise).astype(np.complex64)


def receive(cfg, grid, eq=False):
    rx = nrsar.pusch_receiver(cfg)
    num = cfg.num
    n = num.num_subcarriers
    src = blocks.vector_source_c(grid.reshape(-1).tolist(), False, n)
    dbg = blocks.message_debug()
    tb = gr.top_block()
    tb.connect(src, rx)
    snk = None
    if eq:
        snk = blocks.vector_sink_c()
        tb.connect(rx, snk)
    tb.msg_connect(rx, "pdus", dbg, "store")
    tb.run()
    expected = grid.shape[0] // num.symbols_per_slot // cfg.repetitions
    for _ in range(200):  # message delivery is asynchronous
        if dbg.num_messages() >= expected:
            break
        time.sleep(0.01)
    msgs = [backhaul.pdu_to_python(dbg.get_message(i)) for i in range(dbg.num_messages())]
    return rx, msgs, (np.array(snk.data(), np.complex64) if eq else None)


# Es/N0 of the HARQ test (flat channel, pusch2, the receiver's own channel estimate): one
# transmission of QPSK at R 0.59 failed 10 of 10 TBs at 1-2 dB and 8 of 10 at 3 dB; rv 0 + rv 2
# combined (twice the energy, rate 0.29) decoded 10 of 10 from 1 dB, 1 of 10 at -0.5 dB
HARQ_ESN0_DB = 1.5


class qa_pusch_receiver(gr_unittest.TestCase):

    def test_loopback_bit_exact_odd_pdus(self):
        num = nrsar.make_numerology("tiny")
        for modname, coding in (("qam256", "none"), ("qam16", "nr-ldpc"), ("qpsk", "nr-ldpc"),
                                ("qam256", "nr-ldpc")):
            cfg = cfg_of(modname, coding)
            rng = np.random.default_rng(3)
            pdus = [bytes(rng.integers(0, 256, n, dtype=np.uint8)) for n in (1, 37, 501, 3, 129)]
            grid, enc = transmit(cfg, pdus, 40)
            rx, msgs, _ = receive(cfg, channel(grid, num, 45.0, 1, drift=0.01))
            what = f"{modname} {coding}"
            self.assertEqual(len(msgs), 40)
            self.assertTrue(all(m["crc_ok"] for m, _ in msgs), what)
            self.assertEqual([m["slot"] for m, _ in msgs], list(range(40)))
            got = backhaul.reassemble(msgs)
            self.assertEqual([p for p, _ in got], pdus, what)
            self.assertTrue(all(ok for _, ok in got))
            self.assertEqual(rx.payload_bytes_ok(), sum(len(p) for p in pdus))
            self.assertEqual(rx.blocks_ok(), 40)
            self.assertEqual(rx.filler_blocks(), 40 - enc.tbs_sent() + enc.filler_tbs_sent())
            self.assertEqual(rx.tbs_bits(), enc.tbs_bits())
            for meta, _ in msgs:
                self.assertEqual(set(meta), set(backhaul.META_KEYS))
                self.assertGreater(meta["snr_db"], 35.0)
                self.assertLess(meta["evm_db"], -35.0)
                self.assertEqual(meta["transmissions"], 1)
                self.assertEqual(meta["code_blocks"], rx.code_blocks())
                if coding == "nr-ldpc":  # a clean word passes every parity check at once
                    self.assertEqual(meta["ldpc_iterations"], 1.0)

    def test_uncoded_256qam_ber_matches_theory(self):
        # Flat channel (unknown phase), pusch4 + a wide frequency window: against the exact
        # AWGN BER of the mapping (computed here), with the channel estimate's own noise.
        num, mod, dmrs = (nrsar.make_numerology("tiny"), nrsar.make_modulation("qam256"),
                          nrsar.make_dmrs("pusch4"))
        nslots, esn0_db = 60, 26.0
        cfg = cfg_of("qam256", "none", "pusch4", freq_window=31)
        grid, _ = transmit(cfg, [], nslots)
        rxgrid = channel(grid, num, esn0_db, 7, selective=False)
        _, _, eq = receive(cfg, rxgrid, eq=True)
        data_sym = [l for l in range(14) if l not in (2, 5, 8, 11)]
        sent = grid.reshape(nslots, 14, -1)[:, data_sym, :].reshape(-1)
        self.assertEqual(eq.size, sent.size)
        pts = qam_points(256)
        tx_idx = np.argmin(np.abs(sent[:, None] - pts[None, :]), axis=1)
        rx_idx = np.argmin(np.abs(eq[:, None] - pts[None, :]), axis=1)
        diff = np.bitwise_xor(tx_idx, rx_idx)
        errors = sum(int(bin(d).count("1")) for d in diff)
        bits = 8 * sent.size
        ber = errors / bits
        # The estimate (pusch_rx.h): a least-squares line over the 31 DMRS REs of each DMRS
        # symbol (32 per symbol on the 64 subcarriers), whose error variance at offset x from
        # the centre is N0 (1/31 + x^2 / sum x_i^2), 2 N0 / 31 averaged over the band; then
        # linear inter-/extrapolation in time from DMRS symbols 2, 5, 8, 11, weights (w, 1-w)
        # with w^2 + (1-w)^2 = 29/9, 17/9 for symbols 0 and 1 (13 and 12) and 5/9 between:
        # mean 1.356 over the 10 data symbols. kappa = 2 / 31 x 1.356 = 0.0875 (0.36 dB).
        kappa = 2.0 / 31.0 * (2 * 29 / 9 + 2 * 17 / 9 + 6 * 5 / 9) / 10.0
        theory = ber_min_distance(256, esn0_db, kappa)
        self.assertGreater(errors, 300)
        # Poisson count: 4 standard deviations sqrt(expected errors) (Gray mapping: nearly
        # every symbol error is one bit error)
        expected = theory * bits
        self.assertLess(abs(errors - expected), 4.0 * math.sqrt(expected),
                        f"BER {ber:.4e}, theory {theory:.4e} (AWGN alone "
                        f"{ber_min_distance(256, esn0_db):.4e})")

    def test_ldpc_bler_below_uncoded(self):
        num = nrsar.make_numerology("tiny")
        nslots, esn0_db = 20, 8.0
        bler = {}
        for coding in ("none", "nr-ldpc"):
            cfg = cfg_of("qpsk", coding)
            grid, _ = transmit(cfg, [], nslots)
            rx, msgs, _ = receive(cfg, channel(grid, num, esn0_db, 11))
            bler[coding] = rx.blocks_failed() / nslots
            self.assertEqual(rx.blocks_failed() + rx.blocks_ok(), nslots)
        self.assertGreater(bler["none"], 0.5)
        self.assertLess(bler["nr-ldpc"], 0.2)

    def test_harq_combines_repetitions(self):
        # QPSK, qam256 MCS 4 (R 602/1024), each TB in 2 slots (rv 0 then rv 2) at an Es/N0
        # where one transmission alone fails: the receiver decodes after combining both
        # (HARQ_ESN0_DB: 1.5 dB below where single TBs start to pass, 2 dB above where the
        # combination fails).
        num = nrsar.make_numerology("tiny")
        ntb, esn0_db = 10, HARQ_ESN0_DB
        pdus = [bytes([i]) * 100 for i in range(ntb)]
        single = cfg_of("qpsk")
        grid1, _ = transmit(single, pdus, ntb)
        rx1, _, _ = receive(single, channel(grid1, num, esn0_db, 21, selective=False))
        self.assertGreaterEqual(rx1.blocks_failed(), 8)  # one transmission: mostly lost
        cfg = cfg_of("qpsk", repetitions=2)
        grid, enc = transmit(cfg, pdus, 2 * ntb)
        rx, msgs, _ = receive(cfg, channel(grid, num, esn0_db, 21, selective=False))
        self.assertEqual(len(msgs), ntb)  # one report per TB
        self.assertEqual([m["slot"] for m, _ in msgs], list(range(0, 2 * ntb, 2)))
        self.assertGreaterEqual(rx.blocks_ok(), 9)
        self.assertGreaterEqual(rx.harq_combined_ok(), 8)
        for meta, data in msgs:
            if meta["crc_ok"]:
                self.assertEqual(data, pdus[meta["slot"] // 2])
                self.assertIn(meta["transmissions"], (1, 2))

    def test_crc_failures_reported_not_delivered(self):
        num = nrsar.make_numerology("tiny")
        for coding in ("none", "nr-ldpc"):
            cfg = cfg_of("qam256", coding)
            pdus = [bytes(range(200))] * 4
            grid, _ = transmit(cfg, pdus, 8)
            rx, msgs, _ = receive(cfg, channel(grid, num, 3.0, 2))
            self.assertEqual(len(msgs), 8)
            self.assertEqual(rx.blocks_failed(), 8)
            self.assertEqual(rx.payload_bytes_ok(), 0)
            for meta, data in msgs:
                self.assertFalse(meta["crc_ok"])
                self.assertEqual(data, b"")
                self.assertEqual(meta["payload_len"], 0)
                self.assertEqual(meta["seq"], -1)
            self.assertEqual(backhaul.reassemble(msgs), [])
        # another UE's scrambling (n_RNTI) at a clean SNR: every TB fails its CRC
        grid, _ = transmit(cfg_of("qam16", n_rnti=1), [b"x" * 50], 3)
        rx, msgs, _ = receive(cfg_of("qam16", n_rnti=2), channel(grid, num, 45.0, 3))
        self.assertEqual(rx.blocks_failed(), 3)

    def test_snr_estimate(self):
        num = nrsar.make_numerology("tiny")
        cfg = cfg_of("qam16")
        grid, _ = transmit(cfg, [], 4)
        rx, msgs, _ = receive(cfg, channel(grid, num, 20.0, 4, selective=False))
        # |h| = 1, sigma^2 = 0.01: 20 dB within the spread of 4 x 64 noise samples per slot
        for meta, _ in msgs:
            self.assertAlmostEqual(meta["snr_db"], 20.0, delta=1.0)

    def test_slot_tag_realigns(self):
        cfg = cfg_of("qpsk")
        grid, _ = transmit(cfg, [b"hello"], 3)
        # 5 junk symbols first, then slot 0 tagged
        junk = np.zeros((5, grid.shape[1]), np.complex64)
        full = np.concatenate([junk, grid])
        tag = gr.tag_t()
        tag.offset, tag.key, tag.value = 5, pmt.intern(nrsar.tag_keys.slot), pmt.from_uint64(0)
        rx = nrsar.pusch_receiver(cfg)
        src = blocks.vector_source_c(full.reshape(-1).tolist(), False, grid.shape[1], [tag])
        dbg = blocks.message_debug()
        tb = gr.top_block()
        tb.connect(src, rx)
        tb.msg_connect(rx, "pdus", dbg, "store")
        tb.run()
        time.sleep(0.05)
        msgs = [backhaul.pdu_to_python(dbg.get_message(i)) for i in range(dbg.num_messages())]
        self.assertEqual(rx.partial_slots(), 1)
        self.assertEqual([m["slot"] for m, _ in msgs], [0, 1, 2])
        self.assertEqual(msgs[0][1], b"hello")

    def test_nonfinite_input_counted(self):
        cfg = cfg_of("qpsk")
        grid, _ = transmit(cfg, [], 1)
        grid[4, 7] = np.nan
        rx, msgs, _ = receive(cfg, grid)
        self.assertEqual(rx.nonfinite_samples(), 1)
        self.assertTrue(msgs[0][0]["crc_ok"])  # one erased RE: the LDPC code fills it in

    def test_soft_demapper_binding(self):
        d = nrsar.soft_demapper(nrsar.make_modulation("qpsk"))
        llr = d.demap([complex(0.5, -0.5)], [0.5])
        # per axis: (|y+a|^2 - |y-a|^2) / sigma^2 = 4 a y / sigma^2 with a = 1/sqrt(2)
        a = 1 / np.sqrt(2)
        self.assertAlmostEqual(llr[0], 4 * a * 0.5 / 0.5, places=5)
        self.assertAlmostEqual(llr[1], -4 * a * 0.5 / 0.5, places=5)

    def test_bad_parameters(self):
        num = nrsar.make_numerology("tiny")
        cases = [
            (dict(dmrs=nrsar.make_dmrs("none")), "dmrs symbols"),
            (dict(mod=nrsar.make_modulation("psk8")), "mod"),
            (dict(freq_window=4), "freq_window = 4"),
            (dict(n_id=70000), "n_id = 70000"),
            (dict(max_iterations=0), "max_iterations = 0"),
            (dict(mcs=11), "mcs = 11 of mcs_table qam256 has Qm = 6 but mod has 4"),
        ]
        for kw, text in cases:
            args = dict(num=num, mod=nrsar.make_modulation("qam16"),
                        dmrs=nrsar.make_dmrs("pusch2"), mcs=10)
            args.update(kw)
            with self.assertRaises(ValueError) as ctx:
                nrsar.pusch_receiver(nrsar.pusch_config(**args))
            self.assertIn(text, str(ctx.exception))


if __name__ == "__main__":
    gr_unittest.run(qa_pusch_receiver)
