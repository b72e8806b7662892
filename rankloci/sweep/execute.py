"""Where the cases of a sweep run: in this process, or on Dask distributed.

Both executors yield the same events, in the order they happen:

- ``("start", case)``: a case began on a worker;
- ``("done", case, result)``: a case finished (``result`` as
  :func:`rankloci.sweep.task.run_case` returns it: a failed case is a result too);
- ``("tick",)``: nothing happened for a moment (the caller redraws its progress).

:func:`serial_events` runs the cases one after another in this process (each
in its own forked child under the limits).  :class:`DaskExecutor` submits one
Dask task per case to a cluster: a :class:`distributed.LocalCluster` of
single-threaded worker processes, or a running scheduler.  The task is
:func:`dask_case`, which reports its start and calls
:func:`~rankloci.sweep.task.run_case`; the model texts are scattered to the
workers once, not sent with every case.  Worker processes are started as
non-daemonic (``distributed.worker.daemon: False``) because each case forks a
child that enforces its limits, and daemonic processes may not have children.
"""

from __future__ import annotations

import time

from .task import run_case

__all__ = ["serial_events", "DaskExecutor", "dask_case", "worker_info", "SetupError"]

#: Dask event topic on which the tasks report that they started.
START_TOPIC = "rankloci-sweep-start"

#: Seconds between progress ticks while the cluster is busy.
TICK_SECONDS = 0.25

#: Seconds to wait for the first worker of a running scheduler.
WORKER_WAIT_SECONDS = 60.0

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


class SetupError(Exception):
    """The cluster cannot run the sweep (no worker, a worker without rankloci, ...)."""


def serial_events(cases, sources, *, timeout: float, memory: int):
    """Run the cases one after another in this process; yield the events."""
    for case in cases:
        yield ("start", case)
        yield ("done", case, run_case(case, sources.get(case.source), timeout=timeout,
                                      memory=memory))


def dask_case(case, text, timeout, memory):
    """The Dask task of one case: report the start, then :func:`run_case`."""
    try:
        from distributed import get_worker

        get_worker().log_event(START_TOPIC, case.id)
    except ValueError:            # not on a worker (a test calling it directly)
        pass
    return run_case(case, text, timeout=timeout, memory=memory)


def worker_info() -> dict:
    """What a worker can tell the client before the sweep: rankloci's version, daemon or not."""
    import multiprocessing

    from .. import __version__

    return {"version": __version__, "daemon": bool(multiprocessing.current_process().daemon)}


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


class DaskExecutor:
    """A Dask client and, for a local cluster, the cluster it owns.

    Use :meth:`local` or :meth:`remote`, then :meth:`events`; :meth:`close`
    (or ``with``) shuts down what it started.
    """

    def __init__(self, client, cluster=None, config=None):
        self.client = client
        self.cluster = cluster
        self._config = config
        self._futures: dict = {}

    @classmethod
    def local(cls, workers: int) -> "DaskExecutor":
        """A LocalCluster of ``workers`` single-threaded worker processes, no dashboard."""
        import logging

        import dask
        from distributed import Client, LocalCluster

        config = dask.config.set(DASK_CONFIG)
        try:
            # no dashboard; the scheduler's own HTTP server (health checks) on a free port,
            # not on 8787, which another cluster on the machine may hold
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None, memory_limit=0,
                                   silence_logs=logging.ERROR, scheduler_port=0,
                                   scheduler_kwargs={"dashboard_address": ":0"})
            client = Client(cluster)
        except BaseException:
            config.__exit__(None, None, None)
            raise
        return cls(client, cluster, config)

    @classmethod
    def remote(cls, address: str) -> "DaskExecutor":
        """A client of the scheduler at ``address`` (``tcp://HOST:8786``)."""
        from distributed import Client

        greeted(address, CONNECT_SECONDS)
        try:
            client = Client(address, timeout=WORKER_WAIT_SECONDS)
        except (OSError, TimeoutError) as e:
            raise SetupError(f"cannot reach the Dask scheduler at {address}: {e}") from None
        except (Exception, MemoryError) as e:  # noqa: BLE001 -- whatever answered is no scheduler
            # (a web server's reply read as a message length asks for exabytes)
            raise SetupError(f"no Dask scheduler answers at {address} ({type(e).__name__}: "
                             f"{str(e)[:120]})") from None
        return cls(client)

    def check_workers(self) -> int:
        """The number of worker threads; raises :class:`SetupError` for an unusable cluster."""
        from .. import __version__

        try:
            self.client.wait_for_workers(1, timeout=WORKER_WAIT_SECONDS)
        except TimeoutError:
            raise SetupError(f"no Dask worker joined the scheduler within "
                             f"{WORKER_WAIT_SECONDS:g} s") from None
        try:
            info = self.client.run(worker_info)
        except Exception as e:  # noqa: BLE001 -- any failure here is a worker without rankloci
            raise SetupError(f"the Dask workers cannot run rankloci ({type(e).__name__}: {e}); "
                             f"install it on every worker machine") from None
        for address, got in sorted(info.items()):
            if got["version"] != __version__:
                raise SetupError(f"worker {address} has rankloci {got['version']}, this "
                                 f"machine {__version__}: install the same version")
            if got["daemon"]:
                raise SetupError(f"worker {address} runs as a daemon process and cannot start "
                                 f"the child process that enforces each case's limits: start "
                                 f"it with DASK_DISTRIBUTED__WORKER__DAEMON=False")
        return sum(self.client.nthreads().values())

    def events(self, cases, sources, *, timeout: float, memory: int):
        """Submit every case (the most joints first) and yield the events as they happen."""
        import queue

        from distributed import as_completed

        started: queue.SimpleQueue = queue.SimpleQueue()
        by_id = {c.id: c for c in cases}
        self.client.subscribe_topic(START_TOPIC, lambda event: started.put(event[1]))
        needed = {c.source for c in cases if not c.problem}
        scattered = self.client.scatter({k: sources[k] for k in needed}, broadcast=False,
                                        hash=False) if needed else {}
        for case in cases:
            text = scattered.get(case.source)
            fut = self.client.submit(dask_case, case, text, timeout, memory, pure=False,
                                     priority=case.joints or 0)
            self._futures[fut.key] = (fut, case)
        pending = as_completed([f for f, _ in self._futures.values()])
        while not pending.is_empty():
            while not started.empty():
                cid = started.get()
                if cid in by_id:
                    yield ("start", by_id[cid])
            if not pending.has_ready():
                yield ("tick",)
                time.sleep(TICK_SECONDS)
                continue
            for fut in pending.next_batch(block=False):
                _, case = self._futures.pop(fut.key)
                yield ("done", case, self._result(fut, case, timeout, memory))
        self.client.unsubscribe_topic(START_TOPIC)

    @staticmethod
    def _result(fut, case, timeout, memory):
        """The result of a finished future; a task that failed (its worker died three
        times) is a failed case, not an exception."""
        if fut.status == "finished":
            return fut.result()
        from .task import failed_result

        try:
            error = fut.exception()
        except Exception as e:  # noqa: BLE001 -- a cancelled future
            error = e
        return failed_result(case, f"the Dask task failed: {type(error).__name__}: {error}",
                             timeout=timeout, memory=memory, transient=True)

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
        raise SetupError(f"no Dask scheduler answers at {address}: nothing came within "
                         f"{seconds:g} s (a Dask scheduler greets at once)") from None
    except (OSError, ValueError) as e:
        raise SetupError(f"cannot reach the Dask scheduler at {address}: "
                         f"{getattr(e, 'strerror', None) or e}") from None
    if not 0 < struct.unpack("<Q", head)[0] < 2 ** 24:
        raise SetupError(f"no Dask scheduler answers at {address}: what answers there speaks "
                         f"another protocol")
