#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Flowgraph throughput (time-domain samples/s) of ofdm_mod, ofdm_demod and ofdm_sync against
gr-digital's OFDM blocks, same run, at the `paper` (3333 of 4096, CP 1024, 122.88 Msps) and
`sdr20` (612 of 1024, CP 256, 30.72 Msps) numerologies.

Peers (all with one FFTW thread):
- ofdm_mod: stream_to_tagged_stream (one symbol per packet) -> digital.ofdm_carrier_allocator_cvc (same subcarrier ->
  bin map, unshifted) -> fft.fft_vcc (inverse) -> digital.ofdm_cyclic_prefixer. The peer
  does not scale by 1/sqrt(fft_size) (favours it).
- ofdm_demod: blocks.keep_m_in_n (drop the CP) -> stream_to_vector -> fft.fft_vcc (forward);
  the peer neither scales nor extracts the N subcarriers from the fft_size bins (favours it).
- ofdm_sync: digital.ofdm_sync_sc_cfb (S&C metric, plateau detector, CFO output, every
  sample). Ours is measured searching (pure noise, never locks: the metric on every sample)
  and tracking (locked on a burst at the start, then CFO derotation of every sample).
"""

import numpy as np
from gnuradio import blocks, digital, fft, gr

from gnuradio import nrsar
from gnuradio.nrsar.bench import benchutil


def _grid(num, symbols, seed=1, dmrs=True):
    rng = np.random.default_rng(seed)
    n = num.num_subcarriers
    g = ((2 * rng.integers(0, 2, (symbols, n)) - 1) +
         1j * (2 * rng.integers(0, 2, (symbols, n)) - 1)) / np.sqrt(2)
    if dmrs:
        for s in range(symbols):
            if s % num.symbols_per_slot in (2, 11):
                g[s, 1::2] = 0
    return g.astype(np.complex64)


def _samples(num, grid):
    tb = gr.top_block()
    snk = blocks.vector_sink_c()
    tb.connect(blocks.vector_source_c(grid.ravel().tolist(), False, num.num_subcarriers),
               nrsar.ofdm_mod(num), snk)
    tb.run()
    return np.array(snk.data(), np.complex64)


def run(quick=False):
    rows = []
    for preset in ("paper", "sdr20"):
        num = nrsar.make_numerology(preset)
        n, f, cp = num.num_subcarriers, num.fft_size, num.cp_samples
        L = f + cp
        k0 = num.dc_subcarrier()
        symbols = (400 if quick else 4000) * (4 if preset == "sdr20" else 1)
        grid = _grid(num, 14)
        flat = grid.ravel().tolist()
        bins = [[(k - k0) % f for k in range(n)]]

        def mod_ours(tb, items):
            src = blocks.vector_source_c(flat, True, n)
            head = blocks.head(gr.sizeof_gr_complex * n, items)
            tb.connect(src, head, nrsar.ofdm_mod(num), blocks.null_sink(gr.sizeof_gr_complex))

        def mod_peer(tb, items):
            src = blocks.vector_source_c(flat, True, 1)
            head = blocks.head(gr.sizeof_gr_complex, items * n)
            tag = blocks.stream_to_tagged_stream(gr.sizeof_gr_complex, 1, n, "packet_len")
            alloc = digital.ofdm_carrier_allocator_cvc(f, bins, [[]], [[]], [], "packet_len",
                                                       False)
            ifft = fft.fft_vcc(f, False, [], False, 1)
            cpx = digital.ofdm_cyclic_prefixer(f, L, 0, "packet_len")
            cpx.set_min_output_buffer(2 * L)  # a tagged-stream block writes whole packets
            tb.connect(src, head, tag, alloc, ifft, cpx, blocks.null_sink(gr.sizeof_gr_complex))

        a = benchutil.items_per_second(mod_ours, symbols) * L
        b = benchutil.items_per_second(mod_peer, symbols) * L
        rows.append(benchutil.row(f"ofdm_mod {preset}", a,
                                  "carrier_allocator_cvc + fft_vcc + ofdm_cyclic_prefixer", b,
                                  unit="samples/s", sample_rate=num.sample_rate_hz()))

        x = _samples(num, grid).tolist()

        def demod_ours(tb, items):
            src = blocks.vector_source_c(x, True)
            head = blocks.head(gr.sizeof_gr_complex, items * L)
            tb.connect(src, head, nrsar.ofdm_demod(num),
                       blocks.null_sink(gr.sizeof_gr_complex * n))

        def demod_peer(tb, items):
            src = blocks.vector_source_c(x, True)
            head = blocks.head(gr.sizeof_gr_complex, items * L)
            keep = blocks.keep_m_in_n(gr.sizeof_gr_complex, f, L, cp)
            s2v = blocks.stream_to_vector(gr.sizeof_gr_complex, f)
            dft = fft.fft_vcc(f, True, [], False, 1)
            tb.connect(src, head, keep, s2v, dft, blocks.null_sink(gr.sizeof_gr_complex * f))

        a = benchutil.items_per_second(demod_ours, symbols) * L
        b = benchutil.items_per_second(demod_peer, symbols) * L
        rows.append(benchutil.row(f"ofdm_demod {preset}", a, "keep_m_in_n (CP) + fft_vcc", b,
                                  unit="samples/s", sample_rate=num.sample_rate_hz()))

        rng = np.random.default_rng(2)
        noise = ((rng.normal(size=1 << 18) + 1j * rng.normal(size=1 << 18)) *
                 0.1).astype(np.complex64).tolist()
        burst = x + noise
        nsamp = symbols * L
        dmrs = nrsar.make_dmrs("pusch2")

        def sync_ours(tb, items, data):
            src = blocks.vector_source_c(data, True)
            head = blocks.head(gr.sizeof_gr_complex, items)
            tb.connect(src, head, nrsar.ofdm_sync(num, dmrs),
                       blocks.null_sink(gr.sizeof_gr_complex))

        def sync_peer(tb, items):
            src = blocks.vector_source_c(burst, True)
            head = blocks.head(gr.sizeof_gr_complex, items)
            sc = digital.ofdm_sync_sc_cfb(f, cp, False, 0.9)
            tb.connect(src, head, sc)
            tb.connect((sc, 0), blocks.null_sink(gr.sizeof_float))
            tb.connect((sc, 1), blocks.null_sink(gr.sizeof_char))

        peer = benchutil.items_per_second(sync_peer, nsamp)
        search = benchutil.items_per_second(lambda tb, i: sync_ours(tb, i, noise), nsamp)
        track = benchutil.items_per_second(lambda tb, i: sync_ours(tb, i, burst), nsamp)
        rows.append(benchutil.row(f"ofdm_sync {preset} searching", search,
                                  "digital.ofdm_sync_sc_cfb", peer, unit="samples/s",
                                  sample_rate=num.sample_rate_hz()))
        rows.append(benchutil.row(f"ofdm_sync {preset} tracking", track,
                                  "digital.ofdm_sync_sc_cfb", peer, unit="samples/s",
                                  sample_rate=num.sample_rate_hz()))
    return rows


if __name__ == "__main__":
    benchutil.main(run, __doc__)
