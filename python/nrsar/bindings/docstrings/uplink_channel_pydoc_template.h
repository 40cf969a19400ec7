/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  Docstrings of the hand-written uplink_channel bindings.
 */

static const char* __doc_gr_nrsar_uplink_channel =
    R"doc(The UAV -> base station channel of nrsar-isac in one pass: timing offset, multipath
taps, carrier frequency offset, AWGN (channel_model's order).
y[n] = exp(j 2 pi cfo n) sum_l taps[l] x[n - delay_samples - l] + noise_voltage z[n], z ~ CN(0, 1)
depending only on (seed, n): the output does not depend on how the stream is cut.)doc";

static const char* __doc_gr_nrsar_uplink_channel_uplink_channel = R"doc()doc";

static const char* __doc_gr_nrsar_uplink_channel_make =
    R"doc(uplink_channel(cfg)

cfg: uplink_channel_config(delay_samples, taps, cfo [cycles/sample], noise_voltage, seed).)doc";
