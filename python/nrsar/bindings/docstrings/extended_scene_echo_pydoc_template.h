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


static const char* __doc_gr_nrsar_extended_scene_echo = R"doc(TF-domain echo of an extended scene (reflectivity maps + point targets), eqs. (1)-(3), (7), (8).

Y[n,m] = S[n,m] sum_k a_k g_k(m) exp(-j 4 pi (fc + n df) R_k(m) / c) + Z[n,m], evaluated by
spreading on an oversampled slant-range grid + FFT. Output 1 (optional): the noise-free echo of S = 1.)doc";


static const char* __doc_gr_nrsar_extended_scene_echo_make = R"doc(extended_scene_echo(num, geo, points, maps, beam=antenna_beam(), snr_db=inf, seed=0, taps=8, oversampling=2.0)

num: numerology, geo: geometry, points: scene of point targets, maps: list of reflectivity_map,
beam: antenna_beam, snr_db: SNR per RE (total power / sigma^2; inf = no noise), seed: noise seed,
taps: Kaiser-Bessel kernel length L (even, 2..32), oversampling: grid oversampling O (1.25..8).)doc";
