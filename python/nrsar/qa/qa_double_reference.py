#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Issue #7's image-quality goal at a small scale: the float32 chain with the fast options
(presum cheby D = 10, range crop, scene band) against its float64 no-skipping reference
(double_reference: float64 echo with the same noise, exact RCMC, full PRF), NMSE within
0.1 dB. The reference's NMSE is also recomputed in float64 numpy from its image (SPEC 8's
formula) against the probe's value."""

import math
import shutil
import tempfile

from gnuradio import gr_unittest
from gnuradio.nrsar import runtime
from gnuradio.nrsar.figures import double_reference


class qa_double_reference(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        runtime.quiet_gnuradio_logs()

    def run_case(self, extra):
        out = tempfile.mkdtemp(prefix="nrsar-dref-")
        try:
            return double_reference.run(
                ["--preset", "small", "--aperture-s", "0.2", "--target", "300,5",
                 "--out", out, "--work", out + "/work"] + extra)
        finally:
            shutil.rmtree(out, ignore_errors=True)

    def test_fast_chain_within_0_1_db_of_the_double_reference(self):
        # WF -20 dB with the fast options (presum cheby D10); MF +5 dB at the full PRF (with
        # the presummer at this short aperture, 480 pulses, MF +5 dB measured -0.11 dB:
        # docs/performance.md)
        for extra in ([], ["--filter", "mf", "--snr-db", "5", "--presum", "none"]):
            res = self.run_case(extra)
            d = res["fast_minus_double"]
            print(f"\n{extra or 'WF -20 dB'}: NMSE fast {res['fast']['nmse_db']:.3f} dB, "
                  f"double {res['double']['nmse_db']:.3f} dB (numpy {res['double']['nmse64_db']:.3f}),"
                  f" fast - double {d['nmse_db']:+.3f} dB, SNR_out {d['snr_out_db']:+.3f} dB, "
                  f"IRW az {d['irw_azimuth_m']:+.3f} m")
            self.assertLessEqual(abs(d["nmse_db"]), 0.1)
            self.assertTrue(res["goal_met"])
            # the probe's NMSE of the reference image vs SPEC 8's formula in float64 numpy
            self.assertAlmostEqual(res["double"]["nmse_db"], res["double"]["nmse64_db"], delta=0.01)
            # same target, same place, same focus
            self.assertLess(abs(d["irw_range_m"]), 0.05 * res["fast"]["irw_range_m"])
            self.assertLess(abs(d["irw_azimuth_m"]), 0.05 * res["fast"]["irw_azimuth_m"])
            self.assertLess(abs(d["snr_out_db"]), 0.5)
            self.assertTrue(math.isfinite(res["double"]["pslr_db"]))


if __name__ == "__main__":
    gr_unittest.run(qa_double_reference)
