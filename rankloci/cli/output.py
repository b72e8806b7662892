"""Where the command line's output goes besides stdout: stderr lines and files."""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

__all__ = ["progress_printer", "show_warning", "write_atomic"]


def progress_printer(quiet: bool):
    """A function printing ``rankloci: MESSAGE`` on stderr, or None when quiet."""
    if quiet:
        return None

    def progress(msg):
        print(f"rankloci: {msg}", file=sys.stderr, flush=True)

    return progress


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
