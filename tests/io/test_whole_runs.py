"""The corpus-wide whole-run benchmark (``benchmarks/whole_runs.py``): one run per process,
timed, its memory measured, its verdict and target recorded, the locus shown graded.

The cases here are the fastest: a built-in model, a time limit that cannot be met, and one
URDF chain graded against Pinocchio; the tables are rendered from rows written here.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def _load(name: str):
    """A script of benchmarks/ as a module (benchmarks/ is no package)."""
    key = f"benchmarks_{name}"
    if key not in sys.modules:
        spec = importlib.util.spec_from_file_location(key, REPO / "benchmarks" / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[key] = module
        spec.loader.exec_module(module)
    return sys.modules[key]


whole_runs = _load("whole_runs")


def _spec(path, **kw):
    return {"path": str(path), "base": None, "tip": None, "task": None, "seed": 0,
            "timeout": 60.0, "grade": False, "n": None, "joint_names": None} | kw


def test_whole_run_of_a_built_in_model_is_certified_timed_and_measured():
    res = whole_runs.run_case(_spec(REPO / "kinematics_models" / "planar2r.toml"))
    assert res["status"] == "certified" and res["complete"] is True
    assert res["certificate_verdict"] == "passed" and res["certificate_s"] > 0
    assert res["shape"] == [2, 2] and res["joints"] == 2 and res["components"] >= 1
    # the process from its start: the imports and the call are inside it
    assert 0 < res["engine_s"] <= res["call_s"] < res["whole_s"] <= res["process_s"]
    # a Python process with sympy and numpy loaded holds tens of MiB at least
    assert 30 < res["peak_rss_mib"] < 8192
    assert res["target_s"] == 10.0
    assert res["within"] == (res["whole_s"] <= 10.0)


def test_a_run_past_its_time_limit_is_a_time_out_and_not_within_target():
    res = whole_runs.run_case(_spec(REPO / "kinematics_models" / "puma560.toml",
                                    timeout=0.001, n=6))
    assert res["status"] == "timeout"
    assert res["within"] is False and res["target_s"] == 10.0
    assert "engine_s" not in res


@pytest.mark.slow
def test_the_locus_shown_of_a_urdf_chain_is_graded_against_pinocchio():
    pytest.importorskip("pinocchio")
    corpus = _load("corpus")
    root = corpus.robots_dir()
    chains, _, _ = corpus.corpus(root)
    chain = next(c for c in chains if c.file == "ur_description/urdf/ur5_robot.urdf")
    res = whole_runs.run_case(_spec(root / chain.file, base=chain.base, tip=chain.tip,
                                    task=chain.task, grade=True, n=chain.n,
                                    joint_names=list(chain.joints)))
    assert res["status"] == "certified"
    assert res["grade"] == "pass", res.get("grade_reason")
    assert res["grading"]["mapping"]["ok"]
    assert res["grading"]["completeness"]["singular"] > 0


def _row(kind, key, status, whole_s, joints=7, grade=None):
    res = {"status": status, "whole_s": whole_s, "joints": joints, "shape": [6, joints],
           "engine_s": whole_s / 2, "certificate_s": 0.5, "peak_rss_mib": 150.0,
           "complete": {"certified": True, "undecided": None}.get(status, False),
           "target_s": whole_runs.target(joints)}
    res["within"] = status in ("certified", "undecided") and whole_s <= res["target_s"]
    if grade:
        res["grade"] = grade
    return {"kind": kind, "key": key, "joints": joints, "result": res}


def test_summary_counts_each_verdict_and_the_missing_chains():
    rows = [_row("chain", "a", "certified", 4.0, grade="pass"),
            _row("chain", "b", "undecided", 40.0, joints=9, grade="pass"),
            _row("chain", "c", "refused", 3.0, grade="fail"),
            _row("chain", "d", "timeout", 140.0),
            _row("model", "m", "certified", 12.0)]
    s = whole_runs.summary(rows, expected_chains=10)
    assert (s["certified"], s["undecided"], s["refused"], s["timeout"]) == (2, 1, 1, 1)
    assert s["within_target"] == 2          # a (4 s of 10) and b (40 s of 60); m is over 10 s
    assert (s["graded_pass"], s["graded_fail"], s["graded_other"]) == (2, 1, 1)
    assert s["chains_missing"] == 6 and s["models"] == 1 and s["with_target"] == 5
    meta = {"command": "whole_runs.py", "date": "today", "seed": 0, "timeout_s": 120.0,
            "python": "3.11", "machine": "x86_64", "cores": 2, "load": "3.0"}
    text = "\n".join(whole_runs.render_whole_section(rows, meta, s))
    assert "**6 chains of the corpus have no whole run yet**" in text
    assert "- refused: c:" in text and "- timeout: d:" in text
    # the slowest first
    assert text.index("| d |") < text.index("| b |") < text.index("| m |")


def test_a_chain_without_a_whole_run_is_pending_in_the_corpus_table():
    corpus = _load("corpus")
    meta = {"example_robot_data": "6.0.0", "pinocchio": "3", "seed": 0, "python": "3.11",
            "machine": "x86_64", "jobs": 2, "timeout_s": 60.0}
    row = {"robot": "ur", "file": "u.urdf", "base": "b", "tip": "t", "n": 6, "task": "full",
           "status": "pass", "reason": "", "locus_s": 0.3, "components": 3}
    done = row | {"tip": "t2", "whole": _row("chain", "x", "certified", 4.0, 6, "pass")["result"]}
    table = corpus.render_markdown([row, done], [], 0, meta)
    assert "| peak RSS (MiB) |" in table
    assert "| pending |" in table
    assert "| 4.0 | 2.0 | 0.5 | 150 | true | yes | pass |" in table
    # without whole runs the table keeps its columns
    assert "peak RSS" not in corpus.render_markdown([row], [], 0, meta)
