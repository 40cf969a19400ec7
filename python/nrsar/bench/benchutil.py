#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Flowgraph-level throughput measurement shared by the bench_*.py modules.

Every comparison runs our block and its peer (stock GNU Radio blocks, gr-radar, numpy)
on the same input in the same process, so the reported ratio is meaningful on any
machine. Each bench_<block>.py module exposes run(quick) -> list of result rows, and runs
alone through main() (python3 -m gnuradio.nrsar.bench.bench_<block> [--quick]).
"""

import argparse
import time

from gnuradio import blocks, gr

from .. import runtime


def items_per_second(build, n_items, repeats=3, clock=time.perf_counter):
    """Best-of-`repeats` throughput of a flowgraph.

    build(tb, head_items) must connect a flowgraph into top block tb that processes
    head_items items through the block under test and then stops by itself.
    clock=time.process_time gives items per CPU second of the process (all flowgraph
    threads), steadier than wall time when other jobs share the cores.
    """
    best = float("inf")
    for _ in range(repeats):
        tb = gr.top_block()
        build(tb, n_items)
        start = clock()
        tb.run()
        best = min(best, clock() - start)
    return n_items / best


def repeat_source(vector, vlen):
    """An endless vector source repeating `vector` (a flat list of vlen-multiple length)."""
    return blocks.vector_source_c(vector, True, vlen)


def row(benchmark, ours, peer_name, peer, unit="items/s", **extra):
    """One result row: our rate, the peer's rate and their ratio (ours / peer)."""
    result = {
        "benchmark": benchmark,
        "unit": unit,
        "ours": ours,
        "peer": peer_name,
        "peer_rate": peer,
        "ratio": (ours / peer) if peer else None,
    }
    result.update(extra)
    return result


def main(run, doc):
    """A bench module run alone: --help shows its doc (instead of starting the benchmark),
    --quick its short run; prints each result row."""
    parser = argparse.ArgumentParser(description=doc,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="short runs (smoke test; ratios are noisier)")
    quick = parser.parse_args().quick
    runtime.quiet_gnuradio_logs()
    for r in run(quick=quick):
        print(", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                        for k, v in r.items()))
