"""``rankloci sweep``: serial and Dask runs agree, limits hold, an interrupted sweep resumes."""

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

import pytest

from rankloci.cli import main

#: Five small cases: planar2r, and planar3r at two lengths of link 2, with and without the
#: orientation row.
SPEC = """models = ["planar2r"]
timeout = 300
seed = 3

[[model]]
name = "planar3r"
[model.grid]
augment = ["", "sum(q1, q2, q3)"]
[model.grid.parameters]
l2 = [0.5, 1.5]
"""

#: Seconds a sweep subprocess may take to write its first case file before the test gives up.
FIRST_CASE_WAIT_S = 120.0


def _rows(path: Path, *, seconds=False) -> list[dict]:
    rows = list(csv.DictReader(io.StringIO(path.read_text())))
    if not seconds:
        for r in rows:
            del r["seconds"]
    return rows


def _without_key(data, key: str):
    """``data`` (JSON) without ``key`` at any depth: the times of a locus and its parts."""
    if isinstance(data, dict):
        return {k: _without_key(v, key) for k, v in data.items() if k != key}
    if isinstance(data, list):
        return [_without_key(v, key) for v in data]
    return data


def _without_seconds(md: str) -> list[str]:
    """summary.md with the seconds column blanked."""
    lines = md.splitlines()
    header = next(line for line in lines if line.startswith("| case "))
    k = [c.strip() for c in header.strip("|").split("|")].index("seconds")
    out = []
    for line in lines:
        if line.startswith("| ") and line.count(" | ") >= k:
            cells = line.strip("|").split(" | ")
            cells[k] = ""
            line = " | ".join(cells)
        out.append(line)
    return out


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    """The spec run with --serial: the reference of the other runs."""
    d = tmp_path_factory.mktemp("serial")
    (d / "spec.toml").write_text(SPEC)
    code = main(["sweep", str(d / "spec.toml"), "-o", str(d / "out"), "--serial"])
    return d, code


def test_a_serial_sweep_writes_a_locus_per_case_and_the_summary(serial):
    d, code = serial
    out = d / "out"
    assert code == 0
    rows = _rows(out / "summary.csv")
    assert [r["case"] for r in rows] == [
        "planar2r", "planar3r l2=0.5", "planar3r l2=0.5 + sum(q1, q2, q3)", "planar3r l2=1.5",
        "planar3r l2=1.5 + sum(q1, q2, q3)"]
    assert all(r["status"] == "done" and r["check"] == "pass" for r in rows)
    # planar2r: sin q2 = 0; planar3r: all links collinear; with the orientation row the one
    # component is mixed (tests/test_augmented.py derives it)
    assert [r["components"] for r in rows] == ["1"] * 5
    assert [r["kinds"] for r in rows] == ["", "", "1 mixed", "", "1 mixed"]
    files = sorted((out / "cases").glob("*.json"))
    assert len(files) == 5
    for f in files:
        data = json.loads(f.read_text())
        assert data["schema"] == "rankloci.locus/2" and data["seed"] == 3
        assert data["sweep"]["status"] == "done" and len(data["components"]) == 1
    md = (out / "summary.md").read_text()
    assert "5 cases: 5 done" in md and "(components.png)" not in md
    assert (out / "time.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_case_file_is_a_locus_that_rankloci_check_reads(serial, capsys):
    d, _ = serial
    f = next(p for p in (d / "out" / "cases").glob("planar2r-*.json"))
    assert main(["check", "planar2r", "--locus", str(f), "--samples", "3", "--quiet"]) == 0


@pytest.mark.slow
def test_a_two_worker_local_cluster_gives_the_serial_summary(serial, tmp_path):
    d, _ = serial
    code = main(["sweep", str(d / "spec.toml"), "-o", str(tmp_path / "out"), "--workers", "2"])
    assert code == 0
    assert _rows(tmp_path / "out" / "summary.csv") == _rows(d / "out" / "summary.csv")
    assert _without_seconds((tmp_path / "out" / "summary.md").read_text()) == _without_seconds(
        (d / "out" / "summary.md").read_text())
    for f in (d / "out" / "cases").glob("*.json"):
        a, b = json.loads(f.read_text()), json.loads((tmp_path / "out" / "cases" / f.name)
                                                     .read_text())
        for data in (a, b):
            data["sweep"].pop("worker")         # which worker ran it ("" in this process)
            data["sweep"].pop("peak_mib")       # a measurement, as the seconds
        assert _without_key(a, "seconds") == _without_key(b, "seconds")


def test_a_sweep_killed_midway_resumes_where_it_stopped(serial, tmp_path):
    d, _ = serial
    out = tmp_path / "out"
    run = "import sys; from rankloci.cli import main; sys.exit(main(sys.argv[1:]))"
    proc = subprocess.Popen([sys.executable, "-c", run, "sweep", str(d / "spec.toml"), "-o",
                             str(out), "--serial", "--quiet"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        end = time.monotonic() + FIRST_CASE_WAIT_S
        while not list((out / "cases").glob("*.json")) and time.monotonic() < end:
            time.sleep(0.05)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)     # the sweep and the child of its current case
        proc.wait()
    saved = {p.name: p.stat().st_mtime_ns for p in (out / "cases").glob("*.json")}
    assert 1 <= len(saved) < 5, "the kill came after the first case and before the last"
    for name in saved:                          # whole files only, never half-written ones
        json.loads((out / "cases" / name).read_text())
    assert not (out / "summary.csv").exists()
    err = io.StringIO()
    stderr, sys.stderr = sys.stderr, err
    try:
        code = main(["sweep", str(d / "spec.toml"), "-o", str(out), "--serial"])
    finally:
        sys.stderr = stderr
    assert code == 0
    assert f"{len(saved)} finished before, {5 - len(saved)} to run" in err.getvalue()
    for name, mtime in saved.items():           # not computed again
        assert (out / "cases" / name).stat().st_mtime_ns == mtime
    assert _rows(out / "summary.csv") == _rows(d / "out" / "summary.csv")
    assert not [p for p in (out / "cases").iterdir() if not p.name.endswith(".json")]


#: A planar arm of eight unit links: its locus takes minutes (over 30 s here), planar2r's
#: about a second.
PLANAR8R = ('name = "planar8r"\ntask = "planar"\n'
            + '[[joint]]\nkind = "revolute"\na = 1\n' * 8)


#: The rows of :func:`write_memory_spec`'s sweep with ``--memory 60``, in every mode.
MEMORY_ROWS = [("memory", "over 90 MiB"), ("done", ""), ("done", "")]


def write_memory_spec(d: Path) -> Path:
    """A spec of planar8r (which needs more than 90 MiB), planar2r and puma560 (which not)."""
    (d / "planar8r.toml").write_text(PLANAR8R)
    spec = d / "memory.toml"
    spec.write_text('models = ["planar8r.toml", "planar2r", "puma560"]\ntimeout = 120\n')
    return spec


def test_a_case_over_its_time_or_memory_is_reported_and_the_rest_still_run(tmp_path, capsys):
    (tmp_path / "planar8r.toml").write_text(PLANAR8R)
    spec = tmp_path / "spec.toml"
    spec.write_text('models = ["planar8r.toml", "planar2r"]\ntimeout = 3\n')
    code = main(["sweep", str(spec), "-o", str(tmp_path / "t"), "--serial"])
    assert code == 1
    rows = _rows(tmp_path / "t" / "summary.csv")
    assert [(r["case"], r["status"], r["note"]) for r in rows] == [
        ("planar8r.toml", "timeout", "over 3 s"), ("planar2r", "done", "")]
    assert "1 out of time" in (tmp_path / "t" / "summary.md").read_text()
    # 90 MiB of the case's own memory: planar8r passes it (it holds over 100 MiB after 15 s),
    # planar2r and puma560 stay near 40 to 60 (what a case touches of what it inherits from
    # its parent, its own allocations, and its certificate)
    # in a process of its own, as a user runs it: a case forked from this test process would
    # count the pages it touches of everything the earlier tests loaded
    run = subprocess.run([sys.executable, "-m", "rankloci", "sweep",
                          str(write_memory_spec(tmp_path)), "-o", str(tmp_path / "m"), "--serial",
                          "--memory", "90", "--quiet"], capture_output=True, text=True)
    assert run.returncode == 1, run.stderr
    rows = _rows(tmp_path / "m" / "summary.csv")
    assert [(r["status"], r["note"]) for r in rows] == MEMORY_ROWS
    # resuming with a larger limit computes the timed-out case again, the finished one not
    code = main(["sweep", str(spec), "-o", str(tmp_path / "t"), "--serial", "--timeout", "3.5"])
    assert code == 1 and "1 finished before, 1 to run" in capsys.readouterr().err
    assert _rows(tmp_path / "t" / "summary.csv")[0]["note"] == "over 3.5 s"


@pytest.mark.parametrize("spec, args, message", [
    ("models = [", [], "s.toml: invalid TOML"),
    ('models = ["planar9r"]\n', [], "no built-in model 'planar9r'"),
    ('models = ["planar2r"]\n[grid.parameters]\nl1 = ["exec(1)"]\n', [],
     "call of 'exec' is not allowed"),
    ('models = ["planar2r"]\n', ["--serial", "--workers", "2"], "--serial runs without Dask"),
    ('models = ["planar2r"]\n', ["--scheduler", "localhost"], "tcp://HOST:8786"),
    ('models = ["planar2r"]\n', ["--workers", "0"], "number of workers"),
])
def test_bad_input_is_one_line_exit_2_and_nothing_written(tmp_path, capsys, spec, args, message):
    (tmp_path / "s.toml").write_text(spec)
    out = tmp_path / "out"
    assert main(["sweep", str(tmp_path / "s.toml"), "-o", str(out), *args]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()


def test_the_progress_bar_on_a_terminal_shows_done_running_failed_and_eta():
    from rankloci.cli.sweep import _Progress

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    class Case:
        def __init__(self, i):
            self.id, self.label = f"c{i}", f"case {i}"

    stream = Terminal()
    bar = _Progress(total=4, to_run=3, quiet=False, stream=stream)
    bar.started(Case(1))
    bar.started(Case(2))
    bar.finished(Case(1), {"status": "timeout", "check": "", "note": "over 1 s", "seconds": 1.0,
                           "components": None})
    last = stream.getvalue().split("\r")[-1]
    assert "2/4 done, 1 running, 1 failed, ETA " in last and "--" not in last
    bar.close()
    assert stream.getvalue().endswith("\n")
