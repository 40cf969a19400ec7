/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  Docstrings of the hand-written tf_filter bindings.
 */

static const char* __doc_gr_nrsar_tf_filter =
    R"doc(Per-RE TF filter, eq. (25): Y_tf = Y * g with RF g = 1/s, MF g = conj(s),
WF g = conj(s) / (|s|^2 + 1/SNR_in). Input 0: echo Y, input 1: reference symbols S,
vlen REs per item each; output Y_tf. Empty REs (s = 0) give 0 and are counted.)doc";

static const char* __doc_gr_nrsar_tf_filter_tf_filter = R"doc()doc";

static const char* __doc_gr_nrsar_tf_filter_make =
    R"doc(tf_filter(vlen, type=filter_type.WF, snr_db=20.0, estimate_snr=False)

vlen: REs per item (num_subcarriers); type: filter_type.RF/MF/WF; snr_db: SNR_in [dB]
for WF; estimate_snr: estimate SNR_in from the data (method of moments).)doc";
