#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Overflow gaps in a recording (docs/recording.md, "Gaps"): a radio that overflows drops
samples; ofdm_demod's rx_time alignment re-aligns to the symbol grid and outputs the lost
symbols as zeros, so the aperture goes on with those pulses missing. Gaps of 1, 100 and
10000 samples are cut out of nrsar-sim's recording (numpy, as a radio would lose them, with
the SigMF overflow annotation), nrsar-process forms each image, and:

- lost_symbols = ceil((p + g) / L) - floor(p / L) for a gap of g samples from flight sample
  p (the symbol in progress is dropped whole);
- the range-compressed data are the gap-free run's with exactly those pulses zeroed;
- the coherent peak of the point target falls by (1 - L / M): PEL rises by
  -20 log10(1 - L / M); the NMSE is nmse_cost_db's float64 expectation (SPEC 8 with the
  lost pulses' focused echo orthogonal to the reference), within 0.3 dB;
- transmit underruns: tx_underrun_counter counts gr-uhd's async underflow events into the
  recording's meta and nrsar-process's JSON.
"""

import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
from gnuradio import gr_unittest
from gnuradio.nrsar import chain, process
from gnuradio.nrsar.options import ProcessOptions, SimOptions

APPS = os.environ.get("NRSAR_APPS_DIR") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps")

C = 299792458.0
# sdr20, 0.05 s = 1200 symbols of L = 1280 samples, one target; QPSK at 40 dB (WF) keeps the
# gap-free NMSE low (about -22 dB: the 84 Hz band holds 15 dB more noise than the target's own
# 3 Hz) so that one lost pulse shows.
FLIGHT = ["--preset", "sdr20", "--aperture-s", "0.05", "--target", "300,1", "--snr-db", "40",
          "--modulation", "qpsk"]
L_SYM, M = 1280, 1200
# (first lost flight sample, lost samples): on a symbol boundary, across one, inside one
GAPS = {1: (600 * L_SYM, 1), 100: (300 * L_SYM - 50, 100), 10000: (900 * L_SYM + 7, 10000)}


def lost_pulses(p, g):
    """The symbols a gap of g samples from flight sample p costs (independent of the code:
    the symbol holding sample p is incomplete, the first whole one starts at or after p + g)."""
    return list(range(p // L_SYM, -(-(p + g) // L_SYM)))


def write_gapped(meta, data, p, g, folder):
    """The recording a radio that lost samples p .. p + g - 1 would have written: the samples
    cut out, an overflow annotation at the first sample after the gap."""
    os.makedirs(folder)
    np.concatenate([data[:p], data[p + g:]]).tofile(os.path.join(folder, "flight.sigmf-data"))
    meta = json.loads(json.dumps(meta))
    meta["annotations"][0]["core:sample_count"] -= g
    meta["annotations"].append({"core:sample_start": p, "core:sample_count": 0,
                                "core:label": "overflow", "nrsar:lost_samples": g})
    path = os.path.join(folder, "flight.sigmf-meta")
    with open(path, "w") as f:
        json.dump(meta, f)
    return path


def nmse_cost_db(run0):
    """The NMSE (dB) nmse_probe should give when the pulses of each gap in GAPS are zeroed,
    from the gap-free run run0 (its NMSE, axes and band) and SPEC 8, in float64 numpy.

    Zeroing the lost set Lambda takes d = c ref_Lambda out of the image, ref_Lambda the
    focused lost pulses of the noise-free echo; the reference keeps them. With beta =
    <ref, d> / (c <ref, ref>) (about L / M) the calibrated error img / c_hat - ref is the
    gap-free error without the lost pulses' share, scaled by 1 / (1 - beta), plus
    d_perp / (c (1 - beta)), the part of ref_Lambda orthogonal to ref:

        NMSE_g = NMSE_0 (1 - L / M) / |1 - beta|^2
                 + (W / s) (N M / (K M_img)) (||ref||^2 / max |ref|^2) rho / |1 - beta|^2,
        rho = (||ref_Lambda||^2 - |<ref, ref_Lambda>|^2 / ||ref||^2) / ||ref||^2,

    W / s the probe's pixel weight (W = R0 (c(f_hi) - c(f_lo)) metres of track in the band,
    s = M dy of it holding pulses: every pixel of this 2.5 m aperture, docs/accuracy.md). ref
    and ref_Lambda are formed here: the point target's slow-time history exp(-j 4 pi R(y_p) /
    lambda) (exact range) in the focuser's zero-padded block (its FFT size and framing),
    FFT, the band's bins times the hyperbolic azimuth matched filter of each range bin
    exp(j 4 pi r_k sqrt(1 - (lambda f / 2v)^2) / lambda), IFFT, the image's lines; across
    range the bins' Dirichlet response of the N subcarriers (no migration: under 0.01 bin)."""
    from gnuradio.nrsar import scenario
    opts = SimOptions.parse(FLIGHT)
    sc = scenario.of(opts)
    geo, num = sc.geo, sc.num
    foc = chain.imaging_chain(opts, sc, False, reference=False).focuser
    n_fft, before, shift = foc.fft_size(), foc.overlap_before(), foc.line_shift()
    lam, v, T = C / geo.carrier_hz, geo.velocity_mps, num.symbol_s()
    x_t, y_t = (float(c) for c in FLIGHT[FLIGHT.index("--target") + 1].split(",")[:2])
    r0 = math.hypot(x_t, geo.height_m)
    k_bins, lines = run0["range_bins"], run0["azimuth_lines"]
    r_k = run0["range_axis_m"][0] + run0["range_axis_m"][1] * np.arange(k_bins)
    lo, hi = run0["doppler_band_hz"]
    n = np.arange(num.num_subcarriers)
    dirichlet = np.exp(4j * np.pi * num.subcarrier_spacing_hz / C * np.outer(r_k - r0, n)).sum(1)
    prf, centre = 1.0 / T, 0.5 * (lo + hi)
    f = centre + np.remainder(np.fft.fftfreq(n_fft, T) - centre + prf / 2, prf) - prf / 2
    band = (f >= lo) & (f <= hi)
    root = np.sqrt(np.maximum(0.0, 1.0 - (lam * f / (2 * v)) ** 2))
    filters = np.where(band, np.exp(4j * np.pi * np.outer(r_k, root) / lam), 0.0)
    y_p = geo.track_start_m + v * T * np.arange(M)
    history = np.exp(-4j * np.pi * np.sqrt(r0 ** 2 + (y_p - y_t) ** 2) / lam)
    first = before - shift  # block index of pulse 0 (the block starts at input line shift - before)

    def focus(pulses):
        s = np.zeros(n_fft, complex)
        s[first + pulses] = history[pulses]
        img = np.fft.ifft(np.fft.fft(s) * filters, axis=1)[:, before:before + lines]
        return (dirichlet[:, None] * img).T

    ref = focus(np.arange(M))
    e_ref = np.vdot(ref, ref).real
    q = e_ref / np.max(np.abs(ref)) ** 2

    def track(freq):
        u = lam * freq / (2 * v)
        return u / math.sqrt(1 - u * u)
    weight = r0 * (track(hi) - track(lo)) / min(r0 * (track(hi) - track(lo)), M * v * T)
    nmse0 = 10 ** (run0["nmse_db"] / 10)
    expected = {}
    for g, (p, count) in GAPS.items():
        lost = np.array(lost_pulses(p, count))
        d = focus(lost)
        beta = np.vdot(ref, d) / e_ref
        rho = (np.vdot(d, d).real - abs(np.vdot(ref, d)) ** 2 / e_ref) / e_ref
        scale = 1.0 / abs(1.0 - beta) ** 2
        cost = (weight * num.num_subcarriers * M / (k_bins * lines) * q * rho * scale +
                nmse0 * (1 - len(lost) / M) * scale)
        expected[g] = 10 * math.log10(cost)
    return expected


class qa_gaps(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="qa_gaps_")
        rec = os.path.join(cls.dir, "rec")
        opts = SimOptions.parse(FLIGHT + ["--record", rec, "--out", os.path.join(cls.dir, "sim")])
        cls.sim = chain.simulate(opts)
        cls.meta_path = os.path.join(rec, "flight.sigmf-meta")
        with open(cls.meta_path) as f:
            cls.meta = json.load(f)
        cls.data = np.fromfile(os.path.join(rec, "flight.sigmf-data"), np.complex64)
        cls.runs = {0: cls.process(cls.meta_path, "p0")}
        for g, (p, count) in GAPS.items():
            path = write_gapped(cls.meta, cls.data, p, count, os.path.join(cls.dir, f"g{g}"))
            cls.runs[g] = cls.process(path, f"p{g}")

    @classmethod
    def process(cls, meta_path, name):
        opts = ProcessOptions.parse([meta_path, "--out", os.path.join(cls.dir, name)])
        result = process.run(opts)
        result["rc"] = np.load(result["range_compressed_npy"])
        return result

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_001_lost_symbols_counted(self):
        self.assertEqual(self.runs[0]["lost_symbols"], 0)
        for g, (p, count) in GAPS.items():
            r = self.runs[g]
            self.assertEqual(r["lost_symbols"], len(lost_pulses(p, count)), g)
            self.assertEqual((r["overflows"], r["lost_samples"]), (1, count))
            self.assertEqual(r["samples_read"], M * L_SYM - count)
            self.assertEqual(r["symbols"], M)
            self.assertTrue(any("symbols lost" in w for w in r["warnings"]), r["warnings"])
        # 1 sample on a boundary: 1 symbol; 100 across one: 2; 10000: 8 (7.8 symbols)
        self.assertEqual([self.runs[g]["lost_symbols"] for g in (1, 100, 10000)], [1, 2, 8])

    def test_002_lost_pulses_zeroed_in_place(self):
        """The aperture goes on: the gap-free run's range-compressed pulses, the lost ones
        zero, every other one where it was."""
        base = self.runs[0]["rc"]
        scale = np.max(np.abs(base))
        for g, (p, count) in GAPS.items():
            want = base.copy()
            want[lost_pulses(p, count)] = 0
            got = self.runs[g]["rc"]
            self.assertEqual(got.shape, base.shape)
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-5 * scale)

    def test_003_image_cost(self):
        """The coherent peak falls by (1 - L / M): each of the M pulses adds one M-th of the
        point target's peak when the processed band holds its history, so the calibration
        c_hat = <ref, img> / <ref, ref> falls by L / M and PEL rises by -20 log10(1 - L / M)
        (the noise moves c_hat by about 1e-4 dB here; the tolerance 2 % + 1e-3 dB). The
        NMSE against nmse_cost_db's float64 expectation (0.3 dB: the noise's cross term with
        the lost echo, measured 0.05 dB at most)."""
        sim0 = self.runs[0]
        expected = nmse_cost_db(self.runs[0])
        for g in (1, 100, 10000):
            p, count = GAPS[g]
            lost = len(lost_pulses(p, count))
            r = self.runs[g]
            want = -20 * math.log10(1 - lost / M)
            print(f"\ngap {count}: {lost} pulses lost; PEL {r['pel_db'] - sim0['pel_db']:+.4f} dB "
                  f"(1 - L/M: {want:+.4f}); NMSE {sim0['nmse_db']:.2f} -> {r['nmse_db']:.2f} dB "
                  f"(expected {expected[g]:.2f} dB)")
            self.assertAlmostEqual(r["pel_db"] - sim0["pel_db"], want, delta=0.02 * want + 1e-3)
            self.assertAlmostEqual(r["nmse_db"], expected[g], delta=0.3)
        self.assertGreater(self.runs[1]["nmse_db"], sim0["nmse_db"] + 0.5)  # one pulse shows

    def test_004_record_gap_flag(self):
        """nrsar-sim --record-gap writes what the numpy cut above writes."""
        p, count = GAPS[100]
        rec = os.path.join(self.dir, "flag")
        out = subprocess.run([sys.executable, os.path.join(APPS, "nrsar-sim")] + FLIGHT +
                             ["--record", rec, "--record-gap", f"{p}:{count}", "--images",
                              "none", "--out", os.path.join(self.dir, "flag-out")],
                             capture_output=True, text=True, timeout=600)
        self.assertEqual(out.returncode, 0, out.stderr)
        got = np.fromfile(os.path.join(rec, "flight.sigmf-data"), np.complex64)
        np.testing.assert_array_equal(got, np.concatenate([self.data[:p],
                                                           self.data[p + count:]]))
        with open(os.path.join(rec, "flight.sigmf-meta")) as f:
            meta = json.load(f)
        self.assertEqual([a for a in meta["annotations"] if a["core:label"] == "overflow"],
                         [{"core:sample_start": p, "core:sample_count": 0,
                           "core:label": "overflow", "nrsar:lost_samples": count}])
        self.assertEqual(meta["annotations"][0]["core:sample_count"], M * L_SYM - count)

    def test_005_bad_gaps(self):
        """Bad gaps are one line naming the flag or the field, exit 2."""
        def sim(args):
            return subprocess.run([sys.executable, os.path.join(APPS, "nrsar-sim")] + FLIGHT +
                                  args + ["--out", os.path.join(self.dir, "bad")],
                                  capture_output=True, text=True, timeout=600)
        for args, text in ((["--record-gap", "5:1"], "--record-gap = '5:1' needs --record"),
                           (["--record", self.dir + "/b", "--record-gap", "5"],
                            "must be SAMPLE:COUNT"),
                           (["--record", self.dir + "/b", "--record-gap", "5:0"],
                            "needs SAMPLE >= 0 and COUNT >= 1"),
                           (["--record", self.dir + "/b", "--record-gap", "5:10",
                             "--record-gap", "9:1"], "must start after the gap '5:10' ends"),
                           (["--record", self.dir + "/b", "--record-gap", f"{M * L_SYM - 5}:5"],
                            "must end before the flight's last sample")):
            out = sim(args)
            self.assertEqual(out.returncode, 2, (args, out.stderr))
            self.assertIn(text, out.stderr)
            self.assertNotIn("Traceback", out.stderr)
        meta = json.loads(json.dumps(self.meta))
        meta["annotations"].append({"core:sample_start": 5, "core:sample_count": 0,
                                    "core:label": "overflow", "nrsar:lost_samples": 0})
        folder = os.path.join(self.dir, "bad-meta")
        os.makedirs(folder)
        shutil.copy(os.path.join(os.path.dirname(self.meta_path), "flight.sigmf-data"), folder)
        with open(os.path.join(folder, "flight.sigmf-meta"), "w") as f:
            json.dump(meta, f)
        out = subprocess.run([sys.executable, os.path.join(APPS, "nrsar-process"),
                              os.path.join(folder, "flight.sigmf-meta"), "--out",
                              os.path.join(self.dir, "bad-out")],
                             capture_output=True, text=True, timeout=600)
        self.assertEqual(out.returncode, 2, out.stderr)
        self.assertIn("nrsar:lost_samples = 0 must be at least 1", out.stderr)

    def test_006_radio_recorder(self):
        """recording.sigmf_sink, the radio graphs' recorder: a stream with a USRP source's
        rx_time tags (first sample, first after a 10000-sample overflow) is recorded with the
        overflow annotation the numpy cut has, and nrsar-process forms the same image."""
        from gnuradio import blocks, gr
        import pmt
        from gnuradio.nrsar import recording
        p, count = GAPS[10000]
        x = np.concatenate([self.data[:p], self.data[p + count:]])
        fs = 30.72e6

        def stamp(offset, t):
            whole = math.floor(t)
            return gr.tag_utils.python_to_tag((offset, pmt.intern("rx_time"), pmt.make_tuple(
                pmt.from_uint64(whole), pmt.from_double(t - whole))))
        t0 = 7.25
        src = blocks.vector_source_c(x.tolist(), False, 1,
                                     [stamp(0, t0), stamp(p, t0 + (p + count) / fs)])
        folder = os.path.join(self.dir, "radio")
        opts = SimOptions.parse(FLIGHT)
        sink = recording.sigmf_sink(folder, opts, hw="test stream", dmrs=None)
        tb = gr.top_block()
        tb.connect(src, sink)
        tb.run()
        rec = recording.read(os.path.join(folder, "flight.sigmf-meta"))
        self.assertEqual(rec.gaps, [(p, count)])
        self.assertIsNone(rec.snr_db)  # a radio does not know it
        np.testing.assert_array_equal(np.fromfile(rec.data_path, np.complex64), x)
        r = process.run(ProcessOptions.parse([rec.meta_path, "--snr-db", "40", "--out",
                                              os.path.join(self.dir, "radio-out")]))
        self.assertEqual(r["lost_symbols"], self.runs[10000]["lost_symbols"])
        self.assertAlmostEqual(r["nmse_db"], self.runs[10000]["nmse_db"], delta=1e-6)

    def test_007_tx_underruns(self):
        """Transmit underruns are counted the way gr-uhd's sink reports them (its async_msgs
        port: (uhd_async_msg . {event_code: (underflow ...), time_spec, channel})): the
        recorder writes the count into the meta and nrsar-process reports it; burst_ack and
        other messages are not underruns. nrsar-sim's simulated transmitter cannot underrun:
        its recording says 0."""
        from gnuradio import blocks, gr
        import pmt
        from gnuradio.nrsar import recording

        def event(codes, t=None):
            value = pmt.PMT_NIL
            for code in codes:
                value = pmt.list_add(value, pmt.intern(code))
            value = pmt.dict_add(pmt.make_dict(), pmt.intern("event_code"), value)
            if t is not None:
                value = pmt.dict_add(value, pmt.intern("time_spec"),
                                     pmt.cons(pmt.from_long(int(t)), pmt.from_double(t % 1)))
            value = pmt.dict_add(value, pmt.intern("channel"), pmt.from_uint64(0))
            return pmt.cons(pmt.intern("uhd_async_msg"), value)

        # the radio's events: the counter's port takes them while a graph runs
        counter = recording.tx_underrun_counter()
        radio = gr.top_block()
        radio.msg_connect(blocks.message_strobe(pmt.PMT_NIL, 10000), "strobe", counter,
                          "async_msgs")
        for msg in (event(["underflow"], 12.5), event(["burst_ack"]),
                    event(["underflow_in_packet", "seq_error"]), event(["time_error"], 13.0),
                    pmt.intern("not an event"), event(["underflow"])):
            counter.to_basic_block()._post(pmt.intern("async_msgs"), msg)
        radio.start()
        for _ in range(200):  # the queue is handled at once; 10 s at most
            if counter.count() == 3:
                break
            time.sleep(0.05)
        radio.stop()
        radio.wait()
        self.assertEqual(counter.count(), 3)
        folder = os.path.join(self.dir, "underruns")
        sink = recording.sigmf_sink(folder, SimOptions.parse(FLIGHT), hw="test stream",
                                    tx_underruns=counter)
        tb = gr.top_block()
        tb.connect(blocks.vector_source_c(self.data.tolist(), False), sink)
        tb.run()
        self.assertEqual(counter.times(), [12.5, None, None])
        rec = recording.read(os.path.join(folder, "flight.sigmf-meta"))
        self.assertEqual(rec.meta["global"]["nrsar:tx_underruns"], 3)
        r = process.run(ProcessOptions.parse([rec.meta_path, "--snr-db", "40", "--images",
                                              "none", "--out",
                                              os.path.join(self.dir, "underruns-out")]))
        self.assertEqual(r["tx_underruns"], 3)
        self.assertTrue(any("underran 3 times" in w for w in r["warnings"]), r["warnings"])
        self.assertEqual(self.meta["global"]["nrsar:tx_underruns"], 0)  # nrsar-sim's


if __name__ == "__main__":
    gr_unittest.run(qa_gaps)
