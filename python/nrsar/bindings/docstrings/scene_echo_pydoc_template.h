/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  This file contains placeholders for docstrings for the Python bindings.
  Do not edit! These were automatically extracted during the binding process
  and will be overwritten during the build process
 */


static const char* __doc_gr_nrsar_scene_echo = R"doc(TF-domain echo of a point-target scene, eq. (7) with the exact range (8).

Y[n,m] = sum_q alpha_q S[n,m] exp(-j 4 pi (fc + n df) R_q(m) / c) + Z[n,m], m the
absolute input item index. Output 1 (optional) is the noise-free echo of S = 1.)doc";


static const char* __doc_gr_nrsar_scene_echo_make = R"doc(scene_echo(num, geo, scn, snr_db=inf, seed=0)

num: numerology (N subcarriers = vector length), geo: geometry, scn: scene,
snr_db: SNR per RE in dB (total RCS / sigma^2; inf = no noise), seed: noise seed.)doc";
