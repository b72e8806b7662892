"""Benchmark: the certificate's codimension 3 on 6 x 8 chains, on coordinate slices.

On a random subspace of dimension 3 the compressed maximal minors of a 6 x 8 chain have
degree 56 (pr2's left arm), and eliminating two variables with resultants squares that
twice: beyond the certificate's budgets.  The certificate decides codimension 3 there on
*coordinate slices* instead (``rankloci.exact.witness._CoordinatePlane``): three variables
free, every other one fixed at a random value of GF(P).  For each chain and each set of three
free variables this script records

- the degree of the compressions in each free variable once their common factor (the
  circles' points at infinity, 1 + t**2) is divided out;
- the seconds to form the compressions, and to find their isolated zeros with the
  certificate's own elimination on the slice, and what it found;

and, for the slice with the highest degrees, the same elimination after a random linear
change of coordinates inside the slice (what makes projections generic again), with its
witness points and seconds, measured without the certificate's elimination budgets.

Only the locus's witness points are measured here (the certificate also computes each
component's own on every slice; ``docs/explanation/certificate.md``, "Long chains").  The
chains need example-robot-data.  The figures go to ``benchmarks/coordinate_slices.md`` and
``.json``.  Usage::

    python benchmarks/coordinate_slices.py [--output PATH] [--seed N]
"""

from __future__ import annotations

import argparse
import itertools
import json
import platform
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

CHAINS = (
    ("pr2 l_wrist_roll_link", "pr2_description/urdf/pr2.urdf", "base_footprint",
     "l_wrist_roll_link"),
    ("tiago arm_7_link", "tiago_description/robots/tiago.urdf", "base_footprint", "arm_7_link"),
)

#: codimension of the slices (the top codimension of a 6 x 8 matrix)
CODIMENSION = 3


def _matrix(path, base, tip):
    import sympy as sp

    import rankloci
    from rankloci.certify import _substituted, _values
    from rankloci.jacobians import task_matrix

    tm = task_matrix(rankloci.load_model(path, base_link=base, tip=tip))
    values = _values(tm.parameters)
    M = sp.Matrix(tm.matrix).applyfunc(lambda e: _substituted(e, values))
    return (M.T if M.rows > M.cols else M), tm


def _solve(rows, n, m, forms, P, roots, free, rng, *, generic=False) -> dict:
    from rankloci.exact import witness as W

    t0 = time.perf_counter()
    plane = W._CoordinatePlane(forms, P, roots, free, rng, mixed=generic)
    Mp = [[plane.restrict(x) for x in row] for row in rows]
    H = W._compressions(Mp, n, m, CODIMENSION + 1, P, rng)
    common = H[0]
    for h in H[1:]:
        common = common.gcd(h)
    degrees = [int(d) for d in (H[0] / common).degrees()]
    formed = time.perf_counter() - t0
    t1 = time.perf_counter()
    budgets = W.MAX_ELIMINATION_DEGREE, W.MAX_ELIMINATION_TERMS
    if generic:
        # measured without the certificate's budgets: what the elimination would cost
        W.MAX_ELIMINATION_DEGREE = W.MAX_ELIMINATION_TERMS = 10 ** 12
    try:
        points, _ = W._isolated_points(H, plane, rng)
        outcome = f"{sum(p.degree for p in points)} witness points"
    except (W._Degenerate, W._TooLarge, W._Curves) as exc:
        outcome = f"{type(exc).__name__.strip('_').lower()}: {exc}"
    finally:
        W.MAX_ELIMINATION_DEGREE, W.MAX_ELIMINATION_TERMS = budgets
    return {"free": list(free), "degrees": degrees, "form_s": round(formed, 3),
            "eliminate_s": round(time.perf_counter() - t1, 3), "outcome": outcome}


def measure(name, path, base, tip, seed) -> dict:
    import sympy as sp

    from rankloci.exact import witness as W

    M, tm = _matrix(path, base, tip)
    n, m = M.shape
    angles = tuple(a for a in tm.variables if a in set(tm.angles))
    others = tuple(v for v in tm.variables if v not in set(angles))
    surds = sorted({p for e in M for a in e.atoms(sp.Pow)
                    if a.is_number and W._integer_root(a)
                    for p in sp.factorint(W._integer_root(a)[0])})
    forms = W._Forms(angles, others, surds)
    rows = forms.homogeneous_rows(M)
    rng = np.random.default_rng(seed)
    P, roots = W._random_prime(rng, surds)
    order = [str(v) for v in angles + others]
    # the padded rows' degree on a random subspace: what the certificate checks today
    padded = int(sum(max(sum(int(e) for e in x.degrees()) for x in row) for row in rows))
    slices = []
    t0 = time.perf_counter()
    for free in itertools.combinations(range(len(order)), CODIMENSION):
        row = _solve(rows, n, m, forms, P, roots, free, rng)
        row["free"] = [order[i] for i in free]
        slices.append(row)
    coordinate_s = time.perf_counter() - t0
    richest = max(range(len(slices)), key=lambda i: sum(slices[i]["degrees"]))
    free = tuple(order.index(v) for v in slices[richest]["free"])
    generic = _solve(rows, n, m, forms, P, roots, free, rng, generic=True)
    generic["free"] = slices[richest]["free"]
    return {"chain": name, "shape": f"{n}x{m}", "variables": order, "padded_degree": padded,
            "slices": slices, "coordinate_s": round(coordinate_s, 2), "generic": generic}


def write(results, out: Path, seed: int) -> None:
    out.with_suffix(".json").write_text(json.dumps(results, indent=1) + "\n")
    lines = ["# Codimension 3 of 6 x 8 chains on coordinate slices", "",
             "`benchmarks/coordinate_slices.py` (see its docstring). Each slice fixes every "
             "variable but three at random values of GF(P), P a 61-bit prime; *degrees*: of the "
             "compressed maximal minors in the three free variables once their common factor "
             "(the circles' points at infinity) is divided out; *outcome*: the witness points "
             "the certificate's elimination on the slice found (projections along the "
             "coordinates, several points per fibre lifted over field extensions, curves in "
             "coordinate planes taken apart), or why it could not decide. "
             "`docs/explanation/certificate.md` (\"Long chains\") says how.", "",
             f"Python {platform.python_version()} on {platform.machine()}, "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, seed {seed}; a shared "
             "2-core machine (other work ran at the same time).", ""]
    for r in results:
        entered = sorted({v for s in r["slices"] for v, d in zip(s["free"], s["degrees"]) if d})
        with_points = [s for s in r["slices"] if not s["outcome"].startswith("0 ")]
        lines += [f"## {r['chain']} ({r['shape']})", "",
                  f"- variables: {', '.join(r['variables'])}; those the minors depend on: "
                  f"{', '.join(entered)};",
                  f"- the padded rows' degree on a random 3-dimensional subspace (beyond the "
                  f"budgets): {r['padded_degree']};",
                  f"- all {len(r['slices'])} coordinate slices: {r['coordinate_s']} s; the "
                  f"largest degrees {max(tuple(s['degrees']) for s in r['slices'])};",
                  f"- the same elimination after a random change of coordinates inside the "
                  f"slice {', '.join(r['generic']['free'])}, without the budgets (degrees "
                  f"{tuple(r['generic']['degrees'])}): {r['generic']['outcome']}, "
                  f"{r['generic']['form_s'] + r['generic']['eliminate_s']:.1f} s.", "",
                  "| free | degrees | form (s) | eliminate (s) | outcome |",
                  "| --- | --- | --- | --- | --- |"]
        for s in with_points:
            lines.append(f"| {', '.join(s['free'])} | {tuple(s['degrees'])} | {s['form_s']} | "
                         f"{s['eliminate_s']} | {s['outcome']} |")
        lines += ["", f"The other {len(r['slices']) - len(with_points)} slices have no isolated "
                  "point (a free variable the minors do not depend on, or none on the slice).",
                  ""]
    out.with_suffix(".md").write_text("\n".join(lines))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--output", type=Path, default=HERE / "coordinate_slices")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    from rankloci.io.urdf_chains import example_robot_data_dir

    robots = example_robot_data_dir()
    if robots is None:
        raise SystemExit("example-robot-data is not installed")
    results = []
    for name, rel, base, tip in CHAINS:
        print(name, flush=True)
        results.append(measure(name, str(robots / rel), base, tip, args.seed))
    write(results, args.output, args.seed)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
