/*
 * Copyright 2026 Free Software Foundation, Inc.
 *
 * This file is part of GNU Radio
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 *
 */
#include "pydoc_macros.h"
#define D(...) DOC(gr, nrsar, __VA_ARGS__)
/*
  This file contains placeholders for docstrings for the Python bindings.
  Do not edit! These were automatically extracted during the binding process
  and will be overwritten during the build process
 */



static const char* __doc_gr_nrsar_td_echo = R"doc(Time-domain monostatic echo of a point-target scene.

y(t) = sum_q sqrt(rcs_q) e^{j phase_q} x(t - tau_q(m)) e^{-j 2 pi (fc + k0 df) tau_q(m)} + noise,
tau_q(m) = 2 R_q(m) / c with R of eq. (8) at t_m = m Tsym, m the OFDM symbol of the output
sample. Demodulated with ofdm_demod it equals scene_echo's eq. (7) when the delay is inside the CP.)doc";


 static const char *__doc_gr_nrsar_td_echo_td_echo = R"doc()doc";


static const char* __doc_gr_nrsar_td_echo_make = R"doc(td_echo(num, geo, scn, snr_db=inf, seed=0, taps=32, kaiser_beta=-1, beam=antenna_beam())

num: numerology, geo: geometry, scn: scene (check_scenario must accept it), snr_db: SNR
per RE in dB (total RCS / sigma^2; inf = no noise), seed: noise seed, taps: fractional-delay
FIR length (even, 2..256), kaiser_beta: Kaiser window parameter (negative: automatic),
beam: antenna illumination (nrsar.make_beam; default: whole block).)doc";

  
