"""Benchmark: the Panda, alone and with an elbow row, beside the Singular pipeline.

Two whole runs, one after the other on the same machine, for each case:

- ``rankloci locus ARGS`` as a user types it (certificate included), in a fresh process,
  timed from start to exit, with the peak RSS of its processes;
- the Singular pipeline for the same matrix (the parameters' values as rationals, in
  c_i = cos q_i and s_i = sin q_i with c_i^2 + s_i^2 = 1): the maximal minors (Singular's
  ``minor``), the factorising Groebner basis (``facstd``) that splits the ideal on the factors
  of its generators, and the minimal associated primes of each piece (``minAssChar``), with a
  time limit; building its input (J in c, s) is not counted.

The Panda is example-robot-data's ``panda_link0 -> panda_link8`` (7 joints, 6x7 J); the elbow
row is the height of the elbow (the origin of link frame 4), ``--augment "position(4, z)"``
(7x7).  The target: rankloci under 3 s a case, at least 20x Singular.  The figures go to
``benchmarks/singular_pipeline.json`` and ``.md``.  Usage::

    python benchmarks/singular_pipeline.py [--singular-timeout SECONDS] [--jobs N]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

PANDA = ("panda_description/urdf/panda.urdf", "panda_link0", "panda_link8")

#: name, --augment texts
CASES = (("Panda", ()), ("Panda with an elbow row", ("position(4, z)",)))

#: seconds of a whole rankloci run
TARGET_S = 3.0
#: rankloci at least this many times faster than Singular
TARGET_RATIO = 20.0


def timed(cmd, *, timeout=None, stdin=None) -> dict:
    """Run ``cmd``; its seconds, exit code, output and peak RSS (MiB: GNU time's maximum
    resident set of the process and of its children that it waited for)."""
    start = time.perf_counter()
    proc = subprocess.Popen(["/usr/bin/time", "-f", "PEAK-RSS-KB %M", *cmd],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = proc.communicate(stdin, timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, 9)
        proc.communicate()
        return {"seconds": time.perf_counter() - start, "timeout": True}
    seconds = time.perf_counter() - start
    rss = [int(x.split()[1]) for x in err.splitlines() if x.startswith("PEAK-RSS-KB")]
    err = "\n".join(x for x in err.splitlines() if not x.startswith("PEAK-RSS-KB"))
    return {"seconds": seconds, "exit": proc.returncode, "stdout": out, "stderr": err,
            "peak_rss_mib": round(rss[-1] / 1024, 1) if rss else None, "timeout": False}


def singular_script(path, base, tip, augment) -> tuple[str, str]:
    """The Singular input for the case's matrix, and its shape."""
    import sympy as sp

    from rankloci.augmented import parse_augment
    from rankloci.io import load_model
    from rankloci.jacobians import task_matrix

    model = load_model(path, base_link=base, tip_link=tip)
    tm = task_matrix(model, frame="auto", numeric=True,
                     augment=parse_augment(model, augment))
    J = sp.Matrix(tm.matrix)
    if J.rows > J.cols:
        J = J.T
    cs = {q: (sp.Symbol(f"c{i + 1}"), sp.Symbol(f"s{i + 1}")) for i, q in enumerate(tm.variables)}
    rep = {f(q): g for q, (c, s) in cs.items() for f, g in ((sp.cos, c), (sp.sin, s))}
    entries = [sp.sstr(sp.nsimplify(sp.expand(sp.expand_trig(e).xreplace(rep)), rational=True))
               .replace("**", "^") for e in J]
    gens = [str(x) for pair in cs.values() for x in pair]
    circles = [f"{c}^2+{s}^2-1" for c, s in cs.values()]
    script = (
        'LIB "primdec.lib";\n'
        f"ring r = 0, ({','.join(gens)}), dp;\n"
        f"matrix J[{J.rows}][{J.cols}] = {', '.join(entries)};\n"
        f"ideal I = minor(J, {J.rows}), {', '.join(circles)};\n"
        "list F = facstd(I);\n"
        "int i; int n = 0;\n"
        "for (i = 1; i <= size(F); i++) { n = n + size(minAssChar(F[i])); }\n"
        'print("PRIMES " + string(n) + " PIECES " + string(size(F)));\nquit;\n')
    return script, f"{J.rows}x{J.cols}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--singular-timeout", type=float, default=150.0)
    ap.add_argument("--jobs", type=int, default=None, help="rankloci --jobs (default: its own)")
    ap.add_argument("--output", default=str(HERE / "singular_pipeline"))
    opts = ap.parse_args(argv)
    from rankloci.io.urdf_chains import example_robot_data_dir

    root = example_robot_data_dir()
    if root is None or shutil.which("Singular") is None:
        print("needs example-robot-data and Singular", file=sys.stderr)
        return 1
    path, base, tip = str(root / PANDA[0]), PANDA[1], PANDA[2]
    rows = []
    for name, augment in CASES:
        args = [path, "--base-link", base, "--tip", tip]
        for a in augment:
            args += ["--augment", a]
        if opts.jobs is not None:
            args += ["--jobs", str(opts.jobs)]
        print(f"{name}: rankloci ...", file=sys.stderr, flush=True)
        ours = timed([sys.executable, "-m", "rankloci", "locus", *args, "--format", "json",
                      "--quiet"])
        try:        # exit 1 (a locus the certificate disproves) still prints the locus
            doc = json.loads(ours.pop("stdout", "") or "{}")
        except json.JSONDecodeError:
            doc = {}
        ours["error"] = (ours.pop("stderr", "") or "").strip().splitlines()[-1:]
        ours.update(complete=doc.get("complete"), components=len(doc.get("components", ())),
                    locus_s=doc.get("seconds"),
                    certificate_s=(doc.get("certificate") or {}).get("seconds"))
        script, shape = singular_script(path, base, tip, augment)
        print(f"{name}: Singular ...", file=sys.stderr, flush=True)
        theirs = timed(["Singular", "-q", "--no-warn"], stdin=script,
                       timeout=opts.singular_timeout)
        out = theirs.pop("stdout", "") or ""
        theirs.pop("stderr", None)
        line = next((x for x in out.splitlines() if x.startswith("PRIMES")), "")
        theirs["primes"] = int(line.split()[1]) if line else None
        theirs["pieces"] = int(line.split()[3]) if line else None
        row = {"name": name, "augment": list(augment), "shape": shape, "rankloci": ours,
               "singular": theirs}
        print(f"{name}: {row}", file=sys.stderr, flush=True)
        rows.append(row)
    meta = {"python": platform.python_version(), "machine": platform.machine(),
            "cores": len(os.sched_getaffinity(0)), "jobs": opts.jobs,
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "singular_timeout_s": opts.singular_timeout}
    out = Path(opts.output)
    out.with_suffix(".json").write_text(json.dumps({"meta": meta, "rows": rows}, indent=1) + "\n")
    out.with_suffix(".md").write_text(render_markdown(rows, meta))
    print(f"wrote {out.with_suffix('.md')}", file=sys.stderr)
    return 0


def fmt(x) -> str:
    return "" if x is None else f"{x:.2f}"


def render_markdown(rows, meta) -> str:
    lines = [
        "# The Panda beside the Singular pipeline",
        "",
        "`python benchmarks/singular_pipeline.py`: each case's whole `rankloci locus` run "
        "(fresh process, certificate included, timed from start to exit) and then the Singular "
        "pipeline on the same matrix (maximal minors, `facstd`, `minAssChar` of each piece; "
        f"time limit {meta['singular_timeout_s']:g} s), one after the other. "
        f"Python {meta['python']}, {meta['machine']}, {meta['cores']} cores, {meta['date']}, "
        f"rankloci --jobs {meta['jobs'] if meta['jobs'] is not None else 'default (every core)'}."
        " Other work ran on the machine at the same time: the seconds are those of a loaded "
        "machine; the two columns of a row were measured minutes apart under similar load.",
        "",
        f"Targets: rankloci under {TARGET_S:g} s, at least {TARGET_RATIO:g}x Singular.",
        "",
        "| case | J | rankloci whole run (s) | locus (s) | certificate (s) | complete | "
        "peak RSS (MiB) | Singular (s) | Singular primes | ratio | within target |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        o, s = r["rankloci"], r["singular"]
        if s["timeout"]:
            sing, ratio = f"over {s['seconds']:.0f}, stopped", f"over {s['seconds'] / o['seconds']:.0f}x"
            r_val = s["seconds"] / o["seconds"]
        else:
            sing, r_val = f"{s['seconds']:.1f}", s["seconds"] / o["seconds"]
            ratio = f"{r_val:.0f}x"
        ok = o.get("complete") is True and o["seconds"] <= TARGET_S and r_val >= TARGET_RATIO
        lines.append(
            f"| {r['name']} | {r['shape']} | {o['seconds']:.2f} | {fmt(o.get('locus_s'))} | "
            f"{fmt(o.get('certificate_s'))} | {json.dumps(o.get('complete'))} | "
            f"{o.get('peak_rss_mib', '')} | {sing} | {s.get('primes') or ''} | {ratio} | "
            f"{'yes' if ok else 'no'} |")
    lines.append("")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
