#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Seeded mutation fuzzing of the YAML scene-file loader (scenes.load_scene_file).

Thousands of mutated, spliced and truncated versions of the example scene files (and of the
map images they name), plus random bytes and a few hostile shapes (deep nesting, aliases,
huge numbers, binary): every input either loads or raises SceneFileError whose message is
'<file>:<line>: <field>: <what>' with a line >= 1. Any other exception (KeyError,
TypeError, UnicodeDecodeError, RecursionError, MemoryError, numpy errors ...) fails the test
with the seed and the input, so it can be replayed.
"""

import os
import random
import re
import shutil
import tempfile

import numpy as np

from gnuradio import gr_unittest
from gnuradio.nrsar import scenes

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..",
                        "examples", "scenes")
if not os.path.isdir(EXAMPLES):  # run from the source tree
    EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                            "examples", "scenes")

# Every key of the format, maps from each image type.
FULL = b"""# every key of the scene file format
numerology: {preset: small, num_subcarriers: 256, fft_size: 256, cp_samples: 64}
geometry:
  preset: paper
  track_start_m: -20
  aperture_s: 0.5
beam: {mode: azimuth_elevation, az_aperture_m: 0.1, el_aperture_m: 0.2, el_center_deg: 40,
       cutoff: 6}
targets:
  - {x: 300, y: 100, rcs: 1, phase_deg: 30}
  - x: 250
    y: 90
maps:
  - {file: tiny.pgm, dx: 1, dy: 1, origin: [280, 80], kind: amplitude, scale: 0.5,
     speckle: false, seed: 3}
  - file: tiny.npy
    dx: 0.5
    dy: 0.5
    speckle: yes
  - {file: tiny_p2.pgm, dx: 2, dy: 2, origin: [270, 60]}
"""
MINIMAL = b"targets:\n  - {x: 300, y: 0}\n"

TOKENS = [b"nan", b"-nan", b"inf", b"-inf", b"1e999", b"-1", b"0", b"-0", b"1e-320", b"",
          b"~", b"null", b"[]", b"{}", b"[1, 2, 3]", b"{x: 1}", b"true", b"no", b"0x10",
          b"0o17", b"1_000", b"'300'", b'"abc"', b"!!binary aGVsbG8=", b"!!python/none ''",
          b"&a 1", b"*a", b"*undefined", b"? x", b"- ", b": ", b"- - -", b"\t", b"\x00",
          b"\xff\xfe", b"\xc3\x28", b"\xe2\x82", b"99999999999999999999999", b"4294967296",
          b"-4294967297", b"1.5", b"2e9", b"%YAML 1.1\n---", b"---", b"...", b"|\n  x",
          b">-\n  y", b"#", b"file: /", b"file: ../../../../etc/passwd", b"file: .",
          b"file: tiny.npy", b"file: ship_and_sea.yaml", b"kind: amplitude", b"mode: azimuth",
          b"preset: nr273", b"preset: paper9", b"num_subcarriers: 0", b"fft_size: 1",
          b"symbols_per_slot: 0.5", b"unknown_key: 1", b"origin: [1]", b"origin: [1, 2, 3]"]


def tiny_images(folder):
    """The small map images FULL names (npy float32, P5 8-bit, P2 16-bit ASCII)."""
    rng = np.random.default_rng(3)
    np.save(os.path.join(folder, "tiny.npy"), rng.random((4, 5)).astype(np.float32))
    with open(os.path.join(folder, "tiny.pgm"), "wb") as f:
        f.write(b"P5\n# a comment\n5 4\n255\n" + bytes(range(20)))
    with open(os.path.join(folder, "tiny_p2.pgm"), "wb") as f:
        f.write(b"P2\n3 2\n65535\n0 1 2\n3 4 65535\n")


def mutate_bytes(rng, data, tokens):
    data = bytearray(data)
    for _ in range(rng.randint(1, 3)):
        op = rng.randrange(9)
        pos = rng.randint(0, len(data))
        if op == 0 and data:  # flip bits
            i = rng.randrange(len(data))
            data[i] ^= 1 << rng.randrange(8)
        elif op == 1:  # delete a span
            del data[pos:pos + rng.randint(1, 16)]
        elif op == 2:  # insert a token
            data[pos:pos] = rng.choice(tokens)
        elif op == 3:  # truncate
            del data[pos:]
        elif op == 4:  # replace the value after a ': ' or '- ' with a token
            marks = [m.end() for m in re.finditer(rb"(: |- |\[|, )", bytes(data))]
            if marks:
                start = rng.choice(marks)
                end = start
                while end < len(data) and data[end:end + 1] not in b",]}\n#":
                    end += 1
                data[start:end] = rng.choice(tokens)
        else:  # line operations: delete, duplicate, swap, re-indent, splice
            lines = bytes(data).split(b"\n")
            i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
            if op == 5:
                del lines[i]
            elif op == 6:
                lines.insert(i, lines[j])
            elif op == 7:
                lines[i], lines[j] = lines[j], lines[i]
            else:
                lines[i] = b" " * rng.choice((0, 1, 2, 4, 8)) + lines[i].lstrip()
            data = bytearray(b"\n".join(lines))
    return bytes(data)


HOSTILE = [
    b"", b"\n", b"# only a comment\n", b"---\n...\n", b"targets:\n", b"targets: []\n",
    b"[" * 5000 + b"]" * 5000, b"targets: " + b"[" * 5000, b"{a: " * 3000,
    b"targets:\n" + b"  - " * 2000 + b"{x: 1, y: 2}\n",
    b"a: &a [1, 2]\nb: &b [*a, *a, *a, *a]\nc: &c [*b, *b, *b, *b]\ntargets: [*c]\n",
    b"targets: &t\n  - {x: 300, y: 0}\nmaps: *t\n",
    b"targets:\n  - {x: 300, y: 0, x: 301}\n",
    b"targets:\n  - {x: 1e308, y: -1e308, rcs: 1e308}\n",
    b"targets:\n  - {x: 300, y: 0, phase_deg: 1e308}\n",
    b"\xef\xbb\xbftargets:\n  - {x: 300, y: 0}\n", b"\xff\xfe\x00t\x00a", b"\x00" * 64,
    b"targets:\n  - {? [1, 2]: 3, x: 1, y: 2}\n", b"targets:\n  - {[x]: 1}\n",
    b"maps:\n  - {file: tiny.npy, dx: 1, dy: 1, origin: {x: 1}}\n",
    b"maps:\n  - {file: [tiny.npy], dx: 1, dy: 1}\n",
    b"maps:\n  - {file: tiny.npy, dx: 1e-320, dy: 1e308}\n",
    b"maps:\n  - {file: tiny.npy, dx: 1, dy: 1, seed: 1e30}\n",
    b"maps:\n  - {file: tiny.npy, dx: 1, dy: 1, seed: -0}\n",
    b"numerology: {preset: paper, num_subcarriers: 1e30}\n" + MINIMAL,
    b"numerology: {preset: paper, num_subcarriers: -3}\n" + MINIMAL,
    b"numerology: {preset: paper, fft_size: 4294967296}\n" + MINIMAL,
    b"numerology: {preset: [paper]}\n" + MINIMAL,
    b"numerology: {preset: paper, validate: 1}\n" + MINIMAL,
    b"numerology: {preset: paper, __class__: 1}\n" + MINIMAL,
    b"geometry: {velocity_mps: 0}\n" + MINIMAL,
    b"geometry: [paper]\n" + MINIMAL, b"beam: {cutoff: -1}\n" + MINIMAL,
    b"beam: {mode: [azimuth]}\n" + MINIMAL, b"beam: azimuth\n" + MINIMAL,
    b"!!python/object/apply:os.system ['true']\n", b"targets: !!set {a, b}\n",
    b"targets:\n  - !!map {x: 1, y: 2}\n", b"targets:\n  - {x: !!float 1, y: !!int 2}\n",
]


class qa_scene_file_fuzz(gr_unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="qa_scene_file_fuzz_")
        shutil.copy(os.path.join(EXAMPLES, "ship_and_sea.npy"), self.dir)
        tiny_images(self.dir)
        self.images = {name: open(os.path.join(self.dir, name), "rb").read()
                       for name in ("tiny.npy", "tiny.pgm", "tiny_p2.pgm", "ship_and_sea.npy")}
        with open(os.path.join(EXAMPLES, "ship_and_sea.yaml"), "rb") as f:
            self.seeds = [f.read(), FULL, MINIMAL]
        self.path = os.path.join(self.dir, "scene.yaml")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def load(self, data, what):
        """Loads data as a scene file: success or a SceneFileError naming file, line, field."""
        with open(self.path, "wb") as f:
            f.write(data)
        try:
            scenes.load_scene_file(self.path)
        except scenes.SceneFileError as e:
            msg = str(e)
            m = re.match(re.escape(self.path) + r":(\d+): \S.*: \S", msg, re.S)
            self.assertTrue(m, f"{what}: message without file:line: field: {msg!r}\n"
                               f"input: {data[:400]!r}")
            self.assertGreaterEqual(int(m.group(1)), 1, f"{what}: line 0 in {msg!r}")
            self.assertTrue(msg.isprintable(), f"{what}: {msg!r}")
            return "error"
        except Exception as e:  # anything else is a bug of the loader
            self.fail(f"{what}: {type(e).__name__}: {e}\ninput: {data[:400]!r}")
        return "ok"

    def test_seed_files_load(self):
        for i, seed in enumerate(self.seeds):
            self.assertEqual(self.load(seed, f"seed {i}"), "ok")

    def test_hostile_inputs(self):
        for i, data in enumerate(HOSTILE):
            self.load(data, f"hostile {i}")

    def test_random_bytes(self):
        rng = random.Random(20261122)
        for i in range(400):
            data = bytes(rng.randrange(256) for _ in range(rng.randint(0, 200)))
            self.load(data, f"random bytes {i}")
            # YAML-ish alphabet: more likely to get past the syntax
            data = bytes(rng.choice(b"targets:maps- {}[],#x y 1.5e-\n\t'\"&*!?|>")
                         for _ in range(rng.randint(0, 200)))
            self.load(data, f"random yaml-ish {i}")

    def test_mutated_scene_files(self):
        rng = random.Random(8)
        outcomes = {"ok": 0, "error": 0}
        for i in range(3000):
            base = rng.choice(self.seeds)
            if rng.random() < 0.1:  # splice two seeds
                other = rng.choice(self.seeds)
                base = base[:rng.randint(0, len(base))] + other[rng.randint(0, len(other)):]
            data = mutate_bytes(rng, base, TOKENS)
            outcomes[self.load(data, f"mutation {i} (seed 8)")] += 1
        # the mutations keep a fair share of valid files (they exercise the deep checks)
        self.assertGreater(outcomes["ok"], 100, outcomes)
        self.assertGreater(outcomes["error"], 1000, outcomes)

    def test_mutated_map_images(self):
        rng = random.Random(11)
        for i in range(600):
            name = rng.choice(sorted(self.images))
            data = mutate_bytes(rng, self.images[name],
                                [b"\x00", b"\xff" * 8, b"P5", b"P2", b"99999 99999", b"-1",
                                 b"\x93NUMPY", b"{'descr': '<c16', 'fortran_order': True, "
                                 b"'shape': (3, 0), }", b"(999999999, 999999999)", b"#"])
            with open(os.path.join(self.dir, name), "wb") as f:
                f.write(data)
            self.load(FULL if name != "ship_and_sea.npy" else self.seeds[0],
                      f"image mutation {i} of {name} (seed 11)")
            with open(os.path.join(self.dir, name), "wb") as f:
                f.write(self.images[name])


if __name__ == "__main__":
    gr_unittest.run(qa_scene_file_fuzz)
