"""Benchmark: the whole run a user waits for, certificate included, on every chain and model.

For every chain of ``benchmarks/corpus.py`` (example-robot-data's URDF files) and every model
file of ``kinematics_models/`` and ``kinematics_models/extra/``, in its own process with a
time limit, one at a time:

- the whole computation of ``rankloci locus``: ``rankloci.load_model`` and ``rankloci.locus``
  (through ``certified_locus``: engine, numeric self-check, certificate, recomputations), with
  the default ``jobs`` (every core the process may use) and seed 0.  The chains' task is the
  corpus's (tip position up to 3 joints, full otherwise), the model files' their default;
- timed: *engine* is the locus's ``seconds`` (the engine's time for the locus shown),
  *certificate* its certificate's ``seconds``, *whole run* the process from its start (Python
  and the imports included) to the locus, as a user of the command line waits for it;
- *peak RSS*: the largest resident set (``VmHWM``) of any process of the run (the run and the
  worker processes it starts, sampled every POLL_S seconds) until the locus is done;
- the verdict, ``complete``: true (certified), null (undecided), false (refused);
- *within target*: certified or undecided, and the whole run within TARGETS;
- for the URDF chains, the locus shown graded against Pinocchio with
  :func:`corpus.grade` (mapping, soundness, completeness).

Each row is appended to ``benchmarks/whole_runs.jsonl`` as soon as it is done, so a run that
is stopped leaves its rows; ``--resume`` skips the rows already there.  ``--render`` merges
the rows into ``benchmarks/corpus.json`` (a ``whole`` entry per chain, and ``models``) and
writes ``benchmarks/corpus.md`` again with the new columns.  Usage::

    nice -n 10 python benchmarks/whole_runs.py [--timeout 120] [--robots a,b,...]
        [--max-per-robot N] [--min-joints N] [--only chains|models] [--resume] [--render]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import threading
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
MODELS_DIR = HERE.parent / "kinematics_models"
ROWS = HERE / "whole_runs.jsonl"

#: the whole run's target, by number of joints: (at most this many joints, seconds)
TARGETS = ((7, 10.0), (9, 60.0))

#: Seconds between two samples of the run's processes' peak resident sets.
POLL_S = 0.25

#: The locus call has its own time limit (``timeout``); a process still running this many
#: seconds after it is stopped (a long step in compiled code is not interrupted).
KILL_GRACE_S = 20.0

#: Once the locus is done, grading against Pinocchio gets this many seconds.
GRADING_ALLOWANCE_S = 120.0

#: Model files that need an option to name their chain.
MODEL_OPTIONS = {"iiwa_offsets.urdf": {"tip": "link_7"}}


def target(joints: int) -> float | None:
    """The whole run's target in seconds for a chain of ``joints`` joints (None beyond 9)."""
    return next((t for n, t in TARGETS if joints <= n), None)


def _corpus_module():
    sys.path.insert(0, str(HERE))
    import corpus

    return corpus


# --- one case, in its own process ----------------------------------------------------------

def _vm_hwm_kib(pid) -> int | None:
    """The peak resident set of process ``pid`` in KiB (``VmHWM``), or None once it is gone."""
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def _session_pids(sid: int) -> list[int]:
    """The processes of session ``sid`` (the run and every process it started)."""
    out = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        # the fields after the command name (in parentheses, which may hold spaces)
        fields = stat[stat.rindex(")") + 2:].split()
        if len(fields) > 3 and int(fields[3]) == sid:
            out.append(int(entry))
    return out


def _child_case(spec: dict) -> int:
    """Compute one whole run in this process; print the result, then the grading, as JSON."""
    import numpy as np

    import rankloci
    from rankloci.api.calls import certified_locus
    from rankloci.errors import LocusTimeout, RanklociError

    def emit(d):
        print(json.dumps(d), flush=True)

    t0 = time.perf_counter()
    try:
        model = rankloci.load_model(spec["path"], base_link=spec.get("base"), tip=spec.get("tip"))
        locus = rankloci.locus(model, task=spec.get("task"), seed=spec["seed"],
                               timeout=spec["timeout"])
    except LocusTimeout as e:
        emit({"status": "timeout", "reason": str(e), "call_s": time.perf_counter() - t0})
        return 0
    except RanklociError as e:
        emit({"status": "error", "reason": f"rankloci: {e}", "call_s": time.perf_counter() - t0})
        return 0
    call_s = time.perf_counter() - t0
    # the matrix the locus was computed from: the pipeline keeps it beside the locus
    _, tm = certified_locus(model, task=spec.get("task"), seed=spec["seed"])
    cert = locus.certificate
    verdict = {True: "certified", None: "undecided", False: "refused"}[locus.complete]
    emit({"status": verdict,
          "reason": "" if cert is None or cert.passed else "; ".join(cert.findings)[:300],
          "call_s": call_s, "engine_s": locus.seconds,
          "certificate_s": None if cert is None else cert.seconds,
          "certificate_verdict": None if cert is None else cert.verdict,
          "complete": locus.complete, "shape": list(tm.shape), "joints": len(tm.variables),
          "components": sum(c.for_model for c in locus.components),
          "degenerate": locus.degenerate, "done": True})
    if not spec.get("grade"):
        return 0
    corpus = _corpus_module()
    path = Path(spec["path"])
    try:
        ref = corpus.PinocchioJacobian(path.read_text(encoding="utf-8"),
                                       tuple(spec["joint_names"]),
                                       spec["tip"], spec["task"])
        g = corpus.grade(model, tm, locus, ref, np.random.default_rng(spec["seed"]))
    except Exception as e:  # a grading failure is a result, not a crash of the benchmark
        emit({"grade": "error", "grade_reason": corpus._short(f"{type(e).__name__}: {e}", 300)})
        return 0
    emit({"grade": "pass" if g["ok"] else "fail", "grade_reason": g["reason"],
          "grading": {k: g[k] for k in ("mapping", "completeness")}})
    return 0


def run_case(spec: dict) -> dict:
    """``_child_case`` in a fresh process of its own session, timed, its memory sampled."""
    import queue

    cmd = [sys.executable, str(Path(__file__).resolve()), "--case", json.dumps(spec)]
    start = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    peaks: dict[int, int] = {}
    sampling = threading.Event()

    def sample():
        while not sampling.is_set():
            for pid in _session_pids(proc.pid):
                kib = _vm_hwm_kib(pid)
                if kib is not None:
                    peaks[pid] = max(peaks.get(pid, 0), kib)
            sampling.wait(POLL_S)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    lines: queue.Queue = queue.Queue()
    err: list[str] = []

    def pump():
        for line in proc.stdout:
            lines.put(line)
        lines.put(None)

    threading.Thread(target=pump, daemon=True).start()
    err_reader = threading.Thread(target=err.extend, args=(proc.stderr,), daemon=True)
    err_reader.start()
    deadline = start + spec["timeout"] + KILL_GRACE_S
    res: dict = {}
    stopped = False
    while True:
        try:
            line = lines.get(timeout=max(0.01, min(1.0, deadline - time.monotonic())))
        except queue.Empty:
            if time.monotonic() > deadline:
                stopped = True
                break
            continue
        if line is None:
            break
        if not line.startswith("{"):
            continue
        part = json.loads(line)
        if part.get("done") or part.get("status") in ("timeout", "error"):
            res.update(part, whole_s=time.monotonic() - start,
                       peak_rss_mib=round(max(peaks.values(), default=0) / 1024, 1) or None)
            deadline = time.monotonic() + GRADING_ALLOWANCE_S
        else:
            res.update(part)
    if stopped:
        os.killpg(proc.pid, 9)
    proc.wait()
    sampling.set()
    sampler.join(timeout=5)
    err_reader.join(timeout=5)
    wall = time.monotonic() - start
    if not res:
        if stopped:
            res = {"status": "timeout", "reason": f"stopped after {wall:.0f} s",
                   "whole_s": wall}
        else:
            tail = ("".join(err).strip().splitlines() or ["(no output)"])[-1]
            res = {"status": "error", "reason": f"exit code {proc.returncode}: {tail}"[:300],
                   "whole_s": wall}
        res["peak_rss_mib"] = round(max(peaks.values(), default=0) / 1024, 1) or None
    elif stopped and res.get("done") and "grade" not in res:
        res.update(grade="timeout", grade_reason=f"grading did not finish within "
                                                 f"{GRADING_ALLOWANCE_S:g} s")
    elif "grade" not in res and spec.get("grade") and res.get("done"):
        tail = ("".join(err).strip().splitlines() or ["(no output)"])[-1]
        res.update(grade="error", grade_reason=f"exit code {proc.returncode}: {tail}"[:300])
    res.pop("done", None)
    res["process_s"] = wall
    n = res.get("joints", spec.get("n"))
    t = target(n) if n is not None else None
    res["target_s"] = t
    res["within"] = bool(t is not None and res.get("status") in ("certified", "undecided")
                         and res["whole_s"] <= t)
    return res


# --- the cases -----------------------------------------------------------------------------

def chain_cases(args) -> list[dict]:
    """The corpus's chains as cases (the selection options of ``corpus.py``)."""
    corpus = _corpus_module()
    root = corpus.robots_dir()
    if root is None:
        return []
    chains, _, _ = corpus.corpus(root)
    chains = corpus.select_chains(chains, args.robots, args.min_joints, args.max_per_robot)
    return [{"kind": "chain", "key": f"{c.file}: {c.label}", "robot": c.robot, "file": c.file,
             "base": c.base, "tip": c.tip, "joints": c.n, "task": c.task,
             "path": str(root / c.file), "grade": True, "chain_joints": list(c.joints)}
            for c in chains]


def model_cases() -> list[dict]:
    """The model files of kinematics_models/ and kinematics_models/extra/."""
    out = []
    for path in sorted(MODELS_DIR.glob("*.toml")) + sorted((MODELS_DIR / "extra").glob("*")):
        if path.suffix not in (".toml", ".urdf"):
            continue
        opts = MODEL_OPTIONS.get(path.name, {})
        out.append({"kind": "model", "key": str(path.relative_to(HERE.parent)),
                    "path": str(path), "tip": opts.get("tip"), "joints": None, "grade": False})
    return out


def done_keys() -> set[str]:
    if not ROWS.is_file():
        return set()
    return {json.loads(line)["key"] for line in ROWS.read_text().splitlines() if line.strip()}


# --- the tables ----------------------------------------------------------------------------

def load_rows() -> list[dict]:
    if not ROWS.is_file():
        return []
    rows = {}
    for line in ROWS.read_text().splitlines():
        if line.strip():
            r = json.loads(line)
            rows[r["key"]] = r       # a later row of the same case replaces an earlier one
    return list(rows.values())


def summary(rows, expected_chains: int | None) -> dict:
    by = lambda s: sum(r["result"]["status"] == s for r in rows)  # noqa: E731
    chains = [r for r in rows if r["kind"] == "chain"]
    out = {"rows": len(rows), "chains": len(chains), "models": len(rows) - len(chains),
           "certified": by("certified"), "undecided": by("undecided"), "refused": by("refused"),
           "timeout": by("timeout"), "error": by("error"),
           "within_target": sum(r["result"]["within"] for r in rows),
           "with_target": sum(r["result"].get("target_s") is not None for r in rows),
           "graded_pass": sum(r["result"].get("grade") == "pass" for r in chains),
           "graded_fail": sum(r["result"].get("grade") == "fail" for r in chains),
           "graded_other": sum(r["result"].get("grade") not in ("pass", "fail")
                               for r in chains)}
    if expected_chains is not None:
        out["chains_missing"] = expected_chains - len(chains)
    return out


def _f(x, digits=1) -> str:
    return "" if x is None else f"{x:.{digits}f}"


def _row_cells(res) -> str:
    """The whole-run cells of a table row."""
    complete = {True: "true", None: "null", False: "false"}.get(res.get("complete"), "")
    if res["status"] in ("timeout", "error"):
        complete = res["status"]
    shape = "x".join(map(str, res["shape"])) if res.get("shape") else ""
    return (f"{shape} | {_f(res.get('engine_s'))} | {_f(res.get('certificate_s'))} | "
            f"{_f(res.get('whole_s'))} | {_f(res.get('peak_rss_mib'), 0)} | {complete} | "
            f"{_within_text(res)}")


def _within_text(res) -> str:
    if res.get("target_s") is None:
        return "no target"
    return "yes" if res["within"] else "no"


def render_whole_section(rows, meta, s) -> list[str]:
    """The whole-run part of corpus.md: how it was run, the counts, the slowest rows, the
    model files' table."""
    corpus = _corpus_module()
    _cell, _short = corpus._cell, corpus._short
    lines = [
        "## The whole run a user waits for, certificate included",
        "",
        f"`{meta['command']}` ({meta['date']}"
        + (f"; {meta['rerun']}" if meta.get("rerun") else "")
        + "): for each chain of the table above and each "
        "model file of "
        "`kinematics_models/` and `kinematics_models/extra/`, in a fresh process, one at a "
        "time, `rankloci.load_model` and `rankloci.locus` as `rankloci locus` computes it "
        "(through `certified_locus`: engine, numeric self-check, certificate, recomputations; "
        f"seed {meta['seed']}, default jobs: every core, time limit {meta['timeout_s']:g} s). "
        f"Python {meta['python']} on {meta['machine']}, {meta['cores']} cores, niced (`nice -n "
        "10`). **The machine was loaded by other work during the run** (several other "
        "computations shared its 2 cores; load average "
        f"{meta.get('load', 'not recorded')} at the start): the seconds are those of a loaded "
        "machine, and the same run on a quiet one is faster.",
        "",
        "Columns: *shape* of the matrix; *engine*: the locus's `seconds` (the engine's time for "
        "the locus shown); *certificate*: its certificate's `seconds`; *whole*: the process from "
        "its start to the locus (Python, imports, loading, J, engine, self-check, certificate, "
        "recomputations), what a user waits for; *RSS*: peak resident set in MiB, the largest "
        "of the run's processes (workers included, sampled every "
        f"{POLL_S:g} s); *complete*: the JSON `complete` (true: certified, null: undecided, "
        "false: the certificate refused the locus), or timeout/error; *within*: certified or "
        "undecided and whole <= the target ("
        + ", ".join(f"{t:g} s for up to {n} joints" for n, t in TARGETS) + "); *shown*: the "
        "locus shown graded against Pinocchio as above (mapping, sound, complete).",
        "",
        f"**{s['rows']} whole runs ({s['chains']} chains, {s['models']} model files): "
        f"{s['certified']} certified, {s['undecided']} undecided, {s['refused']} refused, "
        f"{s['timeout']} timed out, {s['error']} errors; {s['within_target']} of the "
        f"{s['with_target']} with a target (up to {TARGETS[-1][0]} joints) within it. "
        f"Locus shown graded against Pinocchio: {s['graded_pass']} pass, {s['graded_fail']} "
        f"fail, {s['graded_other']} not graded (time-out, error).**",
        "",
    ]
    if s.get("chains_missing"):
        lines += [f"**{s['chains_missing']} chains of the corpus have no whole run yet** (the "
                  "run was stopped at the deadline); their rows say *pending*. To finish "
                  "it: `nice -n 10 python benchmarks/whole_runs.py --resume && python "
                  "benchmarks/whole_runs.py --render`.", ""]
    slow = sorted((r for r in rows if r["result"].get("whole_s") is not None),
                  key=lambda r: -r["result"]["whole_s"])[:12]
    lines += ["The slowest whole runs:", "",
              "| case | joints | shape | engine (s) | certificate (s) | whole (s) | RSS (MiB) "
              "| complete | within |", "| --- " * 9 + "|"]
    lines += [f"| {_cell(r['key'])} | {r['result'].get('joints', r.get('joints')) or ''} | "
              f"{_row_cells(r['result'])} |" for r in slow]
    odd = [r for r in rows if r["result"]["status"] in ("refused", "timeout", "error")
           or r["result"].get("grade") in ("fail", "error")]
    if odd:
        lines += ["", "Runs that time out, fail, are refused or whose locus fails grading:", ""]
        for r in odd:
            res = r["result"]
            why = res.get("reason") or ""
            if res.get("grade") in ("fail", "error", "timeout"):
                why += f" grading: {res['grade']}: {res.get('grade_reason', '')}"
            lines.append(f"- {res['status']}: {_cell(r['key'])}: {_cell(_short(why, 300))}")
    models = [r for r in rows if r["kind"] == "model"]
    if models:
        lines += ["", "Model files (not graded against Pinocchio):", "",
                  "| model | joints | shape | engine (s) | certificate (s) | whole (s) | RSS "
                  "(MiB) | complete | within |", "| --- " * 9 + "|"]
        lines += [f"| {r['key']} | {r['result'].get('joints', '')} | {_row_cells(r['result'])} |"
                  for r in models]
    lines.append("")
    return lines


def _with_joints(row) -> dict:
    """A model file's row that stopped before its matrix was known (a time-out) gets its
    number of joints, and so its target, from the model."""
    res = row["result"]
    if row["kind"] != "model" or res.get("joints") is not None:
        return row
    import rankloci

    opts = MODEL_OPTIONS.get(Path(row["key"]).name, {})
    n = len(rankloci.load_model(str(HERE.parent / row["key"]), **opts).joints)
    return row | {"result": res | {"joints": n, "target_s": target(n)}}


def render(meta_run) -> None:
    """Merge the rows into corpus.json and write corpus.md again."""
    corpus = _corpus_module()
    data = json.loads((HERE / "corpus.json").read_text())
    rows = [_with_joints(r) for r in load_rows()]
    by_key = {r["key"]: r["result"] for r in rows if r["kind"] == "chain"}
    for c in data["chains"]:
        res = by_key.get(f"{c['file']}: {c['base']} -> {c['tip']}")
        if res is not None:
            c["whole"] = res
        else:
            c.pop("whole", None)
    s = summary(rows, len(data["chains"]))
    meta = dict(meta_run or data.get("whole_meta") or {})
    data["whole_meta"], data["whole_summary"] = meta, s
    data["models"] = [r for r in rows if r["kind"] == "model"]
    (HERE / "corpus.json").write_text(json.dumps(data, indent=2) + "\n")
    md = corpus.render_markdown(data["chains"], data["skipped_files"],
                                data["paths_outside_joint_range"], data["meta"])
    whole = render_whole_section(rows, meta, s)
    title, rest = md.split("\n", 1)
    lead = (f"The columns from *whole run* on, and the last section, are the whole runs of "
            f"`rankloci locus` with its certificate (`benchmarks/whole_runs.py`, "
            f"{meta.get('date', '')}: one process at a time, niced, on {meta.get('cores', '?')} "
            "cores of a machine loaded by other work at the same time; seconds of a loaded "
            f"machine). {s['chains']} of the {len(data['chains'])} chains have one"
            + (f", {s['chains_missing']} are pending" if s.get("chains_missing") else "")
            + ". The columns before them grade the engine's first computation "
            "(`benchmarks/corpus.py`), as described next.")
    (HERE / "corpus.md").write_text(title + "\n\n" + lead + "\n" + rest.rstrip("\n")
                                    + "\n\n" + "\n".join(whole))
    render_frontier(rows, meta)


FRONTIER_BEGIN = "<!-- whole_runs.py: begin -->"
FRONTIER_END = "<!-- whole_runs.py: end -->"


def frontier_rows(rows) -> list[tuple]:
    """``(frontier case, joints, whole-run row or None, its key)`` for each case of
    ``frontier.py``: a model file's row, or the corpus chain with the same joints (its tip is
    the child link of the last movable joint, which may lie before the case's tip)."""
    import rankloci

    sys.path.insert(0, str(HERE))
    import frontier

    corpus = _corpus_module()
    root = corpus.robots_dir()
    by_key = {r["key"]: r for r in rows}
    chains = corpus.corpus(root)[0] if root is not None else []
    out = []
    for name, joints, args, _ in frontier.CASES:
        if "--numeric" in args:
            continue         # the corpus-wide run computes what the command computes by default
        if not args[0].startswith("{robots}"):
            key = str(Path(args[0]).relative_to(HERE.parent))
            out.append((name, joints, by_key.get(key), key))
            continue
        file = args[0].removeprefix("{robots}/")
        base, tip = args[args.index("--base-link") + 1], args[args.index("--tip") + 1]
        if root is None:
            continue
        model = rankloci.load_model(str(root / file), base_link=base, tip=tip)
        names = tuple(j.name for j in model.joints)
        # or the chain that names the tip among its other leaves (a mimic joint's link)
        chain = next((c for c in chains if c.file == file and c.base == base
                      and (c.joints == names or tip in c.also)), None)
        key = None if chain is None else f"{chain.file}: {chain.label}"
        out.append((name, joints, by_key.get(key), key))
    return out


def render_frontier(rows, meta) -> None:
    """The frontier chains' whole runs, between markers in frontier.md."""
    _cell = _corpus_module()._cell
    lines = [FRONTIER_BEGIN, "", "## The frontier chains in the corpus-wide whole runs", "",
             f"From `benchmarks/whole_runs.py` ({meta.get('date', '')}"
             + (f"; {meta['rerun']}" if meta.get("rerun") else "") + ", time limit "
             f"{meta.get('timeout_s', 120):g} s, default jobs, niced, one run at a time on "
             "the loaded 2-core machine; see `benchmarks/corpus.md` for how it is run): the "
             "same whole computation as `rankloci locus` (API call in a fresh process, imports "
             "included), with the peak resident set of the run's processes (workers included); "
             "*shown*: the locus shown graded against Pinocchio (URDF chains). "
             "A URDF case is the corpus chain with the same joints (the corpus's tip is the "
             "child link of the last movable joint), or the one that lists the case's tip among "
             "its other leaves (tiago's index finger follows its thumb by a mimic joint). "
             "A table of `frontier.py` above this section from a run before it recorded peak RSS "
             "has no memory column: its figures are pending until `frontier.py` runs again; "
             "`benchmarks/frontier_jobs.md` has them for the same chains with `--jobs 1` and "
             "`--jobs 2`.", "",
             "| chain | joints | corpus row | shape | engine (s) | certificate (s) | whole (s) | "
             "peak RSS (MiB) | complete | within | shown |", "| --- " * 11 + "|"]
    for name, joints, row, key in frontier_rows(rows):
        if row is None:
            lines.append(f"| {name} | {joints} | {_cell(key or 'not in the corpus')} | pending "
                         "| | | | | | | |")
        else:
            lines.append(f"| {name} | {joints} | {_cell(key)} | {_row_cells(row['result'])} | "
                         f"{row['result'].get('grade', '')} |")
    lines += ["", FRONTIER_END]
    path = HERE / "frontier.md"
    text = path.read_text()
    if FRONTIER_BEGIN in text:
        head, rest = text.split(FRONTIER_BEGIN, 1)
        tail = rest.split(FRONTIER_END, 1)[1] if FRONTIER_END in rest else ""
        text = head.rstrip("\n") + "\n\n" + "\n".join(lines) + tail
    else:
        text = text.rstrip("\n") + "\n\n" + "\n".join(lines) + "\n"
    path.write_text(text)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--timeout", type=float, default=120.0, help="time limit per run (s)")
    ap.add_argument("--robots", default="", help="comma-separated robot names (default: all)")
    ap.add_argument("--max-per-robot", type=int, default=0)
    ap.add_argument("--min-joints", type=int, default=2)
    ap.add_argument("--only", choices=("chains", "models"), default=None)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--resume", action="store_true", help="skip the cases already in the rows")
    ap.add_argument("--render", action="store_true",
                    help="only merge the rows into corpus.json and corpus.md")
    ap.add_argument("--case", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.case:
        return _child_case(json.loads(args.case))
    meta_file = HERE / "whole_runs_meta.json"
    if args.render:
        render(json.loads(meta_file.read_text()) if meta_file.is_file() else None)
        return 0
    cases = ([] if args.only == "chains" else model_cases()) \
        + ([] if args.only == "models" else chain_cases(args))
    # fewest joints first: the most rows for the time a run is given
    cases.sort(key=lambda c: (c["kind"] != "model", c["joints"] or 0))
    skip = done_keys() if args.resume else set()
    if not args.resume and ROWS.exists():
        ROWS.unlink()
    cases = [c for c in cases if c["key"] not in skip]
    meta = {"python": platform.python_version(), "machine": platform.machine(),
            "cores": len(os.sched_getaffinity(0)), "timeout_s": args.timeout, "seed": args.seed,
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "load": " ".join(f"{x:.1f}" for x in os.getloadavg()),
            "command": "nice -n 10 python benchmarks/whole_runs.py"
                       + "".join(f" {a}" for a in (argv if argv is not None else sys.argv[1:]))}
    if not args.resume or not meta_file.is_file():
        meta_file.write_text(json.dumps(meta, indent=1) + "\n")
    print(f"{len(cases)} cases", file=sys.stderr, flush=True)
    for c in cases:
        spec = {"path": c["path"], "base": c.get("base"), "tip": c.get("tip"),
                "task": c.get("task"), "seed": args.seed, "timeout": args.timeout,
                "grade": c["grade"], "n": c["joints"], "joint_names": c.get("chain_joints")}
        res = run_case(spec)
        row = {k: v for k, v in c.items() if k not in ("path", "grade")} | {"result": res}
        with ROWS.open("a") as f:
            f.write(json.dumps(row) + "\n")
        print(f"{res['status']:>10} {res.get('whole_s', 0):6.1f} s "
              f"{res.get('peak_rss_mib') or 0:6.0f} MiB {c['key']} {res.get('grade', '')} "
              f"{(res.get('reason') or '')[:100]}", file=sys.stderr, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
