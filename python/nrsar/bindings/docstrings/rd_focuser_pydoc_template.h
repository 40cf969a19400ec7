/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 *
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  This file contains placeholders for docstrings for the Python bindings.
  Do not edit! These were automatically extracted during the binding process
  and will be overwritten during the build process
 */


static const char* __doc_gr_nrsar_rd_focuser =
    R"doc(Range-Doppler SAR focusing of range-compressed pulses, eqs. (31)-(47).)doc";


static const char* __doc_gr_nrsar_rd_focuser_make = R"doc(make(num, geo, scn, num_range_bins, first_range_m, range_bin_m=0, cfg=focuser_config()))doc";
