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
import time
import warnings
from pathlib import Path

from ..errors import ModelError, RanklociError
from .commands import COMMANDS, EXIT_OK, EXIT_USAGE
from .output import detach_progress, show_warning
from ..errors import UsageError
from .parser import OLD_OPTIONS, build_parser

__all__ = ["main", "main_exit", "build_parser"]


def main(argv=None, *, started: float | None = None) -> int:
    """Run the command line; return the exit code.

    ``--timeout`` is measured from ``started``, a :func:`time.monotonic` reading
    (default: the call; the console script passes the start of the process).

    Bad input, a :class:`~rankloci.errors.RanklociError` or a
    :class:`~rankloci.errors.UsageError`, is one line on stderr and exit
    code 2 (naming the model file, when the model is a file and the error
    does not name one); any other exception is a bug and propagates.  Warnings are
    printed as ``rankloci: warning: ...`` while it runs; the process's
    warning settings are as they were when it returns.
    """
    with warnings.catch_warnings():  # restores showwarning and the filters on return
        warnings.showwarning = show_warning
        try:
            return _run(argv, time.monotonic() if started is None else started)
        finally:
            detach_progress()  # the progress handler belongs to this run only


def _run(argv, started) -> int:
    parser = build_parser()
    args = None
    try:
        args = parser.parse_args(argv)
        args.started = started
        if args.command is None:
            parser.print_help()
            return EXIT_USAGE
        _check_chain_options(args)
        code = COMMANDS[args.command](args)
        # after the run, so that bad input stays one line on stderr
        for old in getattr(args, "old_options", ()):
            print(f"rankloci: note: {old} is deprecated; use {OLD_OPTIONS[old]}", file=sys.stderr)
        return code
    except (UsageError, RanklociError) as e:
        print(f"rankloci: error: {_error_line(e, args)}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("rankloci: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return EXIT_OK


def _is_model_file(spec: str) -> bool:
    """Whether ``rankloci.io.load_model`` reads ``spec`` as a file (not a built-in name)."""
    path = Path(spec)
    try:
        return path.suffix.lower() in (".toml", ".urdf") or path.exists()
    except OSError:               # a name longer than the file system takes
        return False


def _check_chain_options(args) -> None:
    """Refuse ``--base-link`` and ``--tip`` (the chain of a URDF file) for any other model."""
    given = [option for option, dest in (("--base-link", "base_link"), ("--tip", "tip_link"))
             if getattr(args, dest, None) is not None]
    spec = getattr(args, "model", "")
    if given and Path(spec).suffix.lower() != ".urdf":
        what = ("not a .urdf file" if _is_model_file(spec)
                else "the built-in models" if args.command == "report" and spec == "all"
                else "a built-in model")
        verb = "applies" if len(given) == 1 else "apply"
        raise UsageError(f"{' and '.join(given)} {verb} to URDF files only; {spec!r} is {what}")


def _error_line(error, args) -> str:
    """The message of ``error`` on one line, naming the model file when it does not already.

    An error found in the algebra (a :class:`~rankloci.errors.LocusError`,
    which may come back from a child process as a plain
    :class:`~rankloci.errors.RanklociError`) knows only the matrix entry, not
    the file it came from.
    """
    text = " ".join(str(error).split())
    if isinstance(error, UsageError) or (isinstance(error, ModelError) and error.file):
        return text
    spec = getattr(args, "model", None)
    if not spec or not _is_model_file(spec):
        return text
    name = Path(spec).name
    return text if text.startswith(f"{name}:") else f"{name}: {text}"


def main_exit() -> None:
    """Console-script entry point: run :func:`main` and exit with its code.

    ``--timeout`` counts from the start of the process.  The exit runs the
    ``atexit`` handlers and flushes the output, then skips the interpreter's
    teardown of its modules, which takes about 0.3 s once sympy's caches are
    full: time the limit's last second has no room for.
    """
    import atexit
    import os

    from ..process_limits import process_started

    code = main(started=process_started())
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):      # a closed pipe or stream: nothing more to say
            pass
    os._exit(code)
