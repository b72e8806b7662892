"""Benchmark: whole runs of ``rankloci locus`` on robots outside the built-in set.

Each case is the command a user types, self-check included (``rankloci locus ARGS --format
json``), run in its own process, one at a time, and timed from start to exit.  The cases are
the long chains of the URDF corpus (example-robot-data) whose whole runs were slowest, and the
model files in ``kinematics_models/extra/``: a 9R snake, Kinova's Jaco2 (twists of pi/3),
Baxter's DH table (equal offsets a1 = a3) and an iiwa-like arm with half-millimetre offsets.
The targets: 10 s for chains of up to 7 joints, 60 s for up to 9.

The figures go to ``benchmarks/frontier.json`` and ``benchmarks/frontier.md``.  Usage::

    python benchmarks/frontier.py [--cases a,b,...] [--jobs 1,2] [--timeout SECONDS] [--output PATH]

Times on a shared machine vary from day to day (by up to a factor of two here); the table
also gives, from the same run, the locus time of a reference chain next to its figure in
``benchmarks/corpus.md``, so that the two tables can be compared.
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

#: seconds allowed per chain, by number of joints
TARGETS = ((7, 10.0), (9, 60.0))


def _urdf(file: str, base: str, tip: str) -> list:
    """Arguments for a chain of an example-robot-data URDF file."""
    return ["{robots}/" + file, "--base-link", base, "--tip", tip]


#: name, joints, arguments after ``rankloci locus`` (``{robots}``: example-robot-data's
#: ``robots`` directory), what the case shows
CASES = (
    ("snake9", 9, [str(EXTRA / "snake9.toml")], "9R, equal links, twists +-pi/2; parameters symbolic"),
    ("snake9 numeric", 9, [str(EXTRA / "snake9.toml"), "--numeric"],
     "the same with l = 0.1 put in first"),
    ("jaco2", 6, [str(EXTRA / "jaco2.toml")], "twists pi/3: sqrt(3) in J"),
    ("baxter_dh", 7, [str(EXTRA / "baxter_dh.toml")], "special values a1 = a3"),
    ("iiwa_offsets", 7, [str(EXTRA / "iiwa_offsets.urdf"), "--tip", "link_7"],
     "0.5 mm offsets at joints 2 and 4"),
    ("panda", 7, _urdf("panda_description/urdf/panda.urdf", "panda_link0", "panda_link8"),
     "Franka Panda's arm"),
    ("pr2 l_wrist_roll_link", 8, _urdf("pr2_description/urdf/pr2.urdf", "base_footprint",
                                       "l_wrist_roll_link"), "torso lift + 7R"),
    ("romeo l_wrist", 8, _urdf("romeo_description/urdf/romeo.urdf", "base_link", "l_wrist"), ""),
    ("human middle_head", 8, _urdf("human_description/robots/human.urdf", "middle_pelvis",
                                   "middle_head"), ""),
    ("xarm7 link7", 7, _urdf("xarm_description/urdf/xarm7.urdf", "world", "link7"), ""),
    ("tiago arm_7_link", 8, _urdf("tiago_description/robots/tiago.urdf", "base_footprint",
                                  "arm_7_link"), "torso lift + 7R"),
    ("tiago hand_index_link", 9, _urdf("tiago_description/robots/tiago.urdf", "base_footprint",
                                       "hand_index_link"), "torso lift + 7R + finger"),
    ("tiago_dual hand_right_thumb_link", 9,
     _urdf("tiago_description/robots/tiago_dual.urdf", "base_footprint",
           "hand_right_thumb_link"), "the corpus's slowest locus"),
    ("alex_nub_hands LeftWristYawLink", 8,
     _urdf("alex_description/urdf/alex_nub_hands.urdf", "Pelvis", "LeftWristYawLink"),
     "two 40-degree rotations"),
)

#: the reference chain timed alone (``locus`` seconds as the corpus records them)
REFERENCE = ("talos base_link -> arm_left_7_link", "talos_data/robots/talos_reduced.urdf",
             "base_link", "arm_left_7_link")


def target(joints: int) -> float:
    return next(t for n, t in TARGETS if joints <= n)


def robots_dir() -> Path | None:
    from rankloci.io.urdf_chains import example_robot_data_dir

    return example_robot_data_dir()


def run_case(args, timeout: float, jobs: int | None = None) -> dict:
    """``rankloci locus ARGS --format json`` in a fresh process, timed, with its peak RSS
    (GNU time's maximum resident set: the largest of the process and the children it
    waited for)."""
    cmd = [sys.executable, "-m", "rankloci", "locus", *args, "--format", "json", "--quiet",
           "--timeout", f"{timeout:g}"] + ([] if jobs is None else ["--jobs", str(jobs)])
    start = time.perf_counter()
    try:
        proc = subprocess.run(["/usr/bin/time", "-f", "PEAK-RSS-KB %M", *cmd],
                              capture_output=True, text=True, timeout=timeout + 60)
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "seconds": time.perf_counter() - start}
    seconds = time.perf_counter() - start
    rss = [int(x.split()[1]) for x in proc.stderr.splitlines() if x.startswith("PEAK-RSS-KB")]
    stderr = [x for x in proc.stderr.splitlines() if not x.startswith("PEAK-RSS-KB")]
    peak = round(rss[-1] / 1024, 1) if rss else None
    try:
        out = json.loads(proc.stdout)
    except json.JSONDecodeError:
        last = (stderr or [""])[-1]
        return {"status": "error", "seconds": seconds, "exit": proc.returncode, "error": last,
                "peak_rss_mib": peak}
    cert = out.get("certificate") or {}
    return {"status": {True: "ok", None: "undecided"}.get(out.get("complete"), "incomplete"),
            "seconds": seconds, "exit": proc.returncode,
            "components": len(out.get("components", ())),
            "special": len(out.get("special_components", ())),
            "locus_s": out.get("seconds"), "certificate_s": cert.get("seconds"),
            "verdict": cert.get("verdict"), "peak_rss_mib": peak}


def reference_time(root: Path) -> dict:
    """The reference chain's locus alone, as ``benchmarks/corpus.py`` times it."""
    code = (
        "import sys, time, json\n"
        "from rankloci.io import load_model\n"
        "from rankloci.jacobians import task_matrix\n"
        "from rankloci.methods import compute_locus\n"
        "m = load_model(sys.argv[1], base_link=sys.argv[2], tip=sys.argv[3])\n"
        "tm = task_matrix(m, task='full', frame='auto', numeric=True)\n"
        "t = time.perf_counter(); compute_locus(tm, 'svm')\n"
        "print(json.dumps(time.perf_counter() - t))\n")
    label, file, base, tip = REFERENCE
    proc = subprocess.run([sys.executable, "-c", code, str(root / file), base, tip],
                          capture_output=True, text=True, check=True)
    here = json.loads(proc.stdout)
    corpus = None
    table = HERE / "corpus.md"
    if table.is_file():
        for line in table.read_text().splitlines():
            cells = [c.strip() for c in line.strip("|").split("|")]
            if len(cells) > 5 and cells[1] == file and cells[2] == f"{base} -> {tip}":
                corpus = float(cells[5])
                break
    return {"label": label, "seconds": here, "corpus_seconds": corpus}


def render_markdown(rows, meta) -> str:
    ref = meta["reference"]
    jobs = meta["jobs"]
    lines = [
        "# Whole runs beyond the built-in models",
        "",
        "Each row is `rankloci locus ARGS --jobs N` as a user types it (symbolic parameters "
        "unless the arguments say otherwise), certificate and self-check included, in a fresh "
        "process, one at a time, timed from start to exit. *locus* is the engine's time for the "
        "locus shown (JSON `seconds`), *certificate* its certificate's (each computed once more "
        "in a recomputation is not in these two); *peak RSS* the largest resident set of the "
        "run's processes (GNU time). *result*: certified (JSON `\"complete\": true`), "
        "undecided (`null`: the certificate could not decide, the numeric self-check passed) or "
        "INCOMPLETE (`false`). *within*: certified, or undecided, in the target time. Targets: "
        + ", ".join(f"{t:g} s for up to {n} joints" for n, t in TARGETS) + ".",
        "",
        f"Python {meta['python']} on {meta['machine']}, {meta['cores']} cores, {meta['date']}. "
        "Other work ran on the machine at the same time (a shared machine): the seconds are "
        "those of a loaded machine."
        + ("" if not ref else " Machine speed in this run: the locus alone of "
           f"{ref['label']} took {ref['seconds']:.2f} s here"
           + (f", {ref['corpus_seconds']:.2f} s in benchmarks/corpus.md"
              if ref.get("corpus_seconds") else "") + "."),
        "",
        "| chain | joints | arguments | jobs | whole run (s) | locus (s) | certificate (s) | "
        "peak RSS (MiB) | target (s) | within | components | special | result |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]

    def f(x, digits=1):
        return "" if x is None else f"{x:.{digits}f}"

    for r in rows:
        for j in jobs:
            res = r["results"].get(str(j))
            if res is None:
                continue
            status = {"ok": "certified", "undecided": "undecided",
                      "incomplete": "INCOMPLETE"}.get(res["status"], res["status"])
            if res.get("error"):
                status += f": {res['error']}"
            within = "yes" if res["status"] in ("ok", "undecided") \
                and res["seconds"] <= r["target"] else "no"
            lines.append(
                f"| {r['name']} | {r['joints']} | `{' '.join(r['args'])}` | {j} | "
                f"{f(res.get('seconds'))} | {f(res.get('locus_s'))} | "
                f"{f(res.get('certificate_s'))} | {f(res.get('peak_rss_mib'), 0)} | "
                f"{r['target']:g} | {within} | {res.get('components', '')} | "
                f"{res.get('special', '')} | {status} |")
    if len(jobs) > 1:
        lines += ["", f"Speed-up of `--jobs {jobs[-1]}` over `--jobs {jobs[0]}` (whole run), "
                  "measured in this run. Nothing was measured on more cores than this machine "
                  "has.", "", "| chain | joints | " + " | ".join(f"jobs {j} (s)" for j in jobs)
                  + " | speed-up |", "| --- " * (len(jobs) + 3) + "|"]
        for r in rows:
            got = [r["results"].get(str(j), {}).get("seconds") for j in jobs]
            if None in got:
                continue
            lines.append(f"| {r['name']} | {r['joints']} | "
                         + " | ".join(f"{x:.1f}" for x in got)
                         + f" | {got[0] / got[-1]:.2f}x |")
    lines.append("")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="", help="comma-separated case names (default: all)")
    ap.add_argument("--timeout", type=float, default=300.0, help="limit per run (s)")
    ap.add_argument("--output", default=str(HERE / "frontier"))
    ap.add_argument("--no-reference", dest="reference", action="store_false",
                    help="leave out the reference chain's timing")
    ap.add_argument("--jobs", default="2",
                    help="comma-separated --jobs values, each case run with each (default 2)")
    opts = ap.parse_args(argv)
    root = robots_dir()
    wanted = {c.strip() for c in opts.cases.split(",") if c.strip()}
    jobs = [int(j) for j in opts.jobs.split(",") if j.strip()]
    rows = []
    for name, joints, args, what in CASES:
        if wanted and name not in wanted:
            continue
        if any("{robots}" in a for a in args) and root is None:
            print(f"{name}: skipped (example-robot-data is not installed)", file=sys.stderr)
            continue
        real = [a.replace("{robots}", str(root)) for a in args]
        shown = [a.replace("{robots}/", "").replace(str(HERE.parent) + "/", "") for a in args]
        results = {}
        for j in jobs:
            print(f"{name}, jobs {j} ...", file=sys.stderr, flush=True)
            results[str(j)] = run_case(real, opts.timeout, j)
            print(f"{name}: {results[str(j)]}", file=sys.stderr, flush=True)
        rows.append({"name": name, "joints": joints, "args": shown,
                     "what": what, "target": target(joints), "results": results})
    import os

    meta = {"python": platform.python_version(), "machine": platform.machine(),
            "cores": len(os.sched_getaffinity(0)), "jobs": jobs,
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "timeout_s": opts.timeout,
            "reference": reference_time(root) if root is not None and opts.reference
            else None}
    out = Path(opts.output)
    out.with_suffix(".json").write_text(json.dumps({"meta": meta, "rows": rows}, indent=1) + "\n")
    out.with_suffix(".md").write_text(render_markdown(rows, meta))
    print(f"wrote {out.with_suffix('.md')}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
