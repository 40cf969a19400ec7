#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-sim --split zmq: the imaging chain as two graphs in two processes, the UAV's and the
ground's, joined by gr-zeromq (docs/scale.md).

    UAV:    nr_isac_tx -> head -> echo -> tf_filter -> range_ifft -> [cheby_presum]
                -> [throttle] -> link.line_framer ~~ LineQueue ~~ link.link_source
                -> zeromq push_sink / pub_sink  (binds --split-address)
    ground: zeromq pull_source / sub_source (connects) -> link.line_deframer
                -> [cheby_presum] -> rd_focuser / bp_focuser -> [autofocus] -> image, nmse_probe
            nr_isac_tx -> head -> echo (S = 1 reference, regenerated from the seed)
                -> tf_filter -> range_ifft -> [cheby_presum] -> focuser -> nmse_probe

The cut (--split-at) is after the presummer (after the range IFFT that follows it with
--presum-domain tf; the range IFFT's output without a presummer) or after the range IFFT.
The link carries range-compressed lines, each signed and numbered (link.py); the ground
regenerates the noise-free reference branch from the seed and the scene as nrsar-process
does, so nothing of the simulation's reference travels. Both halves are spawned processes
(multiprocessing, spawn): `simulate(opts)` starts the UAV, hands its bound address to the
ground, and returns nrsar-sim's JSON from the ground's images plus the link's report
(`split_uav`, `split_ground`). Same seed, same options: the split image equals the
one-graph image (qa_split).
"""

import multiprocessing
import os
import signal
import threading
import time

from gnuradio import blocks, gr

from . import chain, link, results, runtime, scenario
from .options import check_out_dir

# how often the parent and the graphs' watchers look (bounded waits everywhere)
POLL_S = 0.05
# the longest a UAV waits for its start signal
GO_WAIT_S = 600.0


def cut_layout(opts, sc):
    """(crop, focuser config) of the options, as imaging_chain has them."""
    nfft = scenario.fft_size_of(opts, sc.num.num_subcarriers)
    crop, guard = chain.range_crop(opts, sc, nfft)
    return crop, chain.focuser_config_of(opts, sc, guard)


def split_path(opts, sc, path, rif, pre):
    """(UAV blocks, ground blocks, lines crossing the link) of a receive path tuple: the UAV
    keeps up to the presummer or the range IFFT, whichever --split-at names (and always the
    IFFT). Behind a presummer the link carries its outputs: one per D pulses, less the last
    ones whose window would reach past the end (docs/blocks/cheby_presum.md)."""
    last = path.index(rif)
    if opts.split_at == "presum" and pre is not None:
        last = max(last, path.index(pre))
    lines = sc.symbols // sc.pulse_symbols
    if pre is not None and pre in path[:last + 1]:
        lines = (lines - 1 - pre.lookahead()) // opts.presum_factor() + 1
    return path[:last + 1], path[last + 1:], lines


def _connect(tb, blocks_in_order):
    if len(blocks_in_order) > 1:
        tb.connect(*blocks_in_order)


def uav_graph(tb, opts, sc, key):
    """The UAV's top block (module doc). Returns its blocks by name."""
    n = sc.num.num_subcarriers
    crop, cfg = cut_layout(opts, sc)
    tx = chain.make_transmitter(opts, sc)
    head = blocks.head(gr.sizeof_gr_complex * n, sc.symbols)
    echo = chain.make_echo(opts, sc)
    tb.connect(tx, head, echo)
    tb.connect((echo, 1), blocks.null_sink(gr.sizeof_gr_complex * n))  # no reference here
    tff = chain.data_filter(opts, n)
    tb.connect((echo, 0), (tff, 0))
    tb.connect(head, (tff, 1))
    entry, rif, _, pre, paths = chain.receive_path(opts, sc, crop, cfg, sc.navigation,
                                                       focuser=False)
    uav_part, _, lines = split_path(opts, sc, paths[0], rif, pre)
    chain.connect_pulses(tb, tff, entry, sc)
    _connect(tb, uav_part)
    bins = rif.num_bins()
    # without a radio clock (--split-line-rate 0) the simulation waits for the link as one
    # graph would; a paced UAV drops what the link cannot take
    wait_s = opts.split_idle_s if opts.split_line_rate == 0 else 0.0
    uplink = link.uav_link(bins, key, opts.split_address, opts.split_pattern, lines,
                           opts.split_queue_lines, opts.split_hwm, wait_s)
    last = uav_part[-1]
    if opts.split_line_rate > 0:
        throttle = blocks.throttle(gr.sizeof_gr_complex * bins, opts.split_line_rate)
        tb.connect(last, throttle)
        last = throttle
    tb.connect(last, uplink)
    return {"echo": echo, "filter": tff, "range_ifft": rif, "presum": pre,
            "presum_on_uav": pre in uav_part, "link": uplink}


def ground_graph(tb, opts, sc, key, address):
    """The ground's top block (module doc). Returns the blocks by name, as chain.build
    does (the reference branch's filter and IFFT stand for the data branch's, which are on
    the UAV: same crop, same axes)."""
    n = sc.num.num_subcarriers
    keep = opts.images != "none"
    crop, cfg = cut_layout(opts, sc)
    entry, rif, foc, pre, paths = chain.receive_path(opts, sc, crop, cfg, sc.navigation)
    _, ground_part, lines = split_path(opts, sc, paths[0], rif, pre)
    bins = rif.num_bins()
    downlink = link.ground_link(bins, key, address, opts.split_pattern, lines,
                                opts.split_idle_s, opts.split_hwm)
    _connect(tb, (downlink,) + ground_part)
    # the reference branch, regenerated here from the seed and the scene
    tx = chain.make_transmitter(opts, sc)
    head = blocks.head(gr.sizeof_gr_complex * n, sc.symbols)
    echo = chain.make_echo(opts, sc)
    tb.connect(tx, head, echo)
    tb.connect((echo, 0), blocks.null_sink(gr.sizeof_gr_complex * n))
    entry_ref, rif_ref, foc_ref, _, paths_ref = chain.receive_path(opts, sc, crop, cfg,
                                                                 sc.trajectory)
    tff_ref, ones = chain.reference_filter(opts, n)
    tb.connect((echo, 1), (tff_ref, 0))
    tb.connect(ones, (tff_ref, 1))
    chain.connect_pulses(tb, tff_ref, entry_ref, sc)
    _connect(tb, paths_ref[0])
    probe = chain.make_probe(opts, sc, foc, cfg, True)
    k = foc.num_output_bins()
    if keep:  # the received lines stand for the range-compressed data
        range_sink, image_sink = chain.array_sink(bins), chain.array_sink(k)
    else:
        range_sink = blocks.null_sink(gr.sizeof_gr_complex * bins)
        image_sink = blocks.null_sink(gr.sizeof_gr_complex * k)
    reference_sink = blocks.null_sink(gr.sizeof_gr_complex * k)
    tb.connect(downlink, range_sink)
    image = af = chain.make_autofocus(opts, sc, k)  # the data branch's, as imaging_chain's
    if af is None:
        image = foc
    else:
        tb.connect(foc, af)
    tb.connect(image, image_sink)
    tb.connect(image, (probe, 0))
    tb.connect(foc_ref, (probe, 1))
    tb.connect(foc_ref, reference_sink)
    return {"tx": tx, "head": head, "echo": echo, "chain": None, "filter": tff_ref,
            "range_ifft": rif_ref, "presum": pre if pre in ground_part else None,
            "focuser": foc, "focuser_ref": foc_ref, "probe": probe, "range_sink": range_sink,
            "image_sink": image_sink, "reference_sink": reference_sink,
            "autofocus": af, "link": downlink}


def _start(tb):
    os.environ["GR_CONF_PERFCOUNTERS_ON"] = "True"  # rx_block_s, as runtime.run
    tb.start()
    waiter = threading.Thread(target=tb.wait, daemon=True)
    waiter.start()
    return waiter


def run_uav(opts, key, go, conn):
    """The UAV process: builds its graph, sends {"address"}, waits for `go` (an Event, or
    None: at once), runs until the radio path has ended and the link drained (or
    --split-idle-s passed), sends its report."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent stops its children
    try:
        sc = scenario.of(opts)
        tb = gr.top_block("nrsar-uav")
        g = uav_graph(tb, opts, sc, key)
        uplink = g["link"]
        conn.send({"address": uplink.address()})
        if go is not None:
            go.wait(GO_WAIT_S)
        start = time.perf_counter()
        waiter = _start(tb)
        framer, seen, since = uplink.framer, -1, time.monotonic()
        while not framer.done.wait(POLL_S):
            # the radio path ended short of the expected lines: end the stream anyway
            if framer.nitems_read(0) != seen:
                seen, since = framer.nitems_read(0), time.monotonic()
            elif time.monotonic() - since > opts.split_idle_s:
                framer.finish()
        radio_s = time.perf_counter() - start
        waiter.join(opts.split_idle_s)  # the link drains (or no ground takes it)
        drained = not waiter.is_alive()
        if not drained:
            tb.stop()
            waiter.join()
        rx = runtime.rx_block_times({"filter": g["filter"], "range_ifft": g["range_ifft"],
                                     "presum": g["presum"] if g["presum_on_uav"] else None})
        conn.send({"report": dict(
            uplink.report(), link_drained=drained,
            frame_bytes=link.frame_bytes(g["range_ifft"].num_bins()),
            radio_s=radio_s, address=uplink.address(), **{
            "nonfinite": g["echo"].nonfinite_count() + g["filter"].nonfinite_count(),
            "empty_res": g["filter"].empty_re_count(), "rx_block_s": rx,
            "warnings": list(g["presum"].warnings()) if g["presum_on_uav"] else [],
            "peak_rss_mb": runtime.peak_rss_mb()})})
    except Exception as err:  # reported to the parent, which names the process
        conn.send({"error": f"{type(err).__name__}: {err}"})


def run_ground(opts, key, address, conn):
    """The ground process: receives until the stream ends (link.line_deframer), lets the
    focuser flush, writes the images into opts.out and sends nrsar-sim's JSON dict and the
    deframer's report."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        sc = scenario.of(opts)
        check_out_dir(opts.out)
        tb = gr.top_block("nrsar-ground")
        g = ground_graph(tb, opts, sc, key, address)
        conn.send({"started": True})
        start = time.perf_counter()
        waiter = _start(tb)
        consumers = [(g["image_sink"], 0), (g["probe"], 0), (g["probe"], 1)]
        foc = g["focuser"]
        expected = (foc.lines_per_aperture() if opts.focuser == "rd"
                    else foc.image_lines_per_aperture())
        while not all(b.nitems_read(p) >= expected for b, p in consumers):
            # the deframer's idle timeout bounds the wait for lines; the focuser then
            # flushes, which is bounded work
            time.sleep(POLL_S)
            if not waiter.is_alive():
                break
        tb.stop()  # the zeromq source never ends by itself
        waiter.join()
        result = results.image_results(opts, g, sc, time.perf_counter() - start)
        conn.send({"result": result, "report": g["link"].report()})
    except Exception as err:
        conn.send({"error": f"{type(err).__name__}: {err}"})


def _receive(conn, proc, name, what):
    """The next message of a child, or RuntimeError naming it when it died first."""
    while not conn.poll(POLL_S):
        if not proc.is_alive():
            if conn.poll(0):
                break
            raise RuntimeError(f"the {name} process ended (exit {proc.exitcode}) before "
                               f"sending its {what}")
    msg = conn.recv()
    if "error" in msg:
        raise RuntimeError(f"{name}: {msg['error']}")
    return msg


class Half:
    """One spawned half (UAV or ground) and the pipe to it."""

    def __init__(self, name, target, *args):
        ctx = multiprocessing.get_context("spawn")
        self.name = name
        self.conn, child = ctx.Pipe(duplex=False)
        self.proc = ctx.Process(target=target, args=args + (child,), name=name, daemon=True)
        self.proc.start()
        child.close()

    def receive(self, what):
        return _receive(self.conn, self.proc, self.name, what)

    def stop(self):
        if self.proc.is_alive():
            self.proc.terminate()
        self.proc.join(10)


def start_uav(opts, key, go=None):
    """(Half, bound address) of a UAV process; with `go` (a spawn-context Event) its radio
    starts when the event is set."""
    uav = Half("UAV", run_uav, opts, key, go)
    return uav, uav.receive("address")["address"]


def start_ground(opts, key, address):
    ground = Half("ground", run_ground, opts, key, address)
    ground.receive("start")
    return ground


def finish(uav, ground):
    """(the UAV's report, the ground's {"result", "report"}) once both halves are done;
    both processes stopped in any case."""
    try:
        return uav.receive("report")["report"], ground.receive("images")
    finally:
        uav.stop()
        ground.stop()


def merge(result, uav_report, ground_report):
    """nrsar-sim's JSON of a split run: the ground's images and metrics, the UAV's counts of
    the blocks it ran, and both sides' link reports."""
    rx = dict(uav_report["rx_block_s"])
    rx.update({k: v for k, v in result["rx_block_s"].items()
               if k in ("presum", "focuser", "probe")})
    result.update(nonfinite=uav_report["nonfinite"], empty_res=uav_report["empty_res"],
                  rx_block_s=rx, rx_runtime_s=sum(rx.values()),
                  split_uav=uav_report, split_ground=ground_report)
    result["warnings"] += uav_report["warnings"]
    lost = ground_report["lines_lost"]
    if lost:
        result["warnings"].append(
            f"the link lost {lost} of {uav_report['lines']} lines (zero-filled: "
            f"{ground_report['gaps']}); the UAV dropped {uav_report['lines_dropped']}")
    return result


def simulate(opts):
    """nrsar-sim --split zmq: the JSON dict of one run, its halves in two processes."""
    scenario.of(opts.validate())  # a bad scenario is refused before the processes start
    check_out_dir(opts.out)
    key = link.read_key(opts.split_key) if opts.split_key else link.new_key()
    halves = []
    try:
        # a simulation has no radio clock: its UAV starts once the ground listens
        go = multiprocessing.get_context("spawn").Event()
        uav, address = start_uav(opts, key, go)
        halves.append(uav)
        ground = start_ground(opts, key, address)
        halves.append(ground)
        go.set()
        uav_report, msg = finish(uav, ground)
        return merge(msg["result"], uav_report, msg["report"])
    except KeyboardInterrupt:
        raise runtime.Interrupted("interrupted: the UAV and ground processes were stopped "
                                  "before the end of the aperture") from None
    finally:
        for half in halves:
            half.stop()


def link_budget(opts, sc=None):
    """Bytes per second on the link at each cut for the options' numerology and presummer:
    {"range": ..., "presum": ..., "tf": ...} (the TF pulses themselves, for comparison),
    payload only and with the frame overhead."""
    sc = scenario.of(opts) if sc is None else sc
    bins = chain.layout(opts).range_bins
    prf = 1.0 / (sc.num.symbol_s() * sc.pulse_symbols)
    d = opts.presum_factor()
    out = {"pulse_rate_hz": prf, "bins": bins, "decim": d}
    for name, rate, width in (("tf", prf, sc.num.num_subcarriers), ("range", prf, bins),
                              ("presum", prf / d, bins)):
        out[name + "_payload_Bps"] = rate * 8 * width
        out[name + "_framed_Bps"] = rate * (link.frame_bytes(width))
    out["presum_saves"] = d
    return out
