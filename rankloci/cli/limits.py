"""Time and memory limits that hold: the work runs in a child process, killed at the limit.

The locus computation polls its own deadline between branches, but a single
step (one factorisation inside FLINT, one huge expansion in sympy) cannot be
interrupted from Python.  So the command runs its work in a forked child:

- the child stops itself cooperatively at ``timeout`` (the work's own
  ``should_stop``), which reports how far it got;
- the parent kills the child at ``timeout + KILL_GRACE`` seconds, whatever it
  is doing, and reports the last progress message it received;
- the child's address space is limited to ``memory_mb`` (``RLIMIT_AS``), so
  running out of memory ends the child (a ``MemoryError``, or an abort inside
  compiled code) instead of the machine.

Progress messages and the result travel back through a pipe; the parent does
all the printing.
"""

from __future__ import annotations

import multiprocessing
import os
import resource
import signal
import sys
import time
import traceback

from ..errors import LocusTimeout, RanklociError
from .output import shortened

__all__ = ["run_limited", "LimitExceeded", "KILL_GRACE", "DEFAULT_MEMORY_MB", "MAX_TIMEOUT_S",
           "MAX_MEMORY_MB", "process_started"]

#: Seconds between the work's own deadline and the parent's kill: the kill, the error line
#: and the exit of the process fit in what is left of a second past the limit.
KILL_GRACE = 0.5

#: Default address-space limit of the child, in MiB.  The built-in models peak below 300 MB
#: of resident memory; the address space of an idle child (Python, numpy, sympy, FLINT and
#: their thread arenas) is about 1.5 GB.
DEFAULT_MEMORY_MB = 8192


#: The longest time limit, in seconds (about 11.6 days): the operating system's waits refuse
#: much longer ones (2147483 s and above overflow them).
MAX_TIMEOUT_S = 1_000_000

#: The largest memory limit, in MiB (16 TiB): an address-space limit in bytes must fit 64 bits.
MAX_MEMORY_MB = 2 ** 24


class LimitExceeded(Exception):
    """The work ran out of time or memory; ``str`` says which and how far it got."""


class ChildFailed(Exception):
    """The work raised an exception that is not bad input: a bug, with the child's traceback."""


def process_started() -> float:
    """The :func:`time.monotonic` reading at which this process started.

    A ``--timeout`` is measured from the start of the process, the interpreter's
    start and the imports included.  On Linux the start time is the kernel's
    (``/proc/self/stat``, in clock ticks since boot); elsewhere it is the time
    of the first call.
    """
    global _STARTED
    if _STARTED is None:
        now = time.monotonic()
        _STARTED = now
        try:
            with open("/proc/self/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
            ticks = int(fields[19])          # field 22, starttime; fields[0] is field 3
            age = time.clock_gettime(time.CLOCK_BOOTTIME) - ticks / os.sysconf("SC_CLK_TCK")
            if 0.0 <= age < 3600.0:
                _STARTED = now - age
        except (OSError, ValueError, IndexError, AttributeError):
            pass
    return _STARTED


_STARTED = None


def run_limited(work, *, timeout: float | None, memory_mb: int | None, progress=None,
                started: float | None = None):
    """``work(progress)`` run in a child process under the limits; its return value.

    Parameters
    ----------
    work : callable
        Called in the child with a progress function; returns a picklable result.
    timeout : float or None
        Seconds; None or 0 for no limit.
    memory_mb : int or None
        Address-space limit of the child in MiB; None or 0 for no limit.
    progress : callable, optional
        Called in the parent with each progress message of the child.
    started : float, optional
        The :func:`time.monotonic` reading the timeout is measured from (default: now).
        The child is killed at ``started + timeout + KILL_GRACE``.

    Raises
    ------
    LimitExceeded
        When the time or memory ran out.
    RanklociError
        Bad input found by the work (its message is kept).
    ChildFailed
        Any other exception in the work (a bug): the child's traceback.
    """
    from .parser import UsageError

    # Load the compiled libraries before the fork: OpenBLAS (scipy's copy is loaded lazily)
    # spins instead of failing when it cannot map its buffers under the child's limit.
    import scipy.linalg  # noqa: F401
    import scipy.optimize  # noqa: F401

    ctx = multiprocessing.get_context("fork")
    receive, send = ctx.Pipe(duplex=False)
    child = ctx.Process(target=_child, args=(work, send, memory_mb), daemon=True)
    start = time.monotonic() if started is None else started
    child.start()
    send.close()
    last = "(no progress reported)"
    kill_at = start + timeout + KILL_GRACE if timeout else None
    try:
        while True:
            wait = None if kill_at is None else max(0.0, kill_at - time.monotonic())
            if not receive.poll(wait):
                _kill(child)
                raise LimitExceeded(f"did not finish within {timeout:g} s and was stopped "
                                    f"(last progress: {last})")
            try:
                kind, payload = receive.recv()
            except EOFError:
                child.join()
                raise LimitExceeded(_death(child.exitcode, memory_mb, last)) from None
            if kind == "progress":
                last = shortened(payload)
                if progress:
                    progress(payload)
            elif kind == "result":
                child.join()
                return payload
            elif kind == "timeout":
                child.join()
                raise LocusTimeout(payload)
            elif kind == "bad-input":
                child.join()
                raise RanklociError(payload)
            elif kind == "usage":
                child.join()
                raise UsageError(payload)
            elif kind == "memory":
                child.join()
                raise LimitExceeded(f"ran out of memory (limit {memory_mb} MiB; raise --memory) "
                                    f"(last progress: {last})")
            else:
                child.join()
                raise ChildFailed(payload)
    except KeyboardInterrupt:
        _kill(child)
        raise
    finally:
        receive.close()


def _die_with_parent():
    """On Linux, have the kernel kill this child when its parent dies (even by SIGKILL).

    Otherwise a parent killed outright (a sweep worker, a shell's ``kill -9``)
    leaves the child computing until its own time limit.  Elsewhere the child
    still ends at its limit.
    """
    if not sys.platform.startswith("linux"):
        return
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):
        return
    if os.getppid() == 1:          # the parent died before the call
        os._exit(1)


#: prctl option: the signal the kernel sends when the parent thread ends (linux/prctl.h).
PR_SET_PDEATHSIG = 1


def _child(work, send, memory_mb):
    from .parser import UsageError

    signal.signal(signal.SIGINT, signal.SIG_IGN)       # the parent handles Ctrl-C
    _die_with_parent()
    if memory_mb:
        limit = int(memory_mb) * 2 ** 20
        try:
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        except (ValueError, OverflowError, OSError) as e:
            send.send(("usage", f"--memory {memory_mb}: the system refuses this limit ({e})"))
            send.close()
            os._exit(0)

    def progress(msg):
        send.send(("progress", str(msg)))

    try:
        result = work(progress)
        message = ("result", result)
    except LocusTimeout as e:
        message = ("timeout", str(e))
    except UsageError as e:
        message = ("usage", str(e))
    except RanklociError as e:
        message = ("bad-input", str(e))
    except MemoryError:
        message = ("memory", "")
    except BaseException:        # a bug: its traceback goes to the parent
        message = ("bug", traceback.format_exc())
    try:
        send.send(message)
    except MemoryError:
        send.send(("memory", ""))
    finally:
        send.close()
        sys.stdout.flush()
        os._exit(0)


def _kill(child):
    if child.is_alive():
        child.kill()
    child.join()


def _death(exitcode, memory_mb, last) -> str:
    """Why a child that sent no result ended.

    Under the address-space limit an allocation that fails inside compiled code
    aborts the child (SIGABRT, or SIGSEGV/SIGBUS on a null pointer).  Nothing in
    rankloci sends SIGKILL to a child except at the time limit (reported
    before this is reached), and the address-space limit never does: SIGKILL,
    SIGTERM and any other signal came from outside, from a user or from the
    system's out-of-memory killer.
    """
    if exitcode is not None and exitcode < 0:
        number = -exitcode
        try:
            name = signal.Signals(number).name
        except ValueError:
            name = "an unnamed signal"
        if memory_mb and number in (signal.SIGABRT, signal.SIGSEGV, signal.SIGBUS):
            return (f"ended by {name}, most likely out of memory inside compiled code (limit "
                    f"{memory_mb} MiB; raise --memory) (last progress: {last})")
        return (f"was killed by signal {number} ({name}) from outside rankloci: by a user or "
                f"by the system's out-of-memory killer (last progress: {last})")
    return f"ended without a result (exit code {exitcode}) (last progress: {last})"
