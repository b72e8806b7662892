"""Benchmark: where the time of a whole ``rankloci locus`` run goes, stage by stage.

Each case runs in a fresh process (``python benchmarks/stages.py --child ...``) through
:func:`rankloci.api.calls.certified_locus`, the pipeline of ``rankloci locus``, with the
stages' functions wrapped by timers.  The time of a stage called inside another (the
certificate of a slice inside the recovery) is counted once, in the inner stage:

- **imports**: ``import rankloci`` and what the pipeline imports on its first call
  (measured apart, in a process of its own, and subtracted from nothing);
- **J**: :func:`rankloci.jacobians.task_matrix` (the matrix and the self-check's reference);
- **engine**: the first :func:`rankloci.augmented.augmented_locus_and_tree` (the pipeline's
  engine stage);
- **recomputation**: every later one (with the self-check's hints, other seeds or values)
  and the loci of slices (:func:`rankloci.methods.locus_and_tree` called by the recovery);
- **self-check**: :func:`rankloci.numeric.crosscheck.cross_check`;
- **certificate**: :func:`rankloci.certify.certify_locus`;
- **worker wait**: waiting for a part computed in a worker process (``--jobs`` above 1; the
  part itself, in the worker, is in no other column); with one job, the parts run inside it
  and are counted in their own columns;
- **other**: the rest of the run (loading the model, merging, notes).

The figures go to ``benchmarks/stages.json`` and ``benchmarks/stages.md``.  Usage::

    python benchmarks/stages.py [--cases a,b,...] [--jobs N] [--output PATH]
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
EXTRA = HERE.parent / "kinematics_models" / "extra"

#: name, model file ({robots}: example-robot-data's robots directory), base link, tip, augment
CASES = (
    ("panda", "{robots}/panda_description/urdf/panda.urdf", "panda_link0", "panda_link8", ()),
    ("snake9", str(EXTRA / "snake9.toml"), None, None, ()),
    ("tiago hand_index_link", "{robots}/tiago_description/robots/tiago.urdf", "base_footprint",
     "hand_index_link", ()),
    ("iiwa_offsets", str(EXTRA / "iiwa_offsets.urdf"), None, "link_7", ()),
)

STAGES = ("J", "engine", "recomputation", "self-check", "certificate", "worker wait")


def _child(path, base, tip, augment, jobs) -> dict:
    """Run the pipeline once in this process with the stages timed."""
    from importlib import import_module

    # by import_module: the package's own names may be API functions of the same name
    augmented, certify, jacobian, methods, crosscheck = (import_module(f"rankloci.{m}") for m in (
        "augmented", "certify", "jacobians", "methods", "numeric.crosscheck"))
    try:
        parallel = import_module("rankloci.parallel")
    except ImportError:         # a version without worker processes
        parallel = None
    from rankloci.api.calls import certified_locus
    from rankloci.api.models import as_model

    spent = dict.fromkeys(STAGES, 0.0)
    stack = []          # [stage, start, time of inner stages]
    engine_calls = [0]

    def timed(module, name, stage):
        inner = getattr(module, name)

        def wrapper(*args, **kwargs):
            s = stage
            if stage == "engine":
                engine_calls[0] += 1
                if engine_calls[0] > 1:
                    s = "recomputation"
            elif stage == "recomputation" and stack and stack[-1][0] in ("engine",
                                                                           "recomputation"):
                s = stack[-1][0]        # the engine's own call of compute_locus
            stack.append([s, time.perf_counter(), 0.0])
            try:
                return inner(*args, **kwargs)
            finally:
                s, begun, nested = stack.pop()
                took = time.perf_counter() - begun
                spent[s] += took - nested
                if stack:
                    stack[-1][2] += took
        # pickled by name for a worker process, where it is the function itself
        wrapper.__module__, wrapper.__qualname__ = inner.__module__, inner.__qualname__
        setattr(module, name, wrapper)

    timed(jacobian, "task_matrix", "J")
    # the engine's functions; a version before the pipeline's stages had only the first names
    timed(augmented, "augmented_locus_and_tree" if hasattr(augmented, "augmented_locus_and_tree")
          else "augmented_locus", "engine")
    timed(methods, "locus_and_tree" if hasattr(methods, "locus_and_tree") else "compute_locus",
          "recomputation")
    timed(crosscheck, "cross_check", "self-check")
    timed(certify, "certify_locus", "certificate")
    if parallel is not None:
        timed(parallel.Task, "result", "worker wait")
    start = time.perf_counter()
    model = as_model(path, tip=tip, base_link=base)
    options = {"jobs": jobs} if jobs is not None else {}
    result, _ = certified_locus(model, augment=tuple(augment), **options)
    whole = time.perf_counter() - start
    import resource

    return {"whole": whole, "stages": spent, "engine_calls": engine_calls[0],
            "peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            "complete": result.complete, "components": len(result.components)}


def _imports() -> float:
    """Seconds of ``import rankloci`` and the pipeline's modules in a fresh process."""
    code = ("import time; t = time.perf_counter(); import rankloci, rankloci.api.calls, "
            "rankloci.methods, rankloci.verify, rankloci.certify, rankloci.exact.witness, "
            "rankloci.numeric.crosscheck, rankloci.io.urdf; print(time.perf_counter() - t)")
    return float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                check=True).stdout)


def run_case(path, base, tip, augment, jobs) -> dict:
    """One case in a fresh process: its stages, whole time and peak RSS."""
    cmd = [sys.executable, __file__, "--child", json.dumps([path, base, tip, list(augment),
                                                            jobs])]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode:
        return {"error": (proc.stderr.strip().splitlines() or [""])[-1]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _rss(mib) -> str:
    return "pending" if mib is None else f"{mib:.0f}"


def render_markdown(rows, meta) -> str:
    lines = [
        "# Where the time of a whole run goes",
        "",
        "`python benchmarks/stages.py`: each model's whole `rankloci locus` pipeline "
        "(`certified_locus`: J, engine, self-check, certificate, recomputation) in a fresh "
        "process with its stages timed; a stage called inside another is counted in the inner "
        "one. *imports*: `import rankloci` and the pipeline's modules, in a process of their own. "
        f"Python {meta['python']}, {meta['machine']}, {meta['cores']} cores, {meta['date']}, "
        f"jobs {meta['jobs']}. The machine was shared with other work running at the same time: "
        "the seconds are those of a loaded machine, compare the shares.",
        "",
        f"imports: {meta['imports']:.2f} s",
        "",
        "*peak RSS*: the largest resident set of the process that runs the pipeline "
        "(`getrusage`; worker processes, each a process of its own, are not in it).",
        "",
        "| model | whole (s) | " + " | ".join(f"{s} (s)" for s in STAGES)
        + " | other (s) | engine calls | components | complete | peak RSS (MiB) |",
        "| --- " * (len(STAGES) + 7) + "|",
    ]
    for r in rows:
        res = r["result"]
        if "error" in res:
            lines.append(f"| {r['name']} | error: {res['error']} |" + " |" * (len(STAGES) + 6))
            continue
        other = res["whole"] - sum(res["stages"].values())
        lines.append(f"| {r['name']} | {res['whole']:.1f} | "
                     + " | ".join(f"{res['stages'].get(s, 0.0):.1f}" for s in STAGES)
                     + f" | {other:.1f} | {res['engine_calls']} | {res['components']} | "
                     f"{json.dumps(res['complete'])} | {_rss(res.get('peak_rss_mib'))} |")
    lines.append("")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="", help="comma-separated case names (default: all)")
    ap.add_argument("--jobs", type=int, default=None, help="processes (default: the API's)")
    ap.add_argument("--output", default=str(HERE / "stages"))
    ap.add_argument("--child", help=argparse.SUPPRESS)
    opts = ap.parse_args(argv)
    if opts.child:
        print(json.dumps(_child(*json.loads(opts.child))))
        return 0
    from rankloci.io.urdf_chains import example_robot_data_dir

    root = example_robot_data_dir()
    wanted = {c.strip() for c in opts.cases.split(",") if c.strip()}
    rows = []
    for name, path, base, tip, augment in CASES:
        if wanted and name not in wanted:
            continue
        if "{robots}" in path and root is None:
            print(f"{name}: skipped (example-robot-data is not installed)", file=sys.stderr)
            continue
        print(f"{name} ...", file=sys.stderr, flush=True)
        res = run_case(path.replace("{robots}", str(root)), base, tip, augment, opts.jobs)
        print(f"{name}: {res}", file=sys.stderr, flush=True)
        rows.append({"name": name, "result": res})
    import os

    meta = {"python": platform.python_version(), "machine": platform.machine(),
            "cores": len(os.sched_getaffinity(0)), "date": time.strftime("%Y-%m-%d %H:%M UTC",
                                                                          time.gmtime()),
            "jobs": opts.jobs, "imports": _imports()}
    out = Path(opts.output)
    out.with_suffix(".json").write_text(json.dumps({"meta": meta, "rows": rows}, indent=1) + "\n")
    out.with_suffix(".md").write_text(render_markdown(rows, meta))
    print(f"wrote {out.with_suffix('.md')}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
