/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  Docstrings of the hand-written ofdm_sync bindings.
 */

static const char* __doc_gr_nrsar_ofdm_sync =
    R"doc(Base-station acquisition: Schmidl & Cox timing and fractional CFO (|CFO| < Delta f) on
the first PUSCH DMRS symbol (even subcarriers only, period fft_size / 2). Outputs the stream
from the CP start of that symbol's slot (minus backoff * cp samples), CFO-derotated, with
"sync", "symbol", "slot" and "frame" tags; slot 0 is the burst's first slot.)doc";

static const char* __doc_gr_nrsar_ofdm_sync_ofdm_sync = R"doc()doc";

static const char* __doc_gr_nrsar_ofdm_sync_make =
    R"doc(ofdm_sync(num, dmrs, threshold=0.1, backoff=0.125)

num: numerology (even fft_size); dmrs: dmrs_config with at least one symbol;
threshold: on the metric M in (0, 1); backoff: fraction of the CP in [0, 1) by which the
output starts before the estimated slot start.)doc";
