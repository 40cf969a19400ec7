#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of nrsar.td_echo: through a slow numpy OFDM modulator/demodulator (np.fft, subcarrier n
at (n - k0) Delta f, unitary, CP first) the time-domain echo equals scene_echo's eq. (7) and
the numpy float64 evaluation of eqs. (7)-(8); the noise per RE matches snr_db; tags and
non-finite input; parameter rules."""

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest
from gnuradio.nrsar.theory import ofdm_demodulate, ofdm_modulate

try:
    from gnuradio import nrsar
except ImportError:
    import os
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bindings"))
    from gnuradio import nrsar

C = 299792458.0
PAPER3 = [(300.0, 100.0, 1.0, 0.0), (250.0, 100.0, 1.0, 0.0), (300.0, 140.0, 1.0, 0.0)]


def qam256(rng, shape):
    """Random 256-QAM symbols (38.211 levels, unit mean power)."""
    levels = np.arange(-15, 16, 2) / np.sqrt(170.0)
    return rng.choice(levels, shape) + 1j * rng.choice(levels, shape)


def k0_of(num):
    return (num.num_subcarriers // 2) & ~1


def echo_reference(num, geo, targets, s):
    """eq. (7) without noise, exact range (8), float64."""
    M, N = s.shape
    tsym = (num.fft_size + num.cp_samples) / (num.fft_size * num.subcarrier_spacing_hz)
    yp = geo.track_start_m + geo.velocity_mps * np.arange(M) * tsym
    f = geo.carrier_hz + np.arange(N) * num.subcarrier_spacing_hz
    h = np.zeros((M, N), dtype=np.complex128)
    for (x, yq, rcs, phase) in targets:
        R = np.sqrt(x**2 + geo.height_m**2 + (yp - yq) ** 2)
        h += np.sqrt(rcs) * np.exp(1j * phase) * np.exp(-4j * np.pi * np.outer(R, f) / C)
    return s * h


def nmse_db(got, ref):
    return 10.0 * np.log10(np.sum(np.abs(got - ref) ** 2) / np.sum(np.abs(ref) ** 2))


def scene_of(targets):
    return nrsar.scene([nrsar.point_target(*t) for t in targets])


class qa_td_echo(gr_unittest.TestCase):

    def setUp(self):
        self.tb = gr.top_block()
        # 48 of 64 subcarriers (band edge 0.375 cycles/sample), CP of 32 samples (16.7 us):
        # the paper3 round trip (~13.4 samples) leaves 18 samples of CP margin for the FIR.
        self.num = nrsar.make_numerology("tiny", num_subcarriers=48, cp_samples=32)
        self.geo = nrsar.make_geometry("paper")
        self.N = 48

    def tearDown(self):
        self.tb = None

    def run_td(self, x, scn, snr_db=float("inf"), seed=0, taps=32, tags=(), num=None, geo=None,
               max_items=0, beam=None):
        src = blocks.vector_source_c(list(x.astype(np.complex64)), False, 1, list(tags))
        blk = nrsar.td_echo(num or self.num, geo or self.geo, scn, snr_db, seed, taps, -1.0,
                            beam or nrsar.make_beam("whole_block"))
        if max_items:
            blk.set_max_noutput_items(max_items)  # many small work() calls
        snk = blocks.vector_sink_c()
        tb = gr.top_block()
        tb.connect(src, blk, snk)
        tb.run()
        return np.array(snk.data(), dtype=np.complex128), snk.tags(), blk

    def run_tf(self, grid, scn):
        src = blocks.vector_source_c(list(grid.astype(np.complex64).reshape(-1)), False, self.N)
        blk = nrsar.scene_echo(self.num, self.geo, scn)
        snk = blocks.vector_sink_c(self.N)
        tb = gr.top_block()
        tb.connect(src, blk, snk)
        tb.run()
        return np.array(snk.data(), dtype=np.complex128).reshape(-1, self.N)

    def test_demodulated_echo_equals_scene_echo(self):
        rng = np.random.default_rng(1)
        M = 300
        targets = [(300.0, 100.0, 1.0, 0.3), (250.0, 100.0, 0.5, -1.0), (300.0, 140.0, 2.0, 2.0)]
        grid = qam256(rng, (M, self.N))
        y, _, _ = self.run_td(ofdm_modulate(grid, self.num), scene_of(targets))
        got = ofdm_demodulate(y, self.num)
        tf = self.run_tf(grid, scene_of(targets))
        ref = echo_reference(self.num, self.geo, targets, grid)
        e_tf, e_ref = nmse_db(got, tf), nmse_db(got, ref)
        print(f"demodulated td_echo vs scene_echo: {e_tf:.1f} dB, vs float64 eq. (7): {e_ref:.1f} dB")
        self.assertLess(e_tf, -60.0)
        self.assertLess(e_ref, -60.0)

    def test_azimuth_beam_scales_each_symbol(self):
        # Two-way azimuth pattern of eq. (1): amplitude sinc^2(D_a (y_q - y_p(m)) / (R lambda)),
        # evaluated here in float64 per symbol; D_a = 2 m puts the target (20 m ahead of the
        # platform) on the main lobe's slope (gain ~0.46).
        rng = np.random.default_rng(6)
        M, Da = 200, 2.0
        geo = nrsar.make_geometry("paper", track_start_m=80.0)
        targets = [(300.0, 100.0, 1.0, 0.7)]
        grid = qam256(rng, (M, self.N))
        beam = nrsar.make_beam("azimuth", az_aperture_m=Da)
        y, _, blk = self.run_td(ofdm_modulate(grid, self.num), scene_of(targets), geo=geo, beam=beam)
        self.assertAlmostEqual(blk.beam().az_aperture_m, Da)
        got = ofdm_demodulate(y, self.num)
        tsym = (self.num.fft_size + self.num.cp_samples) / (self.num.fft_size * self.num.subcarrier_spacing_hz)
        yp = geo.track_start_m + geo.velocity_mps * np.arange(M) * tsym
        R = np.sqrt(300.0**2 + geo.height_m**2 + (yp - 100.0) ** 2)
        g = np.sinc(Da * (100.0 - yp) / (R * C / geo.carrier_hz)) ** 2
        ref = echo_reference(self.num, geo, targets, grid) * g[:, None]
        e = nmse_db(got, ref)
        print(f"azimuth beam (gain {g[0]:.3f} .. {g[-1]:.3f}): {e:.1f} dB")
        self.assertLess(e, -60.0)
        # beyond the cutoff (|u| = 0.45 > 0.3): the target is not lit at all
        narrow = nrsar.make_beam("azimuth", az_aperture_m=Da, cutoff=0.3)
        y0, _, _ = self.run_td(ofdm_modulate(grid[:10], self.num), scene_of(targets), geo=geo, beam=narrow)
        self.assertEqual(np.max(np.abs(y0)), 0.0)

    def test_error_grows_as_the_cp_margin_shrinks(self):
        # With the tiny preset's 16-sample CP the paper3 round trip leaves 2.6 samples of
        # margin: the FIR's tails reach the previous symbol (inter-symbol interference).
        rng = np.random.default_rng(2)
        grid = qam256(rng, (100, self.N))
        res = {}
        for cp in (16, 32):
            num = nrsar.make_numerology("tiny", num_subcarriers=48, cp_samples=cp)
            y, _, _ = self.run_td(ofdm_modulate(grid, num), scene_of(PAPER3), num=num)
            res[cp] = nmse_db(ofdm_demodulate(y, num),
                              echo_reference(num, self.geo, PAPER3, grid))
        print(f"NMSE vs eq. (7): CP 16 samples {res[16]:.1f} dB, CP 32 samples {res[32]:.1f} dB")
        self.assertLess(res[32], res[16] - 10.0)

    def test_noise_per_re_matches_snr(self):
        rng = np.random.default_rng(3)
        M, snr_db = 400, 7.0
        grid = qam256(rng, (M, self.N))
        x = ofdm_modulate(grid, self.num)
        scn = scene_of(PAPER3)
        clean, _, _ = self.run_td(x, scn)
        noisy, _, blk = self.run_td(x, scn, snr_db=snr_db, seed=9)
        z = ofdm_demodulate(noisy, self.num) - ofdm_demodulate(clean, self.num)
        var = np.mean(np.abs(z) ** 2)
        expected = 3.0 / 10 ** (snr_db / 10)  # total RCS / 10^(snr/10)
        self.assertAlmostEqual(blk.noise_variance(), expected, places=12)
        err_db = 10 * np.log10(var / expected)
        print(f"noise per RE: {err_db:+.3f} dB from snr_db")
        self.assertLess(abs(err_db), 0.2)
        # circular: real and imaginary parts carry half each
        self.assertLess(abs(np.mean(z.real**2) / np.mean(z.imag**2) - 1.0), 0.05)

    def test_tone_and_integer_delay_in_time(self):
        # One target with the delay tau evaluated here (eq. 8 at symbol 0): a subcarrier
        # tone comes out as sqrt(rcs) e^{j phase} x(t - tau) e^{-j 2 pi (fc + k0 df) tau}.
        num, geo = self.num, self.geo
        fs = num.fft_size * num.subcarrier_spacing_hz
        sym = num.fft_size + num.cp_samples
        t = np.arange(sym)  # symbol 0 only: one delay
        f = 5.0 / num.fft_size
        x = np.exp(2j * np.pi * f * t)
        R = np.sqrt(300.0**2 + geo.height_m**2 + 100.0**2)
        tau = 2 * R / C
        y, _, _ = self.run_td(x, scene_of([(300.0, 100.0, 4.0, 0.5)]))
        frf = geo.carrier_hz + k0_of(num) * num.subcarrier_spacing_hz
        ref = 2.0 * np.exp(0.5j) * np.exp(2j * np.pi * f * (t - tau * fs)) * \
            np.exp(-2j * np.pi * np.mod(frf * tau, 1.0))
        steady = slice(int(tau * fs) + 20, sym)  # after the start-up transient (zeros before 0)
        self.assertLess(nmse_db(y[steady], ref[steady]), -70.0)

    def test_tags_and_nonfinite(self):
        rng = np.random.default_rng(4)
        x = ofdm_modulate(qam256(rng, (20, self.N)), self.num)
        x[100] = np.nan
        x[501] = np.inf
        tag = gr.tag_utils.python_to_tag((250, pmt.intern("mark"), pmt.from_long(7)))
        y, tags, blk = self.run_td(x, scene_of(PAPER3), tags=[tag])
        self.assertTrue(np.all(np.isfinite(y)))
        self.assertEqual(blk.nonfinite_count(), 2)
        marks = [t.offset for t in tags if pmt.symbol_to_string(t.key) == "mark"]
        self.assertEqual(marks, [250])
        bad = [t for t in tags if pmt.eq(t.key, pmt.intern(nrsar.tag_keys.nonfinite))]
        self.assertGreaterEqual(len(bad), 1)
        self.assertEqual(sum(pmt.to_uint64(t.value) for t in bad), 2)
        self.assertEqual(min(t.offset for t in bad), 100)
        # the zeroed sample equals the echo of an input with zeros there
        x0 = x.copy()
        x0[[100, 501]] = 0
        y0, _, _ = self.run_td(x0, scene_of(PAPER3))
        self.assertLess(np.max(np.abs(y - y0)), 1e-6)
        # the same with work() calls of 37 samples: the bad samples sit in the history of
        # later calls and must stay zero there; noise identical however the stream is cut
        y_small, tags_small, blk = self.run_td(x, scene_of(PAPER3), max_items=37)
        self.assertEqual(blk.nonfinite_count(), 2)
        self.assertLess(np.max(np.abs(y_small - y0)), 1e-6)
        n1, _, _ = self.run_td(x0, scene_of(PAPER3), snr_db=10.0, seed=3)
        n2, _, _ = self.run_td(x0, scene_of(PAPER3), snr_db=10.0, seed=3, max_items=37)
        np.testing.assert_array_equal(n1, n2)

    def test_matches_gr_radar_static_target_simulator(self):
        """Peer: gr-radar's static_target_simulator_cc delays each tagged packet circularly
        (FFT, phase ramp over the FFT bins), with c = 3e8 m/s, the radar-equation amplitude
        b = (c / fc) sqrt(rcs) / (R^2 (4 pi)^1.5) and no carrier phase. For a signal that
        repeats with the packet length, circular and linear delay agree after the first
        packet, so td_echo's output equals the peer's times e^{-j 2 pi (fc + k0 df) tau} / b
        when the peer gets the range R' = R 3e8 / c (the same delay)."""
        try:
            from gnuradio import radar
        except ImportError:
            self.skipTest("gr-radar is not installed")
        num = nrsar.make_numerology("sdr20", num_subcarriers=800)  # band edge 0.39
        geo = nrsar.make_geometry("paper", velocity_mps=1e-6, track_start_m=100.0)  # static
        P, fs = num.fft_size, num.fft_size * num.subcarrier_spacing_hz
        R = float(np.sqrt(300.0**2 + geo.height_m**2))
        tau = 2.0 * R / C
        rng = np.random.default_rng(5)
        X = np.zeros(P, dtype=np.complex128)
        bins = np.r_[1:400, P - 399:P]  # both signs of frequency, |f| < 0.39
        X[bins] = np.exp(2j * np.pi * rng.random(bins.size))
        x = np.tile(np.fft.ifft(X) * np.sqrt(P), 12)
        ours, _, _ = self.run_td(x, scene_of([(300.0, 100.0, 1.0, 0.0)]), num=num, geo=geo)

        r_peer = R * 3e8 / C
        tb = gr.top_block()
        src = blocks.vector_source_c(list(x.astype(np.complex64)))
        s2t = blocks.stream_to_tagged_stream(gr.sizeof_gr_complex, 1, P, "packet_len")
        sim = radar.static_target_simulator_cc([r_peer], [0.0], [1.0], [0.0], [0.0], int(fs),
                                               geo.carrier_hz, -10.0, False, False, "packet_len")
        snk = blocks.vector_sink_c()
        tb.connect(src, s2t, sim, snk)
        tb.run()
        peer = np.array(snk.data(), dtype=np.complex128)
        rp32 = float(np.float32(r_peer))
        b = 3e8 / float(np.float32(geo.carrier_hz)) / rp32**2 / (4 * np.pi) ** 1.5
        frf = geo.carrier_hz + k0_of(num) * num.subcarrier_spacing_hz
        peer_conv = peer / b * np.exp(-2j * np.pi * np.mod(frf * tau, 1.0))
        steady = slice(P, len(x))  # after the first packet (ours starts from zeros)
        e = nmse_db(ours[steady], peer_conv[steady])
        print(f"td_echo vs gr-radar static_target_simulator_cc: {e:.1f} dB (delay {tau * fs:.3f} samples)")
        self.assertLess(e, -80.0)

    def test_parameter_rules(self):
        scn = scene_of(PAPER3)
        for kw, msg in (({"taps": 7}, "taps = 7"), ({"taps": 0}, "taps = 0"),
                        ({"taps": 258}, "taps = 258"), ({"kaiser_beta": 60.0}, "kaiser_beta = 60"),
                        ({"snr_db": float("nan")}, "snr_db = nan")):
            with self.assertRaisesRegex(ValueError, msg):
                nrsar.td_echo(self.num, self.geo, scn, **kw)
        short_cp = nrsar.make_numerology("tiny", num_subcarriers=48, cp_samples=8)
        with self.assertRaisesRegex(ValueError, "cyclic prefix too short"):
            nrsar.td_echo(short_cp, self.geo, scn)
        blk = nrsar.td_echo(self.num, self.geo, scn)
        with self.assertRaisesRegex(ValueError, "snr_db = -inf"):
            blk.set_snr_db(float("-inf"))
        self.assertEqual(blk.taps(), 32)
        self.assertGreater(blk.kaiser_beta(), 0.0)


if __name__ == "__main__":
    gr_unittest.run(qa_td_echo)
