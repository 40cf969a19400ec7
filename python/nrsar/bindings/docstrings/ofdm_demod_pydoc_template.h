/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  Docstrings of the hand-written ofdm_demod bindings.
 */

static const char* __doc_gr_nrsar_ofdm_demod =
    R"doc(CP-OFDM demodulator: cp + fft_size samples per symbol -> N REs per output item, the
inverse of ofdm_mod. The FFT window starts fft_start samples into the symbol (default cp);
an earlier start multiplies subcarrier n by exp(-j 2 pi (n - k0) (cp - fft_start) / fft_size).
A tag on input sample s goes to output item floor(s / (cp + fft_size)).)doc";

static const char* __doc_gr_nrsar_ofdm_demod_ofdm_demod = R"doc()doc";

static const char* __doc_gr_nrsar_ofdm_demod_make =
    R"doc(ofdm_demod(num, fft_start=-1)

num: numerology; fft_start: FFT window start in the symbol, 0 .. cp_samples (< 0: cp_samples).)doc";
