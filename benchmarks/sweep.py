"""Sweep: the example-robot-data chains on 1 and 2 Dask workers, measured speed-ups.

Runs ``rankloci sweep`` on every serial chain with 2 to 9 movable joints of
example-robot-data's URDF files (the chains of ``benchmarks/corpus.py``: tip
position for up to 3 joints, the full task otherwise, parameters substituted,
the self-check on) with a time limit of ``--timeout`` seconds per case, once on
a local cluster of 1 worker and once on 2, and writes ``benchmarks/sweep.md`` and
``benchmarks/sweep.json``:

- the wall time of each run and the speed-up, with the machine's load (``uptime``)
  before and after each run (the machine is shared);
- whether the two summaries agree except for the seconds;
- the makespan predicted from the 1-worker run's case times, scheduled as the
  sweep schedules them (longest expected first, each case to the first free
  worker), beside the measured wall time of each run, and its error;
- for 8, 32 and 128 workers, which this machine does not have, the same
  prediction, marked as not measured, with the two lower bounds (the total over
  the workers, and the longest case).

Usage::

    python benchmarks/sweep.py [--timeout SECONDS] [--workers 1,2] [--revision COMMIT]
                               [--output PATH] [--render]

The rankloci it runs is the one ``python`` imports: to measure a commit while the working
tree changes, export it (``git archive COMMIT | tar -x -C DIR``) and run with
``PYTHONPATH=DIR`` and ``--revision COMMIT``.
"""

from __future__ import annotations

import argparse
import csv
import heapq
import io
import json
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent

#: Worker counts of the scaling estimate.
ESTIMATE_WORKERS = (8, 32, 128)


def robots_dir() -> Path | None:
    """example-robot-data's ``robots`` directory (as ``benchmarks/corpus.py`` finds it)."""
    sys.path.insert(0, str(HERE))
    from corpus import robots_dir as find

    return find()


def spec_text(robots: Path, timeout: float) -> str:
    """The sweep spec of the corpus chains."""
    return f"""# the chains of benchmarks/corpus.py
timeout = {timeout:g}
numeric = true

[[model]]
path = {json.dumps(str(robots))}
pattern = "**/*.urdf"
chains = "all"
min_joints = 2
max_joints = 3
task = "position"

[[model]]
path = {json.dumps(str(robots))}
pattern = "**/*.urdf"
chains = "all"
min_joints = 4
max_joints = 9
task = "full"
"""


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return "(uptime not available)"


def run(spec: Path, out: Path, workers: int) -> dict:
    """One ``rankloci sweep`` on a local cluster of ``workers``; its wall time and records."""
    cmd = [sys.executable, "-c", "import sys; from rankloci.cli import main; "
           "sys.exit(main(sys.argv[1:]))", "sweep", str(spec), "-o", str(out),
           "--workers", str(workers)]
    before = uptime()
    t0 = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    after = uptime()
    if proc.returncode not in (0, 1):
        raise SystemExit(f"rankloci sweep failed ({proc.returncode}): {proc.stderr[-2000:]}")
    records = []
    for row in csv.DictReader(io.StringIO((out / "summary.csv").read_text())):
        records.append(row)
    return {"workers": workers, "wall_s": wall, "uptime_before": before, "uptime_after": after,
            "summary_csv": (out / "summary.csv").read_text(), "records": records,
            "log_tail": proc.stderr.strip().splitlines()[-1:]}


def makespan(times, workers: int) -> float:
    """List scheduling of ``times`` (in the order given) on ``workers`` identical workers."""
    free = [0.0] * workers
    heapq.heapify(free)
    end = 0.0
    for t in times:
        start = heapq.heappop(free)
        heapq.heappush(free, start + t)
        end = max(end, start + t)
    return end


def _sweep_order(records) -> list[float]:
    """The case times in the order the sweep starts the cases: the most joints first (the
    cases here have no constraint rows and substituted parameters, the other keys of
    ``rankloci.sweep.cases.expected_cost``), the spec's order among equals."""
    return [float(r["seconds"]) for r in sorted(records, key=lambda r: -int(r["joints"] or 0))]


def predictions(data) -> list[dict]:
    """For each measured run: the makespan predicted from the first run's case times, and
    its error against the measured wall time."""
    base = data["runs"][0]
    times = _sweep_order(base["records"])
    per_case = base["workers"]            # the first run's times are on this many workers
    out = []
    for r in data["runs"]:
        predicted = makespan(times, r["workers"]) if per_case == 1 else float("nan")
        out.append({"workers": r["workers"], "predicted_s": predicted,
                    "measured_s": r["wall_s"],
                    "error": (predicted - r["wall_s"]) / r["wall_s"]})
    return out


def estimate(records, workers=ESTIMATE_WORKERS) -> list[dict]:
    """Makespans at ``workers`` from the 1-worker case times, in the sweep's order."""
    times = _sweep_order(records)
    total, longest = sum(times), max(times)
    out = []
    for w in workers:
        m = makespan(times, w)
        out.append({"workers": w, "makespan_s": m, "total_over_workers_s": total / w,
                    "longest_case_s": longest, "speed_up": total / m})
    return out


def _without_seconds(text: str) -> list:
    rows = list(csv.reader(io.StringIO(text)))
    k = rows[0].index("seconds")
    return [r[:k] + r[k + 1:] for r in rows]


def render(data) -> str:
    meta, runs = data["meta"], data["runs"]
    base = runs[0]
    recs = base["records"]
    times = sorted(float(r["seconds"]) for r in recs)
    n = len(times)
    counts = {s: sum(r["status"] == s for r in recs) for s in ("done", "timeout", "memory",
                                                                 "error")}
    failed_check = sum(r["check"] == "fail" for r in recs)
    lines = [
        "# Sweep benchmark: example-robot-data chains on Dask",
        "",
        f"`python benchmarks/sweep.py`: `rankloci sweep` over the {n} cases of every serial "
        f"chain with 2 to 9 movable joints in the URDF files of example-robot-data "
        f"{meta['example_robot_data']} (the chains of `benchmarks/corpus.py`; tip position up "
        "to 3 joints, full task otherwise; parameters substituted; the self-check on), on a "
        "local Dask cluster of single-threaded worker processes, Python "
        f"{meta['python']} on {meta['machine']} with {meta['cores']} cores"
        + (f", rankloci at commit {meta['revision'][:10]}{meta['revision'][40:]}"
           if meta.get("revision") else "")
        + ". **The time limit "
        f"is {meta['timeout_s']:g} s per case** (the child is killed 1 s after it), so that "
        "the benchmark finishes in reasonable time; the cases that run out of it are the "
        "longest of the sweep.",
        "",
        "The machine is shared with other work, so each run's load is given (`uptime` just "
        "before and just after).",
        "",
        "| workers | wall time (s) | speed-up | load before | load after |",
        "| --- | --- | --- | --- | --- |",
    ]
    for r in runs:
        lines.append(f"| {r['workers']} | {r['wall_s']:.1f} | {base['wall_s'] / r['wall_s']:.2f}x"
                     f" | {r['uptime_before'].split('load average:')[-1].strip()} | "
                     f"{r['uptime_after'].split('load average:')[-1].strip()} |")
    same = all(_without_seconds(r["summary_csv"]) == _without_seconds(base["summary_csv"])
               for r in runs)
    diffs, slowest = [], []
    for r in runs[1:]:
        for x, y in zip(base["records"], r["records"]):
            if {k: v for k, v in x.items() if k != "seconds"} != {
                    k: v for k, v in y.items() if k != "seconds"}:
                what = "; ".join(
                    f"{k} {x[k] or '-'} with {base['workers']} worker(s), {y[k] or '-'} with "
                    f"{r['workers']}" for k in x if x[k] != y[k] and (
                        k == "status" if x["status"] != y["status"]
                        else k not in ("seconds", "note")))
                diffs.append(f"`{x['case']}` ({float(x['seconds']):.1f} s on "
                             f"{base['workers']}): {what}")
                slowest.append(float(x["seconds"]))
    lines += [
        "",
        f"Cases ({base['workers']}-worker run): {counts['done']} done ({failed_check} failing "
        f"the self-check), {counts['timeout']} out of time, {counts['memory']} out of memory, "
        f"{counts['error']} error{'' if counts['error'] == 1 else 's'}.",
        "",
        "Summaries of the runs, the seconds column aside: "
        + ("**identical**." if same else
           f"**they differ in {len(diffs)} rows**, every one a case that took "
           f"{min(slowest):.1f} s or more with one worker: with two workers sharing the "
           "two loaded cores it ran slower and crossed the wall-clock limit, in its locus "
           "or in its self-check (then `not run`, or a recomputation cut at another "
           "attempt). The "
           "limit is wall time, so a case near it can end either way on a shared machine; "
           "cases well inside their limit give the same row for any number of workers "
           "(`tests/sweep/` checks whole summaries). The rows:"),
    ]
    if diffs:
        lines += [""] + [f"- {d}" for d in diffs]
    lines += [
        "",
        "Case times of the 1-worker run (seconds, wall time on the worker, the child's start "
        "and the self-check included): "
        f"median {times[n // 2]:.2f}, 90th percentile {times[int(0.9 * (n - 1))]:.2f}, "
        f"largest {times[-1]:.2f}, total {sum(times):.0f}.",
        "",
        "## Measured speed-up and its prediction",
        "",
        "The makespan predicted from the 1-worker run's case times, scheduled as the sweep "
        "schedules them (longest expected first: the most joints; each case to the first "
        "free worker; no start-up, submission or transfer cost), beside the measured wall "
        "time of each run (which includes starting the cluster and the sweep's own work):",
        "",
        "| workers | measured (s) | predicted (s) | error of the prediction |",
        "| --- | --- | --- | --- |",
    ]
    for e in predictions(data):
        lines.append(f"| {e['workers']} | {e['measured_s']:.1f} | {e['predicted_s']:.1f} | "
                     f"{e['error']:+.0%} |")
    two = next((e for e in predictions(data) if e["workers"] == 2), None)
    lines += [
        "",
        "### Not measured: 8, 32 and 128 workers",
        "",
        "This machine has 2 cores, so larger clusters are not measured here. The same "
        "prediction for them"
        + (f" (off by {two['error']:+.0%} at 2 workers, where it can be checked; a larger "
           "cluster adds transfer and scheduling costs that the prediction leaves out)"
           if two else "")
        + ", with the two lower bounds, the total over the workers and the longest case:",
        "",
        "| workers | predicted makespan (s) | total / workers (s) | longest case (s) | "
        "predicted speed-up over 1 | longest case / makespan |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for e in estimate(recs):
        lines.append(f"| {e['workers']} | {e['makespan_s']:.1f} | "
                     f"{e['total_over_workers_s']:.1f} | {e['longest_case_s']:.1f} | "
                     f"{e['speed_up']:.1f}x | {e['longest_case_s'] / e['makespan_s']:.0%} |")
    lines += ["", reading(data), ""]
    timeouts = [float(r["seconds"]) for r in recs if r["status"] == "timeout"] or [0.0]
    done = sorted(float(r["seconds"]) for r in recs if r["status"] == "done") or [0.0]
    two = next((r for r in runs if r["workers"] == 2), None)
    bound = [e["workers"] for e in estimate(recs)
             if e["longest_case_s"] >= 0.9 * e["makespan_s"]]
    free = [e["workers"] for e in estimate(recs) if e["workers"] not in bound]
    at_two = (f" On 2 workers the sweep took {two['wall_s']:.0f} s, "
              f"{two['wall_s'] / max(timeouts):.0f} times the longest case: no single case is "
              "its long pole" + (f", nor at {' or '.join(map(str, free))} workers in the "
                                 "estimate." if free else ".") if two else "")
    where = (f"Where the longest case does bound the makespan (at least 90 % of it: "
             f"{' and '.join(map(str, bound))} workers above), it is " if bound
             else "The longest case is ")
    lines += [
        "## One locus across workers",
        "",
        "The branch tree of one case is not split across Dask tasks. Measured here: the "
        f"longest case that finished took {done[-1]:.1f} s, and the cases stopped by the limit "
        f"{min(timeouts):.1f} to {max(timeouts):.1f} s each (the limit, plus starting the "
        f"child and stopping it).{at_two} {where}a case stopped by the limit, whose tree is "
        "unknown: "
        "there is no measurement that splitting it would pay. Nor would the result stay "
        "identical to the serial one: a branch is pruned when it lies inside a component "
        "found on the branches explored before it, and the sample points come from one "
        "seeded generator consumed along the tree, so subtrees explored apart would prune "
        "differently and draw other points.",
    ]
    lines.append("")
    return "\n".join(lines)


def reading(data) -> str:
    """The plain-language reading of the estimate (not measured)."""
    est = estimate(data["runs"][0]["records"])
    parts = []
    for e in est:
        excess = e["longest_case_s"] / e["total_over_workers_s"]
        if e["makespan_s"] <= e["longest_case_s"] * 1.0001:
            parts.append(f"at {e['workers']} workers the longest case is the makespan: "
                         f"{e['longest_case_s']:.1f} s, {excess:.1f} times the "
                         f"{e['total_over_workers_s']:.1f} s a perfect split would take")
        else:
            parts.append(f"at {e['workers']} workers the makespan is "
                         f"{e['makespan_s']:.1f} s, {e['makespan_s'] / e['longest_case_s']:.1f} "
                         f"times the longest case and "
                         f"{e['makespan_s'] / e['total_over_workers_s']:.2f} times the total "
                         f"over the workers")
    return ("Reading of the prediction: " + "; ".join(parts) + ". The longest cases are those stopped at the "
            "time limit, so with a larger limit the long pole grows with it.")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds per case (default 20)")
    ap.add_argument("--workers", default="1,2", help="comma list of worker counts (default 1,2)")
    ap.add_argument("--output", default=str(HERE / "sweep"))
    ap.add_argument("--revision", default="", help="the commit measured, for the record")
    ap.add_argument("--render", action="store_true",
                    help="only write OUTPUT.md again from OUTPUT.json")
    args = ap.parse_args(argv)
    if args.render:
        data = json.loads(Path(args.output + ".json").read_text())
        data["predictions"] = predictions(data)
        data["estimate"] = estimate(data["runs"][0]["records"])
        data.pop("reading", None)
        Path(args.output + ".json").write_text(json.dumps(data, indent=1) + "\n")
        Path(args.output + ".md").write_text(render(data))
        return 0
    from importlib.metadata import version

    robots = robots_dir()
    if robots is None:
        print("example-robot-data is not installed (pip install -e '.[test]')", file=sys.stderr)
        return 2
    runs = []
    with tempfile.TemporaryDirectory(prefix="rankloci-sweep-bench-") as tmp:
        spec = Path(tmp) / "corpus.toml"
        spec.write_text(spec_text(robots, args.timeout))
        for w in (int(x) for x in args.workers.split(",")):
            print(f"{w} worker(s) ...", file=sys.stderr, flush=True)
            runs.append(run(spec, Path(tmp) / f"out{w}", w))
            print(f"  {runs[-1]['wall_s']:.1f} s", file=sys.stderr, flush=True)
    import os

    data = {"meta": {"python": platform.python_version(), "machine": platform.machine(),
                     "cores": len(os.sched_getaffinity(0)), "timeout_s": args.timeout,
                     "example_robot_data": version("example-robot-data"),
                     "dask": version("dask"), "distributed": version("distributed"),
                     "revision": args.revision},
            "runs": runs}
    data["predictions"] = predictions(data)
    data["estimate"] = estimate(runs[0]["records"])
    Path(args.output + ".json").write_text(json.dumps(data, indent=1) + "\n")
    Path(args.output + ".md").write_text(render(data))
    return 0


if __name__ == "__main__":
    sys.exit(main())
