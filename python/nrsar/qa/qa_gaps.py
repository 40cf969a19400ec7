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
- the image's cost is a float64 model's: the target's slow-time history d_m (SPEC 3's round
  trip), the lost pulses e = d on the lost set, compressed in the focuser's Doppler band by
  the target's own phase-only matched filter onto the image's lines. With Pd and Pe those
  images, the calibration c_hat = <Pd, P(d - e)> / <Pd, Pd> = 1 - beta falls by beta (L / M
  when the band holds all of the history: the coherent peak falls by (1 - L / M)), so PEL
  rises by -20 log10|1 - beta|; the calibrated error (P(d - e) / c_hat - Pd) =
  (beta Pd - Pe) / (1 - beta) adds its energy to the NMSE:

      NMSE_gap = NMSE_0 (1 - L/M) / |1 - beta|^2
                 + N M rho_r sum_l w_l |beta Pd_l - Pe_l|^2 / (|1 - beta|^2 n_w max_l |Pd_l|^2)

  (the first term: the noise and data randomness of the M - L pulses left, recalibrated; the
  second: SPEC 8's NMSE of the separable error rp(k) x (beta Pd - Pe)(l), rho_r = sum_k
  |rp(k)|^2 / max |rp|^2 from the reference image's peak line, w_l the probe's pixel weights
  at the target's bin, n_w the pixels of non-zero weight). A lost pulse costs the image in
  proportion to the target's energy, not the noise's: one pulse of 1200 raises the NMSE
  from -16 to about -10 dB here.
"""

import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from gnuradio import gr_unittest
from gnuradio import nrsar
from gnuradio.nrsar import chain, params, process
from gnuradio.nrsar.options import ProcessOptions, SimOptions

APPS = os.environ.get("NRSAR_APPS_DIR") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps")

C = 299792458.0
# sdr20, 0.05 s = 1200 symbols of L = 1280 samples, one target; QPSK at 20 dB (WF) keeps the
# gap-free NMSE low (-16 dB) so that one lost pulse shows.
FLIGHT = ["--preset", "sdr20", "--aperture-s", "0.05", "--target", "300,1", "--snr-db", "20",
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


def azimuth_images(sim, geo, num, target, lost):
    """(Pd, Pe) on the image's lines: the target's slow-time history d (float64, SPEC 3) and
    its lost part e, in the focuser's band, compressed by the target's own phase-only matched
    filter (the image of d peaks at the target's y), linear (zero-padded) correlation."""
    x, y = target
    t = np.arange(M) * num.symbol_s()
    yp = geo.track_start_m + geo.velocity_mps * t
    r = np.sqrt(x ** 2 + geo.height_m ** 2 + (yp - y) ** 2)
    d = np.exp(-4j * np.pi * geo.carrier_hz * r / C)
    e = np.zeros_like(d)
    e[lost] = d[lost]
    nf = 1 << 16
    f = np.fft.fftfreq(nf, num.symbol_s())
    lo, hi = sim["doppler_band_hz"]
    band = (f >= lo) & (f <= hi)
    spec_d, spec_e = np.fft.fft(d, nf), np.fft.fft(e, nf)
    # the band must hold the target's history (else the focuser's band is not the scene's)
    assert np.sum(np.abs(spec_d[band]) ** 2) > 0.95 * np.sum(np.abs(spec_d) ** 2)
    y0, dy = sim["azimuth_axis_m"]
    lines = y0 + dy * np.arange(sim["azimuth_lines"])
    mf = np.where(band, np.exp(-1j * np.angle(spec_d)), 0)
    steer = np.exp(2j * np.pi * np.outer(lines - y, f[band]) / geo.velocity_mps)
    return (steer @ (mf[band] * spec_d[band]) / nf, steer @ (mf[band] * spec_e[band]) / nf,
            lines)


class qa_gaps(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="qa_gaps_")
        rec = os.path.join(cls.dir, "rec")
        opts = SimOptions.parse(FLIGHT + ["--record", rec, "--out", os.path.join(cls.dir, "sim")])
        cls.sim, graph = chain.simulate_graph(opts, keep_reference=True)
        k = cls.sim["range_bins"]
        cls.ref = np.asarray(graph["reference_sink"].data(), np.complex64).reshape(-1, k)
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
        """PEL and NMSE of each gapped image against the float64 model of the module doc."""
        geo = params.make_geometry("paper", **self.meta["global"]["nrsar:geometry"])
        num = params.make_numerology("sdr20")
        sim0 = self.runs[0]
        target = (300.0, 1.0)
        # range factor and weights from the reference image (the S = 1 branch)
        ref = self.ref
        peak_line, peak_bin = np.unravel_index(np.argmax(np.abs(ref)), ref.shape)
        rp = np.abs(ref[peak_line]) ** 2
        rho_r = rp.sum() / rp.max()
        y0, dy = sim0["azimuth_axis_m"]
        r0, dr = sim0["range_axis_m"]
        lines, bins = ref.shape
        span = (geo.track_start_m, geo.track_start_m + M * dy)
        lo, hi = sim0["doppler_band_hz"]
        w = np.asarray(nrsar.strip_pixel_weights(
            lines, bins, y0, dy, r0, dr, span[0], span[1], lo, hi, C / geo.carrier_hz,
            geo.velocity_mps)).reshape(lines, bins)
        n_w = np.count_nonzero(w)
        w_t = w[:, peak_bin]
        nm = num.num_subcarriers * M
        nmse0 = 10 ** (sim0["nmse_db"] / 10)
        for g, (p, count) in GAPS.items():
            lost = lost_pulses(p, count)
            pd, pe, _ = azimuth_images(sim0, geo, num, target, lost)
            beta = np.vdot(pd, pe) / np.vdot(pd, pd)
            err = beta * pd - pe
            gain = abs(1 - beta) ** 2
            want = (nmse0 * (1 - len(lost) / M) / gain +
                    nm * rho_r * np.sum(w_t * np.abs(err) ** 2) /
                    (gain * n_w * np.max(np.abs(pd)) ** 2))
            r = self.runs[g]
            print(f"\ngap {count}: {len(lost)} pulses lost, beta {abs(beta):.5f} (L/M "
                  f"{len(lost) / M:.5f}); PEL {r['pel_db'] - sim0['pel_db']:+.4f} dB "
                  f"(model {-10 * math.log10(gain):+.4f}); NMSE {sim0['nmse_db']:.2f} -> "
                  f"{r['nmse_db']:.2f} dB (model {10 * math.log10(want):.2f})")
            self.assertAlmostEqual(r["pel_db"] - sim0["pel_db"], -10 * math.log10(gain),
                                   delta=0.1 * abs(10 * math.log10(gain)) + 1e-3)
            self.assertAlmostEqual(r["nmse_db"], 10 * math.log10(want), delta=0.5)

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
        r = process.run(ProcessOptions.parse([rec.meta_path, "--snr-db", "20", "--out",
                                              os.path.join(self.dir, "radio-out")]))
        self.assertEqual(r["lost_symbols"], self.runs[10000]["lost_symbols"])
        self.assertAlmostEqual(r["nmse_db"], self.runs[10000]["nmse_db"], delta=1e-6)


if __name__ == "__main__":
    gr_unittest.run(qa_gaps)
