"""The ``rankloci`` command line.

This package is the only place that prints, writes files, reads the clock
and chooses exit codes: 0 success, 1 a check failed, 2 bad input.

- :mod:`.parser`: the arguments of each subcommand;
- :mod:`.commands`: one function per subcommand, returning its exit code;
- :mod:`.output`: progress and warning lines on stderr, atomic file writes;
- :func:`main` (here): parse, run, and turn errors into exit codes.
"""

from __future__ import annotations

import sys
import warnings

from ..errors import RanklociError
from .commands import COMMANDS, EXIT_OK, EXIT_USAGE
from .output import show_warning
from .parser import UsageError, build_parser

__all__ = ["main", "main_exit", "build_parser"]


def main(argv=None) -> int:
    """Run the command line; return the exit code.

    Bad input, a :class:`~rankloci.errors.RanklociError` or a
    :class:`~rankloci.cli.parser.UsageError`, is one line on stderr and exit
    code 2; any other exception is a bug and propagates.  Warnings are
    printed as ``rankloci: warning: ...`` while it runs; the process's
    warning settings are as they were when it returns.
    """
    with warnings.catch_warnings():  # restores showwarning and the filters on return
        warnings.showwarning = show_warning
        return _run(argv)


def _run(argv) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return EXIT_USAGE
        return COMMANDS[args.command](args)
    except (UsageError, RanklociError) as e:
        print(f"rankloci: error: {e}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("rankloci: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return EXIT_OK


def main_exit() -> None:
    """Console-script entry point: run :func:`main` and exit with its code."""
    sys.exit(main())
