"""The subcommands of the ``rankloci`` command line, one function each.

Each takes the parsed arguments and returns the exit code: :data:`EXIT_OK`,
or :data:`EXIT_FAILED` when a check fails or a computation runs out of time.
Bad input raises (a :class:`~rankloci.errors.RanklociError` or a
:class:`~rankloci.errors.UsageError`); :func:`rankloci.cli.main` turns
that into :data:`EXIT_USAGE`.  Heavy libraries are imported inside the
functions so that ``rankloci --help`` stays fast.
"""

from __future__ import annotations

import contextlib
import json
import signal
import sys
import time

from .output import (check_names, clear_status, output_target, progress_printer, require_module,
                     write_atomic)
from .near import cmd_ik, cmd_manipulability
from ..errors import UsageError
from .running import command_deadline, limited
from .sweep import cmd_sweep

__all__ = ["COMMANDS", "EXIT_OK", "EXIT_FAILED", "EXIT_USAGE"]

EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2


def cmd_models(args) -> int:
    from ..io import builtin_models, models_dir
    from ..io.toml_model import read_model
    from ..model import RobotModel

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


def _check_link_numbers(args, model) -> None:
    """``--frame N`` and ``--point N`` must name a link frame 0..n of a robot model."""
    from ..model import RobotModel

    if not isinstance(model, RobotModel):
        return  # task_matrix refuses --frame for a matrix; cmd_jacobian refuses --point
    for option in ("frame", "point"):
        value = getattr(args, option, None)
        if isinstance(value, int) and not 0 <= value <= model.dof:
            raise UsageError(f"--{option} {value}: {model.name} has no link frame {value} "
                             f"(its link frames are 0..{model.dof}, base and tool)")


def _load_model(args):
    """The model and its parsed constraint rows (quick: the parser bounds the work)."""
    from ..augmented import parse_augment
    from ..io import load_model

    model = load_model(args.model, base_link=getattr(args, "base_link", None),
                       tip=getattr(args, "tip_link", None))
    _check_link_numbers(args, model)
    return model, parse_augment(model, args.augment or ())


def _task_matrix(args, model, extra, progress=None):
    """The task matrix the arguments ask for (symbolic work: run it under the limits)."""
    from ..jacobians import task_matrix

    if progress:
        progress(f"building the symbolic matrix of {model.name}")
    frame = args.frame if args.frame is not None else getattr(args, "frame_default", None)
    return task_matrix(model, task=args.task, frame=frame,
                       point=getattr(args, "point", "tool"), augment=extra,
                       numeric=getattr(args, "numeric", False))


def cmd_jacobian(args) -> int:
    from ..model import RobotModel

    model, extra = _load_model(args)
    if isinstance(model, RobotModel) is False and args.point != "tool":
        raise UsageError("--point applies to robot models only")
    notes = tuple(getattr(model, "notes", ()))
    text = limited(args, lambda tell: _jacobian_text(args, _task_matrix(args, model, extra, tell),
                                                      notes), None, "building the Jacobian")
    if text is None:
        return EXIT_FAILED
    print(text)
    return EXIT_OK


def _jacobian_text(args, tm, notes=()) -> str:
    """The matrix in the requested format; ``notes`` say what reading the model file changed."""
    import sympy as sp

    lines = []
    print = lines.append         # the lines of the output, in order
    J = tm.matrix
    if args.format == "json":
        out = {
            "schema": "rankloci.jacobian/1",
            "model": tm.name,
            "variables": [v.name for v in tm.variables],
            "parameters": {k.name: float(v) for k, v in tm.parameters.items()},
            "rows": list(tm.row_labels),
            "matrix": [[sp.sstr(J[i, j]) for j in range(J.cols)] for i in range(J.rows)],
            "notes": list(notes),
        }
        print(json.dumps(out, indent=2))
    elif args.format == "latex":
        for note in notes:
            print(f"% note: {note}")
        print(r"\begin{bmatrix}")
        for i in range(J.rows):
            print(" & ".join(sp.latex(J[i, j]) for j in range(J.cols)) + (r" \\" if i < J.rows - 1 else ""))
        print(r"\end{bmatrix}")
    else:
        print(f"# {tm.name}: {J.rows}x{J.cols} matrix in {', '.join(v.name for v in tm.variables)}")
        if tm.parameters:
            print("# parameters: " + ", ".join(f"{k} = {float(v):g}" for k, v in tm.parameters.items()))
        for note in notes:
            print(f"# note: {note}")
        for i in range(J.rows):
            for j in range(J.cols):
                print(f"J[{tm.row_labels[i]}, {tm.variables[j]}] = {sp.sstr(J[i, j])}")
    return "\n".join(lines)


def cmd_locus(args) -> int:
    from pathlib import Path

    from ..errors import LocusError
    from ..methods import method_for
    from ..render_text import locus_json, locus_latex, locus_text, tree_dot, tree_json, tree_text

    if args.tree:                 # before the computation, not after it
        output_target(args.tree, "--tree", (".dot", ".json", ".txt"))
    progress = progress_printer(args.quiet)
    model, extra = _load_model(args)

    def work(report):
        tell = report            # the parent prints it unless --quiet, and keeps the last one
        should_stop = command_deadline(args.timeout, getattr(args, "started", None))
        tm = _task_matrix(args, model, extra, tell)
        try:
            method = method_for(tm.shape, args.method)
        except LocusError:  # a method this shape does not allow: determinant on a non-square J
            raise UsageError(f"--method {args.method} needs a square matrix; this one is "
                             f"{tm.shape[0]}x{tm.shape[1]}") from None
        if tell:
            tell(f"{tm.name}: {tm.shape[0]}x{tm.shape[1]} matrix, method {method}, "
                 f"seed {args.seed}")
        from ..api.calls import model_locus
        from ..parallel import check_jobs

        locus = model_locus(model, tm, method, task=args.task, extra=extra, seed=args.seed,
                            verify=args.verify, progress=tell, should_stop=should_stop,
                            jobs=check_jobs(args.jobs), rank_rtol=args.rank_rtol)
        return locus, tm.row_labels

    got = limited(args, work, progress, "the locus computation")
    if got is None:
        return EXIT_FAILED
    locus, row_labels = got
    from ..api.results import with_model_notes

    locus = with_model_notes(locus, model, args.task)
    if args.tree:
        text = {".dot": tree_dot, ".json": tree_json, ".txt": tree_text}[Path(args.tree).suffix.lower()](locus.tree)
        write_atomic(args.tree, text + "\n", "--tree")
    import numpy as np

    from ..limits import within_limits

    checks = within_limits(locus, model, rng=np.random.default_rng(args.seed))
    if args.format == "json":
        print(locus_json(locus, within_limits=checks, rows=list(row_labels), seed=args.seed,
                         tolerances={"rank_rtol": args.rank_rtol}))
    elif args.format == "latex":
        print(locus_latex(locus))
    else:
        print(locus_text(locus, row_labels=row_labels, within_limits=checks))
        if args.show_tree:
            print()
            print(tree_text(locus.tree))
    if locus.complete is False:
        print("rankloci: the locus failed its certificate and is incomplete (see its notes)",
              file=sys.stderr)
        return EXIT_FAILED
    if locus.complete is None and args.verify:
        why = locus.certificate.findings[0] if locus.certificate is not None and \
            locus.certificate.findings else "no certificate"
        print(f"rankloci: the locus is not certified ({why}); the numeric self-check passed",
              file=sys.stderr)
    return EXIT_OK


#: The largest locus file ``check --locus`` reads (the built-in models' loci are below 100 kB).
MAX_LOCUS_BYTES = 20_000_000


def _parsed_locus(raw: bytes, file: str, model):
    """The locus of a ``--locus`` file's bytes; a ModelError naming the file."""
    from ..errors import ModelError
    from ..loci import Locus

    try:
        data = json.loads(raw.decode("utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise ModelError(f"not JSON: {e}", file=file) from None
    except RecursionError:
        raise ModelError("not a locus: nested too deeply", file=file) from None
    try:
        return Locus.from_dict(data, model)
    except ModelError as e:
        raise e.located(file=file) from None


def cmd_check(args) -> int:
    from ..errors import LocusTimeout, ModelError
    from ..io import load_model
    from ..process_limits import LimitExceeded, run_limited

    if args.samples < 1:
        raise UsageError(f"--samples must be at least 1, got {args.samples}")
    progress = progress_printer(args.quiet)
    model = load_model(args.model, base_link=args.base_link, tip=args.tip_link)
    raw = None
    if args.locus:
        from ..io.files import read_bounded

        try:
            raw = read_bounded(args.locus, MAX_LOCUS_BYTES)
        except OSError as e:
            raise ModelError(f"cannot read: {e.strerror}", file=args.locus) from None

    def work(report_progress):
        from ..api.calls import check_model

        # parsed here, in the child, under --timeout and --memory: a large locus file
        # takes time and memory to read
        locus = None if raw is None else _parsed_locus(raw, args.locus, model)
        return check_model(model, locus, samples=args.samples, seed=args.seed,
                           numeric=args.numeric,
                           should_stop=command_deadline(args.timeout, getattr(args, "started", None)),
                           progress=report_progress, jobs=args.jobs,
                           rank_rtol=args.rank_rtol)

    try:
        result = run_limited(work, timeout=args.timeout, memory_mb=args.memory,
                             progress=progress, started=getattr(args, "started", None))
    except LocusTimeout as e:
        # e says which computation stopped ("the svm computation did not finish ...")
        clear_status()
        print(f"rankloci: error: the check stopped: {e}; raise --timeout (now "
              f"{args.timeout:g} s)", file=sys.stderr)
        return EXIT_FAILED
    except LimitExceeded as e:
        # e is a predicate ("did not finish within 5 s and was stopped ...")
        clear_status()
        print(f"rankloci: error: the check {e}", file=sys.stderr)
        return EXIT_FAILED
    clear_status()
    ok = result.ok
    if args.format == "json":
        print(json.dumps(result.to_dict(), indent=2))
    else:
        print(result)
    return EXIT_OK if ok else EXIT_FAILED


#: A report runs several locus computations (the model's, the other method's, J under an
#: augmented J_aug), each stopped at --timeout and the report still written; the whole report
#: is killed at REPORT_TIME_FACTOR * --timeout + REPORT_TIME_EXTRA seconds.
REPORT_TIME_FACTOR = 4
REPORT_TIME_EXTRA = 120.0


@contextlib.contextmanager
def _terminate_as_interrupt():
    """SIGTERM raises KeyboardInterrupt while the block runs, so that its cleanup runs."""
    def interrupt(signum, frame):
        raise KeyboardInterrupt

    try:
        old = signal.signal(signal.SIGTERM, interrupt)
    except ValueError:        # not the main thread: signals stay as they are
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)


def cmd_report(args) -> int:
    import shutil
    from pathlib import Path

    from ..io import builtin_models, load_model
    from ..process_limits import LimitExceeded, run_limited
    from ..reporting import (FORMATS, ReportError, build_report, file_stem, read_model_notes,
                          write_report)
    from ..reporting.write import report_workdir

    formats = [f.strip() for f in args.format.split(",") if f.strip()]
    require_module("matplotlib", "report", "rankloci report")  # the figures
    bad = [f for f in formats if f not in FORMATS]
    if bad or not formats:
        raise UsageError(f"--format {args.format!r}: give a comma list of {', '.join(FORMATS)}")
    if args.samples < 1:
        raise UsageError(f"--samples must be at least 1, got {args.samples}")
    specs = builtin_models() if args.model == "all" else [args.model]
    models = [load_model(spec, base_link=args.base_link, tip=args.tip_link)
              for spec in specs]  # bad input fails here, before any writing
    if args.model == "all":
        targets = [Path(args.output or "reports") / file_stem(m.name) for m in models]
    else:
        targets = [Path(args.output) if args.output
                   else Path("reports") / file_stem(models[0].name)]
    for model, out in zip(models, targets):
        check_names(out, "-o")
        if out.exists() and not out.is_dir():
            raise UsageError(f"-o {str(out)!r}: exists and is not a directory")
        for fmt in formats:
            dest = out / f"{file_stem(model.name)}.{fmt}"
            if dest.is_symlink() or (dest.exists() and not dest.is_file()):
                raise UsageError(f"-o {str(out)!r}: {str(dest)!r} is not a regular file; "
                                 "nothing was written")
        anchor = next(p for p in [out, *out.absolute().parents] if p.exists())
        if not anchor.is_dir():
            raise UsageError(f"-o {str(out)!r}: {str(anchor)!r} is not a directory")
    progress = progress_printer(args.quiet)
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

        try:
            # made here, not in the child, so that it is removed even when the child is killed
            workdir = report_workdir(out)
        except OSError as e:
            raise UsageError(f"-o {str(out)!r}: cannot write there: {e.strerror or e}") from None

        def work(tell, model=model, out=out, workdir=workdir):
            report = build_report(model, seed=args.seed, samples=args.samples,
                                  numeric=args.numeric, timeout=args.timeout,
                                  clock=time.perf_counter, progress=tell,
                                  dot=dot, model_notes=read_model_notes(model), stamp=stamp,
                                  jobs=args.jobs, rank_rtol=args.rank_rtol)
            try:
                paths = write_report(report, out, formats=formats, fragment=args.fragment,
                                     latex=latex, timings=not args.no_timings,
                                     workdir=workdir)
            except ReportError as e:
                return None, str(e), False, False
            except OSError as e:
                raise UsageError(f"-o {str(out)!r}: cannot write there: "
                                 f"{e.strerror or e}") from None
            check_ok = report.check is None or (report.check.ok and (
                report.exact is None or report.exact.status != "disagree"))
            return paths, "", report.locus is None, check_ok

        limit = REPORT_TIME_FACTOR * args.timeout + REPORT_TIME_EXTRA if args.timeout else None
        try:
            with _terminate_as_interrupt():
                paths, failure, no_locus, check_ok = run_limited(
                    work, timeout=limit, memory_mb=args.memory, progress=progress)
        except LimitExceeded as e:
            clear_status()
            print(f"rankloci: error: {model.name}: the report {e}", file=sys.stderr)
            status = EXIT_FAILED
            continue
        finally:
            shutil.rmtree(workdir, ignore_errors=True)
        clear_status()
        if paths is None:
            print(f"rankloci: error: {model.name}: {failure}", file=sys.stderr)
            status = EXIT_FAILED
            continue
        if no_locus:
            print(f"rankloci: note: {model.name}: the locus did not finish within "
                  f"{args.timeout:g} s; the report says so", file=sys.stderr)
        if not check_ok:
            print(f"rankloci: {model.name}: the numeric cross-check FAILED; see the report",
                  file=sys.stderr)
            status = EXIT_FAILED
        if progress:
            progress(f"{model.name}: report written to {out} in {time.perf_counter() - t0:.1f} s")
        clear_status()
        for p in paths:
            if p.suffix in (".md", ".tex", ".pdf", ".html"):
                print(p)
    return status


#: Subcommand name -> the function that runs it.
COMMANDS = {
    "models": cmd_models,
    "jacobian": cmd_jacobian,
    "locus": cmd_locus,
    "check": cmd_check,
    "report": cmd_report,
    "sweep": cmd_sweep,
    "ik": cmd_ik,
    "manipulability": cmd_manipulability,
}
