#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-process --strip-aperture-s S [--dask local:N | tcp://HOST:PORT]: a long recording
as a strip of apertures, each focused by its own graph, on one process or a Dask cluster
(docs/scale.md).

    the flight's lines:      |  aperture 0  |  aperture 1  |  aperture 2  | ...
    task a reads:                 [history | aperture a's pulses | look-ahead]
    task a: file_source(offset of the block's first symbol) -> ofdm_demod -> chain.build
            (the whole flight's geometry; nr_isac_tx's grid started at that symbol, an
            ISAC recording's PUSCH from pusch_encoder started at its slot;
            the focuser told its first aperture, a, and to stop after it)
            -> image lines [a M + s, a M + s + M) of the flight, as one graph makes them
    stitched in aperture order -> strip_image.npy

The focuser's block for aperture a (rd_focuser: overlap-save, its history `before` and
look-ahead `after` of the scene band's azimuth extent, or --strip-overlap-s; bp_focuser: the
aperture's own pulses) is what the task reads, so the stitched strip equals one graph
focusing the whole recording (whole(); qa_distributed_process asserts identical arrays).
With the Wiener filter's --estimate-snr a pre-pass (histories(): tasks of their own, in
parallel, the focusing tasks started beside them as their histories become known) takes
the SNR estimator's sums of every symbol before the last task's block, and each task
starts its filter's estimator from the history one graph has at its first symbol
(Slice.history, tf_filter.set_snr_history), so its SNR estimate is one graph's too. A task
receives the options, the meta's path and its Slice, and reads its samples from the SigMF
data file by offset: no samples go through the scheduler (each worker needs the
recording's folder: a shared file system).

Before the run, range_grid_check() runs nrsar-process's range-grid headroom check per task
(the navigation's sway over the time window the task reads) and warns of the worst aperture.

Faults: a worker that dies costs its task a retry on another worker (the scheduler's own
rescheduling); a slice with non-finite samples fails as SliceError naming its aperture, its
lines stay zero in the strip, and `strip_failed` lists it; the rest completes.

Security: the scheduler of a cluster runs whatever a client sends, so nrsar-process speaks
to it over TLS with certificates only (`distributed.security.Security`, mutual TLS): a
`local:N` cluster gets a self-signed set made for the run (Security.temporary()), a remote
one needs --dask-tls-ca/-cert/-key (a `tcp://` address is upgraded to `tls://`; plain TCP is
refused). `write_certificates(folder)` writes a self-signed set for a scheduler and workers
started by hand (docs/scale.md).
"""

import collections
import contextlib
import dataclasses
import functools
import logging
import math
import os
import tempfile
import time

import numpy as np
from gnuradio import blocks, gr

from . import chain, process, recording, results, scenario
from .nrsar_python import tf_filter
from .options import CERTIFICATES, OptionError, check_certificate_folder
from .scenario import fft_size_of


class SliceError(RuntimeError):
    """A slice that cannot be imaged (its aperture index in the message)."""


@dataclasses.dataclass(frozen=True)
class Slice:
    index: int      # the first aperture along the strip
    apertures: int  # apertures the task images (1; the whole strip in whole())
    lines: int      # image lines per aperture M
    first: int      # the first symbol the chain after the filter takes
    symbols: int    # symbols it takes
    history: tuple = ()  # the SNR estimator's before `first` (prepass); (): a fresh one


@dataclasses.dataclass(frozen=True)
class Layout:
    lines: int        # image lines per aperture M
    step: int         # symbols per image line (pulse symbols x presumming factor)
    total_lines: int  # image lines the recording holds (whole ones)
    before: int       # the focuser's history ahead of an aperture's output window [lines]
    after: int        # and its look-ahead past it
    shift: int        # the output window's offset from the aperture's own pulses [lines]
    slices: list      # one Slice per aperture
    bins: int         # the image's range bins
    reach: tuple = (0, 0)  # --band full: the lines its azimuth reference reaches (full_band_reach)

    def read_factor(self):
        """Lines a task reads per line it keeps (the overlap's cost, docs/scale.md; the
        --estimate-snr pre-pass reads prepass_symbols() more, through the filter only)."""
        return sum(s.symbols for s in self.slices) / (len(self.slices) * self.lines * self.step)


def _scenario(opts, rec, lines=0, first=0, apertures=0):
    """(SimOptions, Scenario) of the whole flight, the focuser's apertures of the strip:
    `lines` per aperture, from aperture `first`, `apertures` of them (0: to the end), with
    --strip-overlap-s as its overlap (-1: automatic)."""
    sim_opts = process.sim_options_of(opts, rec).replace(images="keep", geotiff=False)
    sc = process.scenario_of(sim_opts, rec)
    overlap = -1
    if opts.strip_overlap_s is not None:
        line_s = rec.num.symbol_s() * sc.pulse_symbols * sim_opts.presum_factor()
        overlap = int(round(opts.strip_overlap_s / line_s))
    return sim_opts, dataclasses.replace(sc, strip=(lines, first, apertures, overlap))


def full_band_reach(foc, geo):
    """(back, ahead): the lines the full band's azimuth reference reaches before and after
    an image line at the image's far range R, the stationary times of its compression phase
    over the processed band (the pulse rate around the scene band's centre): E(f) = f lambda
    R / (2 v^2 T D(f)), D = sqrt(1 - u^2), u = lambda f / (2 v) (D = 1 where the focuser takes
    the parabolic formulas: u^2 >= 0.99 or hyperbolic off; E peaks at a band edge or just
    inside u^2 = 0.99). A block whose overlap covers it is linear in every Doppler bin;
    rd_focuser's automatic overlap covers the scene band only (docs/recording.md)."""
    cfg, lam, v = foc.config(), geo.wavelength_m(), geo.velocity_mps
    r = foc.first_range_m() + (cfg.guard_bins + foc.num_output_bins() - 1) * foc.range_bin_m()

    def lines(f):
        u2 = (lam * f / (2.0 * v)) ** 2
        d = math.sqrt(1.0 - u2) if cfg.hyperbolic and u2 < 0.99 else 1.0
        return f * lam * r / (2.0 * v * v * foc.pulse_interval_s() * d)

    lo, hi = foc.band_lo_hz(), foc.band_hi_hz()
    edge = math.nextafter(math.sqrt(0.99), 0.0) * 2.0 * v / lam
    reach = [lines(f) for f in (lo, hi, -edge, edge) if lo <= f <= hi]
    return math.ceil(max(reach + [0.0])), math.ceil(max([-e for e in reach] + [0.0]))


def layout(opts, rec):
    """The strip's Layout: apertures of --strip-aperture-s (whole image lines; the lines
    after the last whole aperture are only look-ahead). Task a reads the lines its
    aperture's processing block needs, as the whole flight's focuser would hold them
    (overlap-save history and look-ahead for rd_focuser, the aperture's own pulses for
    bp_focuser), from the first line of that block (stream_first_line())."""
    sim_opts, sc = _scenario(opts, rec)
    if sim_opts.presum == "lms":
        raise OptionError("--presum = 'lms' with --strip-aperture-s: its filter adapts from "
                          "the flight's first pulse, so a task starting mid-flight cannot "
                          "reproduce it (use cheby, boxcar, drop or filter_drop)")
    step = sc.pulse_symbols * sim_opts.presum_factor()  # symbols per image line
    total = rec.symbols // step
    m = int(round(opts.strip_aperture_s / (rec.num.symbol_s() * step)))
    if m < 2 or m > total:
        raise OptionError(f"--strip-aperture-s = {opts.strip_aperture_s:g} must hold at least "
                          f"two image lines ({2 * step} symbols) and at most the recording's "
                          f"{total} lines ({rec.symbols} symbols)")
    # the focuser the tasks build, asked for its layout (built, never run: its range
    # IFFT's FFT object goes back to the pool, kernel/fft_plans.h, for the tasks)
    sc = dataclasses.replace(sc, strip=(m,) + sc.strip[1:])
    crop, guard = chain.range_crop(sim_opts, sc, fft_size_of(sim_opts, rec.num.num_subcarriers))
    _, _, foc, pre, _ = chain.receive_path(
        sim_opts, sc, crop, chain.focuser_config_of(sim_opts, sc, guard), sc.navigation)
    shift = foc.line_shift()
    before = foc.overlap_before() if sim_opts.focuser == "rd" else 0
    after = foc.overlap_after() if sim_opts.focuser == "rd" else 0
    # a presummer's output line g needs the pulses [g D - history, g D + lookahead]
    d = sim_opts.presum_factor()
    history, lookahead = (pre.history(), pre.lookahead()) if pre else (0, 0)
    slices = []
    for a in range(total // m):
        lo, hi = a * m, a * m + m
        if before + after:  # the overlap-save block around the window [a m + s, a m + s + m)
            lo, hi = lo + shift - before, hi + shift + after
        lo = 0 if a == 0 else max(0, lo)
        hi = min(total, hi)  # a block past the end (overlap below the shift) reads nothing
        first = max(0, lo * d - history)  # pulses
        end = min(total * d, (hi - 1) * d + lookahead + 1) if hi > lo else first
        first, symbols = first * sc.pulse_symbols, (end - first) * sc.pulse_symbols
        slices.append(Slice(a, 1, m, first, symbols))
    full = sim_opts.band == "full" and sim_opts.focuser == "rd"
    reach = full_band_reach(foc, rec.geo) if full else (0, 0)
    return Layout(m, step, total, before, after, shift, slices, foc.num_output_bins(), reach)


def full_band_warnings(lay, symbol_s):
    """The strip's warning when --band full's reference reaches past the tasks' overlap
    (symbol_s: the recording's symbol time)."""
    if lay.before >= lay.reach[0] and lay.after >= lay.reach[1]:
        return []
    need = max(lay.reach)
    overlap_s = math.ceil(need * lay.step * symbol_s * 1e3) / 1e3  # rounded up: >= need lines
    return [f"--band full: the azimuth reference of the full pulse rate reaches "
            f"{lay.reach[0]} / {lay.reach[1]} lines back / ahead of an image line, beyond the "
            f"strip's overlap of {lay.before} / {lay.after} lines: each task's block wraps the "
            f"Doppler bins outside the scene band circularly, so the strip's noise there "
            f"depends on --strip-aperture-s and differs from nrsar-sim's image of the flight "
            f"(its one block wraps too); --strip-overlap-s {overlap_s:g} ({need} lines) makes "
            f"every block linear, --band scene focuses the scene band only (docs/recording.md)"]


def range_grid_check(opts, rec, lay):
    """(each task's spread of the range spectrum / B, [the warning of the worst task]):
    scenario.range_grid_warnings per task, the navigation's sway (sway_spread_hz) over the
    time window of the symbols the task reads (its graph's pulses, as one image's are its
    aperture's), since the strip's flight outlasts its apertures."""
    sim_opts, sc = _scenario(opts, rec)
    ts, band = rec.num.symbol_s(), rec.num.num_subcarriers * rec.num.subcarrier_spacing_hz
    windows = [(sl.first * ts, (sl.first + sl.symbols) * ts) for sl in lay.slices]
    spreads = [scenario.sway_spread_hz(sc, window=w) for w in windows]
    a = max(range(len(spreads)), key=lambda i: spreads[i][0])
    where = f"aperture {a} (its task's t = {windows[a][0]:.3f}-{windows[a][1]:.3f} s)"
    return [h / band for h, _ in spreads], scenario.range_spread_warnings(
        rec.num, fft_size_of(sim_opts, rec.num.num_subcarriers), *spreads[a], where)


def whole(opts, rec, lay):
    """The Slice of one graph over the whole strip: what one process focusing the whole
    recording makes (the tasks' stitched strip equals it, qa_distributed_process)."""
    return Slice(0, len(lay.slices), lay.lines, 0, lay.total_lines * lay.step)


def part_of(rec, first, symbols):
    """The recording's symbols [first, first + symbols) as a Recording of their own: the
    data file from the first sample at or after the part's start, its overflows [(file
    index, lost)] within it (a gap past its end clipped), and one at its first sample where
    it starts inside a gap, so that rx_time_stamper's stamps put the lost symbols back as
    zeros where one graph over the whole recording puts them (docs/recording.md, "Gaps")."""
    f0, f1 = first * rec.symbol_samples, (first + symbols) * rec.symbol_samples
    head, gaps, lost = rec.hardware_delay_samples + f0, [], 0  # lost: before the gap
    for index, count in rec.gaps:
        g0 = index - rec.hardware_delay_samples + lost  # the flight's samples [g0, g0 + count)
        lost += count
        if g0 + count <= f0:  # before the part: the file is that much shorter
            head -= count
        elif g0 <= f0:  # the part starts inside it: its first sample is the gap's end
            head = index
            gaps.append((index, min(g0 + count, f1) - f0))
        elif g0 < f1:
            gaps.append((index, min(g0 + count, f1) - g0))
    return dataclasses.replace(rec, symbols=symbols, hardware_delay_samples=head, gaps=gaps)


def focus_slice(opts, meta_path, sl, reference=False):
    """One task: the image lines of apertures [sl.index, sl.index + sl.apertures) as the
    whole flight's focuser makes them (dict: index, image, compute_s). Raises SliceError
    for non-finite samples in the slice. The strip has no metrics, so the reference branch
    (the noise-free echo's image, NMSE's calibration) is left out; reference=True builds it
    (nrsar-bench measures what it cost)."""
    start = time.perf_counter()
    rec = recording.read(meta_path)
    sim_opts, sc = _scenario(opts, rec, sl.lines, sl.index, sl.apertures)
    sc = dataclasses.replace(sc, symbols=sl.symbols)
    part = part_of(rec, sl.first, sl.symbols)  # file_source's offset, its overflows
    tb = gr.top_block("nrsar-strip")
    graph = chain.build(tb, sim_opts, sc,
                        tx=process.make_transmitter(opts, rec, sim_opts, sc, tb, sl.first),
                        reference=reference,
                        echo_front=process.recording_front(part, reference))
    try:
        if sl.history:
            graph["filter"].set_snr_history(list(sl.history))
        pre = graph["presum"]  # its first output is the focuser's first line
        first = pre.first_pulse() if pre else graph["focuser"].stream_first_line()
        if first * sc.pulse_symbols != sl.first:
            raise RuntimeError(f"aperture {sl.index}: the chain expects its stream from pulse "
                               f"{first}, the slice starts at symbol {sl.first}")
        k = graph["focuser"].num_output_bins()
        if sl.symbols == 0:  # its block lies past the recording's end: zeros, as one graph's
            return {"index": sl.index, "compute_s": time.perf_counter() - start,
                    "image": np.zeros((sl.apertures * sl.lines, k), np.complex64),
                    "snr_db": None}
        tb.run()
        bad = graph["echo"].nonfinite_count()
        if bad:
            raise SliceError(f"aperture {sl.index}: {bad} non-finite samples in symbols "
                             f"[{sl.first}, {sl.first + sl.symbols}) of {rec.data_path}")
        image = np.asarray(graph["image_sink"].data(), np.complex64).reshape(-1, k)
        if image.shape[0] != sl.apertures * sl.lines:
            raise RuntimeError(f"aperture {sl.index}: {image.shape[0]} image lines, expected "
                               f"{sl.apertures * sl.lines}")
        snr = graph["filter"].estimated_snr_db() if sim_opts.estimate_snr else None
        return {"index": sl.index, "image": image, "compute_s": time.perf_counter() - start,
                "snr_db": snr}
    finally:
        graph["chain"].release()  # a worker runs many tasks: their blocks and FFTs go back


def prepass_symbols(opts, rec, lay):
    """The symbols [0, end) whose SNR estimator sums the tasks' histories need: up to the
    last task's first symbol (0 without --estimate-snr with the Wiener filter: RF and MF do
    not use the estimate)."""
    sim_opts = process.sim_options_of(opts, rec)
    if not (sim_opts.estimate_snr and sim_opts.filter == "wf"):
        return 0
    return max((sl.first for sl in lay.slices if sl.symbols), default=0)


def prepass_sums(opts, meta_path, first, symbols):
    """A pre-pass task: the SNR estimator's sums of symbols [first, first + symbols)
    (float32, four per symbol, tf_filter.snr_sums): file_source, ofdm_demod and the data
    filter in pre-pass mode, nothing after it."""
    rec = recording.read(meta_path)
    sim_opts, sc = _scenario(opts, rec)
    n = rec.num.num_subcarriers
    tb = gr.top_block("nrsar-prepass")
    head = blocks.head(gr.sizeof_gr_complex * n, symbols)
    tb.connect(process.make_transmitter(opts, rec, sim_opts, sc, tb, first), head)
    _, echo, _ = process.recording_front(part_of(rec, first, symbols), False)(
        tb, sim_opts, sc, head)
    tff = chain.data_filter(sim_opts, n)
    tff.set_snr_prepass(True)
    tb.connect(echo, (tff, 0))
    tb.connect(head, (tff, 1))
    tb.connect(tff, blocks.null_sink(gr.sizeof_gr_complex * n))
    tb.run()
    return np.asarray(tff.snr_sums(), np.float32)


# The fewest REs a pre-pass part takes: a part's fixed cost (its graph built and started,
# 3-4 ms; its Dask round trip, 8-17 ms) is that of 1-2 M REs' sums (7-11 ns each), so a
# second part pays from about twice that (docs/scale.md)
PART_RES = 1 << 21


def prepass_parts(end, n, workers, parts=0):
    """The pre-pass's parts [(first symbol, symbols)] of symbols [0, end) of n REs each:
    one per worker, but each of at least PART_RES REs (a short strip's pre-pass is one
    part), or `parts` of them."""
    parts = parts or max(1, min(workers, end * n // PART_RES))
    size = -(-end // parts)
    return [(a, min(size, end - a)) for a in range(0, end, size)]


def histories(opts, rec, lay, client=None, parts=0, clock=None):
    """Yields the Layout's slices in aperture order, each with the SNR estimator's history
    at its first symbol, as one graph over the whole recording has it (--estimate-snr;
    unchanged without), as soon as it is known: the sums of symbols [0, prepass_symbols())
    taken by pre-pass tasks (prepass_parts(): `parts`, 0 for one per worker of the client's
    cluster if each carries enough work; submitted at once, in this process run as needed),
    replayed in stream order, a part at a time (tf_filter.snr_histories: the estimator's own
    float and double sums in its own order, so the estimate is one graph's bit for bit
    whatever the parts; the client holds one part's sums). A slice that starts at a part's
    first symbol (the first at symbol 0) comes before that part's sums, so in_order runs its
    task while the pre-pass runs. clock: a list that gets, once the last slice is taken,
    the seconds this generator spent on the pre-pass (submitting its parts, waiting for
    their sums, the replay: all of it in this process; on a cluster what the tasks did not
    hide)."""
    start = time.perf_counter()
    end = prepass_symbols(opts, rec, lay)
    n = rec.num.num_subcarriers
    parts = prepass_parts(end, n, workers_of(client), parts) if end else []
    if client is None:
        sums = (functools.partial(prepass_sums, opts, rec.meta_path, a, k) for a, k in parts)
    else:
        sums = (f.result for f in client.map(
            prepass_sums, [opts] * len(parts), [rec.meta_path] * len(parts),
            *zip(*parts), pure=False, retries=1)) if parts else ()
    # a part's future is dropped once replayed (its sums leave the worker)
    replay, state, at, known = collections.deque(zip(parts, sums)), [], 0, {}
    waited = time.perf_counter() - start
    for sl in lay.slices:
        if not (end and sl.symbols):  # no pre-pass, or a block outside the recording
            yield sl
            continue
        while sl.first > at:  # the next part's sums (at: the state's symbol)
            begun = time.perf_counter()
            (a, k), part = replay.popleft()
            inside = sorted({s.first - a for s in lay.slices
                             if s.symbols and a <= s.first < a + k})
            *found, state = tf_filter.snr_histories(n, part(), inside + [k], state)
            known, at = {a + t: h for t, h in zip(inside, found)}, a + k
            waited += time.perf_counter() - begun
        if sl.first not in known:  # at a part's first symbol: known before its sums
            known[sl.first], = tf_filter.snr_histories(n, np.zeros(0, np.float32), [0], state)
        yield dataclasses.replace(sl, history=tuple(known[sl.first]))
    if clock is not None:
        clock.append(waited)


def prepass(opts, rec, lay, client=None, parts=0):
    """(the Layout's slices with their SNR histories (histories()), the pre-pass's
    seconds)."""
    clock = []
    slices = list(histories(opts, rec, lay, client, parts, clock))
    return slices, clock[0]


def security_of(opts):
    """The distributed Security of --dask (module doc); OptionError without certificates."""
    from distributed.security import Security
    if opts.dask.startswith("local:"):
        return Security.temporary()
    files = (opts.dask_tls_ca, opts.dask_tls_cert, opts.dask_tls_key)
    if None in files:
        raise OptionError(f"--dask = {opts.dask!r} needs --dask-tls-ca, --dask-tls-cert and "
                          f"--dask-tls-key: the scheduler takes TLS clients with a "
                          f"certificate only")
    return Security(tls_ca_file=files[0], tls_client_cert=files[1], tls_client_key=files[2],
                    require_encryption=True)


@contextlib.contextmanager
def connect(opts):
    """The client of --dask (a context: closed, with its local cluster, on leaving):
    local:N starts N single-threaded worker processes on 127.0.0.1 over TLS; tcp:// or
    tls://HOST:PORT connects over TLS."""
    import distributed
    sec = security_of(opts)
    with contextlib.ExitStack() as stack:
        if opts.dask.startswith("local:"):
            target = stack.enter_context(local_cluster(int(opts.dask[len("local:"):]), sec))
        else:
            target = "tls://" + opts.dask.split("://", 1)[1]
        yield stack.enter_context(distributed.Client(target, security=sec, timeout="30s"))


@contextlib.contextmanager
def local_cluster(workers, security):
    """A LocalCluster of single-threaded worker processes on 127.0.0.1 over TLS (a
    context); its HTTP server (plain HTTP) on loopback only, without the dashboard; the
    workers' scratch space in a folder of its own (not the shared dask-worker-space)."""
    import distributed
    with tempfile.TemporaryDirectory(prefix="nrsar-dask-") as scratch, \
            distributed.LocalCluster(
                n_workers=workers, threads_per_worker=1, processes=True, protocol="tls://",
                host="127.0.0.1", security=security, dashboard_address="127.0.0.1:0",
                scheduler_kwargs={"dashboard": False}, silence_logs=logging.ERROR,
                local_directory=scratch) as cluster:
        yield cluster


def workers_of(client):
    """The client's cluster's workers (1: this process, no client)."""
    return len(client.scheduler_info()["workers"]) if client else 1


def in_order(opts, meta_path, slices, client=None, window=0):
    """Yields (slice, task result or SliceError text, held) in aperture order: each task
    runs in this process, or on the client's cluster with at most `window` tasks (0: twice
    the workers) submitted and not yet yielded (held counts them, the one yielded included),
    so the strip's memory stays bounded whatever its length. A task whose worker died runs
    again (retries)."""
    if client is None:
        for sl in slices:
            try:
                yield sl, focus_slice(opts, meta_path, sl), 1
            except SliceError as err:
                yield sl, str(err), 1
        return
    window = window or 2 * workers_of(client)
    waiting, queue = collections.deque(), iter(slices)
    while True:
        while len(waiting) < window:
            sl = next(queue, None)
            if sl is None:
                break
            waiting.append((sl, client.submit(focus_slice, opts, meta_path, sl, pure=False,
                                              retries=1)))
        if not waiting:
            return
        held = len(waiting)
        sl, future = waiting.popleft()
        try:
            result = future.result()
        except SliceError as err:
            result = str(err)
        future.release()  # its image leaves the worker's memory
        yield sl, result, held


def run_slices(opts, meta_path, slices, client=None):
    """{index: task result or SliceError text} of every slice (in memory: for a few)."""
    return {sl.index: r for sl, r, _ in in_order(opts, meta_path, slices, client)}


def write_strip(path, lay, done):
    """Streams the image lines of done ((slice, result, held) in aperture order, as
    in_order yields them) into the .npy file at path, written under a temporary name and
    renamed at the end; a failed slice's lines are zero. Nothing but the aperture in hand is
    kept. Returns (failures [{aperture, error}], task times, the most tasks held at once,
    each task's last SNR estimate (None: failed, read nothing, or no --estimate-snr))."""
    failed, times, peak, snrs = [], [], 0, []
    rows = len(lay.slices) * lay.lines
    with results.atomic(path) as tmp, open(tmp, "wb") as f:
        np.lib.format.write_array_header_1_0(f, {"descr": np.lib.format.dtype_to_descr(
            np.dtype(np.complex64)), "fortran_order": False, "shape": (rows, lay.bins)})
        for sl, r, held in done:
            peak = max(peak, held)
            if isinstance(r, str):
                failed.append({"aperture": sl.index, "error": r})
                image = np.zeros((sl.apertures * sl.lines, lay.bins), np.complex64)
                snrs.append(None)
            else:
                image = r["image"]
                times.append(r["compute_s"])
                snrs.append(r["snr_db"])
            f.write(np.ascontiguousarray(image, np.complex64).tobytes())
    return failed, times, peak, snrs


def run(opts, client=None):
    """nrsar-process's JSON of a strip (--strip-aperture-s, optionally --dask; client: a
    connected distributed.Client to use instead)."""
    rec = recording.read(opts.recording)
    lay = layout(opts, rec)
    os.makedirs(opts.out, exist_ok=True)
    path = os.path.abspath(os.path.join(opts.out, "strip_image.npy"))
    spreads, grid_warnings = range_grid_check(opts, rec, lay)
    start = time.perf_counter()
    with contextlib.ExitStack() as stack:
        if client is None and opts.dask:
            client = stack.enter_context(connect(opts))
        clock = []  # the pre-pass runs alongside the first tasks
        failed, times, peak, snrs = write_strip(path, lay, in_order(
            opts, rec.meta_path, histories(opts, rec, lay, client, clock=clock), client,
            opts.strip_window))
        workers = workers_of(client)
    return {"recording_meta": rec.meta_path, "strip_apertures": len(lay.slices),
            "strip_aperture_lines": lay.lines,
            "strip_slices": [[s.first, s.symbols] for s in lay.slices],
            "strip_overlap_lines": [lay.before, lay.after],
            "strip_line_shift": lay.shift, "strip_prepass_symbols": prepass_symbols(opts, rec, lay),
            "strip_prepass_s": clock[0], "strip_snr_db": snrs,
            "strip_read_factor": lay.read_factor(), "strip_image_npy": path,
            "strip_full_band_reach_lines": list(lay.reach),
            "strip_range_spread_b": spreads,
            "warnings": full_band_warnings(lay, rec.num.symbol_s()) + grid_warnings,
            "strip_lines": len(lay.slices) * lay.lines, "strip_failed": failed,
            "strip_task_s": times, "strip_held_peak": peak, "overflows": len(rec.gaps),
            "lost_samples": sum(count for _, count in rec.gaps), "dask": opts.dask,
            "dask_workers": workers, "wall_s": time.perf_counter() - start}


def write_certificates(folder):
    """A self-signed CA, certificate and key for a scheduler and workers started by hand
    (ca.pem, cert.pem, key.pem, each written atomically with mode 0600): `dask scheduler
    --tls-ca-file ca.pem --tls-cert cert.pem --tls-key key.pem` and the same for each
    worker and client (nrsar-process --dask-make-certs DIR). Returns {name: path}."""
    from distributed.security import Security
    check_certificate_folder(folder)
    sec = Security.temporary()
    os.makedirs(folder, mode=0o700, exist_ok=True)
    paths = {}
    for name, text in zip(CERTIFICATES, (sec.tls_ca_file, sec.tls_client_cert,
                                         sec.tls_client_key)):
        path = os.path.abspath(os.path.join(folder, name))
        with results.atomic(path, mode=0o600) as tmp, open(tmp, "w") as f:
            f.write(text)
        paths[name] = path
    return paths
