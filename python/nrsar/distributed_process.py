#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-process --strip-aperture-s S [--dask local:N | tcp://HOST:PORT]: a long recording
as a strip of apertures, each focused by its own graph, on one process or a Dask cluster
(docs/scale.md).

    the recording, symbols 0 .. S:  | aperture 0 | aperture 1 | ... | (rest left out)
    task a: file_source(offset of its first symbol) -> ofdm_demod -> chain.build (the grid
            from nr_isac_tx skipped to that symbol, the geometry's track start moved there)
            -> the image of aperture a (focused alone, zeros around it: layout())
    stitched in aperture order -> strip_image.npy

A task receives the options, the meta's path and its Slice, and
reads its samples from the SigMF data file by offset: no samples go through the scheduler
(each worker needs the recording's folder: a shared file system). The tasks are the same
function with or without Dask, so the images are identical (qa_distributed_process).

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

import contextlib
import dataclasses
import logging
import os
import tempfile
import time

import numpy as np
from gnuradio import blocks, gr

from . import chain, params, process, recording, results
from .options import OptionError


class SliceError(RuntimeError):
    """A slice that cannot be imaged (its aperture index in the message)."""


@dataclasses.dataclass(frozen=True)
class Slice:
    index: int    # the aperture's index along the strip
    first: int    # first symbol read
    symbols: int  # symbols read
    keep: int     # the aperture's first line in the slice's image
    lines: int    # image lines of the aperture


def _part(rec, first, symbols):
    """The recording of symbols [first, first + symbols): the track start moved there."""
    g, sym_s = rec.geo, rec.num.symbol_s()
    geo = params.make_geometry("paper", carrier_hz=g.carrier_hz, velocity_mps=g.velocity_mps,
                               height_m=g.height_m,
                               track_start_m=g.track_start_m + first * sym_s * g.velocity_mps,
                               aperture_s=symbols * sym_s)
    return dataclasses.replace(rec, geo=geo, symbols=symbols,
                               hardware_delay_samples=rec.hardware_delay_samples +
                               first * rec.symbol_samples)


def layout(opts, rec):
    """The Slices of the strip: apertures of --strip-aperture-s (whole image lines), each
    focused alone with zeros around it, as nrsar-process focuses a one-aperture recording
    (the symbols after the last whole aperture are left out). Not the focuser's streaming
    overlap-save: its before / after overlap spans a target's energy in the scene band,
    18128 / 18373 lines around a 1200-line aperture at sdr20, 0.05 s (docs/scale.md), so a
    task would read 30 times its aperture."""
    if rec.trajectory is not None or rec.navigation is not None or opts.nav is not None:
        raise OptionError(f"--strip-aperture-s = {opts.strip_aperture_s:g} images along the "
                          f"straight track: {rec.meta_path} names a flown path "
                          f"(nrsar:trajectory / nrsar:navigation) or --nav is given, whose "
                          f"time axis the strip's apertures would have to cut too")
    sim_opts = process.sim_options_of(opts, rec)
    step = (process.scenario_of(sim_opts, rec).pulse_symbols *
            sim_opts.presum_factor())  # symbols per image line
    m = int(round(opts.strip_aperture_s / rec.num.symbol_s())) // step * step
    if m < step or m > rec.symbols:
        raise OptionError(f"--strip-aperture-s = {opts.strip_aperture_s:g} must hold at least "
                          f"one image line ({step} symbols) and at most the recording's "
                          f"{rec.symbols} symbols")
    return [Slice(a, a * m, m, 0, m // step) for a in range(rec.symbols // m)]


def _grid_from(tx, n, first):
    """nr_isac_tx's grid from symbol `first` on (a hier block for chain.build's tx=)."""
    hier = gr.hier_block2("grid_from", gr.io_signature(0, 0, 0),
                          gr.io_signature(1, 1, gr.sizeof_gr_complex * n))
    hier.connect(tx, blocks.skiphead(gr.sizeof_gr_complex * n, first), hier)
    return hier


def focus_slice(opts, meta_path, sl):
    """One task: the image lines of aperture sl.index (dict: index, image, compute_s).
    Raises SliceError for non-finite samples in the slice."""
    start = time.perf_counter()
    rec = recording.read(meta_path)
    part = _part(rec, sl.first, sl.symbols)
    sim_opts = process.sim_options_of(opts, part).replace(images="keep", geotiff=False)
    sc = process.scenario_of(sim_opts, part)
    tb = gr.top_block("nrsar-strip")
    tx = _grid_from(chain.make_transmitter(sim_opts, sc), rec.num.num_subcarriers, sl.first)
    graph = chain.build(tb, sim_opts, sc, tx=tx, echo_front=process.recording_front(part))
    tb.run()
    bad = graph["echo"].nonfinite_count()
    if bad:
        raise SliceError(f"aperture {sl.index}: {bad} non-finite samples in symbols "
                         f"[{sl.first}, {sl.first + sl.symbols}) of {rec.data_path}")
    k = graph["focuser"].num_output_bins()
    image = np.asarray(graph["image_sink"].data(), np.complex64).reshape(-1, k)
    return {"index": sl.index, "image": image[sl.keep:sl.keep + sl.lines].copy(),
            "compute_s": time.perf_counter() - start}


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


def run_slices(opts, meta_path, slices, client=None):
    """{index: task result or SliceError text} of every slice, in one process or on the
    client's cluster (retries: a task whose worker died runs again)."""
    out = {}
    if client is None:
        for sl in slices:
            try:
                out[sl.index] = focus_slice(opts, meta_path, sl)
            except SliceError as err:
                out[sl.index] = str(err)
        return out
    futures = client.map(focus_slice, [opts] * len(slices), [meta_path] * len(slices),
                         slices, pure=False, retries=1)
    for sl, fut in zip(slices, futures):
        try:
            out[sl.index] = fut.result()
        except SliceError as err:
            out[sl.index] = str(err)
    return out


def stitch(slices, done, bins):
    """The strip image (apertures in order; a failed one's lines zero) and the failures."""
    parts, failed = [], []
    for sl in slices:
        r = done[sl.index]
        if isinstance(r, str):
            failed.append({"aperture": sl.index, "error": r})
            parts.append(np.zeros((sl.lines, bins), np.complex64))
        else:
            parts.append(r["image"])
    return np.concatenate(parts), failed


def run(opts, client=None):
    """nrsar-process's JSON of a strip (--strip-aperture-s, optionally --dask; client: a
    connected distributed.Client to use instead)."""
    rec = recording.read(opts.recording)
    slices = layout(opts, rec)
    os.makedirs(opts.out, exist_ok=True)
    start = time.perf_counter()
    with contextlib.ExitStack() as stack:
        if client is None and opts.dask:
            client = stack.enter_context(connect(opts))
        done = run_slices(opts, rec.meta_path, slices, client)
        workers = len(client.scheduler_info()["workers"]) if client else 1
    ok = [r for r in done.values() if not isinstance(r, str)]
    bins = ok[0]["image"].shape[1] if ok else 0
    image, failed = stitch(slices, done, bins)
    path = results.write_npy(os.path.abspath(os.path.join(opts.out, "strip_image.npy")), image)
    return {"recording_meta": rec.meta_path, "strip_apertures": len(slices),
            "strip_aperture_lines": slices[0].lines, "strip_slices":
            [[s.first, s.symbols] for s in slices], "strip_image_npy": path,
            "strip_lines": int(image.shape[0]), "strip_failed": failed,
            "strip_task_s": [r["compute_s"] for r in ok], "dask": opts.dask,
            "dask_workers": workers, "wall_s": time.perf_counter() - start}


def write_certificates(folder):
    """A self-signed CA, certificate and key for a scheduler and workers started by hand
    (ca.pem, cert.pem, key.pem; the key mode 0600): `dask scheduler --tls-ca-file ca.pem
    --tls-cert cert.pem --tls-key key.pem` and the same for each worker and client."""
    from distributed.security import Security
    sec = Security.temporary()
    os.makedirs(folder, exist_ok=True)
    paths = {}
    for name, text in (("ca.pem", sec.tls_ca_file), ("cert.pem", sec.tls_client_cert),
                       ("key.pem", sec.tls_client_key)):
        path = os.path.join(folder, name)
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        with os.fdopen(fd, "w") as f:
            f.write(text)
        paths[name] = path
    return paths
