#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""pusch_receiver throughput at the paper numerology (N = 3333, 256-QAM, DMRS pusch2),
uncoded and with the TS 38.212 UL-SCH (qam256 MCS 27, R 0.93), against the stock GNU Radio
peers in the same run: gr-digital constellation_decoder_cb (hard 256-QAM slicing of the same
data REs, no channel estimation, no CRC) and the gr-fec decoder block with gr-fec's
ldpc_decoder of n_1800_k_0902 (belief propagation of the same number of code bits: the
decoder the backhaul used before issue #15)."""

import numpy as np

from gnuradio import blocks, digital, fec, gr
from gnuradio import nrsar

from .. import backhaul
from .benchutil import items_per_second, main, row


def _receiver_rate(cfg, grid, nslots):
    num = cfg.num
    n = num.num_subcarriers
    flat = grid.reshape(-1).tolist()

    def build(tb, items):
        src = blocks.vector_source_c(flat, True, n)
        head = blocks.head(gr.sizeof_gr_complex * n, items)
        rx = nrsar.pusch_receiver(cfg)
        tb.connect(src, head, rx)

    return items_per_second(build, nslots * num.symbols_per_slot, repeats=2)


def run(quick=False):
    num = nrsar.make_numerology("paper")
    mod = nrsar.make_modulation("qam256")
    dmrs = nrsar.make_dmrs("pusch2")
    n, sps = num.num_subcarriers, num.symbols_per_slot
    rows = []
    # uncoded
    nslots = 4 if quick else 40
    cfg = nrsar.make_pusch_config(num, "qam256", dmrs, "none")
    grid, enc = backhaul.transmit_grid(cfg, [], 2)
    grid = grid + (0.003 * (np.random.default_rng(0).standard_normal(grid.shape) +
                            1j * np.random.default_rng(1).standard_normal(grid.shape))).astype(np.complex64)
    sym_rate = _receiver_rate(cfg, grid, nslots)
    data_res = grid.reshape(-1, sps, n)[:, [l for l in range(sps) if l not in (2, 11)], :].reshape(-1)
    pts = nrsar.constellation(mod).points()
    const = digital.constellation_rect(pts, list(range(256)), 4, 16, 16,
                                       float(2 / np.sqrt(170)), float(2 / np.sqrt(170))).base()
    peer_items = nslots * 12 * n

    def build_peer(tb, items):
        src = blocks.vector_source_c(data_res.tolist(), True)
        head = blocks.head(gr.sizeof_gr_complex, items)
        dec = digital.constellation_decoder_cb(const)
        tb.connect(src, head, dec, blocks.null_sink(gr.sizeof_char))

    peer = items_per_second(build_peer, peer_items, repeats=2)
    slot_rate = sym_rate / sps
    rows.append(row("pusch_receiver uncoded 256-QAM (data REs/s)", slot_rate * 12 * n,
                    "digital.constellation_decoder_cb (hard slicing only)", peer, "REs/s",
                    payload_mbps=slot_rate * enc.payload_bits_per_slot() / 1e6,
                    realtime_mbps=enc.throughput_bps() / 1e6))
    # the UL-SCH of 38.212
    nslots = 4 if quick else 20
    cfg = nrsar.make_pusch_config(num, "qam256", dmrs, "nr-ldpc")
    grid, enc = backhaul.transmit_grid(cfg, [], 2)
    grid = grid + (0.003 * np.random.default_rng(3).standard_normal(grid.shape)).astype(np.complex64)
    sym_rate = _receiver_rate(cfg, grid, nslots)
    slot_rate = sym_rate / sps
    alist = "/usr/share/gnuradio/fec/ldpc/n_1800_k_0902_gap_28.alist"
    # the all-zero codeword (gr-fec convention: bit 0 -> -1) at high SNR (sigma 0.05), as the
    # codewords inside the receiver's grid (noise 0.003 per RE): both converge at once
    soft = (-1.0 + 0.05 * np.random.default_rng(2).standard_normal(1800 * 4)).astype(np.float32)

    def build_fec(tb, items):
        src = blocks.vector_source_f(soft.tolist(), True)
        head = blocks.head(gr.sizeof_float, items)
        dec = fec.decoder(fec.ldpc_decoder.make(alist, 0.5, 25), gr.sizeof_float, gr.sizeof_char)
        tb.connect(src, head, dec, blocks.null_sink(gr.sizeof_char))

    peer = items_per_second(build_fec, 1800 * (20 if quick else 200), repeats=1)
    rows.append(row("pusch_receiver NR LDPC 256-QAM (code bits/s)", slot_rate * enc.slot_bits(),
                    "fec.decoder(ldpc_decoder) n_1800_k_0902 (code bits/s)", peer, "bits/s",
                    payload_mbps=slot_rate * enc.payload_bits_per_slot() / 1e6,
                    realtime_mbps=enc.throughput_bps() / 1e6))
    return rows


if __name__ == "__main__":
    main(run, __doc__)
