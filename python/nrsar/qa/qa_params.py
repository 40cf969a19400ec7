#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The shared parameter types as Python and GRC see them: presets, builders, errors."""

import math

from gnuradio import gr_unittest
from gnuradio import nrsar


class qa_params(gr_unittest.TestCase):

    def test_presets_round_trip(self):
        num = nrsar.make_numerology("paper")
        self.assertEqual(num.num_subcarriers, 3333)
        self.assertAlmostEqual(num.prf_hz(), 24e3, places=6)
        self.assertEqual(set(nrsar.numerology.preset_names()) >= {"paper", "small", "nr273"}, True)
        geo = nrsar.make_geometry("paper")
        self.assertEqual(geo.symbols_per_aperture(num), 48000)

    def test_overrides_are_validated(self):
        num = nrsar.make_numerology("small", num_subcarriers=256, fft_size=256)
        self.assertEqual(num.num_subcarriers, 256)
        with self.assertRaisesRegex(ValueError, "fft_size = 100 must be at least"):
            nrsar.make_numerology("small", fft_size=100)
        with self.assertRaisesRegex(ValueError, "no field 'bogus'"):
            nrsar.make_numerology("small", bogus=1)
        with self.assertRaisesRegex(ValueError, "height_m = -1"):
            nrsar.make_geometry("paper", height_m=-1.0)

    def test_scene_from_strings(self):
        scn = nrsar.make_scene("300,100;250,100,4")
        self.assertEqual(len(scn.targets), 2)
        self.assertEqual(scn.targets[1].rcs, 4.0)
        self.assertEqual(scn.total_rcs(), 5.0)
        paper = nrsar.make_scene("paper3")
        self.assertEqual([(t.x_m, t.y_m) for t in paper.targets],
                         [(300.0, 100.0), (250.0, 100.0), (300.0, 140.0)])
        self.assertEqual(len(nrsar.make_scene([(1, 2), "3,4,5"]).targets), 2)
        # fuzz: a fourth field is the phase in degrees; five fields are refused
        phased = nrsar.make_scene("1,2,3,90")
        self.assertAlmostEqual(phased.targets[0].phase_rad, math.pi / 2, places=15)
        with self.assertRaisesRegex(ValueError, r"target 0 '1,2,3,4,5': has 5 fields; "
                                    r"must be X,Y\[,RCS\[,PHASE_DEG\]\]"):
            nrsar.make_scene("1,2,3,4,5")
        with self.assertRaisesRegex(ValueError, "target 1 'a,b': x_m 'a' is not a number"):
            nrsar.make_scene("1,2;a,b")
        with self.assertRaisesRegex(ValueError, "target 1 '3,x': y_m 'x' is not a number"):
            nrsar.make_scene([(1, 2), "3,x"])
        # the fields are read as Python's float() reads them
        for text in ("+1e3, 1_0.5", " inf ,-NaN", ".5,5."):
            x, y = (float(v) for v in text.split(","))
            t = nrsar.parse_target(text)
            self.assertEqual((repr(t.x_m), repr(t.y_m)), (repr(x), repr(y)), text)
        with self.assertRaisesRegex(ValueError, "no targets"):
            nrsar.make_scene([])

    def test_scene_text_numbers_match_python_float(self):
        """fuzz: scene::parse (C++) reads a field exactly as float() did before it, on 20000
        seeded random strings; only an overflow (float: inf, refused by validate anyway) is
        refused by the parser already."""
        import random
        rng = random.Random(5)
        alphabet = "0123456789.eE+-_ infaINFANty\t"
        for _ in range(20000):
            text = "".join(rng.choice(alphabet) for _ in range(rng.randint(0, 8)))
            try:
                expected = float(text)
            except ValueError:
                expected = None
            try:
                got = nrsar.parse_target(text + ",0").x_m
            except ValueError as e:
                got = None
                self.assertIn("target 0", str(e))
            if expected is not None and math.isinf(expected) and "e" in text.lower():
                self.assertIsNone(got, text)  # overflow: "out of the range of a double"
            elif expected is None or got is None:
                self.assertEqual(expected, got, repr(text))
            else:
                self.assertEqual(repr(expected), repr(got), repr(text))

    def test_enums_by_name(self):
        self.assertEqual(nrsar.make_modulation("QAM256"), nrsar.modulation.QAM256)
        self.assertEqual(nrsar.make_filter("wf"), nrsar.filter_type.WF)
        with self.assertRaisesRegex(ValueError, "modulation 'qam1024' is unknown"):
            nrsar.make_modulation("qam1024")

    def test_scenario_check_raises_value_error_with_numbers(self):
        with self.assertRaisesRegex(ValueError, r"cyclic prefix too short.*2\.34"):
            nrsar.check_scenario(nrsar.make_numerology("nr273"), nrsar.make_geometry("paper"),
                                 nrsar.make_scene("paper3"))
        warnings = nrsar.check_scenario(nrsar.make_numerology("paper"),
                                        nrsar.make_geometry("paper"),
                                        nrsar.make_scene("paper3"), 14 * 20)
        self.assertEqual(len(warnings), 1)

    def test_extent_matches_eq8(self):
        geo = nrsar.make_geometry("paper")
        ext = nrsar.compute_extent(geo, nrsar.make_scene("single"))
        self.assertAlmostEqual(ext.min_slant_range_m, math.hypot(300.0, 1000.0), places=9)
        lam = nrsar.speed_of_light / 3.5e9
        r0 = math.sqrt(300.0**2 + 1000.0**2 + 100.0**2)
        self.assertAlmostEqual(ext.max_doppler_hz, 2 * 50 * 100 / (lam * r0), places=9)


if __name__ == '__main__':
    gr_unittest.run(qa_params)
