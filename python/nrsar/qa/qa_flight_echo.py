#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of the echo generators on a flown path (scene_echo, td_echo, extended_scene_echo with a
`path`): the phase history against a float64 numpy evaluation of SPEC 3 written here (exact
range from the antenna phase centre per symbol, the beam of eqs. 1-3 turned by the attitude),
below -80 dB on a `gusty` motion path and on a CSV path with attitude and a lever arm; the
ideal-line default bit-identical; attitude moving the footprint where the geometry puts it;
the checks against targets behind the antenna and round trips beyond the CP."""

import math
import os
import tempfile

import numpy as np
from gnuradio import blocks, gr, gr_unittest
from gnuradio.nrsar.theory import ofdm_demodulate, ofdm_modulate

from gnuradio import nrsar

C = 299792458.0
TARGETS = [(300.0, 100.0, 1.0, 0.3), (250.0, 104.0, 0.5, -1.0), (330.0, 97.0, 2.0, 2.0)]
LEVER = np.array([0.4, -0.3, 0.2])  # body frame [m]


def tsym(num):
    return 1.0 / num.subcarrier_spacing_hz + num.cp_samples / (num.fft_size * num.subcarrier_spacing_hz)


def rotation(roll, pitch, yaw):
    """Body -> frame: right-handed turns about the frame's axes, roll about the flight
    direction y, pitch about the cross-track x, yaw about z; R = Rz(yaw) Rx(pitch) Ry(roll)."""
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch),
                              math.cos(yaw), math.sin(yaw))
    ry = np.array([[cr, 0, sr], [0, 1, 0], [-sr, 0, cr]])
    rx = np.array([[1, 0, 0], [0, cp, -sp], [0, sp, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ rx @ ry


# An analytic flight: sway, speed variation and attitude, written to a 100 Hz CSV file.
def flight_position(geo, t):
    return np.stack([0.25 * np.sin(2 * np.pi * 0.7 * t) + 0.05 * np.sin(2 * np.pi * 2.3 * t),
                     geo.track_start_m + geo.velocity_mps * t + 0.3 * np.sin(2 * np.pi * 0.3 * t),
                     geo.height_m + 0.2 * np.cos(2 * np.pi * 0.9 * t)], axis=-1)


def flight_attitude(t):
    return np.stack([0.03 * np.sin(2 * np.pi * 0.5 * t), 0.02 * np.cos(2 * np.pi * 0.8 * t),
                     0.015 * np.sin(2 * np.pi * 0.4 * t + 1.0)], axis=-1)


def phase_centre(geo, t):
    """Navigated point plus R(attitude) lever, float64, per time."""
    p, a = flight_position(geo, t), flight_attitude(t)
    return np.array([p[i] + rotation(*a[i]) @ LEVER for i in range(len(t))])


def write_flight_csv(path, geo):
    t = np.arange(0.0, geo.aperture_s + 0.1, 0.01)
    p, a = flight_position(geo, t), flight_attitude(t)
    with open(path, "w") as f:
        f.write("t_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad\n")
        for i in range(len(t)):
            f.write(",".join(repr(float(v)) for v in (t[i], *p[i], *a[i])) + "\n")


def beam_gain(beam, geo, pos, att, xq, yq):
    """Two-way amplitude of eqs. (1)-(3) for the antenna at pos turned by att (None: the
    frame's orientation), float64."""
    lam = C / geo.carrier_hz
    d = np.array([xq - pos[0], yq - pos[1], -pos[2]])
    d /= np.linalg.norm(d)
    l = d if att is None else rotation(*att).T @ d
    mode = str(beam.mode).split(".")[-1].lower()
    if mode == "whole_block":
        return 1.0
    u_az = beam.az_aperture_m * l[1] / lam
    g = np.sinc(u_az) ** 2 if abs(u_az) <= beam.cutoff else 0.0
    if mode == "azimuth_elevation":
        u_el = beam.el_aperture_m * math.sin(math.atan2(l[0], -l[2]) - beam.el_center_rad) / lam
        g *= np.sinc(u_el) ** 2 if abs(u_el) <= beam.cutoff else 0.0
    return g


def exact_h(num, geo, scatterers, pos, att=None, beam=None):
    """H[m, n] = sum_q a_q g_q(m) exp(-j 4 pi (fc + n df) |q - p(m)| / c), float64 (SPEC 3);
    pos (M, 3) phase centres, att (M, 3) attitudes or None."""
    f = geo.carrier_hz + np.arange(num.num_subcarriers) * num.subcarrier_spacing_hz
    h = np.zeros((len(pos), num.num_subcarriers), np.complex128)
    for (x, y, a) in scatterers:
        R = np.sqrt((x - pos[:, 0]) ** 2 + (y - pos[:, 1]) ** 2 + pos[:, 2] ** 2)
        cyc = np.outer(2.0 * R, f) / C
        cyc -= np.floor(cyc)  # exact reduction before the exponential (1.5e5 rad)
        g = np.ones(len(pos)) if beam is None else np.array(
            [beam_gain(beam, geo, pos[i], None if att is None else att[i], x, y)
             for i in range(len(pos))])
        h += (a * g)[:, None] * np.exp(-2j * np.pi * cyc)
    return h


def point_scatterers(targets):
    return [(x, y, math.sqrt(rcs) * np.exp(1j * ph)) for (x, y, rcs, ph) in targets]


def err_db(got, ref):
    return 10 * np.log10(np.sum(np.abs(got - ref) ** 2) / np.sum(np.abs(ref) ** 2))


def qam(rng, shape):
    levels = np.arange(-15, 16, 2) / np.sqrt(170.0)
    return (rng.choice(levels, shape) + 1j * rng.choice(levels, shape)).astype(np.complex64)


def run_grid(blk, s, outputs=2):
    """(M, N) grid through a TF echo block -> its outputs as (M, N) arrays."""
    M, N = s.shape
    tb = gr.top_block()
    tb.connect(blocks.vector_source_c(s.ravel().tolist(), False, N), blk)
    sinks = [blocks.vector_sink_c(N) for _ in range(outputs)]
    for i, snk in enumerate(sinks):
        tb.connect((blk, i), snk)
    tb.run()
    return [np.array(snk.data(), np.complex128).reshape(M, N) for snk in sinks]


def run_td(blk, x):
    tb = gr.top_block()
    snk = blocks.vector_sink_c()
    tb.connect(blocks.vector_source_c(x.astype(np.complex64).tolist(), False), blk, snk)
    tb.run()
    return np.array(snk.data(), np.complex128)


class qa_flight_echo(gr_unittest.TestCase):

    def setUp(self):
        # 0.25 s of flight (6000 symbols), the targets passing abeam
        self.geo = nrsar.make_geometry("paper", aperture_s=0.25, track_start_m=95.0)
        self.num = nrsar.make_numerology("tiny")
        self.tmp = tempfile.TemporaryDirectory()
        self.csv = os.path.join(self.tmp.name, "flight.csv")
        write_flight_csv(self.csv, self.geo)
        self.rng = np.random.default_rng(14)

    def tearDown(self):
        self.tmp.cleanup()

    def times(self, num, M):
        return np.arange(M) * tsym(num)

    def test_scene_echo_on_a_gusty_path(self):
        gusty = nrsar.make_trajectory("gusty", self.geo, seed=3)
        M = int(self.geo.symbols_per_aperture(self.num))
        s = qam(self.rng, (M, self.num.num_subcarriers))
        scn = nrsar.make_scene([t for t in TARGETS])
        y, h = run_grid(nrsar.scene_echo(self.num, self.geo, scn, path=gusty), s)
        pos = np.array(gusty.positions(list(self.times(self.num, M))))
        ref = exact_h(self.num, self.geo, point_scatterers(TARGETS), pos)
        e_h, e_y = err_db(h, ref), err_db(y, s * ref)
        line = np.column_stack([np.zeros(M), self.geo.track_start_m + self.geo.velocity_mps *
                                self.times(self.num, M), np.full(M, self.geo.height_m)])
        e_line = err_db(exact_h(self.num, self.geo, point_scatterers(TARGETS), line), ref)
        print(f"scene_echo, gusty seed 3: H {e_h:.1f} dB, Y {e_y:.1f} dB (ideal line: "
              f"{e_line:+.1f} dB off)")
        self.assertLess(e_h, -80.0)
        self.assertLess(e_y, -80.0)
        self.assertGreater(e_line, -3.0)  # the sway is tens of radians: the test can tell

    def test_scene_echo_on_a_csv_path_with_lever_arm(self):
        path = nrsar.make_trajectory(self.csv, self.geo, lever_arm_m=tuple(LEVER))
        self.assertTrue(path.has_attitude())
        M = int(self.geo.symbols_per_aperture(self.num))
        s = qam(self.rng, (M, self.num.num_subcarriers))
        _, h = run_grid(nrsar.scene_echo(self.num, self.geo, nrsar.make_scene(TARGETS),
                                         path=path), s)
        pos = phase_centre(self.geo, self.times(self.num, M))
        e = err_db(h, exact_h(self.num, self.geo, point_scatterers(TARGETS), pos))
        print(f"scene_echo, CSV path with attitude and lever arm: {e:.1f} dB")
        self.assertLess(e, -80.0)

    def test_td_echo_on_paths(self):
        # 32 of 64 subcarriers (band edge 0.25), CP 32 samples, 24 taps: the round trip
        # (~13.4 samples) leaves the FIR whole inside the CP, so the demodulated echo is
        # SPEC 3's TF model to the FIR's own error.
        num = nrsar.make_numerology("tiny", num_subcarriers=32, cp_samples=32)
        M = int(self.geo.symbols_per_aperture(num))
        s = qam(self.rng, (M, num.num_subcarriers))
        t = self.times(num, M)
        beam = nrsar.make_beam("azimuth_elevation", az_aperture_m=2.0, el_aperture_m=1.0,
                               el_center_deg=math.degrees(math.atan2(300.0, 1000.0)))
        gusty = nrsar.make_trajectory("gusty", self.geo, seed=4)
        csv = nrsar.make_trajectory(self.csv, self.geo, lever_arm_m=tuple(LEVER))
        cases = (("gusty seed 4", gusty, np.array(gusty.positions(list(t))), None),
                 ("CSV with attitude", csv, phase_centre(self.geo, t), flight_attitude(t)))
        for name, path, pos, att in cases:
            blk = nrsar.td_echo(num, self.geo, nrsar.make_scene(TARGETS), float("inf"), 0, 24,
                                -1.0, beam, path)
            got = ofdm_demodulate(run_td(blk, ofdm_modulate(s, num)), num)
            ref = s * exact_h(num, self.geo, point_scatterers(TARGETS), pos, att, beam)
            e = err_db(got, ref)
            print(f"td_echo, {name}, steered beam: {e:.1f} dB")
            self.assertLess(e, -80.0)

    def map_and_points(self):
        vals = (self.rng.normal(size=(6, 8)) + 1j * self.rng.normal(size=(6, 8)))
        amap = nrsar.make_map(vals.astype(np.complex64), 1.5, 2.0, 290.0, 94.0, kind="amplitude")
        yy, xx = np.mgrid[0:6, 0:8]
        sc = [(290.0 + 1.5 * i, 94.0 + 2.0 * j, complex(np.complex64(vals[j, i])))
              for j, i in zip(yy.ravel(), xx.ravel())]
        return amap, sc + point_scatterers(TARGETS[1:2])

    def test_extended_scene_echo_on_paths(self):
        amap, sc = self.map_and_points()
        M = int(self.geo.symbols_per_aperture(self.num))
        s = qam(self.rng, (M, self.num.num_subcarriers))
        t = self.times(self.num, M)
        ms = np.arange(0, M, 25)
        beam = nrsar.make_beam("azimuth_elevation", az_aperture_m=2.0, el_aperture_m=1.0,
                               el_center_deg=math.degrees(math.atan2(300.0, 1000.0)))
        gusty = nrsar.make_trajectory("gusty", self.geo, seed=5)
        csv = nrsar.make_trajectory(self.csv, self.geo, lever_arm_m=tuple(LEVER))
        cases = (("gusty seed 5", gusty, np.array(gusty.positions(list(t[ms]))), None),
                 ("CSV with attitude", csv, phase_centre(self.geo, t[ms]),
                  flight_attitude(t[ms])))
        for name, path, pos, att in cases:
            blk = nrsar.extended_scene_echo(self.num, self.geo, nrsar.make_scene(TARGETS[1:2]),
                                            [amap], beam, path=path)
            _, h = run_grid(blk, s)
            e = err_db(h[ms], exact_h(self.num, self.geo, sc, pos, att, beam))
            print(f"extended_scene_echo, {name}, steered beam: {e:.1f} dB")
            self.assertLess(e, -80.0)

    def test_ideal_line_default_is_bit_identical(self):
        M = 400
        s = qam(self.rng, (M, self.num.num_subcarriers))
        scn = nrsar.make_scene(TARGETS)
        line = nrsar.make_trajectory("ideal", self.geo)
        a = run_grid(nrsar.scene_echo(self.num, self.geo, scn, 10.0, 7), s)
        b = run_grid(nrsar.scene_echo(self.num, self.geo, scn, 10.0, 7, line), s)
        self.assertTrue(all(np.array_equal(u, v) for u, v in zip(a, b)))
        amap, _ = self.map_and_points()
        beam = nrsar.make_beam("azimuth_elevation", az_aperture_m=2.0, el_aperture_m=1.0,
                               el_center_deg=16.7)
        a = run_grid(nrsar.extended_scene_echo(self.num, self.geo, scn, [amap], beam), s)
        b = run_grid(nrsar.extended_scene_echo(self.num, self.geo, scn, [amap], beam,
                                               path=line), s)
        self.assertTrue(all(np.array_equal(u, v) for u, v in zip(a, b)))
        x = ofdm_modulate(s[:50], self.num)
        a = run_td(nrsar.td_echo(self.num, self.geo, scn, 10.0, 7), x)
        b = run_td(nrsar.td_echo(self.num, self.geo, scn, 10.0, 7, path=line), x)
        self.assertTrue(np.array_equal(a, b))

    def footprint_peak(self, beam, attitude, xs, ys, geo):
        """(x, y) of the scatterer the antenna, turned by attitude on geo's straight line,
        lights most at t = 0 (one kernel per candidate, |H| of its single scatterer)."""
        t = np.arange(0.0, geo.aperture_s + 0.1, 0.05)
        p = [(0.0, geo.track_start_m + geo.velocity_mps * v, geo.height_m) for v in t]
        path = nrsar.trajectory.from_samples(list(t), p, [tuple(attitude)] * len(t))
        best, where = -1.0, None
        for x in xs:
            for y in ys:
                k = nrsar.extended_scene_kernel(self.num, geo, nrsar.make_scene([(x, y)]), [],
                                                beam, path=path)
                g = abs(k.reference_exact(0)[0])
                if g > best:
                    best, where = g, (x, y)
        return where

    def test_attitude_moves_the_footprint(self):
        geo = nrsar.make_geometry("paper", aperture_s=0.5, track_start_m=0.0)
        H = geo.height_m
        theta_c = math.atan2(300.0, H)
        beam = nrsar.make_beam("azimuth_elevation", az_aperture_m=2.0, el_aperture_m=1.0,
                               el_center_deg=math.degrees(theta_c))
        xs, ys = np.arange(230.0, 371.0, 1.0), [0.0]
        # roll (scene side down) by phi: the boresight looks phi closer to nadir, so the
        # elevation footprint's centre moves in to x = H tan(theta_c - phi)
        for phi in (0.0, 0.03, -0.03):
            x, _ = self.footprint_peak(beam, (phi, 0.0, 0.0), xs, ys, geo)
            print(f"roll {phi:+.2f} rad: footprint centre x = {x:.0f} m "
                  f"(geometry: {H * math.tan(theta_c - phi):.1f} m)")
            self.assertLessEqual(abs(x - H * math.tan(theta_c - phi)), 1.0)
        # yaw by psi (nose left): the beam, perpendicular to the body's y axis, lights the
        # point x tan(psi) ahead along track; pitch by theta (nose up): H tan(theta) ahead
        ys = np.arange(-30.0, 30.1, 0.25)
        for att, ahead in (((0.0, 0.0, 0.04), 300.0 * math.tan(0.04)),
                           ((0.0, 0.01, 0.0), H * math.tan(0.01)),
                           ((0.0, 0.0, 0.0), 0.0)):
            _, y = self.footprint_peak(beam, att, [300.0], ys, geo)
            print(f"attitude {att}: footprint centre y = {y:+.2f} m (geometry {ahead:+.2f} m)")
            self.assertLessEqual(abs(y - ahead), 0.25)

    def test_paths_that_break_the_model_are_refused(self):
        t = np.arange(0.0, 0.4, 0.05)
        line = [(0.0, 95.0 + 50.0 * v, 1000.0) for v in t]
        # 260 m across track: T2 (x = 250) is behind the antenna
        side = nrsar.trajectory.from_samples(list(t), [(260.0, y, z) for (_, y, z) in line])
        with self.assertRaisesRegex(ValueError, r"target 1 .*behind the antenna"):
            nrsar.scene_echo(self.num, self.geo, nrsar.make_scene(TARGETS), path=side)
        # 1300 m up: T1's round trip (1338 m, 8.93 us) exceeds the 8.33 us CP of tiny
        high = nrsar.trajectory.from_samples(list(t), [(x, y, 1300.0) for (x, y, _) in line])
        with self.assertRaisesRegex(ValueError, r"target 0 .*longer than Tcp"):
            nrsar.td_echo(self.num, self.geo, nrsar.make_scene(TARGETS), path=high)
        short = nrsar.trajectory.from_samples(list(t[:5]), line[:5])
        with self.assertRaisesRegex(ValueError, "too short|cover"):
            nrsar.extended_scene_echo(self.num, self.geo, nrsar.make_scene(TARGETS), [],
                                      path=short)


if __name__ == "__main__":
    gr_unittest.run(qa_flight_echo)
