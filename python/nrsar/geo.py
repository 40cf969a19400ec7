#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Focused images on the map: GeoTIFFs in the UTM zone of the flight (GDAL, pyproj).

The frame (SPEC 3): y along the track, in the direction of flight; x across it, on the
ground, towards the scene, which lies to the RIGHT of the heading; z up, the platform at
height H above (0, y). --origin LAT,LON,HEADING_DEG places the frame's origin (x = 0,
y = 0 on the ground) on the WGS 84 ellipsoid, with the flight's heading in degrees clockwise
from true north. Near the origin the UTM grid is the frame rotated by the grid azimuth of
the heading (the heading minus the meridian convergence) and scaled by the point scale
factor k (conformal projection), so the image's pixel grid maps to UTM by one affine
geotransform:

    E = E0 + k (x cos a + y sin a),  N = N0 + k (-x sin a + y cos a),   a = grid azimuth

Every image is written as three files (TIFF holds one sample type per file; GDAL refuses
mixed-type bands):

    image_db.tif        band Float32: power 10 log10 |s|^2 [dB] (what a GIS shows)
    image_complex.tif   band CFloat32: the complex image s
    image.vrt           both as one 2-band dataset (band 1 Float32 dB, band 2 CFloat32)

Grids (--geotiff-grid): `ground` (default) resamples each line from slant range r to a
regular ground-range grid x = sqrt(r^2 - H^2) with the far edge's spacing (the finest);
the power is interpolated linearly, the complex band takes the nearest slant bin (a focused
target's phase turns by about pi per range bin: interpolating it would cancel the peak).
Bins nearer than H have no ground point and are dropped. `slant` keeps the range bins as
they are, placed on the ground by the ground range linearised at the window's middle slant
range r_c (x_c + (r - r_c) r_c / x_c): exact there, off by geotiff_slant_max_error_m (in the
JSON) at the window's edges.
"""

import math
import os
from xml.sax.saxutils import escape

import numpy as np
import pmt
import pyproj
from gnuradio import gr
from osgeo import gdal, osr

from . import results
from .options import parse_origin

gdal.UseExceptions()

def utm_epsg(lat_deg, lon_deg):
    """EPSG code of the standard UTM zone of a point: 326zz north of the equator, 327zz
    south (zones of 6 deg from 180 W; Norway's and Svalbard's exceptions are not applied)."""
    zone = min(int((lon_deg + 180.0) // 6.0) + 1, 60)
    return (32600 if lat_deg >= 0 else 32700) + zone


class Frame:
    """The flight's frame (x, y) [m] on the map of --origin: to_map(x, y) -> UTM (E, N)."""

    def __init__(self, origin_text):
        self.lat, self.lon, self.heading = parse_origin(origin_text)
        self.epsg = utm_epsg(self.lat, self.lon)
        proj = pyproj.Proj(f"EPSG:{self.epsg}")
        self.e0, self.n0 = proj(self.lon, self.lat)
        factors = proj.get_factors(self.lon, self.lat)
        # PROJ's meridian convergence is the angle from true north to grid north, clockwise
        # positive east of the central meridian: grid azimuth = true azimuth - convergence.
        self.azimuth = math.radians(self.heading - factors.meridian_convergence)
        self.k = factors.meridional_scale

    def to_map(self, x, y):
        ca, sa = math.cos(self.azimuth), math.sin(self.azimuth)
        return (self.e0 + self.k * (x * ca + y * sa), self.n0 + self.k * (-x * sa + y * ca))

    def geotransform(self, x_axis, y_axis):
        """GDAL geotransform of a grid whose column c is at x = x0 + c dx and row r at
        y = y0 + r dy (pixel centres; GDAL's (0, 0) is the first pixel's corner)."""
        (x0, dx), (y0, dy) = x_axis, y_axis
        ca, sa = math.cos(self.azimuth), math.sin(self.azimuth)
        e, n = self.to_map(x0 - dx / 2, y0 - dy / 2)
        k = self.k
        return (e, k * dx * ca, k * dy * sa, n, -k * dx * sa, k * dy * ca)

    def wkt(self):
        srs = osr.SpatialReference()
        srs.ImportFromEPSG(self.epsg)
        return srs.ExportToWkt()


def ground_grid(range_axis, bins, height_m):
    """(first ground range, spacing, number) of the regular ground grid of slant bins
    r_k = r0 + k dr: from the first bin at or beyond H to the last, spaced like one slant
    bin at the far edge (dr r / x there, the finest; nearer bins are oversampled)."""
    r0, dr = range_axis
    r_last = r0 + dr * (bins - 1)
    if r_last <= height_m:
        raise ValueError(f"--geotiff-grid ground: the image's slant ranges "
                         f"[{r0:.1f}, {r_last:.1f}] m lie below the height {height_m:g} m: "
                         f"no ground range (use --geotiff-grid slant)")
    x_lo = math.sqrt(max(r0, height_m) ** 2 - height_m ** 2)
    x_hi = math.sqrt(r_last ** 2 - height_m ** 2)
    dx = dr * r_last / x_hi
    return x_lo, dx, int(math.floor((x_hi - x_lo) / dx)) + 1


def to_ground(image, range_axis, height_m):
    """(power [linear] and complex image on the ground grid, [x0, dx]): power interpolated
    linearly in slant range, the complex value of the nearest slant bin."""
    r0, dr = range_axis
    x0, dx, count = ground_grid(range_axis, image.shape[1], height_m)
    x = x0 + dx * np.arange(count)
    pos = (np.sqrt(x ** 2 + height_m ** 2) - r0) / dr  # fractional slant bin
    pos = np.clip(pos, 0.0, image.shape[1] - 1)
    power = np.abs(image.astype(np.complex128)) ** 2
    lo = np.minimum(np.floor(pos).astype(int), image.shape[1] - 2) if image.shape[1] > 1 \
        else np.zeros(count, int)
    frac = pos - lo
    hi = np.minimum(lo + 1, image.shape[1] - 1)
    power_g = power[:, lo] * (1 - frac) + power[:, hi] * frac
    nearest = np.rint(pos).astype(int)
    return power_g, image[:, nearest], [x0, dx]


def power_db(power):
    """10 log10(power), -300 dB for a zero pixel (float32 has no log of 0)."""
    return (10.0 * np.log10(np.maximum(power, 1e-30))).astype(np.float32)


def slant_linearised(range_axis, bins, height_m):
    """([x0, dx] of the slant bins' columns on the ground, largest error [m]): the ground
    range sqrt(r^2 - H^2) linearised at the window's middle r_c, x_c + (r - r_c) r_c / x_c
    (exact there; the error grows with (r - r_c)^2 and is largest at the edges and near
    nadir; bins nearer than H have no ground point and are left out of the error)."""
    r0, dr = range_axis
    r = r0 + dr * np.arange(bins)
    r_c = float(r[bins // 2])
    if r_c <= height_m:
        raise ValueError(f"--geotiff-grid slant: the middle of the image's slant ranges, "
                         f"{r_c:.1f} m, is below the height {height_m:g} m: no ground range")
    x_c = math.sqrt(r_c ** 2 - height_m ** 2)
    slope = r_c / x_c
    beyond = r > height_m
    error = np.abs(np.sqrt(r[beyond] ** 2 - height_m ** 2) - (x_c + (r[beyond] - r_c) * slope))
    return [x_c - (r_c - r0) * slope, dr * slope], float(error.max())


def _write_band(path, array, gdal_type, frame, geotransform, description):
    with results.atomic(path) as tmp:
        ds = gdal.GetDriverByName("GTiff").Create(tmp, array.shape[1], array.shape[0], 1,
                                                  gdal_type)
        ds.SetGeoTransform(geotransform)
        ds.SetProjection(frame.wkt())
        band = ds.GetRasterBand(1)
        band.WriteArray(array)
        band.SetDescription(description)
        ds.FlushCache()
        ds = None  # closes the file (GDAL writes on close)
    return path


def _vrt_text(cols, rows, frame, geotransform, bands):
    """A 2-band VRT over the two GeoTIFFs (relative paths: the folder can move)."""
    lines = [f'<VRTDataset rasterXSize="{cols}" rasterYSize="{rows}">',
             f"  <SRS>{escape(frame.wkt())}</SRS>",
             "  <GeoTransform>" + ", ".join(repr(v) for v in geotransform) + "</GeoTransform>"]
    for i, (type_name, file_name, description) in enumerate(bands, start=1):
        lines += [f'  <VRTRasterBand dataType="{type_name}" band="{i}">',
                  f"    <Description>{escape(description)}</Description>",
                  "    <SimpleSource>",
                  f'      <SourceFilename relativeToVRT="1">{escape(file_name)}'
                  "</SourceFilename>",
                  "      <SourceBand>1</SourceBand>",
                  "    </SimpleSource>",
                  "  </VRTRasterBand>"]
    lines.append("</VRTDataset>")
    return "\n".join(lines) + "\n"


def write_image(image, range_axis, y_axis, origin, height_m, grid, prefix):
    """Writes one focused image (lines x slant bins; range_axis [first, step] of the bins,
    y_axis [first, step] of the lines, both in metres) as prefix_db.tif, prefix_complex.tif
    and prefix.vrt on the map of origin ('LAT,LON,HEADING_DEG'); returns the JSON keys that
    name them."""
    frame = Frame(origin)
    slant_error = None
    if grid == "ground":
        power, cplx, x_axis = to_ground(image, range_axis, height_m)
    else:
        power, cplx = np.abs(image.astype(np.complex128)) ** 2, image
        x_axis, slant_error = slant_linearised(range_axis, image.shape[1], height_m)
    geotransform = frame.geotransform(x_axis, y_axis)
    paths = {key: os.path.abspath(prefix + suffix)
             for key, suffix in (("db", "_db.tif"), ("complex", "_complex.tif"),
                                 ("vrt", ".vrt"))}
    db_text, cplx_text = "power [dB]", "complex image"
    _write_band(paths["db"], power_db(power), gdal.GDT_Float32, frame, geotransform, db_text)
    _write_band(paths["complex"], cplx.astype(np.complex64), gdal.GDT_CFloat32, frame,
                geotransform, cplx_text)
    results.write_text(paths["vrt"], _vrt_text(
        power.shape[1], power.shape[0], frame, geotransform,
        [("Float32", os.path.basename(paths["db"]), db_text),
         ("CFloat32", os.path.basename(paths["complex"]), cplx_text)]))
    return {"geotiff_db": paths["db"], "geotiff_complex": paths["complex"],
            "geotiff_vrt": paths["vrt"], "geotiff_epsg": frame.epsg,
            "geotiff_grid": grid,
            "geotiff_x_axis_m": x_axis,  # [first, step] of the columns' ground range
            "geotiff_slant_max_error_m": slant_error}


def write_geotiffs(opts, result, height_m, name="image"):
    """Writes the focused image of a run (result: the JSON dict of SPEC 9, its image_npy
    and axes) as GeoTIFFs into opts.out; returns the JSON keys that name them."""
    return write_image(np.load(result["image_npy"]), result["range_axis_m"],
                       result["azimuth_axis_m"], opts.origin, height_m, opts.geotiff_grid,
                       os.path.join(opts.out, name))


class geotiff_writer(gr.basic_block):
    """image_sink's GeoTIFF writer: fed by image_sink's `files` message port, it writes every
    aperture's .npy as GeoTIFFs beside it (NAME_db.tif, NAME_complex.tif, NAME.vrt, with
    NAME the .npy's path without .npy) on the map of origin 'LAT,LON,HEADING_DEG', at the
    platform's height_m, on the `ground` or `slant` grid (docs/blocks/image_sink.md). The
    message's range_axis and azimuth_axis tuples (first, step, count) place the pixels.
    Each aperture's keys (write_image's, plus `aperture`) leave on the `geotiffs` port; a
    message without an .npy (image_sink's write_npy off) or that fails is logged and counted
    (failed())."""

    def __init__(self, origin, height_m, grid="ground"):
        gr.basic_block.__init__(self, "geotiff_writer", in_sig=None, out_sig=None)
        Frame(origin)  # checks the origin now
        if not (math.isfinite(height_m) and height_m > 0):
            raise ValueError(f"height_m = {height_m!r} must be finite and > 0")
        if grid not in ("ground", "slant"):
            raise ValueError(f"grid = {grid!r} must be ground or slant")
        self.origin, self.height_m, self.grid = origin, float(height_m), grid
        self.written, self._failed = [], 0
        self.message_port_register_in(pmt.intern("files"))
        self.message_port_register_out(pmt.intern("geotiffs"))
        self.set_msg_handler(pmt.intern("files"), self.handle)

    def failed(self):
        return self._failed

    def handle(self, msg):
        info = pmt.to_python(msg)
        try:
            npy = info.get("npy") if isinstance(info, dict) else None
            if not npy:
                raise ValueError("the message names no .npy (image_sink's write_npy is off)")
            image = np.load(npy)
            range_axis, y_axis = info["range_axis"], info["azimuth_axis"]
            keys = write_image(image, [range_axis[0], range_axis[1]], [y_axis[0], y_axis[1]],
                               self.origin, self.height_m, self.grid, npy[:-len(".npy")])
        except (OSError, ValueError, KeyError, TypeError, IndexError, RuntimeError) as err:
            self._failed += 1
            gr.logger("geotiff_writer").error(f"aperture {info!r:.200}: {err}")
            return
        keys["aperture"] = int(info.get("aperture", len(self.written)))
        self.written.append(keys)
        self.message_port_pub(pmt.intern("geotiffs"), pmt.to_pmt(
            {k: v for k, v in keys.items() if v is not None}))
