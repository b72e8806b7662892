"""Worker processes for the independent parts of one locus computation (``jobs``).

One locus computation has parts that need nothing from each other, and whose results are
merged in a fixed order whatever finishes first:

- the numeric self-check of a computed locus (:func:`~rankloci.numeric.crosscheck.
  cross_check`) and its certificate: the self-check is started in a worker while the
  certificate runs, where the certificate is not expected to decide
  (:data:`~rankloci.verify.CHECK_AHEAD_CODIMENSION`) and after a first computation that it
  did not pass, and its report is taken only when the certificate does not pass;
- the locus of J without the constraint rows of an augmented J_aug
  (:func:`~rankloci.augmented.augmented_locus`), computed while J_aug's is;
- the loci of the slices that the certificate's recovery computes
  (:func:`~rankloci.verify.verified_locus`), one per fixed value.

Parts of matrices in fewer than :data:`WORKER_MIN_VARIABLES` variables run here: they take
less time than a worker takes to start.  Each part is a pure function of its arguments (its
own random generator, seeded as in a computation with one process), so that the locus is
the same for every ``jobs``: with ``jobs=1`` a part runs in the caller's process when its
result is asked for, in the same order as before.  The branch tree itself is grown in one
process: its pruning uses the components found so far, in the order they are found.

Workers start from a forkserver and import what their part needs themselves (a forkserver
that imported it first would hold up the first part until it had).  A part is
polled for the caller's time limit while it is waited for; when the limit passes, or a part's
result is no longer wanted, the workers are ended.  A worker also stops by itself when the
process that started it is gone.
"""

from __future__ import annotations

import os
import time

from .errors import ArgumentError, LocusTimeout

__all__ = ["available_cores", "check_jobs", "Workers"]

#: Joint variables from which a part runs in a worker.  Starting a worker costs about a second
#: of CPU (a process that imports the package); the parts of smaller matrices take about that,
#: and a worker would slow their run on a busy machine.
WORKER_MIN_VARIABLES = 7

#: Seconds between two looks at the caller's time limit while a worker's result is awaited.
POLL_SECONDS = 0.1

#: Seconds between two checks, in a worker, that the process that started it is alive.
PARENT_CHECK_SECONDS = 0.5



def available_cores() -> int:
    """The cores this process may run on: the default of ``jobs``.

    Examples
    --------
    >>> available_cores() >= 1
    True
    """
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:      # not on Linux
        return max(1, os.cpu_count() or 1)


def check_jobs(jobs) -> int:
    """``jobs`` as a number of processes: None for :func:`available_cores`, else an int >= 1.

    Examples
    --------
    >>> check_jobs(2)
    2
    >>> check_jobs(0)
    Traceback (most recent call last):
    ...
    rankloci.errors.ArgumentError: jobs= must be an integer 1 or above, or None for every core, got 0
    """
    if jobs is None:
        return available_cores()
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ArgumentError(f"jobs= must be an integer 1 or above, or None for every core, "
                            f"got {jobs!r}", argument="jobs", value=jobs)
    return int(jobs)


class _ParentAlive:
    """A worker's ``should_stop``: True once the process that started the work is gone."""

    def __init__(self, pid: int):
        self.pid = pid
        self.checked = 0.0

    def __call__(self) -> bool:
        now = time.monotonic()
        if now - self.checked < PARENT_CHECK_SECONDS:
            return False
        self.checked = now
        try:
            os.kill(self.pid, 0)
        except ProcessLookupError:
            return True
        except PermissionError:
            return False
        return False


#: The process that started the forkserver this process may use (None before any).
_FORKSERVER_OWNER = None


def _start_method() -> str:
    """``"forkserver"``, or ``"spawn"`` in a process forked from one that started the
    forkserver (the command line's limited child): the forkserver's state is inherited with
    the fork, and that server is the parent's, which this process cannot wait for."""
    global _FORKSERVER_OWNER

    if _FORKSERVER_OWNER not in (None, os.getpid()):
        return "spawn"
    _FORKSERVER_OWNER = os.getpid()
    return "forkserver"


def _die_with_parent():
    """A worker's initializer: on Linux, the kernel kills the worker when the forkserver that
    started it ends, which it does when the computing process ends (even killed outright)."""
    import sys

    if not sys.platform.startswith("linux"):
        return
    import ctypes
    import signal

    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def _run(fn, args, kwargs, pid):
    """In a worker: ``fn(*args, **kwargs)``, stopped when the caller's process is gone."""
    if "should_stop" in kwargs and kwargs["should_stop"] is None:
        kwargs = {**kwargs, "should_stop": _ParentAlive(pid)}
    return fn(*args, **kwargs)


class Task:
    """A part of the computation: its result, computed in a worker or, with one job, here."""

    def __init__(self, workers, fn, args, kwargs, future=None):
        self._workers = workers
        self._call = (fn, args, kwargs)
        self._future = future
        self._done = False
        self._value = None

    def result(self, should_stop=None):
        """The part's result; raises what the part raised, or :class:`LocusTimeout` once
        ``should_stop`` is true while it is awaited (the workers are then ended)."""
        if self._done:
            return self._value
        if self._future is not None:
            from concurrent.futures import wait
            from concurrent.futures.process import BrokenProcessPool

            while True:
                done, _ = wait([self._future], timeout=POLL_SECONDS)
                if done:
                    break
                if should_stop is not None and should_stop():
                    self._workers.close()
                    raise LocusTimeout("the time ran out while a worker process computed a "
                                       "part of the locus")
            try:
                self._value = self._future.result()
                self._done = True
                return self._value
            except BrokenProcessPool:
                # the worker could not start or died (a script without a __main__ guard,
                # whose import starts the computation again): the part is computed here
                self._workers.close()
                self._future = None
        fn, args, kwargs = self._call
        if "should_stop" in kwargs and kwargs["should_stop"] is None:
            kwargs = {**kwargs, "should_stop": should_stop}
        self._value = fn(*args, **kwargs)
        self._done = True
        return self._value

    def cancel(self):
        """The result is not wanted: the part does not start, or its worker is ended."""
        if self._future is not None and not self._future.cancel() and not self._future.done():
            self._workers.close()


class Workers:
    """Up to ``jobs`` worker processes, started when a part is first submitted.

    With ``jobs=1`` no process is started: :meth:`submit` returns a :class:`Task` computed
    in this process when its result is asked for.  Use as a context manager, or call
    :meth:`close`: the workers are ended there.

    Examples
    --------
    >>> with Workers(1) as w:
    ...     w.submit(max, 2, 3).result()
    3
    """

    def __init__(self, jobs: int = 1):
        self.jobs = check_jobs(jobs)
        self._executor = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def sized(self, n_variables: int) -> "Workers":
        """These workers for the parts of a matrix in ``n_variables`` variables: themselves
        from :data:`WORKER_MIN_VARIABLES` on, below it one job (the parts run here)."""
        if self.jobs == 1 or n_variables >= WORKER_MIN_VARIABLES:
            return self
        return _HERE

    def submit(self, fn, /, *args, **kwargs) -> Task:
        """``fn(*args, **kwargs)`` as a :class:`Task`.

        ``fn`` and its arguments are pickled for a worker: a module-level function and
        plain values.  A keyword ``should_stop=None`` becomes, in a worker, a check that
        this process is alive, and with one job the ``should_stop`` given to
        :meth:`Task.result`.
        """
        if self.jobs == 1:
            return Task(self, fn, args, kwargs)
        if self._executor is None:
            import multiprocessing as mp
            from concurrent.futures import ProcessPoolExecutor

            me = mp.current_process()
            if me.daemon and me.name != "MainProcess":
                # the command line's limited child (rankloci.cli.limits) is daemonic only so
                # that its parent does not wait for it at exit; its workers end with it
                me.daemon = False
            ctx = mp.get_context(_start_method())
            # one worker fewer than the jobs: this process computes too
            self._executor = ProcessPoolExecutor(max_workers=max(1, self.jobs - 1),
                                                 mp_context=ctx, initializer=_die_with_parent)
        future = self._executor.submit(_run, fn, args, kwargs, os.getpid())
        return Task(self, fn, args, kwargs, future)

    def close(self):
        """End the workers (those still computing are killed)."""
        executor, self._executor = self._executor, None
        if executor is None:
            return
        # the pool has no public way to end a worker in the middle of a part: its processes
        # are killed, and the pool, which sees them gone, frees its queues
        processes = list((getattr(executor, "_processes", None) or {}).values())
        for p in processes:
            if p.is_alive():
                p.kill()
        executor.shutdown(wait=True, cancel_futures=True)


#: Workers that run every part here (see :meth:`Workers.sized`).
_HERE = Workers(1)
