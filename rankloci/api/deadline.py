"""Time limits of the Python API that hold for the whole call, building J included.

The computation polls its deadline between branches (the ``should_stop`` of
:func:`time_limit`), which stops it with a message saying how far it got.  But
much of a call is single long steps that poll nothing: one expansion of
``(x + y + z + k + 1)**64`` inside sympy, the transforms of a 20-joint arm.
So :func:`time_limit` also arms a watchdog thread that, once the limit has
passed, raises :class:`~rankloci.errors.LocusTimeout` in the calling thread,
between two Python bytecodes, and again every :data:`REPEAT_S` seconds in
case some code swallowed it.  A step inside compiled code (a factorisation in
FLINT) ends before the exception is seen; the command line, which kills its
child, bounds those too.
"""

from __future__ import annotations

import ctypes
import math
import threading
import time
from contextlib import contextmanager

from ..errors import LocusTimeout

__all__ = ["time_limit", "stop_after", "REPEAT_S", "WATCHDOG_GRACE_S"]

#: Seconds after the limit at which the watchdog interrupts the call: the polled deadline
#: gets this long to stop the computation with its own message first.
WATCHDOG_GRACE_S = 0.25

#: Seconds between two interruptions when the first was swallowed (an ``except Exception``).
REPEAT_S = 0.25


class _Expired(LocusTimeout):
    """What the watchdog raises in the calling thread (no message: raised by class)."""


def _end_time(seconds):
    """The end time of ``seconds`` on the monotonic clock; None for no limit."""
    if seconds is None:
        return None
    if isinstance(seconds, bool) or not isinstance(seconds, (int, float)) \
            or not math.isfinite(seconds) or seconds < 0:
        raise ValueError(f"timeout must be a finite number of seconds 0 or above (0 or None: "
                         f"no limit), got {seconds!r}")
    if seconds == 0:
        return None
    return time.monotonic() + seconds


def stop_after(seconds, started=None, *, clock=time.monotonic):
    """A ``should_stop`` that says True once ``seconds`` have passed; None for no limit.

    The time counts from ``started`` (a :func:`time.monotonic` reading; default
    now) and is read on ``clock``.  ``seconds`` None, 0 or below: no limit.

    Examples
    --------
    >>> stop_after(None) is None
    True
    >>> stop_after(3600)()
    False
    """
    if seconds is None or seconds <= 0:
        return None
    if started is not None:
        seconds -= time.monotonic() - started
    end = clock() + seconds
    return lambda: clock() > end


def _raise_in(thread_id: int, exc) -> None:
    """Have ``exc`` raised in thread ``thread_id`` at its next bytecode (None: cancel)."""
    ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(thread_id),
                                               ctypes.py_object(exc) if exc else None)


@contextmanager
def time_limit(seconds, what: str = "the call"):
    """A block that raises :class:`LocusTimeout` once ``seconds`` have passed.

    Yields the block's ``should_stop`` (None without a limit), for the code that polls.

    Parameters
    ----------
    seconds : float or None
        0 or None: no limit.
    what : str
        Named in the error message.

    Raises
    ------
    ValueError
        ``seconds`` is not a finite number 0 or above.
    LocusTimeout
        The block ran past ``seconds``.

    Examples
    --------
    >>> import time
    >>> from rankloci.errors import LocusTimeout
    >>> try:
    ...     with time_limit(0.05, "the loop"):
    ...         while True:
    ...             pass
    ... except LocusTimeout as e:
    ...     print(e)
    the loop did not finish within 0.05 s
    """
    end = _end_time(seconds)
    if end is None:
        yield None
        return
    target = threading.get_ident()
    lock = threading.Lock()
    finished = threading.Event()
    state = {"fired": False}

    def watch():
        wait = end + WATCHDOG_GRACE_S - time.monotonic()
        while not finished.wait(max(0.0, wait)):
            with lock:
                if finished.is_set():
                    return
                state["fired"] = True
                _raise_in(target, _Expired)
            wait = REPEAT_S

    dog = threading.Thread(target=watch, name="rankloci-time-limit", daemon=True)
    message = f"{what} did not finish within {seconds:g} s"
    try:
        try:
            dog.start()
            yield lambda: time.monotonic() > end
        finally:
            with lock:
                finished.set()
                if state["fired"]:
                    _raise_in(target, None)      # one raised but not yet seen is dropped
            dog.join()
    except _Expired:
        raise LocusTimeout(message) from None
    except LocusTimeout as e:
        raise LocusTimeout(f"{message} ({e})" if str(e) else message) from None
