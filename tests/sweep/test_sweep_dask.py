"""``rankloci sweep`` on real Dask clusters: lost workers, the order of the cases, the checks.

A cluster here is a ``dask scheduler`` and ``dask worker`` processes started as a user
starts them (:func:`cluster`), or the local cluster of ``--workers``.
"""

from __future__ import annotations

import csv
import io
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import psutil
import pytest

from rankloci.cli import main

#: Two models with several cases each, so that a worker killed early holds cases of both.
SPEC = """seed = 1
timeout = 300

[[model]]
name = "planar3r"
[model.grid]
augment = ["", "sum(q1, q2, q3)"]
[model.grid.parameters]
l2 = [0.5, 1.5]

[[model]]
name = "planar2r"
[model.grid.parameters]
l1 = [1, 2, 3]
"""

#: Seconds a cluster may take to start, and a sweep of :data:`SPEC` to finish.
START_WAIT_S = 60.0
SWEEP_WAIT_S = 240.0

#: The environment of a worker that may fork the child of each case.
WORKER_ENV = {"DASK_DISTRIBUTED__WORKER__DAEMON": "False"}


def _rows(path: Path) -> list[dict]:
    return list(csv.DictReader(io.StringIO(path.read_text())))


class Cluster:
    """A ``dask scheduler`` and single-threaded ``dask worker`` processes, without nannies."""

    def __init__(self, tmp: Path, workers: int, worker_args=(), env=None, worker_envs=None):
        self.file = tmp / "scheduler.json"
        env = os.environ | WORKER_ENV | (env or {})
        # run from tmp: "python -m" puts its working directory first on sys.path
        quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
        self.scheduler = subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_scheduler", "--port", "0",
             "--no-dashboard", "--scheduler-file", str(self.file)], env=env, cwd=tmp, **quiet)
        self.workers = []
        try:
            self._wait(lambda: self.file.exists() and self.file.stat().st_size)
            self.address = json.loads(self.file.read_text())["address"]
            for i in range(workers):
                self.workers.append(subprocess.Popen(
                    [sys.executable, "-m", "distributed.cli.dask_worker", self.address,
                     "--nthreads", "1", "--no-nanny", "--memory-limit", "0", "--no-dashboard",
                     *worker_args], env=env | (worker_envs[i] if worker_envs else {}),
                    cwd=tmp, **quiet))
            from distributed import Client

            with Client(self.address, timeout=START_WAIT_S) as client:
                client.wait_for_workers(workers, timeout=START_WAIT_S)
        except BaseException:
            self.close()
            raise

    @staticmethod
    def _wait(ready):
        end = time.monotonic() + START_WAIT_S
        while not ready():
            assert time.monotonic() < end, "the Dask cluster did not start"
            time.sleep(0.05)

    def close(self):
        for proc in [*self.workers, self.scheduler]:
            if proc.poll() is None:
                proc.kill()
            proc.wait()


@pytest.fixture
def cluster(tmp_path):
    clusters = []

    def start(workers=2, worker_args=(), env=None, worker_envs=None):
        clusters.append(Cluster(tmp_path, workers, worker_args, env, worker_envs))
        return clusters[-1]

    yield start
    for c in clusters:
        c.close()


def _sweep(args, **kw):
    run = "import sys; from rankloci.cli import main; sys.exit(main(sys.argv[1:]))"
    return subprocess.Popen([sys.executable, "-c", run, "sweep", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kw)


def _kill_a_worker_mid_case(c: Cluster, args):
    """Run the sweep; kill the first worker seen running a case (its forked child).

    Returns the sweep's exit code, its stderr and the killed worker.
    """
    proc = _sweep([*args, "--scheduler", c.address])
    try:
        victim = None
        end = time.monotonic() + SWEEP_WAIT_S
        while victim is None and proc.poll() is None and time.monotonic() < end:
            victim = next((w for w in c.workers if psutil.Process(w.pid).children()), None)
            time.sleep(0.02)
        assert victim is not None, "no worker ran a case"
        victim.send_signal(signal.SIGKILL)
        victim.wait()
        _, err = proc.communicate(timeout=SWEEP_WAIT_S)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc.returncode, err, victim


@pytest.mark.slow
def test_a_worker_killed_mid_case_costs_its_case_only_and_the_sweep_completes(cluster,
                                                                              tmp_path):
    (tmp_path / "spec.toml").write_text(SPEC)
    c = cluster(workers=2)
    code, err, victim = _kill_a_worker_mid_case(c, [str(tmp_path / "spec.toml"), "-o",
                                                    str(tmp_path / "out")])
    assert code == 0, err
    rows = _rows(tmp_path / "out" / "summary.csv")
    assert len(rows) == 7
    assert all(r["status"] == "done" and r["check"] == "pass" for r in rows), rows
    # the case it was running started again on the other worker, and only that case
    assert err.count("was lost") == 1, err
    survivor = next(w for w in c.workers if w is not victim)
    assert survivor.poll() is None
    records = [json.loads(p.read_text())["sweep"] for p in (tmp_path / "out" / "cases")
               .glob("*.json")]
    assert all(r["worker"] for r in records) and len({r["worker"] for r in records}) <= 2


@pytest.mark.slow
def test_a_case_whose_workers_all_died_names_the_case_the_worker_and_the_cause(cluster,
                                                                                tmp_path):
    """With no failure allowed, the case of the killed worker fails (and is resumed)."""
    (tmp_path / "spec.toml").write_text(SPEC)
    c = cluster(workers=2, env={"DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "0"})
    args = [str(tmp_path / "spec.toml"), "-o", str(tmp_path / "out")]
    code, err, victim = _kill_a_worker_mid_case(c, args)
    assert code == 1, err
    rows = _rows(tmp_path / "out" / "summary.csv")
    failed = [r for r in rows if r["status"] != "done"]
    assert len(failed) == 1 and failed[0]["status"] == "error", rows
    case = failed[0]["case"]
    record = next(d["sweep"] for d in (json.loads(p.read_text()) for p in
                                       (tmp_path / "out" / "cases").glob("*.json"))
                  if d["sweep"]["case"] == case)
    assert record["transient"] and record["worker"].startswith("tcp://")
    message = record["message"]
    assert case in message and record["worker"] in message and "died" in message, message
    assert "NoneType" not in err and f"on worker {record['worker']}" in err
    # run again (on the worker left), only that case is computed
    code = _sweep(args + ["--scheduler", c.address]).wait(timeout=SWEEP_WAIT_S)
    assert code == 0
    assert all(r["status"] == "done" for r in _rows(tmp_path / "out" / "summary.csv"))


#: Cases listed shortest first: the sweep must run them longest expected first.
ORDER_SPEC = """models = ["planar2r", "planar3r", "planar4r"]
timeout = 300

[[model]]
name = "planar3r"
[model.grid]
augment = ["sum(q1, q2, q3)"]
"""


@pytest.mark.slow
def test_the_longest_expected_cases_run_first_on_a_local_cluster(tmp_path, capsys):
    (tmp_path / "spec.toml").write_text(ORDER_SPEC)
    code = main(["sweep", str(tmp_path / "spec.toml"), "-o", str(tmp_path / "out"),
                 "--workers", "1", "--no-dashboard"])
    assert code == 0
    # one worker: the cases finish in the order they start
    finished = [line.split("] ", 1)[1].split(":", 1)[0]
                for line in capsys.readouterr().err.splitlines() if "/4] " in line]
    assert finished == ["planar4r", "planar3r + sum(q1, q2, q3)", "planar3r", "planar2r"]


@pytest.mark.slow
def test_the_memory_limit_gives_the_serial_rows_on_a_local_cluster(tmp_path):
    from test_sweep_cli import MEMORY_ROWS, write_memory_spec

    code = main(["sweep", str(write_memory_spec(tmp_path)), "-o", str(tmp_path / "m"),
                 "--workers", "2", "--memory", "90", "--no-dashboard"])
    assert code == 1
    assert [(r["status"], r["note"]) for r in _rows(tmp_path / "m" / "summary.csv")] == \
        MEMORY_ROWS


def test_an_unanswering_scheduler_is_given_up_at_the_connect_timeout(tmp_path, capsys):
    import socket

    (tmp_path / "spec.toml").write_text(SPEC)
    with socket.socket() as server:       # accepts connections (the kernel does), never answers
        server.bind(("127.0.0.1", 0))
        server.listen(8)
        address = "tcp://127.0.0.1:%d" % server.getsockname()[1]
        t0 = time.monotonic()
        code = main(["sweep", str(tmp_path / "spec.toml"), "-o", str(tmp_path / "out"),
                     "--scheduler", address, "--connect-timeout", "1.5"])
        took = time.monotonic() - t0
    err = capsys.readouterr().err
    assert code == 2 and f"at {address} within 1.5 s (--connect-timeout)" in err
    assert took < 1.5 + 5.0 and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_workers_with_another_or_a_broken_rankloci_are_named(cluster, tmp_path):
    import shutil

    import rankloci

    # a stale copy: the same version string, one line of source changed
    stale = tmp_path / "stale"
    shutil.copytree(Path(rankloci.__file__).parent, stale / "rankloci",
                    ignore=shutil.ignore_patterns("__pycache__"))
    with open(stale / "rankloci" / "locus.py", "a") as f:
        f.write("\n# a local change\n")
    broken = tmp_path / "broken" / "rankloci"
    broken.mkdir(parents=True)
    (broken / "__init__.py").write_text("raise ImportError('a broken installation')\n")
    c = cluster(workers=2, worker_envs=[{"PYTHONPATH": str(stale)},
                                        {"PYTHONPATH": str(broken.parent)}])
    (tmp_path / "spec.toml").write_text(SPEC)
    proc = _sweep([str(tmp_path / "spec.toml"), "-o", str(tmp_path / "out"), "--scheduler",
                   c.address])
    _, err = proc.communicate(timeout=SWEEP_WAIT_S)
    assert proc.returncode == 2 and len(err.strip().splitlines()) == 1, err
    from distributed import Client

    with Client(c.address, timeout=START_WAIT_S) as client:
        pids = client.run(os.getpid)
    by_pid = {w.pid: a for a, w in zip(sorted(pids, key=pids.get), sorted(
        c.workers, key=lambda w: w.pid))}
    stale_worker, broken_worker = by_pid[c.workers[0].pid], by_pid[c.workers[1].pid]
    assert f"worker {stale_worker} " in err and "another rankloci source (version " \
        f"{rankloci.__version__}" in err
    assert f"worker {broken_worker} cannot run rankloci" in err and "broken installation" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_the_local_cluster_serves_its_dashboard():
    import urllib.request

    from rankloci.sweep.execute import DaskExecutor

    with DaskExecutor.local(1) as ex:
        link = ex.dashboard_link
        assert link and link.startswith("http://") and link.endswith("/status")
        with urllib.request.urlopen(link, timeout=30) as page:
            assert page.status == 200 and b"Dask" in page.read()


def _most_cases_at_once(proc, worker) -> int:
    """The most case children ``worker`` had at once while the sweep ``proc`` ran."""
    most = 0
    while proc.poll() is None:
        try:
            most = max(most, len(psutil.Process(worker.pid).children()))
        except psutil.NoSuchProcess:
            break
        time.sleep(0.01)
    return most


@pytest.mark.slow
def test_a_worker_runs_no_more_cases_at_once_than_its_memory_holds(cluster, tmp_path):
    (tmp_path / "spec.toml").write_text(SPEC)
    c = cluster(workers=1, worker_args=["--nthreads", "2", "--resources", "MEMORY=1000"])
    args = [str(tmp_path / "spec.toml"), "--scheduler", c.address]
    proc = _sweep([*args, "-o", str(tmp_path / "big"), "--memory", "2000"])
    _, err = proc.communicate(timeout=SWEEP_WAIT_S)
    assert proc.returncode == 2 and "the largest offers 1000 MiB" in err, err
    for memory, at_once in (("600", 1), ("400", 2)):
        proc = _sweep([*args, "-o", str(tmp_path / memory), "--memory", memory])
        assert _most_cases_at_once(proc, c.workers[0]) == at_once
        assert proc.wait(timeout=SWEEP_WAIT_S) == 0


@pytest.mark.slow
def test_the_robot_collection_example_runs_as_written_and_prints_the_dashboard(tmp_path,
                                                                               capsys):
    spec = Path(__file__).resolve().parents[2] / "examples" / "sweeps" / "robots.toml"
    code = main(["sweep", str(spec), "-o", str(tmp_path / "out"), "--workers", "2"])
    err = capsys.readouterr().err
    assert code == 0, err
    rows = _rows(tmp_path / "out" / "summary.csv")
    assert len(rows) == 6 and all(r["status"] == "done" and r["check"] == "pass" for r in rows)
    assert "rankloci: Dask dashboard: http://" in err
