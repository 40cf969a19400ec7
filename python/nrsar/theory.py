#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Theory of SPEC section 8: statistics of chi = s g per constellation and filter.

Everything here is exact expectation over the equiprobable points of a constellation,
built from the 3GPP TS 38.211 section 5.1 formulas of SPEC section 2 in numpy (float64),
independently of the C++ blocks, so the QA can check the blocks against it.

    RF g = 1/s, MF g = conj(s), WF g = conj(s) / (|s|^2 + 1/SNR_in)        eq. (25)
    chi = s g (real), NMSE_theory = (Var(chi) + E|g|^2 / SNR_in) / E{chi}^2  SPEC 8
"""

import math

import numpy as np

# Only the names come from the bindings' enums (params.py); the statistics are numpy's own.
from .params import FILTERS, MODULATIONS

LIGHT_SPEED = 299792458.0


def _name(value, allowed, kind):
    """Accepts 'qam256', 'QAM256' or an enum value whose str ends with the name."""
    text = str(value).split(".")[-1].lower()
    if text not in allowed:
        raise ValueError(f"{kind} '{value}' is unknown; choose one of {list(allowed)}")
    return text


def _bits(n_bits):
    """All bit patterns of n_bits, b(0) first: array (2**n_bits, n_bits) of 0/1."""
    idx = np.arange(2 ** n_bits)
    return (idx[:, None] >> (n_bits - 1 - np.arange(n_bits))[None, :]) & 1


def constellation(modulation):
    """Points of the constellation (complex128, unit mean power), SPEC 2 / 38.211 5.1."""
    mod = _name(modulation, MODULATIONS, "modulation")
    if mod.startswith("psk"):
        m = int(mod[3:])
        return np.exp(1j * (2 * np.pi * np.arange(m) / m + np.pi / m))
    n_bits = {"qpsk": 2, "qam16": 4, "qam64": 6, "qam256": 8}[mod]
    a = 1 - 2 * _bits(n_bits).astype(float)  # (1 - 2 b(i))
    if mod == "qpsk":
        return (a[:, 0] + 1j * a[:, 1]) / np.sqrt(2)
    if mod == "qam16":
        return (a[:, 0] * (2 - a[:, 2]) + 1j * a[:, 1] * (2 - a[:, 3])) / np.sqrt(10)
    if mod == "qam64":
        return (a[:, 0] * (4 - a[:, 2] * (2 - a[:, 4])) +
                1j * a[:, 1] * (4 - a[:, 3] * (2 - a[:, 5]))) / np.sqrt(42)
    return (a[:, 0] * (8 - a[:, 2] * (4 - a[:, 4] * (2 - a[:, 6]))) +
            1j * a[:, 1] * (8 - a[:, 3] * (4 - a[:, 5] * (2 - a[:, 7])))) / np.sqrt(170)


def filter_gain(s, filt, snr_db):
    """g of eq. (25) for symbols s (numpy, float64); snr_db is used by WF only."""
    f = _name(filt, FILTERS, "filter")
    s = np.asarray(s, dtype=np.complex128)
    if f == "rf":
        return 1.0 / s
    if f == "mf":
        return np.conj(s)
    return np.conj(s) / (np.abs(s) ** 2 + 10.0 ** (-snr_db / 10.0))


def filter_moments(modulation, filt, snr_db):
    """dict(E_chi, Var_chi, E_g2) over the equiprobable points of the constellation."""
    s = constellation(modulation)
    g = filter_gain(s, filt, snr_db)
    chi = (s * g).real
    return {
        "E_chi": float(np.mean(chi)),
        "Var_chi": float(np.var(chi)),
        "E_g2": float(np.mean(np.abs(g) ** 2)),
    }


def nmse_theory(modulation, filt, snr_db):
    """Linear NMSE_theory = (Var(chi) + E|g|^2 / SNR_in) / E{chi}^2 (SPEC 8)."""
    m = filter_moments(modulation, filt, snr_db)
    snr = 10.0 ** (snr_db / 10.0)
    return (m["Var_chi"] + m["E_g2"] / snr) / m["E_chi"] ** 2


def nmse_theory_db(modulation, filt, snr_db):
    """NMSE_theory of SPEC 8 in dB."""
    return 10.0 * math.log10(nmse_theory(modulation, filt, snr_db))


def table(modulation="qam256", snrs_db=(-20.0, 5.0, 20.0)):
    """{filter: [NMSE_theory dB per SNR]}: SPEC 8's table for one constellation."""
    return {f: [nmse_theory_db(modulation, f, x) for x in snrs_db] for f in FILTERS}


if __name__ == "__main__":
    for f, row in table().items():
        print(f.upper(), " ".join(f"{v:6.1f}" for v in row))


def _ofdm_bins(num):
    """FFT bin of every subcarrier: (n - k0) mod fft_size, k0 = floor(N/2) rounded down to even
    (SPEC: the time-domain waveform's DC subcarrier)."""
    n = num.num_subcarriers
    return (np.arange(n) - ((n // 2) & ~1)) % num.fft_size


def ofdm_modulate(grid, num):
    """Grid (M, N) -> CP-OFDM time samples, float64: unitary IFFT, CP of cp_samples."""
    f, cp = num.fft_size, num.cp_samples
    bins = np.zeros((grid.shape[0], f), np.complex128)
    bins[:, _ofdm_bins(num)] = grid
    body = np.fft.ifft(bins, axis=1) * np.sqrt(f)
    return np.concatenate([body[:, f - cp:], body], axis=1).ravel()


def ofdm_demodulate(x, num, fft_start=None):
    """CP-OFDM time samples -> grid (M, N), float64: unitary FFT of the fft_size samples from
    fft_start (default cp_samples, right after the CP) of every symbol."""
    f, cp = num.fft_size, num.cp_samples
    start = cp if fft_start is None else fft_start
    sym = np.asarray(x, np.complex128).reshape(-1, f + cp)
    return (np.fft.fft(sym[:, start:start + f], axis=1) / np.sqrt(f))[:, _ofdm_bins(num)]


# The RD focuser's steps in float64 numpy: the reference of qa_stress and nrsar-bench.
def numpy_focus(s, band_lo, band_hi, full, line_shift=0, taps=16, beta=6.0, phases=None):
    """The same steps in numpy: azimuth FFT, band selection, hyperbolic RCMC by a Kaiser
    windowed sinc on the demodulated range profile, compression, inverse FFT, output rotated
    by `line_shift` lines (the block's line_shift() in its circular mode). `phases`: round
    the fractional shift to that many steps per bin as the block's tabulated kernel does
    (None: exact)."""
    data = s["data"]
    m, k = data.shape
    v = s["geo"].velocity_mps
    lam, t, rho = s["lam"], s["t"], s["rho"]
    n = s["num"].num_subcarriers
    fc_r = (n - 1) * s["num"].subcarrier_spacing_hz * rho / LIGHT_SPEED
    spec = np.fft.fft(data, axis=0) / math.sqrt(m)
    prf = 1.0 / t
    centre = 0.5 * (band_lo + band_hi)
    f = centre + np.remainder(np.fft.fftfreq(m, t) - centre + prf / 2, prf) - prf / 2
    sel = np.arange(m) if full else np.nonzero((f >= band_lo) & (f <= band_hi))[0]
    out = np.zeros_like(spec)
    kk = np.arange(k)
    r0 = s["first"] + rho * kk[None, :]
    j = np.arange(taps) - taps // 2 + 1
    for c0 in range(0, len(sel), 256):  # chunks of band bins keep the memory bounded
        cs = sel[c0:c0 + 256]
        fb = f[cs][:, None]
        u2 = np.minimum((lam * fb / (2 * v)) ** 2, 0.98)
        d = np.sqrt(1 - u2)
        shift = r0 * u2 / (d * (1 + d)) / rho
        col = spec[cs] * np.exp(-2j * np.pi * fc_r * kk)[None, :]
        pos = kk[None, :] + shift
        base = np.floor(pos).astype(int)
        mu = pos - base
        if phases:
            mu = np.floor(mu * phases + 0.5) / phases
        idx = base[:, :, None] + j[None, None, :]
        off = j[None, None, :] - mu[:, :, None]
        h = (np.sinc(off) * np.i0(beta * np.sqrt(np.clip(1 - (off / (taps / 2)) ** 2, 0, 1)))
             / np.i0(beta))
        h /= h.sum(-1, keepdims=True)
        valid = (idx >= 0) & (idx < k)
        rows = np.arange(len(cs))[:, None, None]
        vals = np.where(valid, col[rows, np.clip(idx, 0, k - 1)], 0)
        rc = (vals * h).sum(-1) * np.exp(2j * np.pi * fc_r * pos)
        phase = -4 * np.pi * r0 / lam * u2 / (1 + d)
        out[cs] = rc * np.exp(1j * phase)
    return np.roll(np.fft.ifft(out, axis=0) * math.sqrt(m), -line_shift, axis=0)


# bp_focuser's steps in float64 numpy: the reference of qa_bp_focuser and nrsar-bench.
def numpy_bp(data, antenna, first, rho, lam, fc_r, upsample, y_lines, height, ground=None):
    """Time-domain back-projection of `data` (pulses x K range bins, bin k at first + k rho)
    from the antenna positions (pulses x 3) onto the pixels (y_lines[j], first + k rho):
    scatterer (sqrt(r0^2 - height^2), y, 0), or with ground = (x columns, z) the ground grid's
    points (x[k], y, z); profile demodulated by exp(-j 2 pi fc_r k),
    upsampled by FFT zero padding, linearly interpolated at (R - first) / rho, phase
    exp(+j 2 pi (2 R / lam + fc_r q)), summed over the pulses, / sqrt(pulses)."""
    data = np.asarray(data, np.complex128)
    m, k = data.shape
    kk = np.arange(k)
    spec = np.fft.fft(data * np.exp(-2j * np.pi * fc_r * kk)[None, :], axis=1)
    n_up = upsample * k
    pos, neg = (k + 1) // 2, k // 2
    z = np.zeros((m, n_up), complex)
    z[:, :pos] = spec[:, :pos]
    z[:, n_up - neg:] = spec[:, k - neg:]
    up = np.fft.ifft(z, axis=1) * upsample  # exact at the input bins
    r0 = first + rho * kk
    if ground is None:
        ok_r = r0 > height
        g = np.sqrt(np.where(ok_r, r0 * r0 - height * height, 0.0))
        zg = 0.0
    else:
        g, zg = np.asarray(ground[0], float), float(ground[1])
        ok_r = np.ones(len(g), bool)
    y = np.asarray(y_lines, float)[:, None]
    img = np.zeros((len(y_lines), len(g)), complex)
    for p in range(m):
        ax, ay, az = antenna[p]
        r = np.sqrt((g[None, :] - ax) ** 2 + (y - ay) ** 2 + (az - zg) ** 2)
        q = (r - first) / rho
        x = q * upsample
        i = np.floor(x).astype(int)
        mu = x - i
        ok = (i >= 0) & (i <= upsample * (k - 1) - 1) & ok_r[None, :]
        ic = np.where(ok, i, 0)
        v = up[p, ic] + mu * (up[p, ic + 1] - up[p, ic])
        cyc = np.mod(2.0 * r / lam, 1.0) + fc_r * q
        img += np.where(ok, v * np.exp(2j * np.pi * cyc), 0.0)
    return img / math.sqrt(m)
