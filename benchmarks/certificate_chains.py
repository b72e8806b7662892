"""Benchmark: where the certificate stops on long chains, and what each codimension costs.

On matrices where components of codimension 3 or more can occur (n x m with m - n >= 2), the
certificate's witness points of those codimensions come from eliminating variables with
resultants, within the budgets of ``rankloci/tolerances.py`` (``MAX_ELIMINATION_DEGREE``,
``MAX_ELIMINATION_TERMS``).  For each chain, one after another in one process:

- ``engine``: ``rankloci.locus(model, verify=False)`` and its components per codimension;
- ``certificate``: :func:`rankloci.certify.certify_locus` of that locus, its verdict, its
  witness points, the seconds spent on each codimension (from its progress messages) and why
  each undecided codimension was left undecided.

The chains are the built-in ``mobile10`` (6x10), ``kinematics_models/extra/snake9.toml``
(6x9) and, when example-robot-data is installed, tiago's torso, arm and index finger (9 joints).
The figures go to ``benchmarks/certificate_chains.md`` and ``.json``.  Usage::

    python benchmarks/certificate_chains.py [--models a,b,...] [--output PATH]
"""

from __future__ import annotations

import argparse
import json
import re
import time
from collections import Counter
from pathlib import Path

HERE = Path(__file__).resolve().parent
EXTRA = HERE.parent / "kinematics_models" / "extra"


def chains():
    """(name, model, tip) of each chain that can be loaded here."""
    from rankloci.io.urdf_chains import example_robot_data_dir

    out = [("mobile10", "mobile10", None), ("snake9", str(EXTRA / "snake9.toml"), None)]
    robots = example_robot_data_dir()
    if robots is not None:
        out.append(("tiago_hand_index", str(robots / "tiago_description/robots/tiago.urdf"),
                    "hand_index_link"))
    return out


def measure(name, model, tip) -> dict:
    import rankloci
    from rankloci.certify import certify_locus
    from rankloci.jacobians import task_matrix

    loaded = rankloci.load_model(model, tip=tip)
    t0 = time.perf_counter()
    bare = rankloci.locus(loaded, verify=False)
    engine = time.perf_counter() - t0
    N = len(bare.variables)
    marks = []

    def progress(msg):
        found = re.search(r"witness points of codimension (\d+)", msg)
        if found:
            marks.append((int(found.group(1)), time.perf_counter()))

    t0 = time.perf_counter()
    cert = certify_locus(bare, task_matrix(loaded, frame="auto"), progress=progress)
    total = time.perf_counter() - t0
    # each codimension's witness points run from its progress message to the next one's
    ends = [t for _, t in marks[1:]] + [t0 + total]
    per_codim = {str(c): round(end - start, 3) for (c, start), end in zip(marks, ends)}
    blocked = [f for f in cert.findings if f.startswith("codimension")]
    return {"model": name, "shape": list(bare.shape), "variables": N,
            "engine_s": round(engine, 3),
            "components": {str(k): v for k, v in
                           sorted(Counter(N - c.dimension for c in bare.components).items())},
            "certificate_s": round(total, 3), "verdict": cert.verdict,
            "witness_points": {str(k): v for k, v in cert.witness_points.items()},
            "seconds_per_codimension": per_codim, "undecided_because": blocked}


def render(rows, meta) -> str:
    lines = ["# The certificate on long chains", "",
             f"`python benchmarks/certificate_chains.py`, {meta['date']}, {meta['machine']}, "
             f"Python {meta['python']}. One process, chains one after another, on a shared "
             "machine: compare the ratio, not the seconds.", "",
             "Seconds per codimension run from the certificate's message for that codimension "
             "to the next one; the last runs to the end and includes the soundness checks of "
             "components of the codimensions left undecided (those are refused before any "
             "elimination, by the degree of their determinants).", "",
             "| chain | matrix | engine (s) | components by codimension | certificate (s) "
             "| s per codimension | verdict | witness points |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        comps = ", ".join(f"{k}: {v}" for k, v in r["components"].items()) or "-"
        per = ", ".join(f"{k}: {v:.2f}" for k, v in r["seconds_per_codimension"].items()) or "-"
        pts = ", ".join(f"{k}: {v}" for k, v in r["witness_points"].items()) or "-"
        lines.append(f"| {r['model']} | {r['shape'][0]}x{r['shape'][1]} | {r['engine_s']:.2f} | "
                     f"{comps} | {r['certificate_s']:.2f} | {per} | {r['verdict']} | {pts} |")
    lines += ["", "Why each undecided codimension is undecided (the certificate's findings):", ""]
    for r in rows:
        for f in r["undecided_because"]:
            lines.append(f"- {r['model']}: {f}")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", help="comma-separated names (default: every chain found)")
    parser.add_argument("--output", default=str(HERE / "certificate_chains.md"))
    args = parser.parse_args(argv)
    chosen = chains()
    if args.models:
        wanted = args.models.split(",")
        chosen = [c for c in chosen if c[0] in wanted]
    rows = []
    for name, model, tip in chosen:
        row = measure(name, model, tip)
        print(json.dumps(row), flush=True)
        rows.append(row)
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from certificate import write_results

    write_results(rows, render, args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
