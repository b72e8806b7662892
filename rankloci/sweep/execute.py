"""Where the cases of a sweep run: in this process, or on Dask distributed.

Both executors yield the same events, in the order they happen:

- ``("start", case, worker)``: a case began on a worker (its address; ``""`` in this
  process); a case whose worker was lost starts again elsewhere, with a second event;
- ``("done", case, result)``: a case finished (``result`` as
  :func:`rankloci.sweep.task.run_case` returns it: a failed case is a result too);
- ``("tick",)``: nothing happened for a moment (the caller redraws its progress).

:func:`serial_events` runs the cases one after another in this process (each
in its own forked child under the limits).  :class:`DaskExecutor` submits one
Dask task per case to a cluster: a :class:`distributed.LocalCluster` of
single-threaded worker processes, or a running scheduler.  The task is
:func:`dask_case`, which reports its start and calls
:func:`~rankloci.sweep.task.run_case`.  Each task carries its model's text, so that
no task depends on data held by one worker: when a worker dies (a preempted machine,
``kill -9``), the scheduler runs the cases it was running on the other workers, and
what is lost is their time so far.  The tasks are submitted longest expected first
(:func:`~rankloci.sweep.cases.expected_cost`), with priorities in the same order, and
ask for their memory limit as the Dask resource ``MEMORY`` (MiB) when the workers
declare it, so that the scheduler never starts more cases on a worker than its
memory holds.  Worker processes are started as
non-daemonic (``distributed.worker.daemon: False``) because each case forks a
child that enforces its limits, and daemonic processes may not have children.
"""

from __future__ import annotations

import functools

from ..errors import RanklociError
from .cases import expected_cost
from .task import run_case

__all__ = ["serial_events", "DaskExecutor", "dask_case", "worker_info", "package_digest",
           "SetupError", "MEMORY_RESOURCE"]

#: Dask event topic on which the tasks report that they started.
START_TOPIC = "rankloci-sweep-start"

#: Seconds between progress ticks while the cluster is busy.
TICK_SECONDS = 0.25

#: Default seconds to wait for a running scheduler to answer, and then for its first worker.
CONNECT_TIMEOUT_S = 20.0

#: Times a case's task is run again when it raises (the case itself never raises: this is
#: the machinery failing, e.g. a fork refused).  A worker that dies is another matter: its
#: running cases go to other workers, up to Dask's ``allowed-failures`` (3) times.
TASK_RETRIES = 2

#: The Dask resource of a case's memory, in MiB: a case asks for its memory limit, a worker
#: offers what its share of the machine holds (``dask worker --resources MEMORY=4096``).
MEMORY_RESOURCE = "MEMORY"

#: Most unusable workers named in one error.
MAX_PROBLEMS_SHOWN = 3

#: Address of the local cluster's dashboard; when the port is taken, Dask takes another.
DASHBOARD_ADDRESS = ":8787"

#: Seconds to connect to a scheduler's address and to hear its greeting: a Dask scheduler
#: sends its handshake as soon as a connection is accepted.
CONNECT_SECONDS = 10.0

#: Dask settings of a sweep's cluster: each worker runs one case at a time (the
#: scheduler sends a worker no more tasks than it has threads), worker processes may fork
#: the child of each case, and a worker is never paused or restarted for its memory: each
#: case's child has its own memory limit, and one out-of-memory case must not take the
#: cases queued behind it down with its worker.
DASK_CONFIG = {
    "distributed.worker.daemon": False,
    "distributed.scheduler.worker-saturation": 1.0,
    "distributed.worker.memory.target": False,
    "distributed.worker.memory.spill": False,
    "distributed.worker.memory.pause": False,
    "distributed.worker.memory.terminate": False,
}


class SetupError(RanklociError):
    """The cluster cannot run the sweep (no worker, a worker without rankloci, ...)."""


def serial_events(cases, sources, *, timeout: float, memory: int):
    """Run the cases one after another in this process; yield the events."""
    for case in cases:
        yield ("start", case, "")
        yield ("done", case, run_case(case, sources.get(case.source), timeout=timeout,
                                      memory=memory))


def dask_case(case, text, timeout, memory):
    """The Dask task of one case: report the start, then :func:`run_case`.

    The record names the worker that computed the case (``worker``).
    """
    address = ""
    try:
        from distributed import get_worker

        worker = get_worker()
        address = worker.address
        worker.log_event(START_TOPIC, (case.id, address))
    except ValueError:            # not on a worker (a test calling it directly)
        pass
    result = run_case(case, text, timeout=timeout, memory=memory)
    result["sweep"]["worker"] = address
    return result


@functools.cache
def package_digest() -> str:
    """SHA-256 of rankloci's source: the text of every ``.py`` file of the package, by path.

    Two installations with the same digest compute the same loci; a version string
    says less (a checkout with local changes still calls itself by its version).
    """
    import hashlib
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        if "__pycache__" in path.parts:
            continue
        digest.update(path.relative_to(root).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()


def worker_info() -> dict:
    """What a worker tells the client before the sweep: its rankloci, host, daemon or not."""
    import multiprocessing
    import os
    import socket

    from ..version import __version__

    return {"version": __version__, "digest": package_digest(), "host": socket.gethostname(),
            "pid": os.getpid(),
            "daemon": bool(multiprocessing.current_process().daemon)}


def stop_children() -> int:
    """Kill the children of this worker process (the cases' limit children); how many."""
    import psutil

    children = psutil.Process().children(recursive=True)
    for child in children:
        try:
            child.kill()
        except psutil.NoSuchProcess:
            pass
    return len(children)


def machine_memory_mib() -> int:
    """This machine's memory in MiB."""
    import psutil

    return psutil.virtual_memory().total // 2 ** 20


def dashboard_available() -> bool:
    """Can Dask serve its dashboard here (it needs bokeh)?"""
    import importlib.util

    return importlib.util.find_spec("bokeh") is not None


class DaskExecutor:
    """A Dask client and, for a local cluster, the cluster it owns.

    Use :meth:`local` or :meth:`remote`, then :meth:`check_workers` and
    :meth:`events`; :meth:`close` (or ``with``) shuts down what it started.
    """

    def __init__(self, client, cluster=None, config=None, *,
                 connect_timeout: float = CONNECT_TIMEOUT_S):
        self.client = client
        self.cluster = cluster
        self._config = config
        self._futures: dict = {}
        self.connect_timeout = connect_timeout
        #: ``{worker address: MEMORY it offers}`` of the workers that declare the resource.
        self.memory_offers: dict = {}
        #: Does the local cluster serve a dashboard (a running scheduler: as it was started)?
        self.dashboard = cluster is None
        #: ``{case id: address of the worker that last started it}``.
        self.workers_of: dict = {}

    @classmethod
    def local(cls, workers: int, *, dashboard: bool = True) -> "DaskExecutor":
        """A LocalCluster of ``workers`` single-threaded worker processes.

        Each worker offers the resource ``MEMORY``: its share of this machine's memory
        (MiB), so that the cases running at once never have limits over the machine's
        memory.  With ``dashboard`` (and bokeh installed) the scheduler serves Dask's
        dashboard on port 8787, or another free port when 8787 is taken.
        """
        import logging
        import warnings

        import dask
        from distributed import Client, LocalCluster

        config = dask.config.set(DASK_CONFIG)
        address = DASHBOARD_ADDRESS if dashboard and dashboard_available() else None
        try:
            # without a dashboard, the scheduler's own HTTP server (health checks) on a free
            # port, not on 8787, which another cluster on the machine may hold
            with warnings.catch_warnings():
                warnings.filterwarnings("ignore", message=".*already in use.*")
                cluster = LocalCluster(
                    n_workers=workers, threads_per_worker=1, processes=True,
                    dashboard_address=address, memory_limit=0, silence_logs=logging.ERROR,
                    scheduler_port=0, scheduler_kwargs={"dashboard_address": address or ":0",
                                      "dashboard": address is not None},
                    resources={MEMORY_RESOURCE: machine_memory_mib() // workers})
            client = Client(cluster)
        except BaseException:
            config.__exit__(None, None, None)
            raise
        executor = cls(client, cluster, config)
        executor.dashboard = address is not None
        return executor

    @classmethod
    def remote(cls, address: str, *, connect_timeout: float = CONNECT_TIMEOUT_S
               ) -> "DaskExecutor":
        """A client of the scheduler at ``address`` (``tcp://HOST:8786``).

        Gives up after ``connect_timeout`` seconds without an answer.
        """
        import threading

        from distributed import Client

        greeted(address, min(CONNECT_SECONDS, connect_timeout))
        # Client's own timeout does not cover a server that accepts the connection and never
        # answers: the connection is made in a thread, and given up at the deadline
        got: dict = {}

        def connect():
            try:
                got["client"] = Client(address, timeout=connect_timeout)
            except BaseException as e:  # noqa: BLE001 -- handed to the caller
                got["error"] = e

        thread = threading.Thread(target=connect, daemon=True, name="rankloci-connect")
        thread.start()
        thread.join(connect_timeout + 1.0)
        if thread.is_alive():
            raise SetupError(f"no Dask scheduler answered at {address} within "
                             f"{connect_timeout:g} s (--connect-timeout)")
        e = got.get("error")
        if isinstance(e, (OSError, TimeoutError)):
            raise SetupError(f"cannot reach the Dask scheduler at {address} within "
                             f"{connect_timeout:g} s (--connect-timeout): {e}") from None
        if isinstance(e, (Exception, MemoryError)):
            # whatever answered is no scheduler (a web server's reply read as a message
            # length asks for exabytes)
            raise SetupError(f"no Dask scheduler answers at {address} ({type(e).__name__}: "
                             f"{str(e)[:120]})") from None
        if e is not None:
            raise e
        client = got["client"]
        return cls(client, connect_timeout=connect_timeout)

    @property
    def dashboard_link(self) -> str | None:
        """The link to the scheduler's dashboard, or None when it serves none."""
        try:
            link = self.client.dashboard_link
        except (KeyError, AttributeError, TypeError, OSError):
            return None
        if self.cluster is not None and not self.dashboard:
            return None
        return link or None

    def check_workers(self, memory: int = 0) -> int:
        """The number of worker threads; raises :class:`SetupError` for an unusable cluster.

        Every worker must run the same rankloci source as this machine (compared by
        :func:`package_digest`), as a non-daemon process; when workers declare the
        ``MEMORY`` resource, one must offer ``memory`` MiB (a case's limit).
        """
        from ..version import __version__

        try:
            self.client.wait_for_workers(1, timeout=self.connect_timeout)
        except TimeoutError:
            raise SetupError(f"no Dask worker joined the scheduler within "
                             f"{self.connect_timeout:g} s (--connect-timeout)") from None
        info = self.client.run(worker_info, on_error="return")
        problems = []
        for address, got in sorted(info.items()):
            if isinstance(got, BaseException):
                problems.append(f"worker {address} cannot run rankloci ({type(got).__name__}: "
                                f"{str(got)[:120]}): install it on that machine")
            elif not isinstance(got, dict) or got.get("digest") != package_digest():
                got = got if isinstance(got, dict) else {}
                problems.append(
                    f"worker {address} (host {got.get('host', '?')}) runs another rankloci "
                    f"source (version {got.get('version', '?')}, digest "
                    f"{str(got.get('digest'))[:12]}) than this machine (version {__version__}, "
                    f"digest {package_digest()[:12]}): install the same checkout there")
            elif got["daemon"]:
                problems.append(
                    f"worker {address} (host {got['host']}) runs as a daemon process and "
                    f"cannot start the child process that enforces each case's limits: start "
                    f"it with DASK_DISTRIBUTED__WORKER__DAEMON=False")
        if problems:
            shown = problems[:MAX_PROBLEMS_SHOWN]
            more = len(problems) - len(shown)
            raise SetupError("; ".join(shown) + (f" (and {more} more worker"
                                                 f"{'' if more == 1 else 's'})" if more else ""))
        workers = self.client.scheduler_info(n_workers=-1)["workers"]
        self.memory_offers = {a: w["resources"][MEMORY_RESOURCE] for a, w in workers.items()
                              if MEMORY_RESOURCE in (w.get("resources") or {})}
        if memory and self.memory_offers and not self.slots(memory):
            largest = max(self.memory_offers.values())
            hint = (f"this machine's {machine_memory_mib()} MiB shared by {len(workers)} "
                    f"workers; run fewer --workers or lower --memory" if self.cluster is not None
                    else "lower --memory or give the workers more (dask worker --resources "
                         f"{MEMORY_RESOURCE}=MIB)")
            raise SetupError(f"--memory {memory}: no Dask worker has that much memory for a "
                             f"case (the largest offers {largest:g} MiB: {hint})")
        return sum(self.client.nthreads().values())

    def slots(self, memory: int = 0) -> int:
        """How many cases the workers can run at once: per worker, its threads, and no more
        cases than its ``MEMORY`` holds at ``memory`` MiB each (when it declares it)."""
        workers = self.client.scheduler_info(n_workers=-1)["workers"]
        total = 0
        for w in workers.values():
            offer = (w.get("resources") or {}).get(MEMORY_RESOURCE)
            fits = w["nthreads"] if not (memory and offer is not None) else int(offer // memory)
            total += min(w["nthreads"], fits)
        return total

    def events(self, cases, sources, *, timeout: float, memory: int):
        """Run every case, longest expected first; yield the events as they happen.

        The cases are submitted one by one as workers free up (no more at once than
        :meth:`slots`), so that no case waits in a worker's own queue: the order is the
        sweep's, and a worker that dies holds only the cases it was running.
        """
        import collections
        import queue
        import uuid

        from distributed import wait

        started: queue.SimpleQueue = queue.SimpleQueue()
        by_id = {c.id: c for c in cases}
        self.client.subscribe_topic(START_TOPIC, lambda event: started.put(event[1]))
        resources = ({MEMORY_RESOURCE: memory} if memory and self.memory_offers else None)
        waiting = collections.deque(sorted(cases, key=expected_cost, reverse=True))
        run = uuid.uuid4().hex[:8]
        while waiting or self._futures:
            if waiting and len(self._futures) < max(self.slots(memory), 1):
                case = waiting.popleft()
                fut = self.client.submit(
                    dask_case, case, sources.get(case.source), timeout, memory, pure=False,
                    key=f"rankloci-case-{case.id}-{run}", priority=len(waiting),
                    retries=TASK_RETRIES, resources=resources)
                self._futures[fut.key] = (fut, case)
                continue
            while not started.empty():
                cid, address = started.get()
                if cid in by_id:
                    self.workers_of[cid] = address
                    yield ("start", by_id[cid], address)
            done = [f for f, _ in self._futures.values() if f.done()]
            if not done:
                yield ("tick",)
                try:
                    wait([f for f, _ in self._futures.values()], timeout=TICK_SECONDS,
                         return_when="FIRST_COMPLETED")
                except TimeoutError:
                    pass
                continue
            for fut in done:
                _, case = self._futures.pop(fut.key)
                yield ("done", case, self._result(fut, case, timeout, memory))
        self.client.unsubscribe_topic(START_TOPIC)

    def _result(self, fut, case, timeout, memory):
        """The result of a finished future; a task that failed (its workers died
        ``allowed-failures`` times, say) is a failed case naming the worker and the cause,
        not an exception."""
        if fut.status == "finished":
            return fut.result()
        from .task import failed_result

        try:
            error = fut.exception()
        except Exception as e:  # noqa: BLE001 -- a cancelled future
            error = e
        worker = self.workers_of.get(case.id, "")
        if type(error).__name__ == "KilledWorker":
            last = getattr(getattr(error, "last_worker", None), "address", None)
            worker = last or worker
            cause = ("each worker that ran it died, as often as Dask allows "
                     "(distributed.scheduler.allowed-failures)")
        elif error is None:
            cause = f"the task ended as {fut.status!r} without an exception"
        else:
            cause = f"{type(error).__name__}: {' '.join(str(error).split())}"
        where = f" on worker {worker}" if worker else ""
        result = failed_result(case, f"the Dask task of {case.label} failed{where}: {cause}",
                               timeout=timeout, memory=memory, transient=True)
        result["sweep"]["worker"] = worker
        return result

    def stop(self) -> None:
        """Cancel every case not finished; on a local cluster, kill the cases' children.

        On a running scheduler the workers may serve others too, so their children are left
        to their own deadline (the case's timeout plus one second).
        """
        futures = [f for f, _ in self._futures.values()]
        self._futures.clear()
        try:
            if futures:
                self.client.cancel(futures, force=True)
            if self.cluster is not None:
                self.client.run(stop_children)
        except Exception:  # noqa: BLE001 -- stopping is best effort: the cluster may be gone
            pass

    def close(self) -> None:
        """Close the client and the local cluster this executor started."""
        try:
            self.client.close()
            if self.cluster is not None:
                self.cluster.close()
        finally:
            if self._config is not None:
                self._config.__exit__(None, None, None)
                self._config = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def greeted(address: str, seconds: float) -> None:
    """Raise :class:`SetupError` unless a Dask scheduler greets at ``tcp://HOST:PORT``.

    The client's own handshake waits without end on a server that accepts and says nothing
    (or an HTTP server, which waits for a request).  A Dask scheduler writes its handshake as
    soon as it accepts a connection: a frame whose first 8 bytes are its length, little-endian.
    Other schemes (``tls://``) are left to the client.
    """
    import socket
    import struct

    scheme, _, rest = address.partition("://")
    if scheme != "tcp":
        return
    host, _, port = rest.rpartition(":")
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=seconds) as sock:
            sock.settimeout(seconds)
            head = b""
            while len(head) < 8:
                chunk = sock.recv(8 - len(head))
                if not chunk:
                    raise SetupError(f"no Dask scheduler answers at {address}: the connection "
                                     f"was closed without a greeting")
                head += chunk
    except TimeoutError:
        raise SetupError(f"no Dask scheduler answers at {address} within {seconds:g} s "
                         "(--connect-timeout): nothing came, and a Dask scheduler greets at "
                         "once") from None
    except (OSError, ValueError) as e:
        raise SetupError(f"cannot reach the Dask scheduler at {address}: "
                         f"{getattr(e, 'strerror', None) or e}") from None
    if not 0 < struct.unpack("<Q", head)[0] < 2 ** 24:
        raise SetupError(f"no Dask scheduler answers at {address}: what answers there speaks "
                         f"another protocol")
