"""Time and memory limits that hold: the work runs in a child process, killed at the limit.

The locus computation polls its own deadline between branches, but a single
step (one factorisation inside FLINT, one huge expansion in sympy) cannot be
interrupted from Python.  So the command runs its work in a forked child:

- the child stops itself cooperatively at ``timeout`` (the work's own
  ``should_stop``), which reports how far it got;
- the parent kills the child at ``timeout + KILL_GRACE`` seconds, whatever it
  is doing, and reports the last progress message it received;
- the child's own memory is limited to ``memory_mb``: the parent reads it every
  :data:`MEMORY_POLL_S` seconds (the pages no other process shares, from
  ``/proc/PID/smaps_rollup``: what the child allocated or copied on write, not
  what it inherited from its parent) and kills the child over the limit.  So the
  limit means the same in any parent: the command line, or a sweep's worker,
  which maps other libraries and holds other data.  As a backstop against an
  allocation faster than the polling, the child's address space may grow by
  :data:`BACKSTOP_FACTOR` times the limit (``RLIMIT_AS``, above what it inherited)
  before an allocation fails with a ``MemoryError``.  Where ``/proc`` has no
  ``smaps_rollup`` (not Linux), only that backstop holds.

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

from .errors import LocusTimeout, RanklociError, UsageError, shortened

__all__ = ["run_limited", "LimitExceeded", "KILL_GRACE", "DEFAULT_MEMORY_MB", "MAX_TIMEOUT_S",
           "MAX_MEMORY_MB", "process_started", "own_memory_mib", "MEMORY_POLL_S"]

#: Seconds between the work's own deadline and the parent's kill: the kill, the error line
#: and the exit of the process fit in what is left of a second past the limit.
KILL_GRACE = 0.5

#: Default limit of the child's own memory, in MiB.
DEFAULT_MEMORY_MB = 8192

#: Seconds between two readings of the child's memory.  Reading it costs about 0.1 ms for a
#: child of 1 GB; Python allocates at most a few hundred MB in this time.
MEMORY_POLL_S = 0.05

#: The backstop: the child's address space may grow by this times the limit, plus
#: :data:`BACKSTOP_MIB`, over what it had when it started (its allocations reserve address
#: space before they touch it: malloc arenas, numpy's zeroed arrays).
BACKSTOP_FACTOR = 2
BACKSTOP_MIB = 512


#: The longest time limit, in seconds (about 11.6 days): the operating system's waits refuse
#: much longer ones (2147483 s and above overflow them).
MAX_TIMEOUT_S = 1_000_000

#: The largest memory limit, in MiB (16 TiB): an address-space limit in bytes must fit 64 bits.
MAX_MEMORY_MB = 2 ** 24


class LimitExceeded(RanklociError):
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
                started: float | None = None, usage: dict | None = None):
    """``work(progress)`` run in a child process under the limits; its return value.

    Parameters
    ----------
    work : callable
        Called in the child with a progress function; returns a picklable result.
    timeout : float or None
        Seconds; None or 0 for no limit.
    memory_mb : int or None
        Limit of the child's own memory (:func:`own_memory_mib`) in MiB; None or 0 for
        no limit.
    progress : callable, optional
        Called in the parent with each progress message of the child.
    started : float, optional
        The :func:`time.monotonic` reading the timeout is measured from (default: now).
        The child is killed at ``started + timeout + KILL_GRACE``.
    usage : dict, optional
        Filled with ``peak_mib``: the largest own memory of the child read while it ran
        (read only under a memory limit; None where it cannot be read).

    Raises
    ------
    LimitExceeded
        When the time or memory ran out.
    RanklociError
        Bad input found by the work (its message is kept).
    ChildFailed
        Any other exception in the work (a bug): the child's traceback.
    """
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
    watch = bool(memory_mb) and own_memory_mib(child.pid) is not None
    peak = None
    try:
        while True:
            wait = None if kill_at is None else max(0.0, kill_at - time.monotonic())
            if watch:
                wait = MEMORY_POLL_S if wait is None else min(wait, MEMORY_POLL_S)
            ready = receive.poll(wait)
            if watch:
                now = own_memory_mib(child.pid)
                peak = max(peak or 0.0, now or 0.0)
                if usage is not None:
                    usage["peak_mib"] = round(peak, 1)
                if now is not None and now > memory_mb:
                    _kill(child)
                    raise LimitExceeded(f"ran out of memory: its own memory passed the limit "
                                        f"of {memory_mb} MiB and it was stopped (raise "
                                        f"--memory) (last progress: {last})")
            if not ready:
                if kill_at is None or time.monotonic() < kill_at:
                    continue
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
    signal.signal(signal.SIGINT, signal.SIG_IGN)       # the parent handles Ctrl-C
    _die_with_parent()
    if memory_mb:
        inherited = _address_space()      # 0: unknown, and the limit is the address space
        limit = (inherited + (BACKSTOP_FACTOR * int(memory_mb) + BACKSTOP_MIB) * 2 ** 20
                 if inherited else int(memory_mb) * 2 ** 20)
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


def own_memory_mib(pid: int) -> float | None:
    """The memory process ``pid`` holds alone, in MiB: its private pages and its swap.

    Pages it shares with its parent since the fork are not counted until it writes
    to them.  None where ``/proc/PID/smaps_rollup`` cannot be read (not Linux, or the
    process is gone).
    """
    try:
        with open(f"/proc/{pid}/smaps_rollup", "rb") as f:
            text = f.read()
    except OSError:
        return None
    kb = 0
    for line in text.splitlines():
        if line.startswith((b"Private_Clean:", b"Private_Dirty:", b"Swap:")):
            kb += int(line.split()[1])
    return kb / 1024


def _address_space() -> int:
    """This process's address space in bytes (0 where /proc cannot say)."""
    try:
        with open("/proc/self/statm", "rb") as f:
            return int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return 0


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
