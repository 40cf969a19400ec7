/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  Docstrings of the hand-written bp_focuser bindings.
 */

static const char* __doc_gr_nrsar_bp_focuser =
    R"doc(Time-domain back-projection of range-compressed pulses along the navigation path
onto rd_focuser's image grid: exact distance per pixel and pulse, linear interpolation of
the upsampled profile, carrier and range-centre phase, coherent sum (1 / sqrt(M)).)doc";

static const char* __doc_gr_nrsar_bp_focuser_make = R"doc(bp_focuser(num, geo, scn, num_range_bins, first_range_m, range_bin_m=0, cfg=bp_config(), nav=trajectory()))doc";
