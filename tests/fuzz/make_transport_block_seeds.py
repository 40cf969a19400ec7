#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Writes the seed corpus of fuzz_transport_block (tests/fuzz/corpus/fuzz_transport_block/).

The inputs are built here from the standards, not with the module: the MAC PDU of TS 38.321
6.1.2 with the RLC UMD header of TS 38.322 6.2.2.3 (the framing of docs/nr_coding.md, "PDU
framing"), CRC24A by polynomial division (TS 38.212 5.1) and the Gold sequence bit by bit
(TS 38.211 5.2.1) with c_init = n_RNTI 2^15 + n_ID (38.211 6.3.1.1). The target's codecs use
pusch_config's defaults on the `tiny` numerology: N = 64, 256-QAM, DMRS pusch2, so G = 12 x 64
x 8 = 6144 bits per slot; uncoded A = 8 floor((G - 24) / 8) = 6120 bits (765 bytes), CRC24A,
zeros to G; NR LDPC qam256 MCS 27; n_RNTI 0x4601, n_ID 0, standard scrambling.
Byte 0 of an input is the mode: bit 0 NR LDPC (else uncoded), bit 1 raw float LLRs (else
signed bytes), bit 2 also the whole receiver, bit 3 combine with the previous decode
(LDPC), bits 2-3 the rv, bits 4-7 the slot.
Rerun after changing the target's input format:  tests/fuzz/make_transport_block_seeds.py
"""

import math
import os
import struct

G = 12 * 64 * 8
TB_BYTES = (G - 24) // 8
C_INIT = 0x4601 * 2**15 + 0
LCID, LCID_PADDING = 4, 63
COMPLETE, FIRST, LAST, MIDDLE = 0, 1, 2, 3


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


def mac_pdu(data=None, si=COMPLETE, sn=0, so=0, lcid=LCID, size=TB_BYTES):
    """MAC subheader R F=1 LCID | L(16), RLC SI SN [SO(16)], data, padding subheader (LCID 63),
    zeros to size; data None: the padding subheader alone (a filler TB)."""
    if data is None:
        return bytes([LCID_PADDING]) + bytes(size - 1)
    rlc = bytes([(si << 6) | (0 if si == COMPLETE else sn & 0x3F)])
    if si in (LAST, MIDDLE):
        rlc += struct.pack(">H", so)
    body = bytes([0x40 | lcid]) + struct.pack(">H", len(rlc) + len(data)) + rlc + data
    if len(body) < size:
        body += bytes([LCID_PADDING])
    return body + bytes(size - len(body))


def bits(data):
    return [(b >> (7 - k)) & 1 for b in data for k in range(8)]


def uncoded_llrs(tb, c_init=C_INIT):
    """Signed-byte LLRs (+100 = bit 0) of the uncoded slot: TB, CRC24A, zeros to G, scrambled."""
    f = bits(tb) + bits(crc24a(tb).to_bytes(3, "big"))
    f += [0] * (G - len(f))
    return bytes((0x9C if b ^ c else 0x64) for b, c in zip(f, gold(c_init, G)))


def floats(values):
    return b"".join(struct.pack("<f", v) for v in values)


def seeds():
    hello = mac_pdu(b"hello")
    bad = bytearray(hello)
    bad[10] ^= 0x10
    nonfinite = [math.nan, math.inf, -math.inf, 1e-45, 3e38, -0.0, -3e38, 1.0] * 16
    # the all-zero TB has a zero CRC and zero CB CRCs: the all-zero codeword of the linear
    # code, so its scrambled LLRs are the Gold sequence's alone (the parser refuses LCID 0)
    zero_codeword = bytes((0x9C if c else 0x64) for c in gold(C_INIT, G))
    return {
        # bytes as a TB (part 1 of the target): what the parser accepts ...
        "tb_filler": b"\x00" + mac_pdu(),
        "tb_pdu_hello": b"\x00" + hello,
        "tb_first_segment": b"\x00" + mac_pdu(b"abc", FIRST, sn=5),
        "tb_last_segment": b"\x00" + mac_pdu(b"xyz", LAST, sn=5, so=700),
        "tb_middle_segment_full": b"\x00" + mac_pdu(bytes(range(256)) * 2 + bytes(TB_BYTES - 518),
                                                    MIDDLE, sn=63, so=65000),
        # ... and what it refuses
        "tb_l_beyond_tb": b"\x00" + b"\x44\xff\xff\x00hello",
        "tb_unknown_lcid": b"\x00" + mac_pdu(b"hello", lcid=5),
        "tb_reserved_bit": b"\x00" + bytes([0x80 | 0x44]) + mac_pdu(b"hello")[1:],
        "tb_complete_with_sn": b"\x00" + b"\x44\x00\x06\x05hello\x3f",
        "tb_no_padding_after_data": b"\x00" + b"\x44\x00\x06\x00hello\x44",
        "tb_short": b"\x00\x44\x00",                              # zero-extended to 765 bytes
        "empty": b"",
        # bytes as LLRs (part 2): the hello TB uncoded, and with the wrong RNTI / a flipped bit
        "llr_uncoded_hello": b"\x00" + uncoded_llrs(hello),
        "llr_uncoded_filler_slot3": b"\x30" + uncoded_llrs(mac_pdu()),
        "llr_uncoded_other_rnti": b"\x00" + uncoded_llrs(hello, 0x4602 * 2**15),
        "llr_uncoded_bad_crc": b"\x00" + uncoded_llrs(bytes(bad))[:8 * 765] +
                               uncoded_llrs(hello)[8 * 765:],
        "llr_ldpc_zero_tb": b"\x01" + zero_codeword,
        "llr_ldpc_zero_tb_rv2_combined": b"\x09" + zero_codeword,
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
    for name in os.listdir(folder):  # the old format's seeds go
        os.remove(os.path.join(folder, name))
    for name, data in seeds().items():
        with open(os.path.join(folder, name), "wb") as f:
            f.write(data)
    print(f"{len(seeds())} seeds in {folder}")
