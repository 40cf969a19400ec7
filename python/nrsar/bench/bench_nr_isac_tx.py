#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nr_isac_tx throughput (OFDM symbols/s, paper numerology, 256-QAM) against a stock GNU
Radio chain making the same symbols from random bytes:
vector_source_b -> packed_to_unpacked_bb(8) -> chunks_to_symbols_bc(table) -> stream_to_vector(N).

Real time for the paper numerology is 24,000 symbols/s (PRF); `realtime` = ours / 24,000.
"""

import numpy as np

from gnuradio import blocks, digital, gr

from . import benchutil
from ..nrsar_python import constellation, modulation, nr_isac_tx, srs_config, tx_mode
from ..params import make_numerology

REALTIME_SYMBOLS_PER_S = 24e3


def _bytes(n_sc, seed=1):
    # 16 symbols' worth of random bytes, repeated by the source
    return np.random.default_rng(seed).integers(0, 256, 16 * n_sc, dtype=np.uint8).tolist()


def run(quick=False):
    num = make_numerology("paper")
    n_sc = num.num_subcarriers
    nsym = 3000 if quick else 24000
    item = gr.sizeof_gr_complex * n_sc
    payload = _bytes(n_sc)
    table = list(constellation(modulation.QAM256).points())

    def ours_prbs(tb, n):
        tx = nr_isac_tx(num, modulation.QAM256, tx_mode.DATA, srs_config(), 1)
        tb.connect(tx, blocks.head(item, n), blocks.null_sink(item))

    def ours_stream(tb, n):
        src = blocks.vector_source_b(payload, True)
        tx = nr_isac_tx(num, modulation.QAM256, tx_mode.DATA, srs_config(), 1)
        tb.connect(src, tx, blocks.head(item, n), blocks.null_sink(item))

    def peer(tb, n):
        src = blocks.vector_source_b(payload, True)
        unpack = blocks.packed_to_unpacked_bb(8, gr.GR_MSB_FIRST)
        mapper = digital.chunks_to_symbols_bc(table, 1)
        s2v = blocks.stream_to_vector(gr.sizeof_gr_complex, n_sc)
        tb.connect(src, unpack, mapper, s2v, blocks.head(item, n), blocks.null_sink(item))

    peer_rate = benchutil.items_per_second(peer, nsym)
    rows = []
    for name, build in (("nr_isac_tx 256-QAM PRBS", ours_prbs),
                        ("nr_isac_tx 256-QAM stream bytes", ours_stream)):
        ours = benchutil.items_per_second(build, nsym)
        rows.append(benchutil.row(name, ours,
                                  "vector_source_b>packed_to_unpacked_bb>chunks_to_symbols_bc"
                                  ">stream_to_vector", peer_rate, unit="symbols/s",
                                  subcarriers=n_sc, symbols=nsym,
                                  realtime=ours / REALTIME_SYMBOLS_PER_S))
    return rows


if __name__ == "__main__":
    benchutil.main(run, __doc__)
