#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Writes the seed corpus of fuzz_transport_block (tests/fuzz/corpus/fuzz_transport_block/).

The inputs are built here from the standards, not with the module: CRC24A by polynomial
division (TS 38.212 5.1), the Gold sequence bit by bit (TS 38.211 5.2.1, SPEC 2) and the
codec's documented c_init (include/gnuradio/nrsar/kernel/transport_block.h). The target's
codecs: uncoded G = 1000 (TB 125 bytes, payload 117), LDPC n = 300, k = 152, G = 700 (C = 2
codewords, TB 38 bytes, payload 30), scrambling_id 7. Byte 0 of an input is the mode: bit 0 LDPC,
bit 1 raw float LLRs (else signed bytes), bit 2 the whole receiver; mode >> 2 is the slot.
Rerun after changing the target's input format:  tests/fuzz/make_transport_block_seeds.py
"""

import math
import os
import struct

SCRAMBLING_ID = 7
UNCODED_G, UNCODED_TB = 1000, 125
LDPC_G, LDPC_USED, LDPC_TB = 700, 600, 38
PAYLOAD_START, PAYLOAD_END, FILLER = 2, 4, 1


def crc24a(data):
    """TS 38.212 5.1 CRC24A, g(D) = 0x1864CFB, MSB first, zero initial value."""
    reg = 0
    for byte in data:
        for k in range(7, -1, -1):
            top = (reg >> 23) & 1
            reg = (reg << 1) & 0xFFFFFF
            if top ^ ((byte >> k) & 1):
                reg ^= 0x864CFB
    return reg


def gold(c_init, n):
    """TS 38.211 5.2.1: c(i) = (x1(i + 1600) + x2(i + 1600)) mod 2."""
    nc = 1600
    x1 = [1] + [0] * 30
    x2 = [(c_init >> i) & 1 for i in range(31)]
    for i in range(n + nc):
        x1.append((x1[i + 3] + x1[i]) % 2)
        x2.append((x2[i + 3] + x2[i + 2] + x2[i + 1] + x2[i]) % 2)
    return [(x1[i + nc] + x2[i + nc]) % 2 for i in range(n)]


def c_init(slot):
    """The codec's documented variant of 38.211 6.3.1.1."""
    return (((SCRAMBLING_ID << 15) + slot % 32768) * 0x9E3779B1 + 0x2545F491) % 2**31


def tb(payload_len, seq, flags, payload, size=UNCODED_TB):
    """header (payload_len, seq, flags; big endian) | payload, zero padded | CRC24A."""
    body = struct.pack(">HHB", payload_len, seq, flags) + payload
    body += bytes(size - 3 - len(body))
    return body + crc24a(body).to_bytes(3, "big")


def bits(data):
    return [(b >> (7 - k)) & 1 for b in data for k in range(8)]


def int8_llrs(code_bits, g, slot):
    """Signed-byte LLRs (+100 = bit 0) of the scrambled bits, zeros up to G."""
    code_bits = code_bits + [0] * (g - len(code_bits))
    c = gold(c_init(slot), g)
    return bytes((0x9C if b ^ ci else 0x64) for b, ci in zip(code_bits, c))


def floats(values):
    return b"".join(struct.pack("<f", v) for v in values)


def seeds():
    hello = tb(5, 2, PAYLOAD_START | PAYLOAD_END, b"hello")
    bad_crc = bytearray(hello)
    bad_crc[6] ^= 0x10
    nonfinite = [math.nan, math.inf, -math.inf, 1e-45, 3e38, -0.0, -3e38, 1.0] * 16
    return {
        # bytes as a TB (part 1 of the target)
        "tb_filler": b"\x00" + tb(0, 1, FILLER, b""),
        "tb_pdu_hello": b"\x00" + hello,
        "tb_bad_crc": b"\x00" + bytes(bad_crc),
        "tb_len_over_capacity": b"\x00" + tb(118, 3, 0, b""),   # CRC right, 118 > 117
        "tb_unknown_flag": b"\x00" + tb(0, 4, 0x80, b""),        # CRC right, flag 0x80
        "tb_filler_with_payload": b"\x00" + tb(1, 5, FILLER, b"x"),
        "tb_short": b"\x00\x00\x05",                              # zero-extended to 125 bytes
        "empty": b"",
        # bytes as LLRs (part 2): the hello TB, scrambled for slot 0 and slot 2 (mode 8)
        "llr_uncoded_slot0": b"\x00" + int8_llrs(bits(hello), UNCODED_G, 0),
        "llr_uncoded_slot2": b"\x08" + int8_llrs(bits(hello), UNCODED_G, 2),
        "llr_uncoded_wrong_slot": b"\x00" + int8_llrs(bits(hello), UNCODED_G, 1),
        # LDPC: the all-zero TB (payload_len 0, flags 0, CRC 0) is the all-zero codeword of
        # the linear code, so its scrambled LLRs are the Gold sequence's alone
        "llr_ldpc_zero_tb": b"\x01" + int8_llrs([0] * LDPC_USED, LDPC_G, 0),
        "llr_float_nonfinite": b"\x02" + floats(nonfinite),
        "llr_ldpc_float_nonfinite": b"\x03" + floats(nonfinite),
        # the receiver (part 3): a zero grid (no DMRS energy) and a non-finite one
        "rx_grid_zero": b"\x04",
        "rx_grid_nonfinite": b"\x04" + floats(nonfinite * 14),
    }


if __name__ == "__main__":
    folder = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus",
                          "fuzz_transport_block")
    os.makedirs(folder, exist_ok=True)
    for name, data in seeds().items():
        with open(os.path.join(folder, name), "wb") as f:
            f.write(data)
    print(f"{len(seeds())} seeds in {folder}")
