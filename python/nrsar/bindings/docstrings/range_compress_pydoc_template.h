/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  Docstrings of the hand-written range_compress bindings.
 */

static const char* __doc_gr_nrsar_range_compress =
    R"doc(tf_filter and range_ifft in one block: per-RE filter (eq. 25), window, zero-padded
unitary IFFT (eq. 29) and range crop of each symbol in one pass. Inputs: echo, reference
(N REs per item); output: K range bins per item, as tf_filter followed by range_ifft.)doc";

static const char* __doc_gr_nrsar_range_compress_range_compress = R"doc()doc";

static const char* __doc_gr_nrsar_range_compress_make =
    R"doc(range_compress(num, cfg=range_compress_config())

num: numerology (N REs per input item, Delta f for the range axis); cfg: the filter's and
the range IFFT's options (range_compress_config).)doc";
