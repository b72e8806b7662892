"""Minimum infinity-norm solutions per second for 6x7 and 6x10 Jacobians, on one core.

The Jacobians are those of the built-in pa10 (6x7) and mobile10 (6x10) at random
configurations (seeded), each with a random task velocity.  In one run, over the same
systems: Ha and Lee's algorithm (rankloci.near.min_inf_norm.ha_lee), Cadzow's algorithm
(rankloci.near.cadzow.cadzow) and the linear program with scipy's HiGHS
(rankloci.near.min_inf_norm.linear_program).  Each method is timed over all systems, the
fastest of --repeat passes kept; the norms are compared with the LP's.  Results go to
benchmarks/min_inf_norm.json and .md.
Usage: python benchmarks/min_inf_norm.py [--n 2000] [--repeat 3] [--seed 0]
"""

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

MODELS = (("pa10", "6x7"), ("mobile10", "6x10"))


def systems(name, n, rng):
    from rankloci.io import load_model
    from rankloci.numeric.batch_jacobian import BatchJacobian

    model = load_model(name)
    angles = [j.kind == "revolute" for j in model.joints]
    shape = (n, len(angles))
    Q = np.where(angles, rng.uniform(-np.pi, np.pi, shape), rng.normal(size=shape))
    Js = BatchJacobian(model)(Q)
    ys = rng.normal(size=(n, Js.shape[1]))
    return Js, ys


def timed(solve, Js, ys, repeat):
    best, out = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        res = [solve(J, y) for J, y in zip(Js, ys)]
        best = min(best, time.perf_counter() - start)
        out = res
    return len(Js) / best, out


def main(argv=None):
    from rankloci.near.cadzow import cadzow
    from rankloci.near.min_inf_norm import ha_lee, linear_program

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=2000, help="systems per Jacobian size")
    ap.add_argument("--repeat", type=int, default=3, help="passes per method; the fastest is kept")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    rows = []
    for name, shape in MODELS:
        Js, ys = systems(name, args.n, rng)
        rate_lp, lp = timed(linear_program, Js, ys, args.repeat)
        rate_hl, hl = timed(ha_lee, Js, ys, args.repeat)
        rate_cz, cz = timed(cadzow, Js, ys, args.repeat)
        ref = np.array([s.norm for s in lp])

        def agreement(res, ref=ref):
            ok = np.array([s.converged for s in res])
            norms = np.array([s.norm for s in res])
            err = np.abs(norms - ref) / ref
            return int((~ok).sum()), float(np.nanmax(np.where(ok, err, np.nan)))

        rows.append(dict(model=name, shape=shape, n=args.n, lp=rate_lp, ha_lee=rate_hl,
                         cadzow=rate_cz, ratio=rate_hl / rate_lp,
                         ha_lee_failed=agreement(hl)[0], ha_lee_max_rel_diff=agreement(hl)[1],
                         cadzow_failed=agreement(cz)[0], cadzow_max_rel_diff=agreement(cz)[1],
                         exchanges=float(np.mean([s.iterations for s in hl]))))
        print(rows[-1], flush=True)
    meta = dict(python=platform.python_version(), machine=platform.machine(), seed=args.seed,
                repeat=args.repeat)
    (HERE / "min_inf_norm.json").write_text(json.dumps(dict(meta=meta, rows=rows), indent=1) + "\n")
    lines = [f"Minimum infinity-norm solutions per second, one core, Python {meta['python']} on "
             f"{meta['machine']}; {args.n} random configurations per model (seed {args.seed}), "
             f"each with a random task velocity; fastest of {args.repeat} passes; all methods "
             f"in the same run on the same systems.", "",
             "| model | J | Ha and Lee (1/s) | HiGHS LP (1/s) | Ha and Lee / LP | Cadzow (1/s) "
             "| mean exchanges (Ha and Lee) | not converged (Ha and Lee, Cadzow) "
             "| largest relative norm difference to the LP |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append(f"| {r['model']} | {r['shape']} | {r['ha_lee']:,.0f} | {r['lp']:,.0f} | "
                     f"{r['ratio']:.1f}x | {r['cadzow']:,.0f} | {r['exchanges']:.2f} | "
                     f"{r['ha_lee_failed']}, {r['cadzow_failed']} | "
                     f"{max(r['ha_lee_max_rel_diff'], r['cadzow_max_rel_diff']):.1e} |")
    (HERE / "min_inf_norm.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
