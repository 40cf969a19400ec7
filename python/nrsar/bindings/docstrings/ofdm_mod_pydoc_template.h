/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  Docstrings of the hand-written ofdm_mod bindings.
 */

static const char* __doc_gr_nrsar_ofdm_mod =
    R"doc(CP-OFDM modulator: one grid column of N REs per input item -> cp + fft_size samples.
Subcarrier n at FFT bin (n - k0) mod fft_size (k0 = num.dc_subcarrier()), unitary
1/sqrt(fft_size) scaling; input tags move to the first sample (CP start) of their symbol.)doc";

static const char* __doc_gr_nrsar_ofdm_mod_ofdm_mod = R"doc()doc";

static const char* __doc_gr_nrsar_ofdm_mod_make =
    R"doc(ofdm_mod(num)

num: numerology (N, fft_size, cp_samples).)doc";
