/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  This file contains placeholders for docstrings for the Python bindings.
  Do not edit! These were automatically extracted during the binding process
  and will be overwritten during the build process
 */


static const char* __doc_gr_nrsar_image_sink = R"doc(Writes every focused aperture to <prefix>_<n>.npy (complex64, azimuth x range) and/or <prefix>_<n>.png (dB re the peak over a dynamic range); message port 'files' names them; only the last `keep` apertures' files stay on disk.)doc";


static const char* __doc_gr_nrsar_image_sink_make = R"doc(make(num_range_bins, prefix, write_npy=True, write_png=True, dynamic_range_db=40.0, colormap=image_colormap.VIRIDIS, keep=16, lines_per_aperture=0))doc";
