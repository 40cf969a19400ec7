#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""NR LDPC decoding (nrsar.ldpc_decode: TS 38.212 BG1, layered min-sum, int8 AVX2) against
gr-fec's ldpc_decoder (belief propagation from an alist file) on the same words, same run.

Words: BG1, Zc = 384 (Zc = 96 with --quick: gr-fec's Gaussian elimination of H at Zc = 384
takes tens of seconds), K = 22 Zc information bits at rate 0.9 (the first K / 0.9 bits of
d sent, BPSK over AWGN at Es/N0 = 5 dB, 2 dB above the BI-AWGN limit of the rate), at most
8 iterations for both. gr-fec gets the H of the rows our decoder uses (the 4 core rows and
the one extension row whose parity bits are sent) over the 27 columns they touch, as an
alist, and the same LLRs (its input convention: -LLR sigma^2 / 2). Rate = decoded
information bits per second, one core (gr-fec: a fec.decoder block in a flowgraph; ours:
one ldpc_decode call on all words). Also reported: blocks decoded right, by each (gr-fec's
output bits are its own systematic selection, so its noisy output is compared with its
output for the noiseless word).
"""

import os
import tempfile
import time

import numpy as np
from gnuradio import blocks, fec, gr

from gnuradio import nrsar
from gnuradio.nrsar.bench import benchutil

RATE = 0.9
ESN0_DB = 5.0
MAX_ITER = 8
SIGMA_PEER = 0.5  # gr-fec's BP sigma, as lib/kernel/transport_block.cc uses it


def write_alist(path, base_graph, zc, block_rows, block_cols):
    """H of base-graph rows < block_rows and columns < block_cols (TS 38.212 5.3.2, block
    (i, j) = identity shifted right by V_ij mod Zc), in the alist format gr-fec reads."""
    table = nrsar.ldpc_base_graph(base_graph)
    ils = nrsar.lifting_set_index(zc)
    rows = [[] for _ in range(block_rows * zc)]
    for i, j, *v in table:
        if i < block_rows and j < block_cols:
            for r in range(zc):
                rows[i * zc + r].append(j * zc + (r + v[ils] % zc) % zc)
    cols = [[] for _ in range(block_cols * zc)]
    for r, cs in enumerate(rows):
        for c in cs:
            cols[c].append(r)
    with open(path, "w") as f:
        f.write(f"{len(cols)} {len(rows)}\n{max(map(len, cols))} {max(map(len, rows))}\n")
        f.write(" ".join(str(len(c)) for c in cols) + "\n")
        f.write(" ".join(str(len(r)) for r in rows) + "\n")
        for c in cols:
            f.write(" ".join(str(r + 1) for r in sorted(c)) + "\n")
        for r in rows:
            f.write(" ".join(str(c + 1) for c in sorted(r)) + "\n")


def words(zc, n_words, seed=7):
    """(info bits C x K, channel LLRs C x N, noiseless LLRs C x N) for BG1 at RATE."""
    rng = np.random.default_rng(seed)
    k = 22 * zc
    info = rng.integers(0, 2, (n_words, k))
    d = nrsar.ldpc_encode(info, 1).astype(np.float64)
    n_tx = int(k / RATE)
    sigma = np.sqrt(0.5 / 10 ** (ESN0_DB / 10))
    y = 1.0 - 2.0 * d[:, :n_tx] + sigma * rng.normal(size=(n_words, n_tx))
    llr = np.zeros(d.shape, np.float32)
    llr[:, :n_tx] = 2.0 * y / sigma ** 2
    clean = np.zeros(d.shape, np.float32)
    clean[:, :n_tx] = 10.0 * (1.0 - 2.0 * d[:, :n_tx])
    return info, llr, clean, n_tx


def peer_decode(dec, llr, zc):
    """gr-fec decoder dec in a flowgraph over all words: (seconds, bits per word)."""
    n_cols = 27 * zc
    # gr-fec sees the 2 Zc punctured bits too (input 0), then d up to column 27.
    x = np.zeros((llr.shape[0], n_cols), np.float32)
    x[:, 2 * zc:] = -llr[:, :n_cols - 2 * zc] * SIGMA_PEER ** 2 / 2
    k = dec.get_output_size()
    tb = gr.top_block()
    src = blocks.vector_source_f(x.ravel().tolist(), False)
    snk = blocks.vector_sink_b()
    tb.connect(src, fec.decoder(dec, gr.sizeof_float, gr.sizeof_char), snk)
    t = time.perf_counter()
    tb.run()
    seconds = time.perf_counter() - t
    return seconds, np.array(snk.data(), np.uint8).reshape(-1, k)


def run(quick=False):
    zc = 96 if quick else 384
    n_words = 8 if quick else 32
    info, llr, clean, n_tx = words(zc, n_words)
    k = 22 * zc
    best = None
    for _ in range(3):
        t = time.perf_counter()
        bits, iters, ok = nrsar.ldpc_decode(llr, 1, MAX_ITER)
        dt = time.perf_counter() - t
        best = dt if best is None else min(best, dt)
    ours_ok = int(np.sum(np.all(bits == info, axis=1)))
    with tempfile.TemporaryDirectory() as tmp:
        alist = os.path.join(tmp, f"nr_bg1_z{zc}_rows5_cols27.alist")
        write_alist(alist, 1, zc, 5, 27)  # rows 0..4: core + the extension row of column 26
        dec = fec.ldpc_decoder.make(alist, SIGMA_PEER, MAX_ITER)
    peer_s, peer_bits = peer_decode(dec, llr, zc)
    _, peer_ref = peer_decode(dec, clean, zc)
    peer_ok = int(np.sum(np.all(peer_bits == peer_ref, axis=1)))
    return [benchutil.row(f"nr ldpc decode BG1 Zc {zc} R 0.9 <= 8 it", n_words * k / best,
                          "fec.ldpc_decoder (BP, alist of the same rows)", n_words * k / peer_s,
                          unit="info bits/s", iterations_mean=float(np.mean(iters)),
                          blocks=n_words, ours_ok=ours_ok, peer_ok=peer_ok, n_tx=n_tx)]


if __name__ == "__main__":
    benchutil.main(run, __doc__)
