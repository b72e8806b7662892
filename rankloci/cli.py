"""The ``rankloci`` command line.

This module is the only place that prints, writes files, reads the clock
and chooses exit codes: 0 success, 1 a check failed, 2 bad input.
Heavy libraries (sympy, numpy, matplotlib) are imported inside the
subcommands so that ``rankloci --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings

__all__ = ["main"]

EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2


class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line and an exception, not an exit."""

    def error(self, message):
        raise _UsageError(message)


def _fmt_warning(message, category, filename, lineno, file=None, line=None):
    return f"rankloci: warning: {message}\n"


# --- subcommands ------------------------------------------------------------

def cmd_models(args) -> int:
    from .io import builtin_models, models_dir
    from .io.toml_model import read_model
    from .model import RobotModel

    rows = []
    for name in builtin_models():
        model = read_model(models_dir() / f"{name}.toml", require_source=True)
        if isinstance(model, RobotModel):
            joints = model.dof
            shape = f"{len(model.task) + len(model.augment)}x{joints}"
        else:
            joints = len(model.variables)
            shape = f"{model.matrix.rows + len(model.augment)}x{model.matrix.cols}"
        source = " ".join(model.source.split())
        rows.append((name, str(joints), shape, source))
    if args.format == "json":
        print(json.dumps([dict(zip(("name", "joints", "shape", "source"), r)) for r in rows], indent=2))
        return EXIT_OK
    width = max(len(r[0]) for r in rows) if rows else 4
    print(f"{'name':<{width}}  joints  shape  source")
    for name, n, shape, source in rows:
        if len(source) > 70:
            source = source[:67] + "..."
        print(f"{name:<{width}}  {n:>6}  {shape:>5}  {source}")
    return EXIT_OK


def _frame_arg(text):
    if text in ("base", "tool"):
        return text
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not 'base', 'tool' or a link number") from None


def _task_arg(text):
    from .model import TASKS
    if text in TASKS:
        return text
    try:
        rows = [int(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not one of {', '.join(TASKS)} or a comma-separated row list like 0,1,5"
        ) from None
    from .model import task_rows
    try:
        return list(task_rows(rows))
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _load_task_matrix(args, progress=None):
    from .augmented import parse_augment
    from .io import load_model
    from .jacobian import task_matrix

    model = load_model(args.model, base_link=getattr(args, "base_link", None),
                       tip_link=getattr(args, "tip_link", None))
    extra = parse_augment(model, args.augment or ())
    if progress:
        progress(f"building the symbolic matrix of {model.name}")
    frame = args.frame if args.frame is not None else getattr(args, "frame_default", None)
    tm = task_matrix(model, task=args.task, frame=frame,
                     point=getattr(args, "point", "tool"), augment=extra,
                     numeric=getattr(args, "numeric", False))
    return model, tm


def cmd_jacobian(args) -> int:
    import sympy as sp

    from .model import RobotModel

    model, tm = _load_task_matrix(args)
    if isinstance(model, RobotModel) is False and args.point != "tool":
        raise _UsageError("--point applies to robot models only")
    J = tm.matrix
    if args.format == "json":
        out = {
            "schema": "rankloci.jacobian/1",
            "model": tm.name,
            "variables": [v.name for v in tm.variables],
            "parameters": {k.name: float(v) for k, v in tm.parameters.items()},
            "rows": list(tm.row_labels),
            "matrix": [[sp.sstr(J[i, j]) for j in range(J.cols)] for i in range(J.rows)],
        }
        print(json.dumps(out, indent=2))
    elif args.format == "latex":
        print(r"\begin{bmatrix}")
        for i in range(J.rows):
            print(" & ".join(sp.latex(J[i, j]) for j in range(J.cols)) + (r" \\" if i < J.rows - 1 else ""))
        print(r"\end{bmatrix}")
    else:
        print(f"# {tm.name}: {J.rows}x{J.cols} matrix in {', '.join(v.name for v in tm.variables)}")
        if tm.parameters:
            print("# parameters: " + ", ".join(f"{k} = {float(v):g}" for k, v in tm.parameters.items()))
        for i in range(J.rows):
            for j in range(J.cols):
                print(f"J[{tm.row_labels[i]}, {tm.variables[j]}] = {sp.sstr(J[i, j])}")
    return EXIT_OK


def _progress_printer(quiet: bool):
    if quiet:
        return None

    def progress(msg):
        print(f"rankloci: {msg}", file=sys.stderr, flush=True)

    return progress


def _deadline(seconds):
    import time

    if seconds is None or seconds <= 0:
        return None
    end = time.monotonic() + seconds
    return lambda: time.monotonic() > end


def _write_atomic(path, text):
    """Write ``text`` to ``path`` through a temporary file: never half-written."""
    import os
    import tempfile
    from pathlib import Path

    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent if str(path.parent) else ".", prefix=f".{path.name}.")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def cmd_locus(args) -> int:
    import time
    from pathlib import Path

    import numpy as np

    from .augmented import augmented_locus
    from .errors import LocusTimeout
    from .render_text import locus_json, locus_latex, locus_text, tree_dot, tree_json, tree_text

    if args.tree and Path(args.tree).suffix not in (".dot", ".json", ".txt"):
        raise _UsageError(f"--tree {args.tree!r}: the file must end in .dot, .json or .txt")
    if args.tree and not Path(args.tree).resolve().parent.is_dir():
        raise _UsageError(f"--tree {args.tree!r}: directory does not exist")
    progress = _progress_printer(args.quiet)
    model, tm = _load_task_matrix(args, progress)
    method = args.method
    if method is None:
        method = "determinant" if tm.shape[0] == tm.shape[1] else "svm"
    if method == "determinant" and tm.shape[0] != tm.shape[1]:
        raise _UsageError(f"--method determinant needs a square matrix; this one is "
                          f"{tm.shape[0]}x{tm.shape[1]}")
    if progress:
        progress(f"{tm.name}: {tm.shape[0]}x{tm.shape[1]} matrix, method {method}, seed {args.seed}")
    try:
        locus = augmented_locus(model, tm, method, seed=args.seed, progress=progress,
                                should_stop=_deadline(args.timeout), clock=time.perf_counter)
    except LocusTimeout as e:
        print(f"rankloci: error: {e}; raise --timeout (now {args.timeout:g} s) or try "
              f"--numeric-parameters", file=sys.stderr)
        return EXIT_FAILED
    if tm.frame is not None and (tm.frame, tm.point) != (getattr(model, "frame", None), "tool"):
        import dataclasses

        where = f"link frame {tm.frame}" if isinstance(tm.frame, int) else f"the {tm.frame} frame"
        about = f", about the origin of link frame {tm.point}" if isinstance(tm.point, int) else ""
        locus = dataclasses.replace(locus, notes=locus.notes + (
            f"J was computed in {where}{about} (same rank); symbolic lost directions are "
            f"expressed there, the directions at the sample points in the model's frame",))
    if args.tree:
        text = {".dot": tree_dot, ".json": tree_json, ".txt": tree_text}[Path(args.tree).suffix](locus.tree)
        _write_atomic(args.tree, text + "\n")
    if args.format == "json":
        print(locus_json(locus, rows=list(tm.row_labels), seed=args.seed))
    elif args.format == "latex":
        print(locus_latex(locus))
    else:
        print(locus_text(locus, row_labels=tm.row_labels))
        if args.show_tree:
            print()
            print(tree_text(locus.tree))
    return EXIT_OK


def cmd_check(args) -> int:
    import numpy as np

    from .errors import ModelError
    from .io import load_model
    from .jacobian import task_matrix
    from .numeric.crosscheck import cross_check, parse_locus, render_check_text

    if args.samples < 1:
        raise _UsageError(f"--samples must be at least 1, got {args.samples}")
    progress = _progress_printer(args.quiet)
    model = load_model(args.model)
    if args.locus:
        try:
            with open(args.locus, encoding="utf-8") as fh:
                data = json.load(fh)
        except OSError as e:
            raise ModelError(f"cannot read: {e.strerror}", file=args.locus) from None
        except (json.JSONDecodeError, UnicodeDecodeError) as e:
            raise ModelError(f"not JSON: {e}", file=args.locus) from None
        try:
            locus = parse_locus(data, model)
        except ModelError as e:
            raise e.located(file=args.locus) from None
    else:
        from .methods import compute_locus

        tm = task_matrix(model, frame="auto", numeric=args.numeric)
        method = "determinant" if tm.shape[0] == tm.shape[1] else "svm"
        if progress:
            progress(f"{tm.name}: computing the locus ({method}, seed {args.seed})")
        locus = compute_locus(tm, method, rng=np.random.default_rng(args.seed), progress=progress)
    J = task_matrix(model)  # the model's own frame; parameters substituted by cross_check
    if progress:
        progress(f"{model.name}: checking {len(locus.components)} component(s), "
                 f"{args.samples} samples, seed {args.seed}")
    report = cross_check(locus, J.matrix, J.variables, angles=J.angles, parameters=J.parameters,
                         samples=args.samples, rng=np.random.default_rng(args.seed),
                         seed=args.seed)
    from .exact.singular import singular_cross_check

    exact = singular_cross_check(task_matrix(model, frame="auto", numeric=True), locus,
                                 rng=np.random.default_rng(args.seed))
    ok = report.ok and exact.status != "disagree"
    if args.format == "json":
        print(json.dumps({**report.to_dict(), "singular": exact.to_dict(), "ok": ok}, indent=2))
    else:
        print(render_check_text(report))
        line = f"Singular (minimal associated primes of the maximal minors): {exact.status}, {exact.reason}"
        print(line)
        for finding in exact.findings:
            print(f"  {finding}")
    return EXIT_OK if ok else EXIT_FAILED


def cmd_report(args) -> int:
    import shutil
    import time
    from pathlib import Path

    from .io import builtin_models, load_model
    from .report import FORMATS, ReportError, build_report, read_model_notes, write_report

    formats = [f.strip() for f in args.format.split(",") if f.strip()]
    bad = [f for f in formats if f not in FORMATS]
    if bad or not formats:
        raise _UsageError(f"--format {args.format!r}: give a comma list of {', '.join(FORMATS)}")
    if args.samples < 1:
        raise _UsageError(f"--samples must be at least 1, got {args.samples}")
    if args.timeout < 0:
        raise _UsageError(f"--timeout must be 0 (no limit) or positive, got {args.timeout:g}")
    specs = builtin_models() if args.model == "all" else [args.model]
    models = [load_model(spec, base_link=args.base_link, tip_link=args.tip_link)
              for spec in specs]  # bad input fails here, before any writing
    if args.model == "all":
        targets = [Path(args.output or "reports") / m.name for m in models]
    else:
        targets = [Path(args.output) if args.output else Path("reports") / models[0].name]
    for out in targets:
        if out.exists() and not out.is_dir():
            raise _UsageError(f"-o {str(out)!r}: exists and is not a directory")
    progress = _progress_printer(args.quiet)
    latex = None
    if "pdf" in formats:
        latex = next(((kind, exe) for kind in ("latexmk", "pdflatex")
                      if (exe := shutil.which(kind))), None)
        if latex is None:
            print("rankloci: note: PDF skipped: neither latexmk nor pdflatex is installed",
                  file=sys.stderr)
    dot = shutil.which("dot")
    stamp = ""
    if args.timestamp:
        import datetime

        stamp = datetime.datetime.now().astimezone().isoformat(timespec="seconds")
    status = EXIT_OK
    for model, out in zip(models, targets):
        t0 = time.perf_counter()
        report = build_report(model, seed=args.seed, samples=args.samples, numeric=args.numeric,
                              timeout=args.timeout, clock=time.perf_counter, progress=progress,
                              dot=dot, model_notes=read_model_notes(model), stamp=stamp)
        try:
            paths = write_report(report, out, formats=formats, fragment=args.fragment,
                                 latex=latex, timings=not args.no_timings)
        except ReportError as e:
            print(f"rankloci: error: {model.name}: {e}", file=sys.stderr)
            status = EXIT_FAILED
            continue
        if report.locus is None:
            print(f"rankloci: note: {model.name}: the locus did not finish within "
                  f"{args.timeout:g} s; the report says so", file=sys.stderr)
        check_ok = report.check is None or (report.check.ok and (
            report.exact is None or report.exact.status != "disagree"))
        if not check_ok:
            print(f"rankloci: {model.name}: the numeric cross-check FAILED; see the report",
                  file=sys.stderr)
            status = EXIT_FAILED
        if progress:
            progress(f"{model.name}: report written to {out} in {time.perf_counter() - t0:.1f} s")
        for p in paths:
            if p.suffix in (".md", ".tex", ".pdf"):
                print(p)
    return status


# --- parser -----------------------------------------------------------------

_EPILOG_JACOBIAN = """examples:
  rankloci jacobian planar2r
  rankloci jacobian puma560 --frame tool --format latex
  rankloci jacobian ssrms --augment q3 --numeric --format json
  rankloci jacobian my_robot.urdf --tip tool0
"""

_EPILOG_LOCUS = """examples:
  rankloci locus puma560
  rankloci locus ssrms --numeric-parameters --format json > ssrms.json
  rankloci locus planar4r --augment "q1 + q2 + q3 + q4" --tree tree.dot
  rankloci locus pa10 --augment "lock(q3)"      # J, J_aug, kinds of J_aug's components
  rankloci locus pa10 --augment "elbow(z)" --format json
  rankloci locus my_matrix.toml --method subdeterminant --show-tree

The locus is printed as components: equations that vanish on each, the solved
form where there is one, dimension, rank drop and the lost task direction.
"""

_EPILOG_CHECK = """examples:
  rankloci check planar2r
  rankloci check puma560 --numeric-parameters --samples 20 --seed 7
  rankloci locus puma560 --numeric-parameters --format json > puma.json
  rankloci check puma560 --locus puma.json --format json

Samples points on each component (J must be rank deficient there), random
configurations away from every component (J must be full rank) and minima of
sigma_min/sigma_max (each singular one must lie on a component).  The SVD
decides; FSP reducer and maximal-minor disagreements are listed as findings.
Exit 0 when every check passes, 1 when one fails, 2 on bad input.
"""

_EPILOG_MODELS = """examples:
  rankloci models
  rankloci models --format json
"""

_EPILOG_REPORT = """examples:
  rankloci report puma560
  rankloci report planar3r -o out/planar3r --format md --samples 20 --seed 7
  rankloci report ssrms --fragment --format tex,pdf
  rankloci report all -o reports --timeout 120

Writes DIR/NAME.md, DIR/NAME.tex and, when latexmk or pdflatex is installed,
DIR/NAME.pdf, with the PNG figures beside them (default DIR: reports/NAME/;
with 'all', one directory per built-in model under -o).  The report holds the
model, the symbolic Jacobian, the locus component by component with its
reading, heat maps of sigma_min/sigma_max, the branch tree, the numeric
cross-check, the method comparison and the timings.  Equal seeds give equal
reports, the timing table aside (--no-timings leaves it out).  Exit 0 when
written, 1 when the cross-check fails or LaTeX fails, 2 on bad input.
"""


def _model_args(p):
    p.add_argument("model", metavar="MODEL|FILE",
                   help="a built-in model name (see 'rankloci models') or a .toml/.urdf file")
    p.add_argument("--task", type=_task_arg, default=None,
                   help="rows of the 6-row Jacobian: full, position, orientation, planar, or e.g. 0,1,5")
    p.add_argument("--frame", type=_frame_arg, default=None,
                   help="frame the Jacobian is expressed in: base, tool, or a link number 0..n")
    p.add_argument("--augment", action="append", metavar="EXPR",
                   help="constraint function g(q) whose gradient is stacked under J (repeatable): "
                        "an expression, or a preset: lock(q3), sum(q1, q2, q3), position(k, x|y|z), "
                        "elbow(z), wrist(x) (points the model names)")
    p.add_argument("--base-link", dest="base_link", help="URDF only: first link of the chain")
    p.add_argument("--tip", dest="tip_link", help="URDF only: last link of the chain")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="rankloci",
        description="Closed-form rank-deficiency (singularity) loci of robot Jacobians "
                    "and symbolic matrices.",
        epilog="examples:\n  rankloci models\n  rankloci jacobian puma560\n"
               "\nrun 'rankloci COMMAND --help' for the options of a command.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    p = sub.add_parser("models", help="list the built-in models", epilog=_EPILOG_MODELS,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--format", choices=("text", "json"), default="text")
    p.set_defaults(func=cmd_models)

    p = sub.add_parser("jacobian", help="print the symbolic Jacobian of a model",
                       epilog=_EPILOG_JACOBIAN, formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_args(p)
    p.add_argument("--point", type=_frame_arg, default="tool",
                   help="reference point: origin of base, tool, or link frame 0..n (default tool)")
    p.add_argument("--numeric", action="store_true", help="replace parameters by their values")
    p.add_argument("--format", choices=("text", "latex", "json"), default="text")
    p.set_defaults(func=cmd_jacobian)

    p = sub.add_parser("locus", help="compute the rank-deficiency (singularity) locus",
                       epilog=_EPILOG_LOCUS, formatter_class=argparse.RawDescriptionHelpFormatter)
    _model_args(p)
    p.add_argument("--method", choices=("svm", "subdeterminant", "determinant"), default=None,
                   help="svm (default) or subdeterminant; determinant for a square matrix "
                        "(the default when the matrix is square)")
    p.add_argument("--numeric-parameters", dest="numeric", action="store_true",
                   help="replace the geometric parameters by their values before the algebra")
    p.add_argument("--format", choices=("text", "json", "latex"), default="text")
    p.add_argument("--tree", metavar="FILE", help="write the branch tree to FILE.dot, FILE.json or FILE.txt")
    p.add_argument("--show-tree", action="store_true", help="also draw the branch tree in the terminal")
    p.add_argument("--seed", type=int, default=0, help="seed of the numeric probes (default 0)")
    p.add_argument("--timeout", type=float, default=600.0,
                   help="give up after this many seconds (default 600; 0 = never)")
    p.add_argument("--quiet", action="store_true", help="no progress messages on stderr")
    p.set_defaults(func=cmd_locus, frame_default="auto")

    p = sub.add_parser("check", help="cross-check a locus numerically against the SVD of J",
                       epilog=_EPILOG_CHECK, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("model", metavar="MODEL|FILE",
                   help="a built-in model name (see 'rankloci models') or a .toml/.urdf file")
    p.add_argument("--locus", metavar="LOCUS.json",
                   help="check this rankloci.locus/1 file instead of computing the locus")
    p.add_argument("--samples", type=int, default=10,
                   help="points per component, off-locus points and probe starts (default 10)")
    p.add_argument("--seed", type=int, default=0, help="seed of the random points (default 0)")
    p.add_argument("--format", choices=("text", "json"), default="text")
    p.add_argument("--numeric-parameters", dest="numeric", action="store_true",
                   help="replace the geometric parameters by their values before the algebra")
    p.add_argument("--quiet", action="store_true", help="no progress messages on stderr")
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("report", help="write a report (Markdown, LaTeX, PDF, figures) on a model",
                       epilog=_EPILOG_REPORT, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("model", metavar="MODEL|FILE|all",
                   help="a built-in model name, a .toml/.urdf file, or 'all' built-in models")
    p.add_argument("-o", "--output", metavar="DIR",
                   help="directory to write into (default reports/NAME; with 'all', the parent "
                        "directory, default reports)")
    p.add_argument("--format", default="md,tex,pdf", metavar="LIST",
                   help="comma list of md, tex, pdf (default all three; pdf only when latexmk "
                        "or pdflatex is installed)")
    p.add_argument("--samples", type=int, default=10,
                   help="cross-check points per component, off-locus points and probe starts "
                        "(default 10)")
    p.add_argument("--seed", type=int, default=0, help="seed of every random choice (default 0)")
    p.add_argument("--fragment", action="store_true",
                   help="write the .tex without a preamble, to \\input into a paper")
    p.add_argument("--numeric-parameters", dest="numeric", action="store_true",
                   help="replace the geometric parameters by their values before the algebra")
    p.add_argument("--timeout", type=float, default=600.0,
                   help="seconds per locus computation (default 600; 0 = never); when it runs "
                        "out the report is written without the locus and says so")
    p.add_argument("--no-timings", dest="no_timings", action="store_true",
                   help="leave out the timing table (then equal seeds give identical files)")
    p.add_argument("--timestamp", action="store_true",
                   help="print the date and time of writing under the title (off by default, "
                        "so that reports are reproducible)")
    p.add_argument("--base-link", dest="base_link", help="URDF only: first link of the chain")
    p.add_argument("--tip", dest="tip_link", help="URDF only: last link of the chain")
    p.add_argument("--quiet", action="store_true", help="no progress messages on stderr")
    p.set_defaults(func=cmd_report)
    return parser


def main(argv=None) -> int:
    """Run the command line; return the exit code."""
    from .errors import RanklociError

    warnings.showwarning = lambda *a, **k: sys.stderr.write(_fmt_warning(*a[:4]))
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if not getattr(args, "command", None):
            parser.print_help()
            return EXIT_USAGE
        return args.func(args)
    except (_UsageError, ValueError) as e:  # ValueError: a bad --frame/--point index for this model
        print(f"rankloci: error: {e}", file=sys.stderr)
        return EXIT_USAGE
    except RanklociError as e:
        print(f"rankloci: error: {e}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("rankloci: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return EXIT_OK


def main_exit() -> None:
    """Console-script entry point: run :func:`main` and exit with its code."""
    sys.exit(main())
