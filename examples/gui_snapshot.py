#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""GUI test of a grcc-generated Qt flowgraph (run under Xvfb: xvfb-run -a).

Imports the generated script, runs its top block with the Qt event loop for a few seconds,
grabs the raster widget(s) with QWidget.grab() before and after the data arrived, saves the
window as a PNG, and fails unless every raster shows an image: the pixels changed over a large
part of the widget and vary (standard deviation of the grey levels) where they changed.

usage: gui_snapshot.py GENERATED_DIR MODULE CLASS [--seconds S] [--png FILE]
                       [--widget ATTR ...] [ARG=VALUE ...]
"""

import argparse
import importlib
import os
import sys

import numpy as np


def to_array(image):
    """QImage -> (h, w) array of grey levels."""
    from PyQt5 import QtGui
    image = image.convertToFormat(QtGui.QImage.Format_RGB32)
    w, h = image.width(), image.height()
    ptr = image.constBits()
    ptr.setsize(image.byteCount())
    rgb = np.frombuffer(ptr, np.uint8).reshape(h, image.bytesPerLine() // 4, 4)[:, :w, :3]
    return rgb.astype(np.float64).mean(axis=2)


def number_or_text(v):
    """A constructor argument: int, else float, else the text itself (a path)."""
    for kind in (int, float):
        try:
            return kind(v)
        except ValueError:
            pass
    return v


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory")
    parser.add_argument("module")
    parser.add_argument("cls")
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--png", default=None)
    parser.add_argument("--size", default=None, help="window size WxH for the snapshot")
    parser.add_argument("--widget", action="append", default=None,
                        help="attribute of the top block holding a widget to check "
                             "(repeatable; default _raster_win)")
    parser.add_argument("--min-changed", type=float, default=0.01,
                        help="fraction of a widget's pixels that must change (default 0.01)")
    parser.add_argument("args", nargs="*", help="constructor arguments NAME=VALUE (numbers or text)")
    opts = parser.parse_intermixed_args(argv)

    sys.path.insert(0, opts.directory)
    from PyQt5 import Qt, QtCore
    module = importlib.import_module(opts.module)
    kwargs = {k: number_or_text(v) for k, v in (a.split("=", 1) for a in opts.args)}

    app = Qt.QApplication(sys.argv[:1])
    tb = getattr(module, opts.cls)(**kwargs)
    if opts.size:
        tb.resize(*(int(v) for v in opts.size.split("x")))
    tb.show()
    names = opts.widget or ["_raster_win"]
    widgets = [getattr(tb, name) for name in names]
    app.processEvents()
    befores = [to_array(w.grab().toImage()) for w in widgets]
    tb.start()

    result = {}

    def finish():
        result["after"] = [to_array(w.grab().toImage()) for w in widgets]
        if opts.png:
            tb.grab().save(opts.png)
        tb.stop()
        tb.wait()
        app.quit()

    QtCore.QTimer.singleShot(int(opts.seconds * 1000), finish)
    # Safety net: never hang the test if the flowgraph or Qt misbehaves.
    QtCore.QTimer.singleShot(int(opts.seconds * 1000) + 30000, lambda: os._exit(3))
    app.exec_()

    failed = False
    for name, before, after in zip(names, befores, result["after"]):
        failed |= not check(name, before, after, opts.min_changed)
    return 1 if failed else 0


def check(name, before, after, min_changed):
    """True when the widget filled with a non-uniform picture."""
    if before.shape != after.shape:
        print(f"FAIL {name}: widget size changed {before.shape} -> {after.shape}")
        return False
    changed = np.abs(after - before) > 8
    frac = changed.mean()
    std = after[changed].std() if changed.any() else 0.0
    print(f"{name}: raster {after.shape[1]}x{after.shape[0]} px: {100 * frac:.1f} % of the "
          f"pixels changed, grey-level std there {std:.1f}")
    # The throttled source fills a few rows per second: 1 % of the widget is about 4 rows
    # of a 400-row raster, well above cursor or label redraws (which do not change).
    if frac < min_changed:
        print(f"FAIL {name}: the widget did not fill (less than {100 * min_changed:g} % of its "
              "pixels changed)")
        return False
    if std < 5.0:
        print(f"FAIL {name}: the raster is flat (grey-level std < 5)")
        return False
    return True


if __name__ == "__main__":
    sys.exit(main())
