/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  Docstrings of the hand-written range_ifft bindings.
 */

static const char* __doc_gr_nrsar_range_ifft =
    R"doc(Range compression, eq. (29): windowed unitary IFFT (scale 1/sqrt(N)) over the N
subcarriers, zero-padded to fft_size, cropped to the bins in [r_min_m, r_max_m].
Tags the range axis (first bin [m], bin spacing [m], K) on the first item.)doc";

static const char* __doc_gr_nrsar_range_ifft_range_ifft = R"doc()doc";

static const char* __doc_gr_nrsar_range_ifft_make =
    R"doc(range_ifft(num, fft_size=0, window=fft.window.WIN_RECTANGULAR, window_param=-1,
           r_min_m=0.0, r_max_m=0.0)

num: numerology (N inputs per item); fft_size: 0 = N, else >= N; window: window across
the subcarriers; window_param: Kaiser beta etc.; r_min_m, r_max_m: crop [m]
(r_max_m <= 0: up to the last bin).)doc";
