#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The NR channel-coding functions of gnuradio.nrsar (bindings of the TS 38.212 / 38.214
kernels) against numpy references written from the standard's text: CRC by polynomial
division, H c = 0 from the base-graph table, rate-matching positions from Table 5.4.2.1-2,
the Gold sequence of TS 38.211 5.2.1; and the whole chain over AWGN."""

import numpy as np

from gnuradio import gr_unittest
from gnuradio import nrsar

# 38.212 5.1, the exponents of each generator polynomial
POLYS = {"24A": [24, 23, 18, 17, 14, 11, 10, 7, 6, 5, 4, 3, 1, 0],
         "24B": [24, 23, 6, 5, 1, 0],
         "16": [16, 12, 5, 0]}


def crc_ref(bits, poly):
    """Remainder of a(D) D^L / g(D) over GF(2), as numpy arrays."""
    g = np.zeros(POLYS[poly][0] + 1, np.uint8)
    g[[POLYS[poly][0] - e for e in POLYS[poly]]] = 1  # g[0] is D^L
    reg = np.concatenate([np.asarray(bits, np.uint8), np.zeros(len(g) - 1, np.uint8)])
    for i in np.arange(len(bits)):
        if reg[i]:
            reg[i:i + len(g)] ^= g
    return reg[len(bits):]


def h_times(x, base_graph, zc):
    """Syndrome H x over GF(2), numpy, from ldpc_base_graph()."""
    table = nrsar.ldpc_base_graph(base_graph)
    ils = nrsar.lifting_set_index(zc)
    rows = table[:, 0].max() + 1
    s = np.zeros((rows, zc), np.int64)
    r = np.arange(zc)
    for i, j, *v in table:
        s[i] ^= x[j * zc + (r + v[ils] % zc) % zc]
    return s


def oms_ref(llr, base_graph, zc, max_iter, offset=0.5):
    """Layered offset min-sum in float64 (the decoder's algorithm without fixed point): rows
    in order, skipping those whose degree-one parity column received nothing, the syndrome
    tested after each iteration. llr: the N = (cols - 2) Zc LLRs of d (+inf = known 0).
    Returns the hard decisions of [c w] (c_0 .. c_{K-1} first)."""
    table = nrsar.ldpc_base_graph(base_graph)
    ils = nrsar.lifting_set_index(zc)
    cols = table[:, 1].max() + 1
    big = np.zeros((cols, zc))
    big[2:] = np.where(np.isinf(llr), np.sign(llr) * 1e9, llr).reshape(-1, zc)
    degree = np.bincount(table[:, 1], minlength=cols)
    z = np.arange(zc)
    rows = []
    for i in range(table[:, 0].max() + 1):
        e = table[table[:, 0] == i]
        parity = [j for j in e[:, 1] if degree[j] == 1]
        if not parity or np.any(big[parity[0]] != 0):
            rows.append([(j, (z + v[ils] % zc) % zc) for j, *v in e[:, 1:]])
    msg = [np.zeros((len(r), zc)) for r in rows]
    for _ in range(max_iter):
        for r, m in zip(rows, msg):
            t = np.array([big[j][p] for j, p in r]) - m
            a = np.abs(t)
            two = np.sort(a, axis=0)[:2]
            others = np.where(a == two[0], two[1], two[0])
            sign = np.prod(np.where(t < 0, -1.0, 1.0), axis=0) * np.where(t < 0, -1.0, 1.0)
            m[:] = sign * np.maximum(others - offset, 0.0)
            for (j, p), v in zip(r, t + m):
                big[j][p] = v
        if all(np.all(np.prod([np.where(big[j][p] < 0, -1, 1) for j, p in r], axis=0) > 0)
               for r in rows):
            break
    return (big < 0).astype(np.uint8).ravel()


def gold_ref(c_init, n):
    """TS 38.211 5.2.1 from its recursions, in Python integers."""
    nc = 1600
    x1 = [1] + [0] * 30
    x2 = [(c_init >> i) & 1 for i in range(31)]
    while len(x1) < nc + n:
        m = len(x1) - 31
        x1.append(x1[m + 3] ^ x1[m])
        x2.append(x2[m + 3] ^ x2[m + 2] ^ x2[m + 1] ^ x2[m])
    return np.array(x1[nc:nc + n], np.uint8) ^ np.array(x2[nc:nc + n], np.uint8)


def rm_positions(n, zc, k_prime, base_graph, rv, e, qm, n_ref=None):
    """38.212 5.4.2.1 / 5.4.2.2 from the text: circular-buffer index read by each f bit."""
    ncb = n if n_ref is None else min(n, n_ref)
    frac = {1: (0, 17, 33, 56), 2: (0, 13, 25, 43)}[base_graph][rv]
    den = 66 if base_graph == 1 else 50
    k0 = (frac * ncb) // (den * zc) * zc
    k_full = (22 if base_graph == 1 else 10) * zc
    filler = set(range(k_prime - 2 * zc, k_full - 2 * zc))
    sel = []
    j = 0
    while len(sel) < e:
        p = (k0 + j) % ncb
        if p not in filler:
            sel.append(p)
        j += 1
    sel = np.array(sel).reshape(qm, e // qm)  # e_{i E/Qm + j}
    return sel.T.reshape(-1)                   # f_{i + j Qm}


class qa_nr_coding(gr_unittest.TestCase):

    def setUp(self):
        self.rng = np.random.default_rng(15)

    def test_crc_against_polynomial_division(self):
        for poly in POLYS:
            for n in (0, 1, 13, 64, 1000):
                a = self.rng.integers(0, 2, n)
                out = nrsar.crc_attach(a, poly)
                np.testing.assert_array_equal(out[:n], a)
                np.testing.assert_array_equal(out[n:], crc_ref(a, poly))
                self.assertTrue(nrsar.crc_check(out, poly))
        with self.assertRaisesRegex(ValueError, "poly"):
            nrsar.crc_attach([0, 1], "24C")
        with self.assertRaisesRegex(ValueError, "bits"):
            nrsar.crc_attach([0, 2], "16")

    def test_segment_encode_parity_checks(self):
        # TB of 25104 bits + CRC24A: C = 3 code blocks of K' = 8400 (5.2.2), Zc = 384, F = 48
        tb = nrsar.crc_attach(self.rng.integers(0, 2, 25104), "24A")
        self.assertEqual(nrsar.select_base_graph(25104, 0.9), 1)
        cbs = nrsar.segment(tb, 1)
        self.assertEqual(cbs.shape, (3, 8448))
        self.assertTrue(np.all(cbs[:, 8400:] == -1))
        for r in range(3):
            data = tb[r * 8376:(r + 1) * 8376]
            np.testing.assert_array_equal(cbs[r, :8376], data)
            np.testing.assert_array_equal(cbs[r, 8376:8400], crc_ref(data, "24B"))
        cw = nrsar.ldpc_encode(cbs, 1)
        self.assertEqual(cw.shape, (3, 66 * 384))
        for r in range(3):
            # [c w] with the punctured 2 Zc bits from the code block itself
            x = np.concatenate([np.where(cbs[r] < 0, 0, cbs[r]), cw[r, 8448 - 768:]]).astype(np.int64)
            self.assertEqual(h_times(x, 1, 384).sum(), 0)
            np.testing.assert_array_equal(cw[r, :8448 - 768], cbs[r, 768:])  # d_{k-2Zc} = c_k, fillers -1
        # BG2 at a small Zc through the same path
        cb2 = nrsar.segment(self.rng.integers(0, 2, 200), 2)  # Kb = 8, Zc = 26, K = 260
        self.assertEqual(cb2.shape, (1, 260))
        cw2 = nrsar.ldpc_encode(cb2[0], 2)
        x2 = np.concatenate([np.where(cb2[0] < 0, 0, cb2[0]), cw2[260 - 52:]]).astype(np.int64)
        self.assertEqual(h_times(x2, 2, 26).sum(), 0)
        back, ok = nrsar.desegment(cbs, len(tb), 1)
        np.testing.assert_array_equal(back, tb)
        self.assertTrue(ok.all())

    def test_rate_matching_positions(self):
        bg, zc, kp = 2, 72, 600
        n = 50 * zc
        cb = nrsar.segment(self.rng.integers(0, 2, kp), bg)[0]
        d = nrsar.ldpc_encode(cb, bg)
        for rv in range(4):
            for e, qm, n_ref in ((1200, 2, None), (5000, 4, None), (2400, 6, 2000)):
                f = nrsar.rate_match(d, e, rv, qm, bg, n_ref)
                pos = rm_positions(n, zc, kp, bg, rv, e, qm, n_ref)
                np.testing.assert_array_equal(f, d[pos])
                llr = self.rng.normal(size=e).astype(np.float32)
                soft = nrsar.rate_recover(llr, bg, zc, kp, rv, qm, n_ref)
                want = np.zeros(n)
                np.add.at(want, pos, llr.astype(np.float64))
                fill = np.arange(kp - 2 * zc, 10 * zc - 2 * zc)
                self.assertTrue(np.all(np.isinf(soft[fill])))
                keep = np.setdiff1d(np.arange(n), fill)
                # float32 sums of at most ceil(E / N_cb) terms against float64: rounding only
                np.testing.assert_allclose(soft[keep], want[keep], rtol=1e-6, atol=1e-6)
        with self.assertRaisesRegex(ValueError, "rv"):
            nrsar.rate_match(d, 100, 4, 2, bg)
        with self.assertRaisesRegex(ValueError, "e = 101"):
            nrsar.rate_match(d, 101, 0, 2, bg)

    def test_tbs_and_scrambling(self):
        # 38.214 5.1.3.2 by hand: qam64 MCS 10 (Qm 4, R 340/1024), 10 PRB, 12 symbols, 6 DMRS
        # RE: N_RE = 1380, N_info = 1832.8, n = 4, N'_info = 1824 -> table entry 1864
        self.assertEqual(nrsar.tbs("qam64", 10, 10, 12, 6), 1864)
        self.assertEqual(nrsar.mcs("qam256", 27), (8, 948 / 1024))
        with self.assertRaisesRegex(ValueError, "mcs_table"):
            nrsar.tbs("qam16", 1, 1, 14, 12)
        c_init = nrsar.scrambling_c_init(0x1234, 77)
        self.assertEqual(c_init, 0x1234 * 2 ** 15 + 77)
        np.testing.assert_array_equal(nrsar.scrambling_sequence(c_init, 3000), gold_ref(c_init, 3000))

    def _chain(self, esn0_db, blocks, rvs=(0,)):
        """TB -> CRC24A -> segment -> LDPC -> rate match (QPSK bits, BPSK LLRs per bit) ->
        AWGN -> rate recover (HARQ over rvs) -> decode -> desegment -> CRC24A. Blocks ok."""
        a = 8424 - 24  # one BG1 code block at rate ~0.9 (E = 9360)
        ok = 0
        sigma = np.sqrt(0.5 / 10 ** (esn0_db / 10))
        for _ in range(blocks):
            tb = nrsar.crc_attach(self.rng.integers(0, 2, a), "24A")
            s = nrsar.segment_sizes(len(tb), 1)
            cw = nrsar.ldpc_encode(nrsar.segment(tb, 1), 1)[0]
            soft = None
            for rv in rvs:
                f = nrsar.rate_match(cw, 9360, rv, 2, 1)
                y = 1.0 - 2.0 * f + sigma * self.rng.normal(size=f.size)
                soft = nrsar.rate_recover((2 * y / sigma ** 2).astype(np.float32), 1, s["Zc"],
                                          s["K_prime"], rv, 2, buffer=soft)
            bits, _, _ = nrsar.ldpc_decode(soft, 1, 8)
            back, _ = nrsar.desegment(bits.astype(np.int64)[None, :], len(tb), 1)
            ok += nrsar.crc_check(back, "24A")
        return ok

    def test_chain_over_awgn_and_harq(self):
        # Rate 8424 / 9360 = 0.9: the BI-AWGN limit is Es/N0 ~ 2.8 dB. 2 dB above it every
        # block decodes; 2 dB below it none can. At 2 dB below, rv 0 + rv 2 (chase of the
        # systematic part plus new parity: rate ~0.5 after combining) decodes all.
        self.assertEqual(self._chain(4.8, 10), 10)
        self.assertEqual(self._chain(0.8, 5), 0)
        self.assertEqual(self._chain(0.8, 5, rvs=(0, 2)), 5)

    def test_ulsch_is_the_chain_of_38212_62(self):
        # A = 1864 (qam64 MCS 10 above), CRC16, BG2, 16QAM bits into G = 5520, rv 3 (k0 =
        # 43 Zc: the buffer wraps into the systematic bits): the descrambled slot is the
        # rate-matched code block of the steps above, and decodes back noiselessly.
        u = nrsar.ulsch(1864, 340 / 1024, 4, 5520)
        a = self.rng.integers(0, 2, 1864)
        c_init = nrsar.scrambling_c_init(0x4601, 3)
        x = u.encode(a, 3, c_init)
        self.assertEqual(u.base_graph, 2)
        tb = nrsar.crc_attach(a, "16")
        d = nrsar.ldpc_encode(nrsar.segment(tb, 2), 2)[0]
        np.testing.assert_array_equal(x ^ gold_ref(c_init, 5520), nrsar.rate_match(d, 5520, 3, 4, 2))
        b, r = u.decode(np.where(x == 1, -4.0, 4.0), 3, c_init)
        self.assertTrue(r["tb_crc_ok"] and r["parity_ok"])
        np.testing.assert_array_equal(b, a)
        # rv 1 alone (k0 = 13 Zc: 5520 parity bits, no systematic one): nothing is learnt
        # about the systematic bits, the output is all-zero, whose CRC16 is zero too
        _, r1 = u.decode(np.where(u.encode(a, 1, c_init) == 1, -4.0, 4.0), 1, c_init)
        self.assertFalse(r1["parity_ok"])
        with self.assertRaisesRegex(ValueError, "bits"):
            u.encode(a[:-1], 0, c_init)
        with self.assertRaisesRegex(ValueError, "max_iter = 0"):
            nrsar.ldpc_decode(np.zeros(50 * 26, np.float32), 2, 0)
        with self.assertRaisesRegex(ValueError, "N \\(codeword length\\) = 1301"):
            nrsar.ldpc_decode(np.zeros(1301, np.float32), 2)

    def test_bler_against_the_normal_approximation(self):
        # QPSK, qam64 MCS 4 on 20 PRB (TBS 1928 in G = 6240): the finite-length bound
        # (normal approximation over the QPSK BICM channel, computed by Monte Carlo in
        # figures.nr_bler) puts BLER 10 % of the best code at about -2.5 dB. 0.3 dB below
        # it no decoder succeeds on most blocks; our decoder (20 iterations) reaches 10 % about
        # 0.9 dB above the bound (docs/nr_coding.md), and 1.9 dB above it at most 1 of 30
        # fails (the int8 decoder's floor of about 1 % is gone: its code block alone, 0 of
        # 4000 fail at -1.0 and -0.25 dB, 29 and 17 before).
        from gnuradio.nrsar.figures import nr_bler
        na = nr_bler.normal_approximation_snr_db(2, 6240, 1928, symbols=20000)
        below = nr_bler.bler_curve("qam64", 4, 20, [na - 0.3], 10, 20, seed=3)["bler"][0]
        above = nr_bler.bler_curve("qam64", 4, 20, [na + 1.9], 30, 20, seed=4)["bler"][0]
        self.assertGreaterEqual(below, 0.5)
        self.assertLessEqual(above, 1 / 30)

    def test_fer_against_published_curves(self):
        # AFF3CT's published FER of the NR code (BPSK-AWGN, layered belief propagation, 10
        # iterations; figures.nr_bler.PUBLISHED). The criterion: within 0.5 dB of
        # the published curve at 10 %. 0.5 dB past SPA's 10 % point a decoder that just meets
        # it fails 10 % of frames: 300 frames with at most 15 errors (5 %) reject it with
        # probability 0.998 (binomial, mean 30, sd 5.2); ours fails 0 (BG1) and 3 (BG2).
        # 0.3 dB before SPA's 10 % point belief propagation itself fails a third to a half
        # of the frames, and min-sum cannot beat it: at least 20 % must fail (a check of
        # the set-up's Eb/N0, puncturing and fillers, not of the decoder).
        from gnuradio.nrsar.figures import nr_bler
        for (bg, zc, kp, e), pub in nr_bler.PUBLISHED.items():
            spa = {"snr_db": [p for p, _ in pub["SPA"]], "bler": [f for _, f in pub["SPA"]]}
            at10 = nr_bler.snr_at(spa, 0.1)
            worst = nr_bler.bpsk_fer(bg, zc, kp, e, at10 + 0.5, 300, seed=11)
            self.assertLessEqual(worst, 15, (bg, zc, at10))
            early = nr_bler.bpsk_fer(bg, zc, kp, e, at10 - 0.3, 100, seed=12)
            self.assertGreaterEqual(early, 20, (bg, zc, at10))

    def test_bler_against_lena(self):
        # 5G-LENA's published AWGN BLER of one NR code block (figures.nr_bler.LENA: ns-3 NR
        # module, model/nr-eesm-t1.cc, BG2, MCS 4, CBS 1864) reaches 10 % at SINR 1.99 dB per
        # RE (linear in log BLER between its points); the chain sends the same TB (QPSK,
        # R 0.30, TBS 1864 as one BG2 code block) at Es/N0 = that SINR. The issue's
        # criterion: within 0.5 dB of the published curve at 10 %. 0.5 dB past LENA's point a
        # decoder that just meets it fails 10 %: 200 TBs with at most 8 failures reject it
        # with probability 0.9986 (binomial, mean 20); one as good as LENA's (BLER 0.36 %
        # at 2.31 dB) fails more than 8 with probability 6e-8. Ours reaches 10 % 3.6 dB
        # before LENA's point (docs/nr_coding.md) and fails none.
        from gnuradio.nrsar.figures import nr_bler
        name, bg, cbs, pub = nr_bler.LENA[("qam64", 4, 126, 3)]
        at10 = nr_bler.snr_at({"snr_db": [p for p, _ in pub], "bler": [b for _, b in pub]})
        c = nr_bler.bler_curve("qam64", 4, 126, [at10 + 0.5], 200, 20, seed=5, n_symbols=3)
        self.assertEqual((c["tbs"], c["base_graph"], c["code_blocks"]), (cbs, bg, 1))
        self.assertLessEqual(c["bler"][0] * 200, 8)

    def test_bler_against_sionna(self):
        # NVIDIA Sionna's published BLER of one 38.212 code block in its stated set-up
        # (figures.nr_bler.SIONNA_NOTEBOOK / SIONNA_TABLE: exact LLRs, 20 iterations of flooding
        # BP; code_block_bler reproduces the codeword, the 5.4.2.2 interleaver and Es/N0). The
        # issue's criterion: within 0.5 dB of the published curve at 10 %, both ways.
        # 16-QAM, k 600, n 1200 (BICM notebook, In[16]): published 10 % at Eb/N0 3.53 dB. 0.5 dB
        # past it a chain just 0.5 dB worse fails 10 %: at most 15 of 300 reject it (binomial
        # P(X <= 15) = 1.3e-3); ours (about 1 %) passes with P = 1 - 3e-6. 0.5 dB before it a
        # chain 0.5 dB better fails 10 %: at least 20 of 100 must fail (P(X >= 20) = 2e-3 for
        # it); ours fails about half (P(X < 20) = 1e-10).
        # 256-QAM, qam256 MCS 20 (R 0.667), k 2000, n 3008 (PDSCH_table2.json): BLER 0.0753 at
        # Es/N0 18.68 dB. 0.5 dB past it a chain 0.5 dB worse fails 7.5 %: at most 5 of 200
        # (P(X <= 5) = 2e-3); ours fails under 0.5 % there (P(X > 5) < 6e-4).
        from gnuradio.nrsar.figures import nr_bler
        cell, k, n, qm, inter, _, pub = nr_bler.SIONNA_NOTEBOOK["16-QAM, 5.4.2.2 interleaver"]
        at10 = nr_bler.snr_at({"snr_db": [p for p, _, _ in pub], "bler": [b for _, b, _ in pub]})
        es = at10 + 10 * np.log10(qm * k / n)  # ebnodb2no: Es/N0 = Eb/N0 + 10 log10(Qm k / n)
        self.assertLessEqual(nr_bler.code_block_bler(k, n, qm, es + 0.5, 300, seed=41), 15)
        self.assertGreaterEqual(nr_bler.code_block_bler(k, n, qm, es - 0.5, 100, seed=42), 20)
        snr, bler = nr_bler.SIONNA_TABLE[("qam256", 20)][1]
        self.assertEqual(bler, 0.0753)
        qm, rate = nrsar.mcs("qam256", 20)
        n = int(np.ceil(2000 / (rate * qm))) * qm  # CodedAWGNChannelNR's n: 3008
        self.assertLessEqual(nr_bler.code_block_bler(2000, n, qm, snr + 0.5, 200, seed=43), 5)

    def test_no_error_floor_on_short_codes(self):
        # BG2 Zc 64 K' 512 at rate 1/2 (AFF3CT's set-up of test_fer_against_published_curves),
        # Eb/N0 2.25 dB, 10 iterations, 10000 frames. Published float offset min-sum: FER
        # 1.14e-3 (11.4 frames expected); at most 25 may fail (Poisson: P(> 25) = 3e-4). The
        # int8 decoder before the int16 path failed 62-85 (its a-posteriori sums saturated at
        # +-127: an error floor of 4e-3 to 8e-3). Every frame that fails is decoded again by
        # oms_ref, the same algorithm in float64: the frames it decodes are what fixed point
        # costs. 0-2 expected (6 in 30000 measured), at most 8 (the int8 decoder: about 70).
        from gnuradio.nrsar.figures import nr_bler
        failures = []
        failed = nr_bler.bpsk_fer(2, 64, 512, 1024, 2.25, 10000, seed=21, failures=failures)
        fixed_point = sum(np.array_equal(oms_ref(llr.astype(np.float64), 2, 64, 10)[:512], info)
                          for llr, info in failures)
        self.assertLessEqual(failed, 25)
        self.assertLessEqual(fixed_point, 8)

    def test_no_fixed_point_loss_at_rate_09(self):
        # BG1 Zc 384 K' 8448, the first 9386 bits of d sent (rate 0.9, the throughput goal's
        # code), Eb/N0 4.3 dB, 8 iterations, 8000 frames; every frame that fails is decoded
        # again by oms_ref (float64). The frames it decodes are what fixed point costs: the
        # int8 decoder alone lost about 2.5e-3 there (15 of 6000, 14 of them decoded by
        # oms_ref: saturation), 20 expected here; at most 7 may be (Poisson P(<= 7) at a mean
        # of 20: 8e-4). Now near-codewords are decoded again in int16: about 2.5e-4, 2
        # expected (P(> 7) 1e-3). Frames only oms_ref fails count for us, so this also bounds
        # our failures by oms_ref's plus 7 (oms_ref fails about 5e-4 of the frames here).
        from gnuradio.nrsar.figures import nr_bler
        failures = []
        nr_bler.bpsk_fer(1, 384, 8448, 9386, 4.3, 8000, max_iter=8, seed=31, failures=failures)
        fixed_point = sum(np.array_equal(oms_ref(llr.astype(np.float64), 1, 384, 8)[:8448], info)
                          for llr, info in failures)
        self.assertLessEqual(fixed_point, 7)


if __name__ == '__main__':
    gr_unittest.run(qa_nr_coding)
