#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The Python flowgraph of docs/user_guide.md section 4 runs and finds its target."""

import contextlib
import io
import math
import os
import re

from gnuradio import gr_unittest

GUIDE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "docs",
                     "user_guide.md")
if not os.path.exists(GUIDE):  # run from build/test_modules
    GUIDE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..", "..",
                         "docs", "user_guide.md")


class qa_user_guide(gr_unittest.TestCase):

    def test_python_flowgraph_of_the_guide_runs(self):
        with open(GUIDE) as f:
            blocks = re.findall(r"```python\n(.*?)```", f.read(), re.S)
        self.assertEqual(len(blocks), 1, "the guide has one ```python block")
        out = io.StringIO()
        scope = {"__name__": "user_guide"}
        with contextlib.redirect_stdout(out):
            exec(compile(blocks[0], GUIDE, "exec"), scope)
        # its own printout: the peak lands within one range bin of sqrt(300^2 + H^2)
        self.assertIn("peak at slant range", out.getvalue())
        self.assertLess(abs(scope["r"] - math.hypot(300.0, 1000.0)), scope["rif"].range_bin_m())


if __name__ == "__main__":
    gr_unittest.run(qa_user_guide)
