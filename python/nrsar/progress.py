#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Progress of the long runs of nrsar-sim, nrsar-figures and nrsar-bench, on stderr only.

One status line: the steps of the outer loops (figure k of n, sweep point k of n) and the
percentage of the running flowgraph (an item counter of one of its blocks, polled from a
background thread while tb.run() blocks). Off unless configured: the apps call
configure(from_args(args)), on when stderr is a terminal or --progress is given, off with
--quiet. On a terminal the line is redrawn in place; otherwise (--progress into a file or a
pipe) one line is written per step and every 10 % of a flowgraph. stdout is never touched,
so --json output stays clean.

    progress.add_arguments(parser)               # --progress, --quiet
    progress.configure(progress.from_args(args))
    progress.step(k, n, "fig5")                  # outer loop, level 0 (level 1: inner loop)
    with progress.polling("sim", total, lambda: blk.nitems_written(0)):
        tb.run()
    progress.finish()                            # ends the status line
"""

import contextlib
import sys
import threading

_lock = threading.RLock()
_state = {"enabled": False, "stream": None, "steps": {}, "task": "", "last_len": 0,
          "last_decile": -1}


def add_arguments(parser):
    """--progress / --quiet (progress on stderr; default: only when stderr is a terminal)."""
    parser.add_argument("--progress", action="store_true",
                        help="show progress on stderr even when it is not a terminal")
    parser.add_argument("--quiet", action="store_true",
                        help="no progress output (stderr keeps errors and warnings)")
    return parser


def from_args(args, stream=None):
    """Whether progress is shown: --quiet wins, then --progress, else stderr is a terminal."""
    if getattr(args, "quiet", False):
        return False
    if getattr(args, "progress", False):
        return True
    stream = stream or sys.stderr
    return bool(getattr(stream, "isatty", lambda: False)())


def configure(enabled, stream=None):
    with _lock:
        _state.update(enabled=bool(enabled), stream=stream, steps={}, task="", last_len=0,
                      last_decile=-1)


def enabled():
    return _state["enabled"]


def _stream():
    return _state["stream"] or sys.stderr


def _is_tty():
    return bool(getattr(_stream(), "isatty", lambda: False)())


def _draw(force_line=False):
    """Writes the status line: in place on a terminal, as a new line otherwise."""
    parts = [_state["steps"][lvl] for lvl in sorted(_state["steps"])]
    if _state["task"]:
        parts.append(_state["task"])
    text = " | ".join(parts)
    out = _stream()
    try:
        if _is_tty():
            pad = max(0, _state["last_len"] - len(text))
            out.write("\r" + text + " " * pad)
            _state["last_len"] = len(text)
        elif force_line:
            out.write(text + "\n")
        out.flush()
    except (OSError, ValueError):  # closed stream: progress is best effort
        pass


def step(k, n, label="", level=0):
    """Step k (1-based) of n of an outer loop; clears the deeper levels and the task."""
    if not _state["enabled"]:
        return
    with _lock:
        _state["steps"] = {lvl: s for lvl, s in _state["steps"].items() if lvl < level}
        _state["steps"][level] = f"{label} {k}/{n}".strip()
        _state["task"] = ""
        _state["last_decile"] = -1
        _draw(force_line=True)


def bar(fraction, width=24):
    fraction = min(max(fraction, 0.0), 1.0)
    full = int(round(fraction * width))
    return "[" + "#" * full + "." * (width - full) + f"] {100.0 * fraction:5.1f} %"


def update(label, done, total):
    """A task at done / total (redrawn on a terminal, every 10 % otherwise)."""
    if not _state["enabled"] or total <= 0:
        return
    fraction = min(max(done / total, 0.0), 1.0)
    with _lock:
        _state["task"] = f"{label} {bar(fraction)}"
        decile = int(fraction * 10)
        if _is_tty():
            _draw()
        elif decile != _state["last_decile"]:
            _state["last_decile"] = decile
            _draw(force_line=True)


@contextlib.contextmanager
def polling(label, total, counter, interval_s=0.25):
    """Shows counter() / total while the body runs (counter is polled from a thread, e.g. a
    block's nitems_written(0)); ends at the counter's final value."""
    if not _state["enabled"] or total <= 0:
        yield
        return
    stop = threading.Event()

    def poll():
        while not stop.wait(interval_s):
            try:
                update(label, counter(), total)
            except Exception:  # a counter that fails must not break the run
                return

    update(label, 0, total)
    thread = threading.Thread(target=poll, name="nrsar-progress", daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join()
        try:
            update(label, counter(), total)
        except Exception:
            pass


def finish():
    """Ends the status line (a newline on a terminal) and clears the state."""
    if not _state["enabled"]:
        return
    with _lock:
        if _is_tty() and _state["last_len"]:
            try:
                _stream().write("\n")
                _stream().flush()
            except (OSError, ValueError):
                pass
        _state.update(steps={}, task="", last_len=0, last_decile=-1)
