"""Benchmark: what resuming a grown branch tree costs now that the tree is a value.

``rankloci.methods.locus_and_tree`` returns the grown tree as a ``GrownTree``; a computation
with hints resumes from it in a copy of its context (``Context.copy``), so that the value
passed in never changes.  This measures, on the 9R snake (``kinematics_models/extra/
snake9.toml``, svm, numeric parameters, the matrix of ``rankloci locus``):

- the growth of the tree (the first computation, finalisation included);
- ``Context.copy`` of the grown context (median of several copies);
- a resumed computation with hints (the copy, the repair and the finalisation).

The hints are the configurations where the self-check of the first computation found a
component regular (as ``rankloci locus`` passes them back), computed here by the same check.
Writes benchmarks/resume_copy.json and benchmarks/resume_copy.md.  Usage::

    python benchmarks/resume_copy.py [--model PATH] [--copies N]
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SNAKE = HERE.parent / "kinematics_models" / "extra" / "snake9.toml"


def measure(path: Path, copies: int) -> dict:
    import numpy as np

    from rankloci.io import load_model
    from rankloci.jacobians import task_matrix
    from rankloci.methods import locus_and_tree
    from rankloci.numeric.crosscheck import cross_check
    from rankloci.tolerances import SELF_CHECK_SAMPLES

    model = load_model(str(path))
    tm = task_matrix(model, frame="auto", numeric=True)
    reference = task_matrix(model, frame=tm.frame, point=tm.point)
    clock = time.perf_counter
    t = clock()
    locus, tree = locus_and_tree(tm, "svm", rng=np.random.default_rng(0))
    grow = clock() - t
    times = []
    for _ in range(copies):
        t = clock()
        tree.context.copy()
        times.append(clock() - t)
    report = cross_check(locus, reference.matrix, reference.variables, angles=reference.angles,
                         parameters=reference.parameters, samples=SELF_CHECK_SAMPLES,
                         rng=np.random.default_rng(0), seed=0)
    names = [str(v) for v in reference.variables]
    hints = [dict(zip(names, map(float, p.q)))
             for c in report.components for p in c.failures if p.regular]
    resumed = None
    if hints:
        t = clock()
        locus_and_tree(tm, "svm", hints=tuple(hints), grown=tree)
        resumed = clock() - t
    return {"model": path.stem, "nodes": tree.context.tree.number_of_nodes(),
            "leaves": len(tree.context.leaves), "components": len(locus.components),
            "grow_s": grow, "copy_s": statistics.median(times), "copy_runs": times,
            "hints": len(hints), "resume_s": resumed}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", type=Path, default=SNAKE)
    parser.add_argument("--copies", type=int, default=5)
    args = parser.parse_args(argv)
    got = measure(args.model, args.copies)
    got["python"] = platform.python_version()
    got["when"] = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    (HERE / "resume_copy.json").write_text(json.dumps(got, indent=2) + "\n")
    share = got["copy_s"] / got["grow_s"]
    resume = "no hints" if got["resume_s"] is None else f"{got['resume_s']:.2f} s"
    lines = [
        "# Resuming a grown tree: the cost of the copy",
        "",
        f"`python benchmarks/resume_copy.py`: {got['model']} (svm, numeric parameters), Python "
        f"{got['python']}, {got['when']}, on a machine shared with other work.",
        "",
        "| tree nodes | leaves | components | growth | copy (median) | copy / growth | hints "
        "| resumed with hints |",
        "|---|---|---|---|---|---|---|---|",
        f"| {got['nodes']} | {got['leaves']} | {got['components']} | {got['grow_s']:.1f} s | "
        f"{got['copy_s'] * 1000:.1f} ms | {share:.2%} | {got['hints']} | {resume} |",
        "",
    ]
    (HERE / "resume_copy.md").write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
