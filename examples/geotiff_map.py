#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""A GeoTIFF of nrsar-sim / nrsar-process (image_db.tif) drawn where it lies on the map,
without a GIS and without map tiles (no network): the raster in its UTM coordinates, a
latitude / longitude graticule from pyproj, the flight's track (from --origin and the
image's azimuth axis) and, optionally, a point's true position (geodesics from the origin).

    examples/geotiff_map.py proc/image_db.tif --origin 59.9,10.7,30 --track -2,3 \
        --mark 300,1 --out map.png

It is what a GIS shows once the layer is loaded (QGIS: Layer -> Add Raster Layer), minus the
base map: a stand-in for a screenshot where QGIS is not installed.
"""

import argparse
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pyproj
from osgeo import gdal, osr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("geotiff")
    ap.add_argument("--origin", required=True, help="LAT,LON,HEADING_DEG of the flight")
    ap.add_argument("--track", default=None, help="Y0,Y1: along-track span of the flight [m]")
    ap.add_argument("--mark", default=None, help="X,Y: a point of the frame to mark [m]")
    ap.add_argument("--range-db", type=float, default=40.0, help="dB below the peak shown")
    ap.add_argument("--margin-m", type=float, default=150.0)
    ap.add_argument("--out", default="map.png")
    args = ap.parse_args()
    gdal.UseExceptions()
    lat0, lon0, heading = (float(v) for v in args.origin.split(","))
    ds = gdal.Open(args.geotiff)
    power = ds.GetRasterBand(1).ReadAsArray()
    gt = ds.GetGeoTransform()
    epsg = int(osr.SpatialReference(wkt=ds.GetProjection()).GetAuthorityCode(None))
    rows, cols = power.shape
    cc, rr = np.meshgrid(np.arange(cols + 1), np.arange(rows + 1))  # pixel corners
    east = gt[0] + cc * gt[1] + rr * gt[2]
    north = gt[3] + cc * gt[4] + rr * gt[5]
    to_utm = pyproj.Transformer.from_crs(4326, epsg, always_xy=True)
    geod = pyproj.Geod(ellps="WGS84")

    def frame_point(x, y):
        lon1, lat1, back = geod.fwd(lon0, lat0, heading, y)
        lon2, lat2, _ = geod.fwd(lon1, lat1, back + 270.0, x)
        return to_utm.transform(lon2, lat2)

    fig, ax = plt.subplots(figsize=(7.5, 6.5))
    ax.set_facecolor("#e8eef2")
    peak = float(np.nanmax(power))
    mesh = ax.pcolormesh(east, north, np.ma.masked_less(power, peak - args.range_db),
                         cmap="inferno", vmin=peak - args.range_db, vmax=peak, shading="flat")
    fig.colorbar(mesh, ax=ax, label="power [dB]", shrink=0.8)
    e0, n0 = to_utm.transform(lon0, lat0)
    pts_e = [east.min(), east.max(), e0]
    pts_n = [north.min(), north.max(), n0]
    if args.track:
        y0, y1 = (float(v) for v in args.track.split(","))
        (ea, na), (eb, nb) = frame_point(0.0, y0), frame_point(0.0, y1)
        ax.annotate("", (eb, nb), (ea, na), arrowprops=dict(arrowstyle="->", color="tab:blue",
                                                             lw=2))
        ax.text(eb, nb, "  flight", color="tab:blue", va="center")
        pts_e += [ea, eb]
        pts_n += [na, nb]
    if args.mark:
        x, y = (float(v) for v in args.mark.split(","))
        em, nm = frame_point(x, y)
        ax.plot(em, nm, "o", mfc="none", mec="tab:cyan", ms=14, mew=2,
                label=f"true position of the point ({x:g} m, {y:g} m)")
        ax.legend(loc="lower left", fontsize=8)
    ax.plot(e0, n0, "k+", ms=10)
    ax.text(e0, n0, "  origin", va="top")
    m = args.margin_m
    xlim = (min(pts_e) - m, max(pts_e) + m)
    ylim = (min(pts_n) - m, max(pts_n) + m)
    # graticule: lines of constant latitude / longitude through the view
    to_geo = pyproj.Transformer.from_crs(epsg, 4326, always_xy=True)
    lons, lats = to_geo.transform([xlim[0], xlim[1], xlim[0], xlim[1]],
                                  [ylim[0], ylim[0], ylim[1], ylim[1]])
    step = 0.001  # degrees
    for lat in np.arange(math.floor(min(lats) / step) * step, max(lats) + step, step):
        e, n = to_utm.transform(np.linspace(min(lons), max(lons), 50), np.full(50, lat))
        ax.plot(e, n, color="grey", lw=0.5)
        ax.text(xlim[1], np.interp(xlim[1], e, n), f" {lat:.3f} N", fontsize=7, va="center")
    for lon in np.arange(math.floor(min(lons) / step) * step, max(lons) + step, step):
        e, n = to_utm.transform(np.full(50, lon), np.linspace(min(lats), max(lats), 50))
        ax.plot(e, n, color="grey", lw=0.5)
        ax.text(np.interp(ylim[0], n, e), ylim[0], f"{lon:.3f} E", fontsize=7, rotation=90,
                ha="center", va="top")
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal")
    ax.set_xlabel(f"easting [m] (EPSG:{epsg})", labelpad=28)
    ax.set_ylabel("northing [m]")
    ax.set_title(f"{args.geotiff.split('/')[-1]} on the map (UTM, graticule 0.001 deg)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main()
