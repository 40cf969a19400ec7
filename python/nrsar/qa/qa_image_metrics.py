#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The image metrics of the second paper's section 3.2.1 as bound to Python
(image_metrics_python.cc: kernel::image_entropy, edge_preservation_index, nesz_db, the code
nmse_probe reports with) against float64 numpy references of the paper's definitions, and
presum_compare's distributed-target NESZ against its formula."""

import math

import numpy as np
from gnuradio import gr_unittest

from gnuradio import nrsar
from gnuradio.nrsar.figures import presum_compare


def entropy_ref(img):
    """eqs. (P-37), (P-38): E = -sum D ln D, D = |I|^2 / sum |I|^2 (0 ln 0 = 0)."""
    p = np.abs(img.astype(np.complex128)).ravel() ** 2
    d = p / p.sum()
    return float(-sum(v * math.log(v) for v in d if v > 0))


def epi_ref(x, y):
    """eq. (P-39): correlation coefficient of the 4-neighbour Laplacians of |x| and |y| over
    the interior pixels, written out pixel by pixel."""
    def lap(a):
        a = np.abs(a.astype(np.complex128))
        m, k = a.shape
        out = np.empty((m - 2, k - 2))
        for i in range(1, m - 1):
            for j in range(1, k - 1):
                out[i - 1, j - 1] = (a[i - 1, j] + a[i + 1, j] + a[i, j - 1] + a[i, j + 1]
                                     - 4 * a[i, j])
        return out
    dx, dy = lap(x), lap(y)
    dx, dy = dx - dx.mean(), dy - dy.mean()
    return float(np.sum(dx * dy) / math.sqrt(np.sum(dx * dx) * np.sum(dy * dy)))


class qa_image_metrics(gr_unittest.TestCase):

    def setUp(self):
        rng = np.random.default_rng(14)
        shape = (37, 23)
        self.x = (rng.standard_normal(shape) + 1j * rng.standard_normal(shape)).astype(np.complex64)
        noise = rng.standard_normal(shape) + 1j * rng.standard_normal(shape)
        self.y = (self.x + 0.5 * noise).astype(np.complex64)

    def test_001_entropy(self):
        for img in (self.x, self.y, self.x[:1, :5]):
            self.assertAlmostEqual(nrsar.image_entropy(img), entropy_ref(img), delta=1e-9)
        # limits of the definition: a single bright pixel 0, a uniform image ln n
        point = np.zeros((8, 8), np.complex64)
        point[3, 4] = 2.0
        self.assertEqual(nrsar.image_entropy(point), 0.0)
        self.assertAlmostEqual(nrsar.image_entropy(np.full((8, 8), 1 - 1j, np.complex64)),
                               math.log(64), delta=1e-12)

    def test_002_epi(self):
        self.assertAlmostEqual(nrsar.edge_preservation_index(self.x, self.y),
                               epi_ref(self.x, self.y), delta=1e-9)
        # y's edges are x's up to a scale: 1
        self.assertAlmostEqual(nrsar.edge_preservation_index(self.x, 3 * self.x), 1.0,
                               delta=1e-12)
        with self.assertRaises(ValueError):
            nrsar.edge_preservation_index(self.x, self.y[:, :-1])

    def test_003_nesz(self):
        # point-target calibration: the sigma0 whose pixel return P_n equals E_t sigma0 A / sigma
        pn, et, rcs, area = 2.5e-3, 40.0, 4.0, 0.75
        self.assertAlmostEqual(nrsar.nesz_db(pn, et, rcs, area),
                               10 * math.log10(pn * rcs / (et * area)), delta=1e-12)
        self.assertTrue(math.isnan(nrsar.nesz_db(0.0, et, rcs, area)))
        # distributed-target calibration (presum_compare, table 6): sigma0 P_n / (P_s - P_n)
        ps, sigma0 = 0.9, 0.02
        self.assertAlmostEqual(presum_compare.nesz_map_db(pn, ps, sigma0),
                               10 * math.log10(sigma0 * pn / (ps - pn)), delta=1e-12)


if __name__ == "__main__":
    gr_unittest.run(qa_image_metrics)
