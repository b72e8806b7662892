"""Where the command line's output goes besides stdout: stderr lines and files.

Progress travels as :mod:`logging` records of the ``rankloci`` logger, as in the
library (:mod:`rankloci.api.progress`); :func:`progress_printer` attaches the
handler that shows them on stderr: one ``rankloci: MESSAGE`` line each, or,
when stderr is a terminal and the run has lasted :data:`STATUS_DELAY` seconds,
one status line rewritten in place (a spinner, the seconds so far, the number of
steps reported and the latest message).  :func:`clear_status` removes that line
before the results are printed.
"""

from __future__ import annotations

import logging
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

__all__ = ["progress_printer", "clear_status", "detach_progress", "require_module",
           "show_warning", "write_atomic", "shortened", "STATUS_DELAY", "PROGRESS_LINE_MAX"]

#: Seconds after the first progress message before a terminal gets the status line: a run
#: that ends sooner shows none.
STATUS_DELAY = 1.0

#: Characters of a progress message shown on stderr, and in the error line of a run that ran
#: out of its limits: the equations of a component found on a long chain can run to
#: megabytes of digits, which a line of progress does not need.
PROGRESS_LINE_MAX = 300

_SPINNER = "|/-\\"


def shortened(message: str, limit: int = PROGRESS_LINE_MAX) -> str:
    """``message`` cut to ``limit`` characters, saying how many were left out.

    Examples
    --------
    >>> shortened("x" * 10, 4)
    'xxxx ... (6 more characters)'
    >>> shortened("short")
    'short'
    """
    if len(message) <= limit:
        return message
    return f"{message[:limit]} ... ({len(message) - limit} more characters)"


class ProgressHandler(logging.Handler):
    """Shows the ``rankloci`` logger's records on stderr (looked up at each record).

    Parameters
    ----------
    clock : callable
        Returns seconds; :func:`time.monotonic` by default.
    """

    def __init__(self, clock=time.monotonic):
        super().__init__(logging.INFO)
        self.clock = clock
        self.start = None
        self.count = 0
        self.shown = False   # a status line is on the terminal

    def emit(self, record) -> None:
        message = record.getMessage()
        stream = sys.stderr
        if not _is_terminal(stream):
            print(f"rankloci: {shortened(message)}", file=stream, flush=True)
            return
        now = self.clock()
        self.start = now if self.start is None else self.start
        self.count += 1
        if now - self.start < STATUS_DELAY:
            return
        width = shutil.get_terminal_size((80, 24)).columns
        line = (f"rankloci: {_SPINNER[self.count % len(_SPINNER)]} {now - self.start:6.1f} s, "
                f"{self.count} steps | {message}")
        stream.write("\r\x1b[K" + line[:max(width - 1, 20)] + "\r")
        stream.flush()
        self.shown = True

    def clear(self) -> None:
        """Remove the status line, if one is shown."""
        if self.shown:
            sys.stderr.write("\r\x1b[K")
            sys.stderr.flush()
            self.shown = False


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def _handler() -> ProgressHandler | None:
    from ..api.progress import logger

    return next((h for h in logger.handlers if isinstance(h, ProgressHandler)), None)


def progress_printer(quiet: bool):
    """The progress function of a command: it logs to ``rankloci``, shown on stderr; None when quiet.

    The first call attaches a :class:`ProgressHandler` to the ``rankloci``
    logger (level INFO); :func:`detach_progress` takes it off again.
    """
    if quiet:
        return None
    from ..api.progress import log_progress, logger

    if _handler() is None:
        logger.addHandler(ProgressHandler())
        logger.setLevel(logging.INFO)
    return log_progress


def clear_status() -> None:
    """Remove the terminal's status line before results are printed."""
    handler = _handler()
    if handler is not None:
        handler.clear()


def detach_progress() -> None:
    """Take the command line's handler off the ``rankloci`` logger (at the end of a command)."""
    from ..api.progress import logger

    handler = _handler()
    if handler is not None:
        handler.clear()
        logger.removeHandler(handler)
        logger.setLevel(logging.NOTSET)


def require_module(module: str, extra: str, what: str) -> None:
    """Raise a usage error (one line, exit 2) naming what to install when ``module`` is missing.

    Examples
    --------
    >>> require_module("json", "report", "the report")
    """
    import importlib.util

    from ..extras import install_command
    from .parser import UsageError

    if importlib.util.find_spec(module) is None:
        raise UsageError(f"{what} needs {module}, which is not installed: "
                         f"{install_command(extra)}")


def show_warning(message, category, filename, lineno, file=None, line=None):
    """A :data:`warnings.showwarning` that prints one line, without the source location."""
    print(f"rankloci: warning: {message}", file=sys.stderr)


def write_atomic(path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file: never half-written."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent if str(path.parent) else ".", prefix=f".{path.name}.")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
