#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Canvas layout of the example flowgraphs: no block or block comment drawn over another.

GRC sizes a block by its shown parameters (each "label: value" line truncated to about 27
characters) and draws its comment under it, line by line, unwrapped. A flowgraph's coordinates
give each block a row (its y) and a place in the row (its x); layout() keeps that arrangement
and moves blocks right and rows down until no block or comment can overlap another, by sizes
estimated from above. gen_isac_grcs.py lays out the graphs it writes with it; run as a program
it lays out hand-written .grc files in place (only their coordinate lines change).
examples/grc_companion.py checks the extents GRC draws (ctest gui_grc_companion).

usage: grc_layout.py GRC [GRC ...]
"""

import re
import sys
import textwrap

import yaml

COMMENT_CHARS = 44   # comment lines wrapped at this many characters
CHAR_W = 6.0         # px per comment character (Sans 8: 5.7 measured in GRC)
LINE_H = 14          # px per comment line (13 measured)
BLOCK_W = 340        # the widest blocks with their ports (cheby_presum, nmse_probe: 330 px)
SMALL_W = 240        # variables, parameters, probes, labels, imports
SMALL = ("variable", "parameter", "import", "snippet", "variable_function_probe",
         "variable_qtgui_label", "variable_qtgui_range")
PORT_W = 60          # input ports and their labels left of a block's coordinate
GAP = 24             # px between footprints
ROW_SNAP = 16        # blocks less than this much lower than a row's first block join the row


def wrap(comment):
    """A comment as lines GRC draws no wider than COMMENT_CHARS characters."""
    return textwrap.fill(comment, COMMENT_CHARS)


def footprint(block):
    """(width, height) a block and its comment may take, estimated from above."""
    if "id" not in block:  # the options block: title, id and generate options shown
        return 200, 150
    params = block["parameters"]
    lines = str(params.get("comment") or "").splitlines()
    width = max(SMALL_W if block["id"] in SMALL else BLOCK_W,
                CHAR_W * max((len(t) for t in lines), default=0))
    # title and padding, then at most one line per parameter given (hidden ones included)
    height = 40 + 12 * (len(params) - 1) + (LINE_H * len(lines) + 8 if lines else 0)
    return width, height


def layout(blocks):
    """Rows (blocks of one given y) stacked downwards, each below everything above it; in a
    row, blocks left to right (given x), each right of the previous one."""
    rows = {}
    for b in sorted(blocks, key=lambda b: b["states"]["coordinate"][1]):
        y = b["states"]["coordinate"][1]
        row = max((r for r in rows if y - r < ROW_SNAP), default=None)
        rows.setdefault(y if row is None else row, []).append(b)
    bottom = None
    for y in sorted(rows):
        top = y if bottom is None else max(y, bottom + GAP)
        right = None
        for b in sorted(rows[y], key=lambda b: b["states"]["coordinate"][0]):
            w, h = footprint(b)
            x = b["states"]["coordinate"][0]
            if right is not None:
                x = max(x, right + GAP + PORT_W)
            b["states"]["coordinate"] = [int(x), int(top)]
            right = x + w
            bottom = top + h if bottom is None else max(bottom, top + h)


# flow style [x, y] or a block-style list of two lines
COORDINATE = re.compile(r"^( *)coordinate:(?: \[[^\]]*\]|\n *- -?[\d.]+\n *- -?[\d.]+)$",
                        re.MULTILINE)


def relayout_file(path):
    """Lays out a .grc file in place: the options block and the blocks in file order, one
    coordinate line each; nothing else in the file changes."""
    with open(path) as f:
        text = f.read()
    graph = yaml.safe_load(text)
    blocks = [graph["options"]] + graph["blocks"]
    if len(COORDINATE.findall(text)) != len(blocks):
        raise SystemExit(f"{path}: not one coordinate line per block")
    layout(blocks)
    coords = iter(b["states"]["coordinate"] for b in blocks)
    text = COORDINATE.sub(lambda m: "{}coordinate: [{}, {}]".format(m.group(1), *next(coords)),
                          text)
    with open(path, "w") as f:
        f.write(text)


if __name__ == "__main__":
    for p in sys.argv[1:]:
        relayout_file(p)
