/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  Docstrings of the hand-written autofocus bindings.
 */

static const char* __doc_gr_nrsar_autofocus =
    R"doc(Autofocus of focused images (one per aperture): estimates the azimuth phase error the
navigation did not know (PGA or minimum entropy), corrects the image, passes it on with its
tags, and publishes the estimate per image on message port 'phase_error'.)doc";

static const char* __doc_gr_nrsar_autofocus_make = R"doc(autofocus(num_range_bins, cfg=autofocus_config()))doc";
