#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Chunk invariance: a block's output is a function of its input stream only, never of how
the scheduler cuts the stream into work() calls. Each test runs the same graph twice, once
normally and once with tiny, irregular work() sizes on the block under test
(set_max_noutput_items of a few items, different per block, so the calls of neighbouring
blocks are cut irregularly too), and requires BIT-IDENTICAL outputs (images, range lines,
metrics, decoded PDUs, getters): every block of the module computes per item, per OFDM
symbol, per slot or per aperture, so nothing may depend on the call boundaries.

The reference is the same graph run without the limit (independent of the cut, not of the
code); a chunk-dependent block (state reset per call, an estimate per call, a rotator phase
restarted per call) fails with a difference of at least float rounding.

GNU Radio's channels.channel_model is NOT chunk-invariant with SIMD VOLK kernels: its
multipath fir_filter_ccc picks its dot-product kernel by the input buffer's alignment, so
the sums round differently (1e-7 here); nrsar-isac's uplink_channel must be, with the SIMD
kernels too (test_007)."""

import os
import shutil
import tempfile

import numpy as np


def private_fftw_wisdom():
    """gr::fft plans with FFTW_MEASURE and shares wisdom through $HOME/.gr_fftw_wisdom; a
    test running in parallel (ctest -j2) can rewrite it between the reference run and the
    chunked run, so the two would use different FFT plans and differ by rounding (seen in
    CI). A private copy of the wisdom keeps both runs on the same plans."""
    home = tempfile.mkdtemp(prefix="qa_chunking_home_")
    wisdom = os.path.join(os.path.expanduser("~"), ".gr_fftw_wisdom")
    if os.path.isfile(wisdom):
        shutil.copy(wisdom, home)
    os.environ["HOME"] = home


private_fftw_wisdom()

from gnuradio import blocks, gr, gr_unittest
from gnuradio.nrsar import backhaul, chain, isac_chain, options, params, scenario

# max_noutput_items per block of the chunked run: small, different, co-prime
LIMITS = (3, 7, 5, 2, 11, 1)
# free-running streams at the end of the base-station graph (see assert_same) and how far
# their ends may differ, in their own items: a tail of under 256 samples at ofdm_sync's
# output ends ofdm_demod's output at most one OFDM symbol (one row) earlier or later
STREAMS = {"sync_out": 256, "demod_out": 2}


def sim_args(extra):
    return options.IsacOptions.parse(
        ["--preset", "tiny", "--scene", "single", "--snr-db", "10", "--seed", "3"] + extra)


def run_radar(extra, chunk=(), time_domain=False):
    """nrsar-sim's chain (or nrsar-isac's time-domain radar front) on the tiny preset; the
    blocks named in chunk get small max_noutput_items. Returns everything observable."""
    args = sim_args(extra)
    sc = scenario.of(args)
    tb = gr.top_block()
    extra_blocks = {}
    if time_domain:
        from gnuradio.nrsar import ofdm_mod
        mod = ofdm_mod(sc.num)
        front = isac_chain.time_domain_front(mod)
        extra_blocks["ofdm_mod"] = mod
        graph = chain.build(tb, args, sc, echo_front=front)
        tb.connect(graph["head"], mod)
        extra_blocks["ofdm_demod"] = front.demod
    else:
        graph = chain.build(tb, args, sc)
    named = dict(graph, **extra_blocks)
    for i, name in enumerate(chunk):
        named[name].set_max_noutput_items(LIMITS[i % len(LIMITS)])
    tb.run()
    probe = graph["probe"]
    out = {
        "image": np.asarray(graph["image_sink"].data()),
        "range": np.asarray(graph["range_sink"].data()),
        "nmse_db": probe.nmse_db(),
        "pslr_db": probe.pslr_db(),
        "snr_out_db": probe.snr_out_db(),
    }
    if args.estimate_snr:
        out["snr_est"] = graph["filter"].estimated_snr_db()
    return out


def run_base_station(chunk=(), coding="none", slots=4, snr_db=50.0):
    """nrsar-isac's transmitter and base station (sdr20, CFO, delay, multipath, 25 dB):
    pusch_encoder -> nr_isac_tx -> ofdm_mod -> uplink_channel -> ofdm_sync -> ofdm_demod ->
    pusch_receiver; the blocks named in chunk get small max_noutput_items."""
    payload = np.random.default_rng(5).integers(0, 256, 4000, dtype=np.uint8).tobytes()
    args = options.IsacOptions.parse(
        ["--preset", "sdr20", "--coding", coding, "--bs-snr-db", str(snr_db), "--seed", "4"]
        + (["--mcs", "20"] if coding == "nr-ldpc" else []))
    num = params.make_numerology("sdr20")
    tb = gr.top_block()
    enc, tx, dmrs, _ = isac_chain.build_transmitter(tb, num, args, payload)
    from gnuradio.nrsar import ofdm_mod
    mod = ofdm_mod(num)
    # The stream stops half a slot after slot `slots`: the scheduler-dependent tail (see
    # STREAMS) then never decides whether a slot is complete (stopping at a slot boundary,
    # the last slot was decoded in some runs and not in others).
    slot_samples = num.symbols_per_slot * (num.fft_size + num.cp_samples)
    head = blocks.head(gr.sizeof_gr_complex, slots * slot_samples + slot_samples // 2)
    tb.connect(tx, mod, head)
    bs = isac_chain.build_base_station(tb, num, args, dmrs, head)
    named = dict(bs, encoder=enc, tx=tx, ofdm_mod=mod)
    sink_sync = blocks.vector_sink_c()
    sink_demod = blocks.vector_sink_c(num.num_subcarriers)
    tb.connect(bs["sync"], sink_sync)
    tb.connect(bs["demod"], sink_demod)
    for i, name in enumerate(chunk):
        named[name].set_max_noutput_items(LIMITS[i % len(LIMITS)])
    tb.run()
    store, rx, sync = bs["store"], bs["receiver"], bs["sync"]
    pdus = [backhaul.pdu_to_python(store.get_message(i)) for i in range(store.num_messages())]
    return {
        "sync_out": np.asarray(sink_sync.data()),
        "demod_out": np.asarray(sink_demod.data()).reshape(-1, num.num_subcarriers),
        "pdu_data": [np.frombuffer(d, np.uint8) for _, d in pdus] and
                    np.concatenate([np.frombuffer(d, np.uint8) for _, d in pdus]),
        "pdu_count": len(pdus),
        "crc_ok": [bool(m.get("crc_ok")) for m, _ in pdus],
        "evm_db": rx.last_evm_db(), "snr_db": rx.last_snr_db(),
        "blocks_ok": rx.blocks_ok(), "blocks_failed": rx.blocks_failed(),
        "cfo_hz": sync.cfo_hz(), "timing": sync.timing_samples(),
    }


class qa_chunking(gr_unittest.TestCase):

    def assert_same(self, a, b, what):
        self.assertEqual(sorted(a), sorted(b))
        for key in a:
            x, y = np.asarray(a[key]), np.asarray(b[key])
            if key in STREAMS:
                # where a stream stops at the end of the run is up to the scheduler (stock
                # mmse_resampler / fft_filter leave a few samples of the tail unconsumed):
                # the common part must be identical and end within a few samples
                self.assertLess(abs(len(x) - len(y)), STREAMS[key], f"{what}: {key} length")
                x, y = x[:min(len(x), len(y))], y[:min(len(x), len(y))]
            self.assertEqual(x.shape, y.shape, f"{what}: {key} shape")
            diff = np.abs(x.astype(complex) - y).max() if x.size and x.shape == y.shape \
                else 0.0
            self.assertTrue(np.array_equal(x, y, equal_nan=True),
                            f"{what}: {key} differs by {diff:g} with small work() calls")

    def check_radar(self, names, extra=(), time_domain=False):
        ref = run_radar(list(extra), (), time_domain)
        for name in names:
            got = run_radar(list(extra), (name,), time_domain)
            self.assert_same(got, ref, f"{name} {' '.join(extra)}")
        got = run_radar(list(extra), tuple(names), time_domain)
        self.assert_same(got, ref, f"all of {names}")

    def test_001_tf_chain(self):
        # nr_isac_tx, scene_echo, tf_filter, range_ifft, rd_focuser, nmse_probe
        self.check_radar(["tx", "echo", "filter", "range_ifft", "focuser", "focuser_ref",
                          "probe"])

    def test_002_tf_filter_snr_estimation_and_threads(self):
        self.check_radar(["filter", "echo"], ["--estimate-snr", "--filter-threads", "2"])

    def test_003_cheby_presum(self):
        self.check_radar(["range_ifft", "presum", "focuser"], ["--presum", "cheby",
                                                               "--decim", "4"])

    def test_004_time_domain_front(self):
        # ofdm_mod -> td_echo -> ofdm_demod
        self.check_radar(["ofdm_mod", "echo", "ofdm_demod", "filter"], time_domain=True)

    def test_005_base_station(self):
        # ofdm_sync's CFO rotator restarted its float phasor at every work() call: the
        # de-rotated samples, hence EVM and (LDPC at 25 dB) decoded bits, depended on the cut
        ref = run_base_station()
        self.assertEqual(ref["blocks_ok"], 4)  # every slot sent in full, none of the half slot
        for name in ("channel", "sync", "demod", "receiver"):
            self.assert_same(run_base_station((name,)), ref, name)
        self.assert_same(run_base_station(("channel", "sync", "demod", "receiver")), ref, "all")

    def test_006_base_station_ldpc(self):
        # the UL-SCH at qam256 MCS 20 and 25 dB (qa_isac test_006)
        ref = run_base_station(coding="nr-ldpc", slots=3, snr_db=25.0)
        self.assertGreater(ref["blocks_ok"], 0)
        self.assert_same(run_base_station(("channel", "sync", "demod", "receiver"), "nr-ldpc", 3,
                                          25.0), ref, "ldpc")

    def test_007_channel_with_simd_volk(self):
        # The SIMD kernels are where call boundaries change rounding (alignment, FMA body vs
        # scalar tail): this check runs in a child process without VOLK_GENERIC. Stock
        # channel_model is only reported (it differs at ~1e-7 there); nrsar-isac's
        # uplink_channel must be bit-identical.
        import subprocess
        import sys
        env = dict(os.environ)
        env.pop("VOLK_GENERIC", None)
        out = subprocess.run([sys.executable, os.path.abspath(__file__), "--channel-child"],
                             env=env, capture_output=True, text=True, timeout=300)
        self.assertEqual(out.returncode, 0, out.stdout + out.stderr)
        self.assertIn("uplink_channel max diff 0", out.stdout)


def channel_child():
    """Channel output with normal vs tiny work() sizes upstream (SIMD VOLK)."""
    from gnuradio import channels, nrsar
    x = np.random.default_rng(1).standard_normal((2, 60001)).astype(np.float32)
    x = (x[0] + 1j * x[1]).astype(np.complex64)
    taps = options.parse_taps(options.DEFAULT_TAPS)

    def run(make, limit):
        tb = gr.top_block()
        src, cp, chan = blocks.vector_source_c(x.tolist()), blocks.copy(gr.sizeof_gr_complex), make()
        sink = blocks.vector_sink_c()
        if limit:
            cp.set_max_noutput_items(limit)
        tb.connect(src, cp, chan, sink)
        tb.run()
        return np.asarray(sink.data())

    for name, make in (("channel_model", lambda: channels.channel_model(0.05, 0.3 / 64, 1.0, taps, 7)),
                       ("uplink_channel",
                        lambda: nrsar.uplink_channel(nrsar.uplink_channel_config(
                            taps=taps, cfo=0.3 / 64, noise_voltage=0.05, seed=7)))):
        a, b = run(make, 0), run(make, 3)
        n = min(a.size, b.size)
        print(f"{name} max diff {np.abs(a[:n] - b[:n]).max():g} ({a.size} / {b.size} samples)")


if __name__ == "__main__":
    import sys
    if "--channel-child" in sys.argv:
        channel_child()
    else:
        gr_unittest.run(qa_chunking)
