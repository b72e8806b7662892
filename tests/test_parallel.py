"""Worker processes for one locus (rankloci.parallel, ``--jobs``, ``jobs=``): the same locus
for any number of processes, and bad numbers refused in one line."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
import sympy as sp

import rankloci
from rankloci.cli import main
from rankloci.errors import ArgumentError
from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus, method_for
from rankloci.parallel import Workers, available_cores, check_jobs
from rankloci.verify import verified_locus


def _without_seconds(doc):
    """A locus document without its measured times."""
    if isinstance(doc, dict):
        return {k: _without_seconds(v) for k, v in doc.items() if k != "seconds"}
    if isinstance(doc, list):
        return [_without_seconds(v) for v in doc]
    return doc


def _locus_json(capsys, *argv):
    code = main(["locus", *argv, "--format", "json", "--quiet"])
    out, _ = capsys.readouterr()
    assert code == 0
    return _without_seconds(json.loads(out))


@pytest.mark.parametrize("argv", [
    ["planar3r"],
    ["planar4r", "--augment", "q1 + q2 + q3 + q4"],     # J's locus in a worker beside J_aug's
    ["puma560", "--numeric-parameters"],
], ids=lambda a: " ".join(a))
def test_one_and_two_processes_give_the_same_locus(capsys, monkeypatch, argv):
    import rankloci.parallel

    # the parts in workers also for these small chains (the command's child is forked from
    # this process, the workers start afresh)
    monkeypatch.setattr(rankloci.parallel, "WORKER_MIN_VARIABLES", 1)
    one = _locus_json(capsys, *argv, "--jobs", "1")
    two = _locus_json(capsys, *argv, "--jobs", "2")
    assert one["components"] and one == two


def test_the_self_check_in_a_worker_gives_the_same_recomputation(monkeypatch):
    """A first locus that the certificate fails: its numeric check runs in a worker beside the
    certificate (here for 3 joints too), and its regular points go back as hints, as with one
    process."""
    import rankloci.parallel

    monkeypatch.setattr(rankloci.parallel, "WORKER_MIN_VARIABLES", 1)
    model = load_model("planar3r")
    tm, ref = task_matrix(model, frame="auto"), task_matrix(model)
    q2, q3 = tm.variables[1], tm.variables[2]

    def too_large(t, seed, hints=(), method=None):
        locus = compute_locus(t, method or method_for(t.shape), rng=np.random.default_rng(seed),
                              hints=hints)
        if hints:
            return locus
        (c,) = locus.components
        return dataclasses.replace(locus, components=(dataclasses.replace(
            c, equations=(sp.sin(q3),), solved=(), free=(q2,)),))

    got = {}
    for jobs in (1, 2):
        with Workers(jobs) as workers:
            locus, v = verified_locus(too_large, tm, ref, seed=0, workers=workers)
        got[jobs] = (_without_seconds(locus.to_dict()), v.attempts, v.problems)
    assert got[1][1][0] == "as computed: certificate failed, numeric check failed"
    assert got[1] == got[2]


def test_a_part_in_a_worker_raises_what_it_raised():
    with Workers(2) as workers:
        task = workers.submit(check_jobs, 0)
        with pytest.raises(ArgumentError, match="jobs="):
            task.result()


def test_a_part_awaited_past_the_time_limit_stops_the_workers():
    import time

    with Workers(2) as workers:
        task = workers.submit(time.sleep, 30)
        start = time.monotonic()
        with pytest.raises(rankloci.errors.LocusTimeout):
            task.result(should_stop=lambda: time.monotonic() > start + 0.5)
        assert time.monotonic() - start < 10
        assert workers._executor is None


@pytest.mark.parametrize("bad", [0, -1, 1.5, "2", True])
def test_jobs_must_be_a_positive_integer(bad):
    with pytest.raises(ArgumentError, match="jobs="):
        rankloci.locus("planar2r", jobs=bad)


def test_jobs_default_to_the_cores_of_the_process():
    assert check_jobs(None) == available_cores() >= 1


@pytest.mark.parametrize("command", [["locus", "planar2r"], ["check", "planar2r"],
                                     ["report", "planar2r", "--format", "md"]])
@pytest.mark.parametrize("value", ["0", "x", "-2"])
def test_a_bad_jobs_option_is_one_line_and_exit_2(capsys, tmp_path, command, value):
    code = main([*command, "--jobs", value] + (["-o", str(tmp_path / "r")]
                                               if command[0] == "report" else []))
    out, err = capsys.readouterr()
    assert code == 2 and not out
    assert err.count("\n") == 1 and "--jobs" in err and repr(value) in err
    assert not list(tmp_path.iterdir())


def _dies_in_a_worker(parent: int) -> str:
    """Ends its process in a worker (as a worker whose start fails does); here it returns."""
    import os

    if os.getpid() != parent:
        os._exit(3)
    return "computed here"


def test_a_part_whose_worker_dies_is_computed_here():
    """A worker that cannot start or dies breaks the pool: the part, a pure function of its
    arguments, is then computed in this process, and later parts start new workers."""
    import os

    with Workers(2) as workers:
        assert workers.submit(_dies_in_a_worker, os.getpid()).result() == "computed here"
        assert workers.submit(os.getpid).result() != os.getpid()


def test_a_process_forked_from_the_forkserver_owner_spawns_its_workers(monkeypatch):
    """The command line's limited child is forked from a process that may have started the
    forkserver: that server is its parent's, so the child's workers are spawned instead."""
    import os

    import rankloci.parallel as parallel

    monkeypatch.setattr(parallel, "_FORKSERVER_OWNER", None)
    assert parallel._start_method() == "forkserver"
    assert parallel._FORKSERVER_OWNER == os.getpid()
    monkeypatch.setattr(parallel, "_FORKSERVER_OWNER", os.getpid() + 1)   # a parent's server
    assert parallel._start_method() == "spawn"
    with Workers(2) as workers:                                          # and spawned workers
        assert workers.submit(max, 3, 7).result(lambda: False) == 7      # compute
