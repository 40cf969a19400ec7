#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""What the PUSCH scrambler does to the radar reference when the payload has no entropy.

Under the standard scrambler (38.211 6.3.1.1: c_init = n_RNTI 2^15 + n_ID, the same every slot)
an all-zero payload or padding-only TBs give the same data REs in every slot: the grid the radar
correlates with is slot-periodic. The matched filter's point-target response per symbol m is the
range profile p_m(r) = (1/N) sum_k |X_mk|^2 exp(j 2 pi k r / N); its sidelobes (r != 0) repeat
every slot, so across the aperture they focus into Doppler lines at multiples of the slot rate
1 / (14 Tsym) instead of spreading as a floor. This script builds the real transmit grid
(pusch_encoder -> nr_isac_tx, with the DMRS), forms p_m(r) for a point target at zero delay and
Doppler, takes the FFT over the M symbols of the aperture and reports the strongest sidelobe of
the range-Doppler map off the target (its level relative to the peak, and its Doppler), for

  standard scrambler, filler TBs (zero entropy)   |   per-slot scrambler, filler TBs
  standard scrambler, random (ciphered) payload   |   coding none, standard, filler

The DMRS symbols themselves repeat every frame (20 slots at 30 kHz) in every case.

Run: /usr/bin/python3 -m gnuradio.nrsar.figures.scrambler_ghosts [--preset sdr20] [--slots 160]
"""

import dataclasses
import sys

import numpy as np

from gnuradio import nrsar
from gnuradio.nrsar import backhaul, cli
from gnuradio.nrsar.options import Options, option


def grid_of(preset, slots, coding, scrambling, payload):
    num = nrsar.make_numerology(preset)
    cfg = nrsar.make_pusch_config(num, "qam256", "pusch2", coding, scrambling=scrambling)
    per_tb = nrsar.pusch_encoder(cfg).payload_bits_per_slot() // 8
    pdus = []
    if payload == "random":
        rng = np.random.default_rng(1)
        pdus = [rng.integers(0, 256, per_tb, dtype=np.uint8).tobytes() for _ in range(slots)]
    grid, _ = backhaul.transmit_grid(cfg, pdus, slots)
    return num, grid


def ghost_level(num, grid):
    """(strongest sidelobe of the MF range-Doppler map in dB re the peak, its Doppler in Hz,
    the slot rate in Hz, the mean sidelobe level in dB re the peak). Range bins 0 and N/2 are
    left out: there the DMRS comb (odd subcarriers empty) puts its own lines in every case."""
    m, n = grid.shape
    profiles = np.fft.ifft(np.abs(grid) ** 2, axis=1)  # p_m(r), r = 0 .. N-1
    rd = np.abs(np.fft.fft(profiles, axis=0)) ** 2      # Doppler bin x range bin
    peak = rd[0, 0]
    rd = np.delete(rd, [0, n // 2], axis=1)
    i, r = np.unravel_index(np.argmax(rd), rd.shape)
    f = np.fft.fftfreq(m, num.symbol_s())[i]
    return (10 * np.log10(rd[i, r] / peak), f, 1.0 / (num.symbols_per_slot * num.symbol_s()),
            10 * np.log10(rd.mean() / peak))


@dataclasses.dataclass
class ScramblerGhostsOptions(Options):
    preset: str = option("sdr20", "OFDM numerology preset",
                         choices=list(nrsar.numerology.preset_names()))
    slots: int = option(160, "slots of the slow-time record (the ghosts' spectrum needs a "
                        "few slot periods)", at_least=4, at_most=100000)


def main(argv=None):
    args = cli.parse("scrambler_ghosts", ScramblerGhostsOptions, __doc__, argv)
    if args is None:
        return cli.EXIT_USAGE
    cases = [("nr-ldpc", "standard", "filler"), ("nr-ldpc", "per-slot", "filler"),
             ("nr-ldpc", "standard", "random"), ("none", "standard", "filler")]
    print("| coding | scrambling | payload | strongest sidelobe | at Doppler | mean sidelobe |")
    print("|---|---|---|---|---|---|")
    for coding, scrambling, payload in cases:
        num, grid = grid_of(args.preset, args.slots, coding, scrambling, payload)
        level, f, slot_rate, mean = ghost_level(num, grid)
        print(f"| {coding} | {scrambling} | {payload} | {level:.1f} dB | {f:.1f} Hz "
              f"({f / slot_rate:+.2f} x the slot rate) | {mean:.1f} dB |")


if __name__ == "__main__":
    sys.exit(main())
