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
import stat
import sys
import tempfile
import time
from pathlib import Path

from ..errors import UsageError, shortened

__all__ = ["progress_printer", "clear_status", "detach_progress", "require_module",
           "show_warning", "write_atomic", "output_target", "check_names", "new_file_mode",
           "STATUS_DELAY", "NAME_MAX", "TEMP_SUFFIX"]

#: Seconds after the first progress message before a terminal gets the status line: a run
#: that ends sooner shows none.
STATUS_DELAY = 1.0

_SPINNER = "|/-\\"


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
    if importlib.util.find_spec(module) is None:
        raise UsageError(f"{what} needs {module}, which is not installed: "
                         f"{install_command(extra)}")


def show_warning(message, category, filename, lineno, file=None, line=None):
    """A :data:`warnings.showwarning` that prints one line, without the source location."""
    print(f"rankloci: warning: {message}", file=sys.stderr)


#: The longest name of one path component that common file systems take, in bytes.
NAME_MAX = 255

#: The suffix of the temporary file :func:`write_atomic` writes beside its target.
TEMP_SUFFIX = ".rankloci-tmp"


def check_names(path, option: str) -> None:
    """A usage error when a name in ``path`` is longer than the file system takes."""
    if any(len(os.fsencode(part)) > NAME_MAX for part in Path(path).parts):
        raise UsageError(f"{option} {shortened(str(path), 80)!r}: a name in the path is longer "
                         f"than {NAME_MAX} bytes")


def output_target(path, option: str, suffixes: tuple = ()) -> Path:
    """The file that writing ``path`` replaces, checked; a usage error when it may not be.

    A symbolic link is written through: its target is replaced and the link
    stays.  The target must be absent or a regular file (never a device, a
    FIFO or a directory), in an existing directory that can be written to,
    and every name in the path must fit the file system.  Commands call this
    before they compute, and :func:`write_atomic` again before it writes.

    Parameters
    ----------
    path : str or os.PathLike
    option : str
        How the command line names the file in its error line (``"-o"``, ``"--tree"``).
    suffixes : tuple of str
        The endings the file may have (lower case, any case accepted); empty: any.
    """
    shown = f"{option} {shortened(str(path), 80)!r}"
    p = Path(path)
    if suffixes and p.suffix.lower() not in suffixes:
        choices = ", ".join(suffixes[:-1]) + f" or {suffixes[-1]}" if len(suffixes) > 1 \
            else suffixes[0]
        raise UsageError(f"{shown}: the file must end in {choices}")
    check_names(p, option)
    real = Path(os.path.realpath(p))
    try:
        st = os.stat(real)
    except FileNotFoundError:
        st = None
    except OSError as e:
        raise UsageError(f"{shown}: {e.strerror}") from None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise UsageError(f"{shown} is a directory; give a file name")
    if st is not None and not stat.S_ISREG(st.st_mode):
        raise UsageError(f"{shown} is not a regular file (a device, a FIFO or a socket); "
                         "refused")
    if not real.parent.is_dir():
        raise UsageError(f"{shown}: directory does not exist")
    if st is not None and not os.access(real, os.W_OK):
        raise UsageError(f"{shown}: the file is not writable (permission denied)")
    try:       # the only sure test (root, read-only mounts, /proc): create a file there
        fd, probe = tempfile.mkstemp(dir=real.parent, prefix=f".{real.name}.",
                                     suffix=TEMP_SUFFIX)
        os.close(fd)
        os.unlink(probe)
    except OSError as e:
        raise UsageError(f"{shown}: cannot write in {shortened(str(real.parent), 80)!r}: "
                         f"{e.strerror or e}") from None
    return real


def new_file_mode() -> int:
    """The permission bits ``open()`` gives a new file: 0o666 without the process's umask."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return 0o666 & ~int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)       # no other way to read it: set and put back
    os.umask(mask)
    return 0o666 & ~mask


def write_atomic(path, data, option: str = "output") -> None:
    """Write ``data`` (str or bytes) to ``path`` through a temporary file: never half-written.

    The target is checked by :func:`output_target` (a symbolic link is written
    through; a device, FIFO or directory is refused).  The file keeps the
    permission bits of the file it replaces; a new file gets those of
    ``open()``, which respect the umask.
    """
    target = output_target(path, option)
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode)
    except FileNotFoundError:
        mode = new_file_mode()
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.",
                                   suffix=TEMP_SUFFIX)
        with os.fdopen(fd, "wb") as fh:
            os.fchmod(fh.fileno(), mode)
            fh.write(data.encode("utf-8") if isinstance(data, str) else data)
        os.replace(tmp, target)
    except BaseException as e:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass
        if isinstance(e, OSError):
            raise UsageError(f"{option} {shortened(str(path), 80)!r}: cannot write: "
                             f"{e.strerror or e}") from None
        raise
