#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Compares two focused images (complex64 files of BINS range bins per line, or .npy arrays
as nrsar-process writes them): fails unless
they have the same size, the same peak pixel and max |a - b| / max |a| <= TOL.

Two runs of one graph differed by up to ~4e-4 of the peak while the graphs' payload reached
pusch_encoder as asynchronous PDUs (the grid depended on timing; posting them after the start
still gives 5e-4 to 7e-4); with the file queued before the start they are equal bit for bit
under any chunking (docs/sdr.md). TOL 0 asks for bit-exact equality; a one-sample
misalignment of the radar gives ~0.7.

usage: compare_images.py A B BINS [TOL]   (TOL default 0)"""

import sys

import numpy as np


def main(argv):
    if len(argv) not in (3, 4):
        print(__doc__)
        return 2
    bins = int(argv[2])
    tol = float(argv[3]) if len(argv) == 4 else 0.0
    a, b = (np.load(f).ravel() if f.endswith(".npy") else np.fromfile(f, np.complex64)
            for f in argv[:2])
    if a.size != b.size or a.size == 0 or a.size % bins:
        print(f"FAIL: sizes {a.size} and {b.size} (bins {bins})")
        return 1
    a, b = a.reshape(-1, bins), b.reshape(-1, bins)
    pa = np.unravel_index(np.argmax(np.abs(a)), a.shape)
    pb = np.unravel_index(np.argmax(np.abs(b)), b.shape)
    rel = float(np.max(np.abs(a - b)) / np.max(np.abs(a)))
    print(f"{a.shape[0]} lines x {bins} bins, peaks at {tuple(map(int, pa))} and "
          f"{tuple(map(int, pb))}, max |a - b| / max |a| = {rel:.3g} (tolerance {tol:g})")
    if pa != pb or not rel <= tol:
        print("FAIL")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
