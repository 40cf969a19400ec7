#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The rooms of the Python package keep their rules (docs/architecture.md, "Python rooms"):
no import cycles between modules, the library imports none of the programs' sub-packages or
the QA, no QA module imports another QA module, and no library module reads an argparse
namespace (only cli, options and progress touch command lines). Read from the
source with the ast module; nothing is imported."""

import ast
import os

from gnuradio import gr_unittest

PACKAGE = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def module_name(path):
    rel = os.path.relpath(path, PACKAGE)[:-3].replace(os.sep, ".")
    return rel[:-len(".__init__")] if rel.endswith(".__init__") else rel


def modules():
    found = {}
    for folder, dirs, files in os.walk(PACKAGE):
        dirs[:] = [d for d in dirs if d not in ("bindings", "__pycache__")]
        for f in files:
            if f.endswith(".py"):
                path = os.path.join(folder, f)
                found[module_name(path)] = path
    return found


def imports(name, path, known):
    """Modules of the package that `name` imports at module level (function-level imports
    are deferred on purpose and cannot form a cycle at import time)."""
    with open(path) as f:
        tree = ast.parse(f.read(), path)
    package = name if os.path.basename(path) == "__init__.py" else name.rpartition(".")[0]
    out = set()
    for node in tree.body:
        targets = []
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".") if package else []
                base = base[:len(base) - node.level + 1] if node.level > 1 else base
                mod = ".".join(base + ([node.module] if node.module else []))
            elif node.module and node.module.startswith("gnuradio.nrsar"):
                mod = node.module[len("gnuradio.nrsar"):].lstrip(".")
            else:
                continue
            targets = [f"{mod}.{a.name}".lstrip(".") for a in node.names] + [mod]
        elif isinstance(node, ast.Import):
            targets = [a.name[len("gnuradio.nrsar."):] for a in node.names
                       if a.name.startswith("gnuradio.nrsar.")]
        for t in targets:
            if t in known and t != name:
                out.add(t)
    return out


def room(name):
    return name.split(".")[0] if name.split(".")[0] in ("figures", "bench", "qa") else "library"


class qa_rooms(gr_unittest.TestCase):

    def setUp(self):
        self.mods = modules()
        self.graph = {n: imports(n, p, self.mods) for n, p in self.mods.items()}

    def test_001_no_import_cycles(self):
        state = {}

        def visit(n, stack):
            state[n] = "open"
            for m in sorted(self.graph[n]):
                if state.get(m) == "open":
                    self.fail("import cycle: " + " -> ".join(stack[stack.index(m):] + [m]))
                if m not in state:
                    visit(m, stack + [m])
            state[n] = "done"

        for n in sorted(self.graph):
            if n not in state:
                visit(n, [n])

    def test_002_the_library_imports_no_program_and_no_qa(self):
        for n, deps in self.graph.items():
            if room(n) == "library":
                self.assertEqual({d for d in deps if room(d) != "library"}, set(), n)
            if room(n) in ("figures", "bench"):
                self.assertEqual({d for d in deps if room(d) == "qa"}, set(), n)

    def test_003_no_qa_imports_qa(self):
        for n, deps in self.graph.items():
            if room(n) == "qa":
                self.assertEqual({d for d in deps if room(d) == "qa"}, set(), n)

    def test_004_no_namespace_in_the_library(self):
        # an argparse namespace is read only where command lines are parsed: cli (the
        # programs' plumbing), options (from_args) and progress (its own --progress/--quiet)
        for n, path in self.mods.items():
            if room(n) != "library" or n in ("cli", "options", "progress"):
                continue
            with open(path) as f:
                text = f.read()
            for pattern in ("getattr(args", "args.", "parse_args("):
                self.assertNotIn(pattern, text, f"{n}: {pattern}")

    def test_005_the_rules_see_the_package(self):
        # the reader found the rooms and their edges (a reader that saw nothing passes
        # the rules above vacuously)
        self.assertIn("chain", self.mods)
        self.assertIn("qa.qa_rooms", self.mods)
        self.assertIn("scenario", self.graph["chain"])
        self.assertIn("chain", self.graph["isac_chain"])
        self.assertIn("options", self.graph["figures.double_reference"])


if __name__ == "__main__":
    gr_unittest.run(qa_rooms)
