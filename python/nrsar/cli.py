#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""What every gr-nrsar program does around its work: the parser generated from its options
class, validation before any work, one-line errors and exit codes.

    sys.exit(cli.main("nrsar-sim", SimOptions, chain.simulate, __doc__))

Exit codes: 0 done; 1 the program's own verdict (nrsar-soak's leak test failed); 2 bad usage
or a run that could not be done (one line on stderr naming the flag, the value and the limit,
never a traceback); 130 interrupted by Ctrl-C (the graph is stopped, no result is written as
if finished).
"""

import argparse
import json
import sys

from . import progress, runtime
from .options import check_out_dir

EXIT_USAGE = 2
EXIT_INTERRUPTED = 130


def parser_of(prog, options_cls, doc):
    parser = argparse.ArgumentParser(prog=prog, description=doc,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    options_cls.add_arguments(parser)
    progress.add_arguments(parser)
    return parser


def print_result(result, as_json):
    if as_json:
        print(json.dumps(result))
    else:
        for key, value in result.items():
            print(f"{key:28s} {value}")


def parse(prog, options_cls, doc, argv=None):
    """argv parsed into options_cls and validated with the output folder (`out`, where the
    options have one), progress configured; None after a one-line error on stderr (the
    caller exits 2, as argparse's own errors do)."""
    runtime.quiet_gnuradio_logs()
    parser = parser_of(prog, options_cls, doc)
    namespace = parser.parse_args(argv)
    try:
        opts = options_cls.from_args(namespace)
        if hasattr(opts, "out"):
            check_out_dir(opts.out)
    except ValueError as err:
        print(f"{prog}: error: {err}", file=sys.stderr)
        return None
    progress.configure(progress.from_args(namespace))
    return opts


def main_json(prog, options_cls, run, doc, argv=None):
    """parse(), then run(opts) with its result printed as indented JSON (the figure
    studies); returns the exit code."""
    opts = parse(prog, options_cls, doc, argv)
    if opts is None:
        return EXIT_USAGE
    print(json.dumps(run(opts), indent=1, default=float))
    return 0


def main(prog, options_cls, run, doc, argv=None, verdict=lambda result: 0):
    """Parses argv into options_cls (parse()), runs run(opts) and prints its result dict
    (JSON with --json); returns the exit code."""
    opts = parse(prog, options_cls, doc, argv)
    if opts is None:
        return EXIT_USAGE
    try:
        try:
            result, failure = run(opts), None
        except (ValueError, RuntimeError, OSError) as err:
            result, failure = None, err
        # A Ctrl-C inside a C++ system call (FFTW's wisdom lock, a socket) surfaces first as
        # its EINTR error with the KeyboardInterrupt still pending: it is raised here.
        progress.finish()
    except (runtime.Interrupted, KeyboardInterrupt):
        progress.finish()
        print(f"{prog}: interrupted: stopped before the end, no result written",
              file=sys.stderr)
        return EXIT_INTERRUPTED
    if failure is not None:
        print(f"{prog}: error: {failure}", file=sys.stderr)
        return EXIT_USAGE
    print_result(result, opts.json)
    return verdict(result)
