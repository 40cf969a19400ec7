#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""GNU Radio Companion on the example flowgraphs (run under Xvfb: xvfb-run -a).

Starts GRC the way gnuradio-companion does (its GTK start checks, the GUI platform with the
block library, the application with the given .grc files open) and, once the window is drawn,
checks that
- GRC's messages name no error: no block id not found, no block definition that failed to load;
- the block tree's [NR SAR] category holds every nrsar block of the first GRC_BLOCKS_PATH folder;
- every block of every flowgraph resolved (no dummy block) and every flowgraph is valid (all
  parameters evaluate against the module, the blocks' asserts hold);
- on the canvas no block, and no block comment, overlaps another block or comment;
then saves a screenshot of the window (--png; the first flowgraph is shown) and exits 0 or 1.

usage: grc_companion.py GRC [GRC ...] [--png FILE] [--size WxH] [--zoom Z]
"""

import argparse
import glob
import os
import sys

TIMEOUT_S = 60


def start_checks():
    """gnuradio-companion's check_gtk(): the step that fails without GTK's introspection data
    ("Namespace Gtk not available")."""
    import gi
    gi.require_version("Gtk", "3.0")
    gi.require_version("PangoCairo", "1.0")
    gi.require_foreign("cairo", "Context")
    from gi.repository import Gtk
    if not Gtk.init_check()[0]:
        raise RuntimeError("Gtk.init_check() failed: no display (run under xvfb-run)")


def overlaps(a, b):
    """Rectangles (x0, y0, x1, y1) that share area (touching edges do not count)."""
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def canvas_overlaps(flow_graph):
    """'a / b' for every pair of blocks or block comments drawn over each other."""
    rects = []
    for block in flow_graph.blocks:
        rects.append((f"block {block.name}", block.get_extents()))
        comment = block.get_extents_comment()
        if comment[2] > comment[0] and comment[3] > comment[1]:
            rects.append((f"comment of {block.name}", comment))
    found = []
    for i, (name_a, a) in enumerate(rects):
        for name_b, b in rects[i + 1:]:
            if overlaps(a, b):
                found.append(f"{name_a} {tuple(round(v) for v in a)} / "
                             f"{name_b} {tuple(round(v) for v in b)}")
    return found


def tree_blocks(btwin, category):
    """Block keys anywhere under a top-level category of the block tree (GRC shows the
    module category '[NR SAR]' as 'NR SAR')."""
    store = btwin.treestore
    keys = []

    def collect(it):
        while it is not None:
            if store.get_value(it, 1):
                keys.append(store.get_value(it, 1))
            collect(store.iter_children(it))
            it = store.iter_next(it)

    it = store.get_iter_first()
    while it is not None:
        if store.get_value(it, 0) == category:
            collect(store.iter_children(it))
        it = store.iter_next(it)
    return keys


def nrsar_block_ids():
    """The block ids of this tree's grc/ folder (the first GRC_BLOCKS_PATH entry)."""
    first = os.environ.get("GRC_BLOCKS_PATH", "").split(os.pathsep)[0]
    if not first:
        raise RuntimeError("GRC_BLOCKS_PATH must name the tree's grc/ folder")
    return sorted(os.path.basename(p)[:-len(".block.yml")]
                  for p in glob.glob(os.path.join(first, "nrsar_*.block.yml")))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("grc", nargs="+")
    parser.add_argument("--png", default=None, help="screenshot of the window")
    parser.add_argument("--size", default="1600x1000", help="window size WxH")
    parser.add_argument("--zoom", type=float, default=1.0, help="canvas zoom of the screenshot")
    opts = parser.parse_args(argv)
    paths = list(dict.fromkeys(os.path.abspath(p) for p in opts.grc))  # once each, in order

    start_checks()
    from gi.repository import Gdk, GLib
    from gnuradio import gr
    from gnuradio.grc.core import Messages
    from gnuradio.grc.gui.Platform import Platform  # before Application, as grc/main.py
    from gnuradio.grc.gui.Application import Application

    messages = []
    Messages.register_messenger(messages.append)
    platform = Platform(version=gr.version(),
                        version_parts=(gr.major_version(), gr.api_version(), gr.minor_version()),
                        prefs=gr.prefs(), install_prefix=gr.prefix())
    platform.build_library()
    app = Application(paths, platform)
    failures = []
    state = {"ticks": 0}

    def check():
        main_window = app.main_window
        pages = {p.file_path: p for p in main_window.get_pages()}
        for path in paths:
            name = os.path.basename(path)
            page = pages.get(path)
            if page is None:
                failures.append(f"{name}: GRC did not open it")
                continue
            fg = page.flow_graph
            fg.update()  # the pages not shown have no shapes until drawn
            dummies = [b.name for b in fg.blocks if b.is_dummy_block]
            if dummies:
                failures.append(f"{name}: blocks GRC does not know: {dummies}")
            if not fg.is_valid():
                failures.append(f"{name}: not valid: " + "; ".join(
                    str(e) for e in fg.iter_error_messages()))
            for o in canvas_overlaps(fg):
                failures.append(f"{name}: drawn over each other: {o}")
            print(f"{name}: {len(fg.blocks)} blocks, "
                  f"{sum(b.key.startswith('nrsar_') for b in fg.blocks)} of them nrsar")
        expected = nrsar_block_ids()
        in_tree = sorted(k for k in tree_blocks(main_window.btwin, "NR SAR")
                         if k.startswith("nrsar_"))
        print(f"[NR SAR] in the block tree: {len(in_tree)} blocks")
        if in_tree != expected:
            failures.append(f"[NR SAR] block tree holds {in_tree}, grc/ defines {expected}")
        text = "".join(messages)
        for bad in ("not found", "Error", "error", "Traceback", "failed"):
            if bad in text:
                failures.append(f"GRC's messages contain '{bad}':\n{text}")
                break

    def screenshot():
        # read back from the X server (the root window, Xvfb has no compositor)
        window = app.main_window.get_window()
        x, y = window.get_origin()[1:]
        w, h = window.get_width(), window.get_height()
        pixbuf = Gdk.pixbuf_get_from_window(Gdk.get_default_root_window(), x, y, w, h)
        if pixbuf is None:
            failures.append("no screenshot: the window could not be read back")
            return
        pixbuf.savev(opts.png, "png", [], [])
        print(f"screenshot {w}x{h}: {opts.png}")

    def tick():
        try:
            return step()
        except Exception:  # a failing check ends the run, it must not leave GRC running
            import traceback
            failures.append(traceback.format_exc())
            app.quit()
            return False

    def step():
        state["ticks"] += 1
        main_window = getattr(app, "main_window", None)
        if main_window is not None and "sized" not in state:
            state["sized"] = True
            main_window.move(0, 0)
            main_window.resize(*(int(v) for v in opts.size.split("x")))
        page = main_window.current_page if main_window else None
        # loaded: the current page's blocks have their label sizes, and the window is shown
        ready = (page is not None and main_window.get_mapped()
                 and all(b.width > 0 for b in page.flow_graph.blocks))
        if not ready and state["ticks"] * 0.2 < TIMEOUT_S:
            return True
        if not ready:
            failures.append(f"GRC did not show the flowgraph within {TIMEOUT_S} s")
        elif "checked" not in state:
            state["checked"] = state["ticks"]
            main_window.btwin.expand_module_in_tree("NR SAR")  # the blocks in the picture
            page.drawing_area._set_zoom_factor(opts.zoom)
            page.drawing_area.queue_draw()
            check()
            return True
        elif state["ticks"] < state["checked"] + 10:
            return True  # two seconds for the resized, zoomed window to be drawn
        if opts.png and not failures:
            screenshot()
        # leave without GRC's quit dialogs and without saving its preferences
        main_window.hide()
        app.quit()
        return False

    GLib.timeout_add(200, tick)
    app.run([])
    if failures:
        print("FAIL\n" + "\n".join(failures))
        return 1
    print("OK: GRC started, the [NR SAR] blocks loaded, the flowgraphs are valid and "
          "nothing is drawn over anything else")
    return 0


if __name__ == "__main__":
    sys.exit(main())
