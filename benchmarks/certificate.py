"""Benchmark: the certificate's cost beside the locus time, per model.

For each model, in one process and one after another:

- ``engine``: the locus computed by the engine alone (``rankloci.locus(..., verify=False)``);
- ``certificate``: :func:`rankloci.certify.certify_locus` of that locus (witness points modulo a
  prime), with its verdict and witness point counts;
- ``whole run``: ``rankloci.locus`` as the command line computes it (engine, numeric self-check,
  certificate and the recomputations a failing certificate asks for), with the verdict of the
  locus it shows.

The models are the built-in ones, those of ``kinematics_models/extra`` (the 9R snake is
left out by default: its whole run takes minutes) and the raw matrices of
``examples/real_points``, whose real points lie in complex components of larger dimension.  The figures go to
``benchmarks/certificate.json`` and ``benchmarks/certificate.md``.  Usage::

    python benchmarks/certificate.py [--models a,b,...] [--output PATH]
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
EXTRA = HERE.parent / "kinematics_models" / "extra"
#: raw matrices whose locus has real points of lower dimension than a complex component (or
#: none): the engine alone misses them, the whole run finds them (rankloci.exact.real_points)
REAL_POINTS = HERE.parent / "examples" / "real_points"

#: name, what rankloci.locus is given, keyword arguments
MODELS = (
    ("planar2r", "planar2r", {}),
    ("planar3r", "planar3r", {}),
    ("planar3r_orient", "planar3r_orient", {}),
    ("planar4r", "planar4r", {}),
    ("puma560", "puma560", {}),
    ("ur5", "ur5", {}),
    ("pa10", "pa10", {}),
    ("ssrms", "ssrms", {}),
    ("ssrms_lock3", "ssrms_lock3", {}),
    ("mobile10", "mobile10", {}),
    ("jaco2", str(EXTRA / "jaco2.toml"), {}),
    ("baxter_dh", str(EXTRA / "baxter_dh.toml"), {}),
    ("iiwa_offsets", str(EXTRA / "iiwa_offsets.urdf"), {"tip": "link_7"}),
) + tuple((name, str(REAL_POINTS / f"{name}.toml"), {})
          for name in ("rotation", "sines", "tall", "sum_of_squares", "no_real_point"))
OPTIONAL = (("snake9", str(EXTRA / "snake9.toml"), {}),)


def measure(name, model, options) -> dict:
    import rankloci
    from rankloci.api.calls import _PIPELINE
    from rankloci.certify import certify_locus
    from rankloci.jacobians import task_matrix

    loaded = rankloci.load_model(model, tip=options.get("tip"))
    t0 = time.perf_counter()
    bare = rankloci.locus(loaded, verify=False)
    engine = time.perf_counter() - t0
    t0 = time.perf_counter()
    cert = certify_locus(bare, task_matrix(loaded, frame="auto"))
    certificate = time.perf_counter() - t0
    _PIPELINE.clear()
    t0 = time.perf_counter()
    shown = rankloci.locus(loaded)
    whole = time.perf_counter() - t0
    return {"model": name, "shape": list(bare.shape), "variables": len(bare.variables),
            "engine_s": round(engine, 3), "certificate_s": round(certificate, 3),
            "verdict": cert.verdict,
            "witness_points": {str(k): v for k, v in cert.witness_points.items()},
            "whole_run_s": round(whole, 3),
            "shown_verdict": shown.certificate.verdict if shown.certificate else None,
            "complete": shown.complete}


def render(rows, meta) -> str:
    lines = ["# The certificate's cost", "",
             f"`python benchmarks/certificate.py`, {meta['date']}, {meta['machine']}, "
             f"Python {meta['python']}. One process, models one after another.", "",
             "- **engine**: `rankloci.locus(model, verify=False)`;",
             "- **certificate**: `certify_locus` of that locus (witness points modulo a prime), "
             "its verdict and witness points per codimension;",
             "- **whole run**: `rankloci.locus(model)` as `rankloci locus` computes it "
             "(self-check, certificate, recomputation), and whether the locus it shows is "
             "certified (`complete`: true, or null when undecided, false when disproved).", "",
             "| model | matrix | engine (s) | certificate (s) | ratio | verdict | witness points "
             "| whole run (s) | complete |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        ratio = r["certificate_s"] / r["engine_s"] if r["engine_s"] else float("nan")
        pts = ", ".join(f"{k}: {v}" for k, v in r["witness_points"].items()) or "-"
        lines.append(f"| {r['model']} | {r['shape'][0]}x{r['shape'][1]} | {r['engine_s']:.2f} | "
                     f"{r['certificate_s']:.2f} | {ratio:.2f} | {r['verdict']} | {pts} | "
                     f"{r['whole_run_s']:.2f} | {json.dumps(r['complete'])} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", help="comma-separated names (default: all but snake9)")
    parser.add_argument("--output", default=str(HERE / "certificate.md"))
    args = parser.parse_args(argv)
    chosen = MODELS + OPTIONAL
    if args.models:
        wanted = args.models.split(",")
        chosen = tuple(m for m in chosen if m[0] in wanted)
    else:
        chosen = MODELS
    rows = []
    for name, model, options in chosen:
        row = measure(name, model, options)
        print(json.dumps(row), flush=True)
        rows.append(row)
    write_results(rows, render, args.output)
    return 0


def write_results(rows, render, output) -> None:
    """``render(rows, meta)`` to ``output`` and the rows with their meta beside it as JSON."""
    import os

    meta = {"date": time.strftime("%Y-%m-%d"),
            "machine": f"{platform.machine()}, {os.cpu_count()} cores",
            "python": platform.python_version()}
    out = Path(output)
    out.write_text(render(rows, meta), encoding="utf-8")
    out.with_suffix(".json").write_text(json.dumps({"meta": meta, "rows": rows}, indent=1) + "\n",
                                        encoding="utf-8")


if __name__ == "__main__":
    raise SystemExit(main())
