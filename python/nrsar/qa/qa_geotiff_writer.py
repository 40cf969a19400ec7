#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""geo.geotiff_writer, image_sink's GeoTIFF writer (docs/blocks/image_sink.md): fed by the
sink's `files` messages, it writes each aperture as GeoTIFFs; a point's pixel sits at the
point's true latitude and longitude (geodesics from the origin) within one pixel."""

import math
import os
import shutil
import tempfile
import time

import numpy as np
import pmt
import pyproj
from gnuradio import blocks, gr, gr_unittest
from gnuradio import nrsar
from gnuradio.nrsar import geo
from osgeo import gdal, osr

GEOD = pyproj.Geod(ellps="WGS84")
H = 1000.0  # platform height [m]


def true_lon_lat(lat, lon, heading, x, y):
    """The ground point y along the heading, then x to its right (geodesics)."""
    lon1, lat1, back = GEOD.fwd(lon, lat, heading, y)
    lon2, lat2, _ = GEOD.fwd(lon1, lat1, back + 180.0 + 90.0, x)
    return lon2, lat2


def tag(offset, key, value):
    return gr.tag_utils.python_to_tag((offset, pmt.intern(key), value))


class qa_geotiff_writer(gr_unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="qa_geotiff_writer_")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def run_sink(self, image, range_axis, y_axis, origin, grid="slant"):
        lines, bins = image.shape
        tags = [tag(0, "aperture", pmt.from_uint64(0)),
                tag(0, "azimuth_axis", pmt.make_tuple(pmt.from_double(y_axis[0]),
                                                      pmt.from_double(y_axis[1]),
                                                      pmt.from_uint64(lines))),
                tag(0, "range_axis", pmt.make_tuple(pmt.from_double(range_axis[0]),
                                                    pmt.from_double(range_axis[1]),
                                                    pmt.from_uint64(bins)))]
        src = blocks.vector_source_c(image.ravel().tolist(), False, bins, tags)
        sink = nrsar.image_sink(bins, os.path.join(self.dir, "img"), True, False)
        writer = geo.geotiff_writer(origin, H, grid)
        tb = gr.top_block()
        tb.connect(src, sink)
        tb.msg_connect(sink, "files", writer, "files")
        tb.start()
        deadline = time.time() + 60
        while not writer.written and not writer.failed() and time.time() < deadline:
            time.sleep(0.05)
        tb.stop()
        tb.wait()
        return writer

    def test_001_point_at_its_place(self):
        """One bright pixel at line 37 (y = -5 + 37 x 0.5 m) and slant bin 61 (r = 1000 +
        61 x 3 m): the GeoTIFF's pixel of largest power lies at the point's true position,
        within one pixel (0.5 m along, the bin's ground spacing across)."""
        lines, bins, m, k = 80, 120, 37, 61
        y_axis, range_axis = (-5.0, 0.5), (1010.0, 3.0)
        image = (1e-3 * np.ones((lines, bins))).astype(np.complex64)
        image[m, k] = 1.0 + 1.0j
        origin = "59.9,10.7,30"
        for grid in ("slant", "ground"):
            writer = self.run_sink(image, range_axis, y_axis, origin, grid)
            self.assertEqual(writer.failed(), 0)
            keys = writer.written[0]
            self.assertEqual(keys["aperture"], 0)
            self.assertEqual(keys["geotiff_db"], os.path.join(self.dir, "img_0_db.tif"))
            ds = gdal.Open(keys["geotiff_db"])
            srs = osr.SpatialReference(wkt=ds.GetProjection())
            self.assertEqual(int(srs.GetAuthorityCode(None)), 32632)  # UTM 32N
            power = ds.GetRasterBand(1).ReadAsArray()
            line, col = np.unravel_index(np.argmax(power), power.shape)
            gt = ds.GetGeoTransform()
            e = gt[0] + (col + 0.5) * gt[1] + (line + 0.5) * gt[2]
            n = gt[3] + (col + 0.5) * gt[4] + (line + 0.5) * gt[5]
            lon_px, lat_px = pyproj.Transformer.from_crs(32632, 4326, always_xy=True) \
                .transform(e, n)
            r = range_axis[0] + k * range_axis[1]
            x, y = math.sqrt(r * r - H * H), y_axis[0] + m * y_axis[1]
            lon_t, lat_t = true_lon_lat(59.9, 10.7, 30.0, x, y)
            az, _, dist = GEOD.inv(lon_t, lat_t, lon_px, lat_px)
            along = dist * math.cos(math.radians(az - 30.0))
            cross = dist * math.sin(math.radians(az - 30.0))
            cell_x = range_axis[1] * r / x  # one slant bin on the ground
            print(f"\n{grid}: pixel {along:+.3f} m along, {cross:+.3f} m across the point "
                  f"(cells {y_axis[1]} m x {cell_x:.2f} m)")
            self.assertLess(abs(along), y_axis[1])
            self.assertLess(abs(cross), cell_x)

    def test_002_bad_parameters_and_messages(self):
        with self.assertRaises(ValueError) as ctx:
            geo.geotiff_writer("95,10,0", H)
        self.assertIn("latitude", str(ctx.exception).lower())
        with self.assertRaises(ValueError) as ctx:
            geo.geotiff_writer("59.9,10.7,30", -1.0)
        self.assertIn("height_m = -1.0 must be finite and > 0", str(ctx.exception))
        with self.assertRaises(ValueError) as ctx:
            geo.geotiff_writer("59.9,10.7,30", H, "polar")
        self.assertIn("grid = 'polar' must be ground or slant", str(ctx.exception))
        writer = geo.geotiff_writer("59.9,10.7,30", H)
        writer.handle(pmt.to_pmt({"aperture": 3, "npy": ""}))  # write_npy off
        writer.handle(pmt.to_pmt({"aperture": 4, "npy": os.path.join(self.dir, "no.npy"),
                                  "range_axis": (1.0, 1.0, 1), "azimuth_axis": (0.0, 1.0, 1)}))
        self.assertEqual((writer.failed(), writer.written), (2, []))


if __name__ == "__main__":
    gr_unittest.run(qa_geotiff_writer)
