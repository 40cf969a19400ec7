#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""What a run costs and how it ends: performance counters, memory, an interruptible run.

    runtime.run(tb)                 # tb.run() with GNU Radio's performance counters on;
                                    # Ctrl-C stops the graph and raises Interrupted
    runtime.rx_block_times(chain)   # CPU seconds in work() per receive block
    runtime.peak_rss_mb(), runtime.rss_mb(), runtime.heap_mb()
"""

import os
import platform
import resource

from gnuradio import gr


class Interrupted(Exception):
    """Ctrl-C stopped the flowgraph: its sinks hold an unfinished aperture, so nothing that
    depends on them may be written as if it were a result."""


def run(tb, counters=True):
    """tb.run(), with GNU Radio's performance counters on (the executors read
    GR_CONF_PERFCOUNTERS_ON when they start, so setting it for the run is enough).

    GNU Radio's own wait() swallows Ctrl-C (it stops the graph and returns as if it had
    finished); here Ctrl-C stops the graph, waits for its threads and raises Interrupted."""
    old = os.environ.get("GR_CONF_PERFCOUNTERS_ON")
    if counters:
        os.environ["GR_CONF_PERFCOUNTERS_ON"] = "True"
    try:
        tb.handle_sigint = False
        tb.start()
        try:
            tb.wait()
        except KeyboardInterrupt:
            tb.stop()
            tb.wait()
            raise Interrupted("interrupted: the flowgraph was stopped before the end of "
                              "the aperture") from None
    finally:
        if counters:
            if old is None:
                os.environ.pop("GR_CONF_PERFCOUNTERS_ON", None)
            else:
                os.environ["GR_CONF_PERFCOUNTERS_ON"] = old


def rx_block_times(blocks_by_name):
    """CPU time [s] each block of the receive chain (main branch: filter, range IFFT,
    presummer, focuser, autofocus, probe) spent in work(), from pc_work_time_total
    (high-resolution timer ticks, ns on Linux). The reference branch and the generator are
    excluded. A range_compress (--rx-fuse: filter and range IFFT in one block) counts once,
    as "range_compress"."""
    names = ("filter", "range_ifft", "presum", "focuser", "autofocus", "probe")
    times, seen = {}, []
    for name in names:
        blk = blocks_by_name.get(name)
        if blk is None or any(blk is b for b in seen):
            continue
        seen.append(blk)
        key = "range_compress" if blk.name() == "range_compress" else name
        times[key] = blk.pc_work_time_total() / 1e9
    return times


def peak_rss_mb():
    """Peak resident set size of this process so far [MiB] (ru_maxrss is in KiB on Linux)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def rss_mb():
    """Current resident set size of this process [MiB] (VmRSS of /proc/self/status)."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def heap_mb():
    """(in use, free) MiB of glibc's heap over all its arenas (mallinfo2; NaN elsewhere): RSS
    that grows with free bytes is the allocator fragmenting, with bytes in use a leak."""
    import ctypes

    class Mallinfo2(ctypes.Structure):
        _fields_ = [(n, ctypes.c_size_t) for n in ("arena", "ordblks", "smblks", "hblks",
                                                   "hblkhd", "usmblks", "fsmblks", "uordblks",
                                                   "fordblks", "keepcost")]
    try:
        f = ctypes.CDLL(None).mallinfo2
    except AttributeError:  # not glibc >= 2.33
        return float("nan"), float("nan")
    f.restype = Mallinfo2
    m = f()
    return (m.uordblks + m.hblkhd) / 2**20, m.fordblks / 2**20


def quiet_gnuradio_logs():
    """Large vectors make GNU Radio's buffer allocator warn about alignment padding on
    every connection; the apps keep errors only."""
    gr.logging().set_default_level(gr.log_levels.err)


def cpu_model():
    """The processor's model name (benchmarks name the machine they ran on)."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"
