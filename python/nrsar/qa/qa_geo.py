#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""GeoTIFFs of the focused image (geo; nrsar-sim --geotiff --origin): the files GDAL opens,
their CRS (the UTM zone of the origin), their bands, and the target's brightest pixel at the
target's true latitude / longitude, computed here from the origin, the heading and the
target's (x, y) with pyproj's geodesics (WGS 84), within one resolution cell."""

import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import pyproj
from gnuradio import gr_unittest
from osgeo import gdal, osr

from gnuradio.nrsar import geo

gdal.UseExceptions()

APPS = os.environ.get("NRSAR_APPS_DIR") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps")

C = 299792458.0
GEOD = pyproj.Geod(ellps="WGS84")
# sdr20 (612 subcarriers at 30 kHz), paper geometry (fc 3.5 GHz, v 50 m/s, H 1000 m), 0.05 s
X, Y, H, V, TA, FC, BW = 300.0, 1.0, 1000.0, 50.0, 0.05, 3.5e9, 612 * 30e3
FLIGHT = ["--preset", "sdr20", "--aperture-s", str(TA), "--target", f"{X:g},{Y:g}",
          "--snr-db", "20"]


def run_app(program, args):
    return subprocess.run([sys.executable, os.path.join(APPS, program)] + args,
                          capture_output=True, text=True, timeout=600)


def true_lon_lat(lat, lon, heading, x, y):
    """The ground point y along the heading, then x to its right (geodesics)."""
    lon1, lat1, back = GEOD.fwd(lon, lat, heading, y)  # fwd returns the back azimuth
    lon2, lat2, _ = GEOD.fwd(lon1, lat1, back + 180.0 + 90.0, x)
    return lon2, lat2


def resolution_cells():
    """(along-track, ground-range) resolution [m] at the target: rho_a = lambda R0 /
    (2 v Ta) (SPEC 2's v / (Ka Ta)); rho_g = c / (2 B) R0 / x (slant resolution projected on
    the ground)."""
    r0 = math.hypot(X, H)
    return C / FC * r0 / (2 * V * TA), C / (2 * BW) * r0 / X


class qa_geo(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="qa_geo_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_001_utm_zone(self):
        """EPSG codes of UTM zones: 6 deg wide from 180 W, 326zz north, 327zz south."""
        self.assertEqual(geo.utm_epsg(59.9, 10.7), 32632)    # Oslo, zone 32N
        self.assertEqual(geo.utm_epsg(-33.9, 151.2), 32756)  # Sydney, zone 56S
        self.assertEqual(geo.utm_epsg(0.5, -177.1), 32601)
        self.assertEqual(geo.utm_epsg(10.0, 180.0), 32660)   # the antimeridian: zone 60

    def test_002_frame_on_the_map(self):
        """Frame.to_map against geodesics, points up to 2 km from the origin: the frame is
        flat, the ellipsoid departs from it by about d^2 / R = 0.6 m at d = 2 km: 1 m."""
        for origin in ("59.9,10.7,30", "-33.9,151.2,250", "70,29.9,359", "0.5,-177.1,90"):
            frame = geo.Frame(origin)
            lat, lon, heading = (float(v) for v in origin.split(","))
            to_utm = pyproj.Transformer.from_crs(4326, frame.epsg, always_xy=True)
            for x, y in ((0, 2000), (2000, 0), (1400, -1400), (-300, 700)):
                e, n = to_utm.transform(*true_lon_lat(lat, lon, heading, x, y))
                got = frame.to_map(x, y)
                self.assertLess(math.hypot(got[0] - e, got[1] - n), 1.0, (origin, x, y))

    def check_geotiff(self, origin, grid):
        out = os.path.join(self.dir, f"{grid}")
        proc = run_app("nrsar-sim", FLIGHT + ["--geotiff", "--origin=" + origin,
                                              "--geotiff-grid", grid, "--json", "--out", out])
        self.assertEqual(proc.returncode, 0, proc.stderr)
        r = json.loads(proc.stdout)
        lat, lon, heading = (float(v) for v in origin.split(","))
        epsg = (32600 if lat >= 0 else 32700) + int((lon + 180) // 6) + 1
        self.assertEqual(r["geotiff_epsg"], epsg)
        ds = gdal.Open(r["geotiff_vrt"])
        self.assertEqual(ds.RasterCount, 2)
        self.assertEqual([gdal.GetDataTypeName(ds.GetRasterBand(i).DataType) for i in (1, 2)],
                         ["Float32", "CFloat32"])
        for path, kind in ((r["geotiff_db"], "Float32"), (r["geotiff_complex"], "CFloat32")):
            tif = gdal.Open(path)
            self.assertEqual(tif.GetDriver().ShortName, "GTiff")
            self.assertEqual(gdal.GetDataTypeName(tif.GetRasterBand(1).DataType), kind)
            srs = osr.SpatialReference(wkt=tif.GetProjection())
            self.assertEqual(int(srs.GetAuthorityCode(None)), epsg)
        power = ds.GetRasterBand(1).ReadAsArray()
        cplx = ds.GetRasterBand(2).ReadAsArray()
        self.assertEqual(power.shape, cplx.shape)
        line, col = np.unravel_index(np.argmax(power), power.shape)
        image = np.load(r["image_npy"])
        cplx_db = 10 * np.log10(np.abs(cplx.astype(np.complex128)) ** 2)
        if grid == "slant":  # the image itself; band 1 its power in dB (float32 rounding)
            np.testing.assert_array_equal(cplx, image)
            np.testing.assert_allclose(power, cplx_db, atol=1e-4)
        else:
            # every slant bin beyond H is the nearest bin of some ground pixel (the grid is
            # finer than the slant bins everywhere): the complex band holds the image's peak;
            # the power band interpolates between two bins, never above the larger one
            self.assertAlmostEqual(cplx_db.max(), 10 * np.log10(np.max(np.abs(image)) ** 2),
                                   delta=1e-4)
            self.assertLessEqual(power.max(), cplx_db.max() + 1e-4)
        gt = ds.GetGeoTransform()
        e = gt[0] + (col + 0.5) * gt[1] + (line + 0.5) * gt[2]
        n = gt[3] + (col + 0.5) * gt[4] + (line + 0.5) * gt[5]
        lon_px, lat_px = pyproj.Transformer.from_crs(epsg, 4326, always_xy=True).transform(e, n)
        lon_t, lat_t = true_lon_lat(lat, lon, heading, X, Y)
        az, _, dist = GEOD.inv(lon_t, lat_t, lon_px, lat_px)
        along = dist * math.cos(math.radians(az - heading))
        cross = dist * math.sin(math.radians(az - heading))
        rho_a, rho_g = resolution_cells()  # 17.9 m, 28.4 m
        print(f"{grid}: brightest pixel {along:+.2f} m along, {cross:+.2f} m across the "
              f"track from the target (cells {rho_a:.1f} m, {rho_g:.1f} m)")
        self.assertLess(abs(along), rho_a)
        self.assertLess(abs(cross), rho_g)
        return r

    def test_003_ground_grid(self):
        r = self.check_geotiff("59.9,10.7,30", "ground")
        self.assertEqual(r["geotiff_grid"], "ground")

    def test_004_slant_grid(self):
        r = self.check_geotiff("-33.9,151.2,250", "slant")
        # the columns' spacing: one slant bin projected at the window's middle, dr r_c / x_c
        (r0, dr), k = r["range_axis_m"], r["range_bins"]
        r_c = r0 + dr * (k // 2)
        self.assertAlmostEqual(r["geotiff_x_axis_m"][1], dr * r_c / math.sqrt(r_c ** 2 - H ** 2),
                               delta=1e-9)

    def test_005_bad_origin(self):
        """The doors of --origin and --geotiff: exit 2, one line naming the flag and limit."""
        base = ["--preset", "tiny", "--aperture-s", "0.02", "--out",
                os.path.join(self.dir, "bad")]
        for flags, expected in (
                (["--origin", "85,10,0"], "latitude = 85 must be within [-80, 84]"),
                (["--origin=-81,10,0"], "latitude = -81 must be within [-80, 84]"),
                (["--origin", "10,200,0"], "longitude = 200 must be within [-180, 180]"),
                (["--origin", "10,10,360"], "heading = 360 must be within [0, 360)"),
                (["--origin", "10,10"], "must be LAT,LON,HEADING_DEG (3 numbers, got 2)"),
                (["--origin", "a,10,0"], "latitude 'a' is not a number"),
                (["--origin", "nan,10,0"], "latitude = nan must be finite"),
                (["--geotiff"], "--geotiff needs --origin"),
                (["--geotiff", "--origin", "10,10,0", "--images", "none"],
                 "--geotiff needs the image")):
            with self.subTest(flags=flags):
                proc = run_app("nrsar-sim", base + flags)
                self.assertEqual(proc.returncode, 2, proc.stderr)
                self.assertNotIn("Traceback", proc.stderr)
                self.assertIn(expected, proc.stderr)
                self.assertTrue(proc.stderr.startswith("nrsar-sim: error: "), proc.stderr)


if __name__ == "__main__":
    gr_unittest.run(qa_geo)
