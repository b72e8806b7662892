"""How long ``import rankloci`` takes, and the first use of the API, each in a fresh process.

Each run starts a new interpreter: ``python -X importtime -c "import rankloci"`` gives
the cumulative import time of the package (microseconds, its own line of the
report), and a second process times ``import rankloci`` and then the first
``rankloci.Locus`` and ``rankloci.locus`` look-ups with ``time.perf_counter``.
Results go to benchmarks/import_time.json and .md.
Usage: python benchmarks/import_time.py [--runs 5]
"""

import argparse
import json
import platform
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent

TIMED = ("import time; t = time.perf_counter(); import rankloci; a = time.perf_counter() - t; "
         "t = time.perf_counter(); rankloci.Locus; b = time.perf_counter() - t; "
         "t = time.perf_counter(); rankloci.locus; c = time.perf_counter() - t; "
         "import json; print(json.dumps([a, b, c]))")


def importtime_ms() -> float:
    """Cumulative microseconds of the ``rankloci`` line of ``-X importtime``, in ms."""
    err = subprocess.run([sys.executable, "-X", "importtime", "-c", "import rankloci"],
                         capture_output=True, text=True, check=True, cwd=HERE.parent).stderr
    line = next(ln for ln in err.splitlines() if ln.rstrip().endswith("| rankloci"))
    return int(line.split("|")[1]) / 1000


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args(argv)
    rows = []
    for _ in range(args.runs):
        out = subprocess.run([sys.executable, "-c", TIMED], capture_output=True, text=True,
                             check=True, cwd=HERE.parent).stdout
        a, b, c = json.loads(out)
        rows.append({"importtime_ms": importtime_ms(), "import_ms": 1000 * a,
                     "first_Locus_ms": 1000 * b, "first_locus_ms": 1000 * c})
    env = f"Python {platform.python_version()} on {platform.machine()}, {args.runs} fresh processes"
    (HERE / "import_time.json").write_text(json.dumps({"environment": env, "runs": rows},
                                                      indent=2) + "\n")
    lines = [env + ".", "",
             "| run | -X importtime (ms) | import rankloci (ms) | first rankloci.Locus (ms) "
             "| then rankloci.locus (ms) |", "| --- | --- | --- | --- | --- |"]
    lines += [f"| {k} | {r['importtime_ms']:.1f} | {r['import_ms']:.1f} | "
              f"{r['first_Locus_ms']:.0f} | {r['first_locus_ms']:.0f} |"
              for k, r in enumerate(rows, 1)]
    (HERE / "import_time.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
