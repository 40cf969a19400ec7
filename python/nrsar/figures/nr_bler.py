#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""BLER against SNR of the NR UL-SCH (nrsar.ulsch: TS 38.212 LDPC, rv 0, the fixed-point
layered offset min-sum decoder with at most --max-iter iterations) over AWGN with the TS 38.211 constellations and max-log
LLRs (nrsar.soft_demapper), for one MCS per modulation. Prints, per MCS, the BLER at each SNR
and the SNR of BLER 10 % (interpolated in log BLER), beside the Shannon limit of the
information rate A / (G / Qm) bits per symbol, log2(1 + SNR) = rate, and the normal
approximation of the finite-length bound for A bits in G coded bits over the BICM channel of
the constellation (normal_approximation_snr_db): the reference the curves are held to.

Run: /usr/bin/python3 -m gnuradio.nrsar.figures.nr_bler [--blocks 100] [--max-iter 20]
     [--only qam64:4,qam256:24]
     /usr/bin/python3 -m gnuradio.nrsar.figures.nr_bler --published [--blocks 1000]
     /usr/bin/python3 -m gnuradio.nrsar.figures.nr_bler --floor [--blocks 100000]
     /usr/bin/python3 -m gnuradio.nrsar.figures.nr_bler --lena [--blocks 1000] [--max-iter 20]
     /usr/bin/python3 -m gnuradio.nrsar.figures.nr_bler --sionna [--blocks 1000] [--max-iter 20]
       [--max-log]
--published: the decoder against AFF3CT's published 5G NR LDPC curves (PUBLISHED).
--lena: the chain against 5G-LENA's published AWGN BLER of one code block per MCS (LENA), one
case per modulation, at the same MCS and TBS, SNR = Es/N0 per RE as LENA's SINR.
--sionna: the decoder against NVIDIA Sionna's published QPSK / 16-QAM / 64-QAM BLER of one 38.212
code block (SIONNA_NOTEBOOK, SIONNA_TABLE) in their set-up: exact LLRs, Es/N0 from their Eb/N0.
--floor: the FER of PUBLISHED's BG2 K' 512 code down to 1e-5, where an error floor would show.
"""

import dataclasses
import math
import sys

import numpy as np

from gnuradio import nrsar
from gnuradio.nrsar import cli
from gnuradio.nrsar.options import OptionError, Options, option

# (table, MCS, n_prb) of the curves; 14 symbols with one DMRS symbol: 156 data REs per PRB
CASES = [("qam64", 4, 20), ("qam64", 13, 20), ("qam64", 22, 20), ("qam256", 24, 20)]
MODS = {2: nrsar.modulation.QPSK, 4: nrsar.modulation.QAM16, 6: nrsar.modulation.QAM64,
        8: nrsar.modulation.QAM256}


def allocation(table, mcs, n_prb, n_symbols=14):
    """(Qm, R, TBS, G) of n_prb PRBs x n_symbols symbols, one of them DMRS: 12 (n_symbols - 1)
    data REs per PRB (156 in a slot)."""
    qm, rate = nrsar.mcs(table, mcs)
    g = 12 * (n_symbols - 1) * n_prb * qm
    return qm, rate, nrsar.tbs(table, mcs, n_prb, n_symbols, 12), g


def bler_curve(table, mcs, n_prb, snrs_db, blocks, max_iter, seed=1, rvs=(0,), n_symbols=14):
    """BLER per SNR of the TB of allocation(table, mcs, n_prb, n_symbols); rvs: the redundancy
    versions of the TB's transmissions, each through its own noise and combined in the soft
    buffers before the last decoding (HARQ)."""
    qm, rate, a, g = allocation(table, mcs, n_prb, n_symbols)
    ul = nrsar.ulsch(a, rate, qm, g, max_iter=max_iter)
    const = nrsar.constellation(MODS[qm])
    points = np.array(const.points())
    demap = nrsar.soft_demapper(MODS[qm])
    weights = 2 ** np.arange(qm - 1, -1, -1)
    rng = np.random.default_rng(seed)
    out = []
    for snr_db in snrs_db:
        nv = 10 ** (-snr_db / 10)  # unit-energy symbols: noise variance per complex symbol
        errors = 0
        for _ in range(blocks):
            bits = rng.integers(0, 2, a)
            for n, rv in enumerate(rvs):
                x = ul.encode(bits, rv, 1000).reshape(-1, qm)
                s = points[x @ weights]
                y = s + np.sqrt(nv / 2) * (rng.normal(size=s.size)
                                           + 1j * rng.normal(size=s.size))
                llr = np.array(demap.demap(y.astype(np.complex64).tolist(), [nv]), np.float32)
                back, r = ul.decode(llr, rv, 1000, combine=n > 0)
            errors += not (r["tb_crc_ok"] and np.array_equal(back, bits))
        out.append(errors / blocks)
    info_rate = a / (g / qm)  # information bits per symbol
    return {"table": table, "mcs": mcs, "qm": qm, "tbs": a, "g": g, "code_rate": rate,
            "base_graph": ul.base_graph, "code_blocks": ul.segmentation["C"],
            "info_rate": info_rate, "shannon_db": 10 * np.log10(2 ** info_rate - 1),
            "snr_db": list(snrs_db), "bler": out}


# Published FER of the NR LDPC code over BPSK-AWGN: AFF3CT's error_rate_references
# (github.com/aff3ct/error_rate_references, LDPC/AWGN/BPSK/BP_HORIZONTAL_LAYERED/{SPA,OMS}/
# LDPC_N<E>_K<K'>_hlayered_{SPA,OMS}_i10_5G.txt, AFF3CT v4.4-4.5, >= 100 frame errors per
# point): K' information bits, BG and Zc of 38.212, rv 0 rate matching to E bits (the 2 Zc
# first columns punctured, fillers skipped and known), horizontal layered decoding, 10
# iterations without syndrome stop, float32, SPA (belief propagation) and offset min-sum
# (offset 0.5). {(bg, zc, K', E): {decoder: [(Eb/N0 dB, FER), ...]}}
PUBLISHED = {
    (1, 288, 6144, 12288): {
        "SPA": [(1.0, 0.597), (1.1, 0.327), (1.2, 0.0664), (1.3, 0.0101), (1.4, 9.06e-4)],
        "OMS 0.5": [(1.2, 0.661), (1.3, 0.257), (1.4, 0.0617), (1.5, 7.98e-3), (1.6, 4.11e-4)],
    },
    (2, 64, 512, 1024): {
        "SPA": [(1.0, 0.505), (1.25, 0.246), (1.5, 0.0738), (1.75, 0.0202), (2.0, 3.65e-3),
                (2.25, 6.28e-4)],
        "OMS 0.5": [(1.25, 0.384), (1.5, 0.186), (1.75, 0.0556), (2.0, 9.14e-3),
                    (2.25, 1.14e-3)],
    },
}


# Published AWGN BLER of NR code blocks with QAM: the SINR-BLER tables of ns-3's NR module
# (5G-LENA, CTTC; gitlab.com/cttc-lena/nr, model/nr-eesm-t1.cc for MCS table 1 (qam64),
# model/nr-eesm-t2.cc for table 2 (qam256); the same numbers as the per-BG extracts
# nr-eesm-t<table>-bg<BG>.cc in github.com/UniVe-NeDS-Lab/fivegchannel,
# channelmodel/sinr_bler/LENA/), from InterDigital's link-level simulator (Lagen et al., "New
# Radio Physical Layer Abstraction for System-Level Simulations of 5G Networks", IEEE ICC
# 2020). Per base graph, MCS and "CBS" (the TBS A of a TB that its TB CRC and A make one code
# block, as the keys 24, 32, ... of the 38.214 TBS table show): SINR per RE in dB and BLER.
# Decoder, iterations, LLRs and channel estimation are not stated with them. Keyed by an
# allocation (n_prb x n_symbols, one DMRS symbol) whose 38.214 TBS is the CBS:
# {(table, mcs, n_prb, n_symbols): (file, BG, CBS, [(SINR dB, BLER), ...])}
LENA = {
    ("qam64", 4, 126, 3): ("nr-eesm-t1-bg2.cc", 2, 1864, [
        (0.9979, 1.0), (1.4356, 0.9605263), (1.8733, 0.3123449), (2.311, 0.0036),
        (2.7487, 0.0)]),
    ("qam64", 13, 89, 3): ("nr-eesm-t1-bg1.cc", 1, 4096, [
        (7.5, 1.0), (7.85, 0.9980769), (8.2, 0.638125), (8.55, 0.0346), (8.9, 0.0)]),
    ("qam64", 22, 88, 2): ("nr-eesm-t1-bg1.cc", 1, 4096, [
        (15.36, 0.9148936), (15.6226, 0.5069721), (15.883, 0.09200405), (16.1434, 0.0033),
        (16.4038, 0.0)]),
    ("qam256", 24, 52, 2): ("nr-eesm-t2-bg1.cc", 1, 4096, [
        (23.5, 0.9334532), (23.9167, 0.3027578), (24.3333, 0.0114), (24.75, 0.0)]),
}


# Published BLER of one 38.212 code block with QAM over AWGN, set-up stated in code: NVIDIA
# Sionna (github.com/NVlabs/sionna, read at 20d2bca, v1.2.1), the printed outputs of
# tutorials/phy/Bit_Interleaved_Coded_Modulation.ipynb (the same numbers in
# docs/v2.1.0/phy/tutorials/notebooks/). k information bits (no CRC, K' = k), LDPC5GEncoder(k, n):
# BG, Zc and fillers of 38.212 5.2.2 / 5.3.2, the 2 Zc first bits punctured, fillers skipped, the
# next n bits sent (rate_match at rv 0 with N_cb = N), with num_bits_per_symbol the output
# interleaver of 38.212 5.4.2.2, without it the n bits in their order, Qm per symbol; 38.211
# Gray QAM, AWGN, exact ("app") LLRs; LDPC5GDecoder: flooding schedule, 20 iterations without
# syndrome stop, LLRs clipped at +-20; no = 1 / (k/n Qm 10^(Eb/N0 / 10)) (ebnodb2no), i.e.
# Es/N0 = Eb/N0 + 10 log10(Qm k / n). The QPSK cell puts a random interleaver between encoder
# and mapper: both QPSK bits see the same channel, so any interleaver gives the same BLER.
# {name: (cell, k, n, Qm, 5.4.2.2 interleaver, their decoder, [(Eb/N0 dB, BLER, blocks), ...])}
SIONNA_NOTEBOOK = {
    "QPSK": ("In[7] run_ber", 600, 1200, 2, True, "BP boxplus-phi", [
        (0.75, 0.759, 1000), (1.0, 0.478, 1000), (1.25, 0.196, 1000), (1.5, 0.058, 1000),
        (1.75, 0.016667, 3000), (2.0, 1.697e-3, 33000)]),
    "16-QAM, 5.4.2.2 interleaver": ("In[16] model_output_interleaver", 600, 1200, 4, True,
                                    "BP boxplus", [
        (2.75, 0.814, 1000), (3.0, 0.559, 1000), (3.25, 0.329, 1000), (3.5, 0.112, 1000),
        (3.75, 0.047, 2000), (4.0, 0.0127, 10000), (4.25, 2.9333e-3, 30000)]),
    "16-QAM, no interleaver": ("In[13] model_baseline_16", 600, 1200, 4, False, "BP boxplus", [
        (3.0, 0.746, 1000), (3.25, 0.517, 1000), (3.5, 0.274, 1000), (3.75, 0.091, 2000),
        (4.0, 0.03425, 4000), (4.25, 7.2667e-3, 15000)]),
    "16-QAM, no interleaver, min-sum": ("In[20] model_allzero_16_ms", 600, 1200, 4, False,
                                        "min-sum", [
        (3.5, 0.95, 1000), (4.0, 0.657, 1000), (4.5, 0.156, 1000), (5.0, 0.0135, 2000),
        (5.5, 1.8e-4, 50000)]),
}

# Sionna's published BLER tables of its PHY abstraction, src/sionna/sys/bler_tables/
# PDSCH_table1.json and PDSCH_table2.json (since v1.0.1, unchanged at 20d2bca): MCS tables 1 and 2
# of 38.214 (5.1.3.1-1 "qam64", 5.1.3.1-2 "qam256"), code block size CBS = k, written by
# PHYAbstraction.new_bler_table with CodedAWGNChannelNR (src/sionna/phy/nr/utils.py):
# LDPC5GEncoder(k, n = ceil(k / (R Qm)) Qm, num_bits_per_symbol = Qm) as above, exact LLRs,
# LDPC5GDecoder boxplus-phi, 20 iterations, SNR = Es/N0 (their Eb/N0 = SNR - 10 log10(Qm R) with
# the R of the encoder's target). The BLERs are multiples of 1/3000 (one of 1/6000). The SNR grid
# is 15 points from -5 to 20 dB (table 1) or 20 from -5 to 25 dB (table 2), 1.79 / 1.58 dB
# apart: one point per MCS inside the waterfall, where ours is held to it at their BLER. (The
# PUSCH tables beside them are decoded by Sionna's MCSDecoderNR with transform_precoding=True,
# its call's default: 38.214 Table 6.1.4.1-1 / -2, R one step up from 5.1.3.1-1 from MCS 17.)
# CBS 2000, the waterfall point with the grid points beside it: {(table, mcs): [(SNR dB, BLER)]}
SIONNA_TABLE = {
    ("qam64", 6): [(-1.4286, 1.0), (0.3571, 0.2092), (2.1429, 0.0)],
    ("qam64", 13): [(3.9286, 1.0), (5.7143, 0.5867), (7.5, 0.0)],
    ("qam64", 17): [(7.5, 1.0), (9.2857, 0.035), (11.0714, 0.0)],
    ("qam64", 23): [(12.8571, 1.0), (14.6429, 0.0577), (16.4286, 0.0)],
    ("qam64", 25): [(14.6429, 1.0), (16.4286, 0.1477), (18.2143, 0.0)],
    ("qam256", 7): [(4.4737, 1.0), (6.0526, 0.1), (7.6316, 0.0)],
    ("qam256", 12): [(9.2105, 1.0), (10.7895, 0.066), (12.3684, 0.0)],
    ("qam256", 17): [(13.9474, 1.0), (15.5263, 0.1023), (17.1053, 0.0)],
    ("qam256", 20): [(17.1053, 1.0), (18.6842, 0.0753), (20.2632, 0.0)],
    ("qam256", 22): [(18.6842, 1.0), (20.2632, 0.038), (21.8421, 0.0)],
    ("qam256", 24): [(20.2632, 1.0), (21.8421, 0.348), (23.4211, 3.3e-4)],
    ("qam256", 27): [(23.4211, 1.0), (25.0, 0.1503)],
}
SIONNA_TABLE_CBS = 2000


def qam_labels(qm):
    """(points, labels[point, bit]) of the 38.211 constellation of Qm: point p carries the
    bits of p, the first bit the most significant."""
    points = np.array(nrsar.constellation(MODS[qm]).points(), np.complex128)
    return points, (np.arange(points.size)[:, None] >> np.arange(qm - 1, -1, -1)) & 1


def exact_llrs(y, qm, nv):
    """Exact bit LLRs, positive = 0, [symbols, Qm] of received symbols y (1-D complex) of the
    38.211 constellation of Qm at noise variance nv per complex symbol: the log-sum-exp over
    the points whose bit j is 0 minus that over those where it is 1, of -|y - s|^2 / nv. The
    38.211 QAMs are square, the even bits set the real part and the odd bits the imaginary
    part (5.1.3-5.1.5), so the sums factor and each bit's LLR is that of its axis's levels
    (sqrt(2^Qm) terms instead of 2^Qm)."""
    points, labels = qam_labels(qm)
    out = np.empty((y.size, qm))
    for j in range(qm):
        axis, part = (points.real, y.real) if j % 2 == 0 else (points.imag, y.imag)
        lse = []
        for bit in (0, 1):
            levels = np.unique(np.round(axis[labels[:, j] == bit], 12))
            m = -(part[:, None] - levels[None, :]) ** 2 / nv
            top = m.max(axis=1)
            lse.append(top + np.log(np.exp(m - top[:, None]).sum(axis=1)))
        out[:, j] = lse[0] - lse[1]
    return out


def code_block_bler(k, e, qm, esn0_db, frames, max_iter=20, interleave=True, seed=1,
                    llr_max=20.0, max_log=False):
    """Block errors of nrsar.ldpc_decode in Sionna's set-up (SIONNA_NOTEBOOK): one code block
    of k random bits (K' = k, base graph of 38.212 6.2.2 for A = k, R = k / e), ldpc_encode,
    rate_match(rv 0) to e bits, with interleave the bit interleaver of 38.212 5.4.2.2 at Qm
    (else the e bits in order), Qm bits per 38.211 symbol, AWGN at Es/N0 esn0_db, exact LLRs
    (max_log: nrsar.soft_demapper's max-log ones) clipped at +-llr_max, rate_recover,
    at most max_iter iterations. Returns the number of frames whose k bits came back wrong."""
    bg = nrsar.select_base_graph(k, k / e)
    s = nrsar.segment_sizes(k, bg)
    q = qm if interleave else 1  # the interleaver's Qm
    points = qam_labels(qm)[0]
    demap = nrsar.soft_demapper(MODS[qm])
    weights = 2 ** np.arange(qm - 1, -1, -1)
    rng = np.random.default_rng(seed)
    nv = 10 ** (-esn0_db / 10)  # unit-energy symbols
    errors = 0
    for start in range(0, frames, 100):  # 100 frames per call
        n = min(100, frames - start)
        info = rng.integers(0, 2, (n, k)).astype(np.int8)
        d = nrsar.ldpc_encode(np.hstack([info, -np.ones((n, s["K"] - k), np.int8)]), bg)
        x = np.array([nrsar.rate_match(d[f], e, 0, q, bg) for f in range(n)])
        sym = points[x.reshape(-1, qm) @ weights]
        y = sym + np.sqrt(nv / 2) * (rng.normal(size=sym.size) + 1j * rng.normal(size=sym.size))
        llr = (np.array(demap.demap(y.astype(np.complex64).tolist(), [nv])) if max_log
               else exact_llrs(y, qm, nv))
        llr = np.clip(llr, -llr_max, llr_max).astype(np.float32).reshape(n, e)
        soft = np.array([nrsar.rate_recover(llr[f], bg, s["Zc"], k, 0, q) for f in range(n)])
        c, _, _ = nrsar.ldpc_decode(soft, bg, max_iter)
        errors += int(np.count_nonzero(np.any(c[:, :k] != info, axis=1)))
    return errors


def bpsk_fer(bg, zc, k_prime, e, ebn0_db, frames, max_iter=10, seed=1, failures=None):
    """Frame error rate of nrsar.ldpc_decode over BPSK-AWGN in the set-up of PUBLISHED:
    K' random bits and K - K' fillers, ldpc_encode, rate_match(rv 0) to E bits, LLRs
    2 y / sigma^2 at Eb/N0 = Es/N0 - 10 log10(K' / E), rate_recover, at most max_iter
    iterations. Returns the number of frames whose K' bits came back wrong; failures (a
    list), when given, receives (LLRs of d, K' bits) of each of them."""
    k = (22 if bg == 1 else 10) * zc  # K of 38.212 5.3.2
    rng = np.random.default_rng(seed)
    sigma2 = 1.0 / (2.0 * 10 ** ((ebn0_db + 10 * np.log10(k_prime / e)) / 10))
    errors = 0
    for start in range(0, frames, 1000):  # encoded and decoded 1000 frames per call
        n = min(1000, frames - start)
        info = rng.integers(0, 2, (n, k_prime)).astype(np.int8)
        d = nrsar.ldpc_encode(np.hstack([info, -np.ones((n, k - k_prime), np.int8)]), bg)
        soft = np.empty(d.shape, np.float32)
        for f in range(n):
            x = nrsar.rate_match(d[f], e, 0, 1, bg)
            y = 1.0 - 2.0 * x + np.sqrt(sigma2) * rng.normal(size=e)
            soft[f] = nrsar.rate_recover((2.0 * y / sigma2).astype(np.float32), bg, zc, k_prime, 0, 1)
        c, _, _ = nrsar.ldpc_decode(soft, bg, max_iter)
        wrong = np.flatnonzero(np.any(c[:, :k_prime] != info, axis=1))
        errors += len(wrong)
        if failures is not None:
            failures.extend((soft[f], info[f]) for f in wrong)
    return errors


def poisson_interval(n, confidence=0.95):
    """Exact two-sided interval of a Poisson mean from n observed events: the means whose
    P(X <= n) and P(X >= n) are (1 - confidence) / 2, by bisection."""
    tail = (1.0 - confidence) / 2

    def cdf(n_, mu):  # P(X <= n_)
        return math.fsum(math.exp(j * math.log(mu) - mu - math.lgamma(j + 1)) for j in range(n_ + 1))

    def solve(f):  # f falls from positive to negative in mu
        lo, hi = 1e-9, 10.0 * n + 10.0
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if f(mid) > 0 else (lo, mid)
        return 0.5 * (lo + hi)
    lower = 0.0 if n == 0 else solve(lambda mu: tail - (1.0 - cdf(n - 1, mu)))  # P(X >= n)
    return lower, solve(lambda mu: cdf(n, mu) - tail)


def bicm_capacity_dispersion(qm, snr_db, symbols=100000, seed=7):
    """(C, V) per coded bit of BICM over AWGN with the 38.211 constellation of Qm and exact
    (log-sum-exp) bit LLRs, by Monte Carlo: the information density of a coded bit is
    i = 1 - log2(1 + exp(-(1 - 2b) L)); C = its mean over the Qm bit levels, V = the mean of
    the levels' variances (a codeword spreads its bits equally over the levels, so the
    levels' different means add nothing random)."""
    points, labels = qam_labels(qm)
    rng = np.random.default_rng(seed)
    nv = 10 ** (-snr_db / 10)
    sent = rng.integers(0, points.size, symbols)
    y = points[sent] + np.sqrt(nv / 2) * (rng.normal(size=symbols) + 1j * rng.normal(size=symbols))
    llrs = exact_llrs(y, qm, nv)
    c, v = [], []
    for j in range(qm):
        b = labels[sent, j]
        info = 1.0 - np.logaddexp(0.0, -(1 - 2 * b) * llrs[:, j]) / np.log(2)
        c.append(info.mean())
        v.append(info.var())
    return float(np.mean(c)), float(np.mean(v))


def normal_approximation_snr_db(qm, n, k, target=0.1, symbols=100000):
    """SNR (Es/N0, dB) where the normal approximation of Polyanskiy, Poor and Verdu (IEEE
    Trans. IT 56(5), 2010, eq. (296) with the 1/2 log2 n term) gives BLER = target for k
    information bits in n coded bits of BICM: Q((n C - k + log2(n) / 2) / sqrt(n V)) = target.
    No code of that length and rate does better on this channel (to the approximation's
    accuracy); a practical decoder sits some tenths of a dB to a dB above it."""
    from statistics import NormalDist
    need = NormalDist().inv_cdf(1.0 - target)  # Q^-1(target)
    shannon = 10 * np.log10(2 ** (k / (n / qm)) - 1)  # the bound lies above it
    lo, hi = shannon - 0.5, shannon + 4.0
    for _ in range(30):  # bisection, the same noise draws at every SNR
        mid = 0.5 * (lo + hi)
        c, v = bicm_capacity_dispersion(qm, mid, symbols)
        if (n * c - k + 0.5 * np.log2(n)) / np.sqrt(n * v) > need:
            hi = mid
        else:
            lo = mid
        if hi - lo < 0.01:
            break
    return 0.5 * (lo + hi)


def snr_at(curve, target=0.1):
    """SNR of BLER = target, linear in log BLER between the two points around it."""
    s, b = curve["snr_db"], curve["bler"]
    for i in range(len(b) - 1):
        if b[i] >= target > b[i + 1]:
            lo, hi = np.log10(max(b[i], 1e-9)), np.log10(max(b[i + 1], 1e-9))
            return s[i] + (np.log10(target) - lo) / (hi - lo) * (s[i + 1] - s[i])
    return None


def sionna_tables(blocks, max_iter, max_log=False):
    """Prints the --sionna tables: ours (code_block_bler) on a 0.125 dB grid beside each
    published case, at Sionna's 10 % point (SIONNA_NOTEBOOK) or at its BLER (SIONNA_TABLE);
    max_log: our max-log LLRs instead of their exact ones."""
    def db(x, sign=""):
        return "n/a" if x is None else f"{x:{sign}.2f} dB"
    print("| Sionna notebook case (cell) | k / n, Qm, BG, Zc | their decoder | Eb/N0 (dB): "
          "BLER, ours | ours 10 % | Sionna 10 % | ours - Sionna |")
    print("|---|---|---|---|---|---|---|")
    for name, (cell, k, n, qm, inter, theirs, pub) in SIONNA_NOTEBOOK.items():
        bg = nrsar.select_base_graph(k, k / n)
        offset = 10 * np.log10(qm * k / n)  # Es/N0 - Eb/N0 of ebnodb2no
        pts = np.round(np.arange(pub[0][0] - 0.5, pub[-1][0] + 0.01, 0.125), 3)
        c = {"snr_db": list(pts), "bler": [
            code_block_bler(k, n, qm, p + offset, blocks, max_iter, inter, max_log=max_log)
            / blocks for p in pts]}
        ours = snr_at(c)
        at = snr_at({"snr_db": [p for p, _, _ in pub], "bler": [b for _, b, _ in pub]})
        print(f"| {name} ({cell}) | {k} / {n}, {qm}, BG{bg}, {nrsar.segment_sizes(k, bg)['Zc']} | "
              f"{theirs}, 20 it. | "
              + ", ".join(f"{p:g}: {b:.3f}" for p, b in zip(c["snr_db"], c["bler"]))
              + f" | {db(ours)} | {db(at)} | {db(None if ours is None else ours - at, '+')} |")
    print()
    print("| Sionna table, MCS (Qm, R) | k / n, BG | Sionna: SNR (dB): BLER | ours: SNR (dB): "
          "BLER | ours at Sionna's BLER | ours - Sionna |")
    print("|---|---|---|---|---|---|")
    k = SIONNA_TABLE_CBS
    for (table, mcs), pub in SIONNA_TABLE.items():
        qm, rate = nrsar.mcs(table, mcs)
        n = int(np.ceil(k / (rate * qm))) * qm
        snr, bler = next((p, b) for p, b in pub if 0 < b < 1)
        pts = np.round(np.arange(snr - 1.0, snr + 0.51, 0.125), 4)
        c = {"snr_db": list(pts), "bler": [
            code_block_bler(k, n, qm, p, blocks, max_iter, max_log=max_log) / blocks
            for p in pts]}
        ours = snr_at(c, bler)
        name = "PDSCH_table1" if table == "qam64" else "PDSCH_table2"
        print(f"| {name}, {mcs} ({qm}, {rate:.3f}) | {k} / {n}, "
              f"BG{nrsar.select_base_graph(k, k / n)} | "
              + ", ".join(f"{p:g}: {b:.4g}" for p, b in pub) + " | "
              + ", ".join(f"{p:g}: {b:.3f}" for p, b in zip(c["snr_db"], c["bler"]))
              + f" | {db(ours)} | {db(None if ours is None else ours - snr, '+')} |")


@dataclasses.dataclass
class NrBlerOptions(Options):
    blocks: int = option(100, "transport blocks per SNR", at_least=1, at_most=10 ** 7)
    max_iter: int = option(20, "LDPC iterations at most", at_least=1, at_most=100)
    only: str = option("", "table:mcs,... of CASES to run (default: all)")
    published: bool = option(False, "instead: BPSK FER against AFF3CT's published curves "
                             "(PUBLISHED), --blocks frames per point, 10 iterations")
    harq: bool = option(False, "HARQ gain instead: qam64 MCS 13 sent once (rv 0) and twice "
                        "(rv 0 + rv 2, combined)")
    floor: bool = option(False, "instead: the short BG2 code of PUBLISHED (K' 512) from 2.0 to "
                         "3.0 dB, --blocks frames per point, FER with its 95-percent interval")
    lena: bool = option(False, "instead: BLER against 5G-LENA's published AWGN tables (LENA), "
                        "--blocks TBs per point")
    sionna: bool = option(False, "instead: one code block's BLER against Sionna's published "
                          "QAM curves (SIONNA_NOTEBOOK, SIONNA_TABLE), --blocks per point")
    max_log: bool = option(False, "with --sionna: max-log LLRs (nrsar.soft_demapper) instead "
                           "of Sionna's exact ones")

    def check(self):
        cases = [f"{t}:{m}" for t, m, _ in CASES]
        for w in (w for w in self.only.split(",") if w):
            if w not in cases:
                raise OptionError(f"--only = {self.only!r}: {w!r} is not one of "
                                  f"{', '.join(cases)}")


def main(argv=None):
    args = cli.parse("nr_bler", NrBlerOptions, __doc__, argv)
    if args is None:
        return cli.EXIT_USAGE
    if args.published:
        print("| code | Eb/N0 (dB): FER, ours | ours 10 % / 1 % | SPA 10 % / 1 % | "
              "OMS 0.5 10 % / 1 % | ours - SPA at 10 % / 1 % |")
        print("|---|---|---|---|---|---|")
        for (bg, zc, kp, e), pub in PUBLISHED.items():
            pts = np.round(np.arange(pub["SPA"][0][0], pub["SPA"][-1][0] + 0.76, 0.1), 2)
            fer = [bpsk_fer(bg, zc, kp, e, p, args.blocks) / args.blocks for p in pts]
            ours = {"snr_db": list(pts), "bler": fer}
            at = {name: [snr_at({"snr_db": [p for p, _ in c], "bler": [f for _, f in c]}, t)
                         for t in (0.1, 0.01)] for name, c in pub.items()}
            mine = [snr_at(ours, t) for t in (0.1, 0.01)]

            def fmt(v):
                return "/".join("n/a" if x is None else f"{x:.2f}" for x in v)
            gap = [None if m is None or s_ is None else m - s_ for m, s_ in zip(mine, at["SPA"])]
            print(f"| BG{bg} Zc {zc} K' {kp} E {e} | "
                  + ", ".join(f"{p:g}: {f:.3f}" for p, f in zip(pts, fer))
                  + f" | {fmt(mine)} | {fmt(at['SPA'])} | {fmt(at['OMS 0.5'])} | {fmt(gap)} |")
        return 0
    if args.floor:
        bg, zc, kp, e = 2, 64, 512, 1024
        oms = dict(PUBLISHED[(bg, zc, kp, e)]["OMS 0.5"])
        print("| Eb/N0 | frames | failed | FER | 95 % interval | published OMS 0.5 |")
        print("|---|---|---|---|---|---|")
        for p in (2.0, 2.25, 2.5, 2.75, 3.0):
            n = bpsk_fer(bg, zc, kp, e, p, args.blocks)
            lo, hi = poisson_interval(n)
            pub = f"{oms[p]:.2e}" if p in oms else "n/a"
            print(f"| {p:g} dB | {args.blocks} | {n} | {n / args.blocks:.2e} | "
                  f"{lo / args.blocks:.1e} .. {hi / args.blocks:.1e} | {pub} |")
        return 0
    if args.lena:
        print("| LENA: file, MCS, CBS | Qm | R | ours: PRB x symbols, TBS, G, BG, code blocks | "
              "SNR (dB): BLER, ours | ours 10 % | LENA 10 % | ours - LENA | "
              "normal approximation | ours - bound | LENA - bound |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for (table, mcs, n_prb, n_sym), (name, bg, cbs, pub) in LENA.items():
            qm, rate, a, g = allocation(table, mcs, n_prb, n_sym)
            start = np.round(10 * np.log10(2 ** (a / (g / qm)) - 1) * 8) / 8 + 0.75
            c = bler_curve(table, mcs, n_prb, np.arange(start, start + 2.26, 0.125), args.blocks,
                           args.max_iter, n_symbols=n_sym)
            ours = snr_at(c)
            theirs = snr_at({"snr_db": [p for p, _ in pub], "bler": [b for _, b in pub]})
            na = normal_approximation_snr_db(qm, g, a)
            pts = ", ".join(f"{p:g}: {b:.3f}" for p, b in zip(c["snr_db"], c["bler"]))

            def db(x, sign=""):
                return "n/a" if x is None else f"{x:{sign}.2f} dB"
            print(f"| {name}, MCS {mcs}, CBS {cbs} (BG{bg}) | {qm} | {rate:.3f} | "
                  f"{n_prb} x {n_sym}, {a}, {g}, BG{c['base_graph']}, {c['code_blocks']} | "
                  f"{pts} | {db(ours)} | {db(theirs)} | "
                  f"{db(None if ours is None else ours - theirs, '+')} | {db(na)} | "
                  f"{db(None if ours is None else ours - na, '+')} | {db(theirs - na, '+')} |")
        return 0
    if args.sionna:
        sionna_tables(args.blocks, args.max_iter, args.max_log)
        return 0
    if args.harq:
        print("| transmissions | SNR (dB): BLER | BLER 10 % at |")
        print("|---|---|---|")
        for rvs in ((0,), (0, 2)):
            c = bler_curve("qam64", 13, 20, np.arange(1.0, 7.01, 0.5), args.blocks,
                           args.max_iter, rvs=rvs)
            pts = ", ".join(f"{s:g}: {b:.2f}" for s, b in zip(c["snr_db"], c["bler"]))
            at = snr_at(c)
            print(f"| rv {' + '.join(map(str, rvs))} | {pts} | "
                  f"{'n/a' if at is None else f'{at:.2f} dB'} |")
        return 0
    print("| MCS | Qm | R | TBS | G | SNR (dB): BLER | BLER 10 % at | Shannon limit | gap | "
          "normal approximation (BICM) | gap |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    only = {tuple(w.split(":")) for w in args.only.split(",") if w}
    for table, mcs, n_prb in CASES:
        if only and (table, str(mcs)) not in only:
            continue
        qm, rate, a, g = allocation(table, mcs, n_prb)
        start = np.round(10 * np.log10(2 ** (a / (g / qm)) - 1) * 4) / 4 + 0.5
        c = bler_curve(table, mcs, n_prb, np.arange(start, start + 3.51, 0.25), args.blocks,
                       args.max_iter)
        at = snr_at(c)
        pts = ", ".join(f"{s:g}: {b:.2f}" for s, b in zip(c["snr_db"], c["bler"]))
        limit = c["shannon_db"]
        at_s = "n/a" if at is None else f"{at:.2f} dB"
        gap_s = "" if at is None else f"{at - limit:.2f} dB"
        na = normal_approximation_snr_db(qm, c["g"], c["tbs"])
        na_gap = "" if at is None else f"{at - na:.2f} dB"
        print(f"| {table} {mcs} | {qm} | {rate:.3f} | {c['tbs']} | {c['g']} | {pts} | "
              f"{at_s} | {limit:.2f} dB | {gap_s} | {na:.2f} dB | {na_gap} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
