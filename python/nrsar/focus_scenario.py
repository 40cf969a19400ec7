#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""A small focusing scenario with its exact range-compressed echo (eqs. 8, 29): a tiny
numerology whose range bin is 1.5 m, a 600 m high track and point targets near 1000 m.
The independent reference of the rd_focuser and cheby_presum QA (numpy float64, computed
from the geometry, never by the blocks)."""

import numpy as np

from . import params

C = 299792458.0
FC = 3.5e9
LAM = C / FC
V = 50.0
H = 600.0
N_SUB = 32      # subcarriers N
NFFT = 64       # range IFFT size: resolution cell = NFFT / N_SUB = 2 bins
RHO = 1.5       # range bin [m]
K = 64          # range bins (the whole range period NFFT)
R_FIRST = 955.0 # bin 30 is at 1000 m
SPP = 3903      # symbols per pulse: T = SPP / Delta f = 2.4999 ms, PRF 400 Hz


def numerology():
    # Delta f such that the range bin of an NFFT-point IFFT is RHO: c / (2 NFFT Delta f).
    return params.make_numerology("tiny", subcarrier_spacing_hz=C / (2 * NFFT * RHO),
                                 num_subcarriers=N_SUB, fft_size=NFFT, cp_samples=0)


NUM = numerology()
T = NUM.symbol_s() * SPP


def geometry(aperture_s, track_start=0.0):
    return params.make_geometry("paper", carrier_hz=FC, velocity_mps=V, height_m=H,
                               track_start_m=track_start, aperture_s=aperture_s)


def echo(targets, n_lines, t_pulse=T, track_start=0.0, illum=None):
    """Exact range-compressed echo, eqs. (8), (29): line m, bin k:
    sum_q a_q sum_{n<N} exp(j 2 pi n (k - k_q,m) / NFFT) / sqrt(N) exp(-j 4 pi R_q(m) / lambda),
    k_q,m = (R_q(m) - R_FIRST) / RHO. targets: (x, y, amplitude); illum: optional half length
    [m] of the along-track window that illuminates each target (None: the whole strip)."""
    m = np.arange(n_lines)
    yp = track_start + V * m * t_pulse
    k = np.arange(K)
    n = np.arange(N_SUB)
    out = np.zeros((n_lines, K), complex)
    for x, y, a in targets:
        r = np.sqrt(x * x + H * H + (yp - y) ** 2)
        kq = (r - R_FIRST) / RHO
        prof = np.exp(2j * np.pi * (k[None, :, None] - kq[:, None, None]) * n[None, None, :]
                      / NFFT).sum(-1) / np.sqrt(N_SUB)
        w = np.ones(n_lines) if illum is None else (np.abs(yp - y) <= illum).astype(float)
        out += a * w[:, None] * prof * np.exp(-4j * np.pi * np.mod(r / LAM, 1.0))[:, None]
    return out


def echo_along(antenna, targets):
    """Exact range-compressed echo (eq. 29) seen from antenna positions (pulses x 3, the
    frame of SPEC 3) of targets (x, y, amplitude) on the ground: echo()'s sum with the
    range from each position."""
    antenna = np.asarray(antenna, float)
    k = np.arange(K)
    n = np.arange(N_SUB)
    out = np.zeros((len(antenna), K), complex)
    for x, y, a in targets:
        r = np.sqrt((x - antenna[:, 0]) ** 2 + (y - antenna[:, 1]) ** 2 + antenna[:, 2] ** 2)
        kq = (r - R_FIRST) / RHO
        prof = np.exp(2j * np.pi * (k[None, :, None] - kq[:, None, None]) * n[None, None, :]
                      / NFFT).sum(-1) / np.sqrt(N_SUB)
        out += a * prof * np.exp(-4j * np.pi * np.mod(r / LAM, 1.0))[:, None]
    return out
