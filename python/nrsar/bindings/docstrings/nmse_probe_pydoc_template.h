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


static const char* __doc_gr_nrsar_nmse_probe = R"doc(Point-target image metrics per focused aperture (SPEC section 8).)doc";


static const char* __doc_gr_nrsar_nmse_probe_make = R"doc(nmse_probe(num, geo, scn, constellation, filter, snr_in_db, vlen, cfg=probe_config()))doc";
