"""``rankloci sweep SPEC.toml -o DIR``: many locus computations, on Dask distributed.

The spec (:mod:`rankloci.sweep.spec`) expands to cases (:mod:`rankloci.sweep.cases`);
each case runs under its limits (:mod:`rankloci.sweep.task`) in this process or on a
Dask cluster (:mod:`rankloci.sweep.execute`).  This module writes the files:

- ``DIR/cases/ID.json`` for each case as soon as it finishes: the locus as
  ``rankloci locus --format json`` writes it (``rankloci check MODEL --locus``
  reads it), plus a ``sweep`` record: the case, its status, the summary row, the
  limits and the case's hash;
- ``DIR/summary.csv``, ``DIR/summary.md`` and a figure, once every case is done.

Every file is written atomically (a temporary file renamed into place), so an
interrupted sweep leaves whole files only; run again, it skips every case whose
file carries the same hash (cases that ran out of time or memory are computed again
when the limits are now larger).
"""

from __future__ import annotations

import math

import argparse
import contextlib
import json
import re
import signal
import sys
import time
from pathlib import Path

from .output import TEMP_SUFFIX, check_names, write_atomic
from ..errors import UsageError
from .arguments import memory_arg, timeout_arg

__all__ = ["add_sweep_arguments", "cmd_sweep", "EPILOG_SWEEP"]

EPILOG_SWEEP = """examples:
  rankloci sweep examples/sweeps/robots.toml -o out/robots     # a local Dask cluster, one worker per core
  rankloci sweep examples/sweeps/designs.toml -o out/designs --workers 2
  rankloci sweep examples/sweeps/augment.toml -o out/augment --serial  # no Dask: one case after another
  rankloci sweep examples/sweeps/designs.toml -o out/designs --scheduler tcp://head:8786

A spec (TOML, read as data) names the models (built-in names, .toml/.urdf files,
directories, every chain of a URDF file with chains = "all"), a grid over parameter
values and constraint rows, the task, the method and the limits per case; see
examples/sweeps/ in rankloci's source tree (a robot collection, a design grid and an
augment grid) and the user guide's page on sweeps.  Writes DIR/cases/*.json (one
locus per case), DIR/summary.csv, DIR/summary.md and a figure.  Run again to resume:
finished cases are skipped.  The local cluster serves Dask's dashboard (its link is
printed; --no-dashboard for none).
Exit 0 when every case is done and passes its self-check, 1 otherwise, 2 on bad input.
"""


def _workers_arg(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text[:20]!r} is not a number of workers 1 or above")
    return value


def _seconds_arg(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (0 < value <= 3600):
        raise argparse.ArgumentTypeError(f"{text[:20]!r} is not a number of seconds above 0 "
                                         f"and at most 3600")
    return value


def _cores() -> int:
    import os

    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def add_sweep_arguments(p) -> None:
    """The arguments of ``rankloci sweep``."""
    p.add_argument("spec", metavar="SPEC.toml", help="the sweep specification")
    p.add_argument("-o", "--output", metavar="DIR", required=True,
                   help="directory of the case files and the summary (created if needed)")
    p.add_argument("--workers", type=_workers_arg, default=None, metavar="N",
                   help="worker processes of the local Dask cluster (default: one per core)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="use a running Dask scheduler, e.g. tcp://HOST:8786, instead of a local "
                        "cluster")
    p.add_argument("--connect-timeout", type=_seconds_arg, default=None, metavar="SECONDS",
                   help="seconds to wait for the scheduler of --scheduler to answer, then for "
                        "its first worker (default 20)")
    p.add_argument("--no-dashboard", action="store_true",
                   help="no Dask dashboard for the local cluster (by default it is served on "
                        "port 8787, or a free port, and its link printed)")
    p.add_argument("--serial", action="store_true",
                   help="no Dask: run the cases one after another in this process (the default "
                        "when one case is left to run)")
    p.add_argument("--timeout", type=timeout_arg, default=None,
                   help="seconds per case, instead of the spec's (0 = none)")
    p.add_argument("--memory", type=memory_arg, default=None, metavar="MIB",
                   help="limit of each case's own memory in MiB (the pages its process holds "
                        "alone), instead of the spec's (0 = none)")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")


class _Progress:
    """A bar redrawn in place on a terminal; one line per finished case otherwise."""

    def __init__(self, total: int, to_run: int, quiet: bool, stream=None):
        self.stream = stream or sys.stderr
        self.quiet = quiet
        self.tty = not quiet and self.stream.isatty()
        self.total, self.to_run = total, to_run
        self.finished_before = total - to_run
        self.done = self.failed = 0
        self.running: set = set()
        self.workers: dict = {}
        self.finished_ids: set = set()
        self.start = time.monotonic()
        self._drawn = False

    def line(self, text: str) -> None:
        if self.quiet:
            return
        if self._drawn:
            self.stream.write("\r\033[K")
            self._drawn = False
        print(f"rankloci: {text}", file=self.stream, flush=True)

    def _eta(self) -> str:
        if not self.done:
            return "--"
        left = (time.monotonic() - self.start) / self.done * (self.to_run - self.done)
        return f"{int(left // 60)}m{int(left % 60):02d}s" if left >= 60 else f"{left:.0f}s"

    def draw(self) -> None:
        if not self.tty:
            return
        n = self.finished_before + self.done
        width = 24
        full = int(width * n / max(self.total, 1))
        self.stream.write(f"\r\033[Ksweep [{'#' * full}{'.' * (width - full)}] {n}/{self.total} "
                          f"done, {len(self.running)} running, {self.failed} failed, "
                          f"ETA {self._eta()}")
        self.stream.flush()
        self._drawn = True

    def started(self, case, worker: str = "") -> None:
        if case.id in self.finished_ids:      # its start reported after its end
            return
        if case.id in self.running:
            self.line(f"note: {case.label}: running again on {worker or 'another worker'}: the "
                      f"worker that was running it ({self.workers[case.id] or 'unknown'}) "
                      f"was lost")
        self.running.add(case.id)
        self.workers[case.id] = worker
        self.draw()

    def finished(self, case, record) -> None:
        self.running.discard(case.id)
        self.finished_ids.add(case.id)
        self.done += 1
        ok = record["status"] == "done" and record.get("check") != "fail"
        self.failed += not ok
        if not self.tty and not self.quiet:
            what = (f"{record['components']} component{'' if record['components'] == 1 else 's'}"
                    f", check {record['check']}" if record["status"] == "done"
                    else record["note"])
            if not ok and record.get("worker") and record["worker"] not in what:
                what += f" (on worker {record['worker']})"
            self.line(f"[{self.finished_before + self.done}/{self.total}] {case.label}: "
                      f"{record['status']}, {what} ({record['seconds']:.1f} s)")
        self.draw()

    def close(self) -> None:
        if self._drawn:
            self.stream.write("\n")
            self.stream.flush()
            self._drawn = False


def _number(value, *, integer=False) -> bool:
    """Is ``value`` a finite number 0 or above (an integer when asked) in a case file?"""
    kinds = (int,) if integer else (int, float)
    return (isinstance(value, kinds) and not isinstance(value, bool)
            and (isinstance(value, int) or math.isfinite(value)) and value >= 0)


#: The fields of a case file's ``sweep`` record that a resumed sweep takes from the file,
#: and what each must be; the others (model, case, parameters, ...) come from the spec.
_RESULT_FIELDS = {
    "components": lambda v: v is None or _number(v, integer=True),
    "special": lambda v: v is None or _number(v, integer=True),
    "kinds": lambda v: isinstance(v, str),
    "check": lambda v: isinstance(v, str),
    "note": lambda v: isinstance(v, str),
    "message": lambda v: isinstance(v, str),
    "matrix": lambda v: isinstance(v, str),
    "method": lambda v: v is None or isinstance(v, str),
    "seconds": _number,
    "limits": lambda v: isinstance(v, dict) and all(_number(v.get(k, 0))
                                                    for k in ("timeout", "memory")),
}


def _finished_record(path: Path, case, timeout: float, memory: int):
    """The record of ``case`` in ``path`` if it counts as finished for these limits, else None.

    A file that is not what a sweep writes (edited by hand, truncated, from another
    version) does not count: its case is computed again.
    """
    from ..io.files import read_bounded
    from ..sweep.task import STATUSES, failed_result

    try:
        data = json.loads(read_bounded(path, MAX_CASE_BYTES).decode("utf-8"))
        record = data["sweep"]
        if record["hash"] != case.hash or record["status"] not in STATUSES:
            return None
        if not all(ok(record[k]) for k, ok in _RESULT_FIELDS.items()):
            return None
        before = record["limits"]
    except (OSError, ValueError, KeyError, TypeError, RecursionError):
        return None
    if record["status"] == "error" and record.get("transient"):
        return None

    def covers(old, new):           # a limit of 0 is no limit
        return old == 0 or (new != 0 and old >= new)

    if record["status"] == "timeout" and not covers(before.get("timeout", 0), timeout):
        return None
    if record["status"] == "memory" and not covers(before.get("memory", 0), memory):
        return None
    fresh = failed_result(case, "", timeout=timeout, memory=memory)["sweep"]
    return fresh | {k: record[k] for k in (*_RESULT_FIELDS, "status")}


#: The largest case file a resumed sweep reads (a locus of a long chain: a few MB).
MAX_CASE_BYTES = 50_000_000


#: The address schemes a Dask scheduler is reached by from here.
SCHEDULER_SCHEMES = ("tcp", "tls")


def scheduler_address(text: str) -> str:
    """``text`` when it is a Dask scheduler address ``SCHEME://HOST:PORT``; a usage error if not.

    Examples
    --------
    >>> scheduler_address("tcp://10.0.0.5:8786")
    'tcp://10.0.0.5:8786'
    >>> scheduler_address("tcp://[::1]:8786")
    'tcp://[::1]:8786'
    """
    from urllib.parse import urlsplit

    shown = f"--scheduler {text[:80]!r}"
    hint = f"give an address like tcp://HOST:8786 ({' or '.join(SCHEDULER_SCHEMES)})"
    try:
        parts = urlsplit(text)
        port = parts.port
    except ValueError as e:
        raise UsageError(f"{shown}: {e}; {hint}") from None
    if parts.scheme not in SCHEDULER_SCHEMES or not parts.hostname or port is None \
            or parts.path or parts.query or parts.fragment or parts.username:
        raise UsageError(f"{shown}: {hint}")
    if port == 0:
        raise UsageError(f"{shown}: port 0 is not a port; {hint}")
    return text


def _output_dir(text: str) -> Path:
    out = Path(text)
    check_names(out, "-o")
    if out.exists() and not out.is_dir():
        raise UsageError(f"-o {text!r}: exists and is not a directory")
    anchor = next(p for p in [out, *out.absolute().parents] if p.exists())
    if not anchor.is_dir():
        raise UsageError(f"-o {text!r}: {str(anchor)!r} is not a directory")
    return out


#: The name of a temporary file that :func:`~rankloci.cli.output.write_atomic` left in the
#: cases folder (``.ID.json.XXXXXXXX.rankloci-tmp``): nothing else there is removed.
_OWN_TEMP = re.compile(r"\.[A-Za-z0-9_.-]+\.json\.[a-z0-9_]{8}" + re.escape(TEMP_SUFFIX))


def _settings(spec, timeout, memory) -> str:
    task = spec.task if spec.task is not None else (
        "as each entry sets it, else the model's own" if any(e.task is not None
                                                            for e in spec.entries)
        else "each model's own")
    return (f"Spec `{spec.file}`: task {task}, method {spec.method or 'the default for the shape'}"
            f", parameters {'substituted' if spec.numeric else 'symbolic'}, seed {spec.seed}, "
            f"self-check {'on' if spec.verify else 'off'}; at most "
            f"{f'{timeout:g} s' if timeout else 'unlimited time'} and "
            f"{f'{memory} MiB' if memory else 'unlimited memory'} per case.")


def _executor(args, pending, memory):
    """``(DaskExecutor or None, where it runs)`` for the cases to run (None: in this process)."""
    from ..sweep.execute import CONNECT_TIMEOUT_S, DaskExecutor, SetupError

    if args.serial or (len(pending) <= 1 and not args.scheduler):
        # one case runs here, unless a scheduler was named: then its address is used (and a
        # wrong one is reported, not ignored)
        return None, "in this process, one after another"
    try:
        if args.scheduler:
            ex = DaskExecutor.remote(args.scheduler, connect_timeout=args.connect_timeout
                                     or CONNECT_TIMEOUT_S)
        else:
            ex = DaskExecutor.local(args.workers or _cores(), dashboard=not args.no_dashboard)
    except ImportError:
        from ..extras import install_command

        raise UsageError(f"Dask is not installed: {install_command('sweep')}, or use "
                         "--serial") from None
    except SetupError as e:
        raise UsageError(str(e)) from None
    try:
        threads = ex.check_workers(memory)
    except SetupError as e:
        ex.close()
        raise UsageError(str(e)) from None
    where = args.scheduler or "a local Dask cluster"
    return ex, f"on {where}, {threads} worker thread{'' if threads == 1 else 's'}"


@contextlib.contextmanager
def _interrupts_remembered():
    """Ctrl-C raises KeyboardInterrupt and is remembered; yields ``interrupted()``.

    A KeyboardInterrupt raised inside a callback that Python runs and whose exceptions it
    ignores (logging's lock release after each fork of a case's child: "Exception ignored in
    _releaseLock") was lost, and the sweep went on.  Remembered, it stops the sweep at the
    next event at the latest.
    """
    hits = []

    def interrupt(signum, frame):
        hits.append(signum)
        raise KeyboardInterrupt

    try:
        old = signal.signal(signal.SIGINT, interrupt)
    except ValueError:           # not the main thread: signals stay as they are
        yield lambda: False
        return
    try:
        yield lambda: bool(hits)
    finally:
        signal.signal(signal.SIGINT, old)


def _until(interrupted, events):
    """The events, with a KeyboardInterrupt as soon as ``interrupted()`` says one was lost."""
    for event in events:
        if interrupted():
            raise KeyboardInterrupt
        yield event
        if interrupted():
            raise KeyboardInterrupt


def cmd_sweep(args) -> int:
    from ..sweep.cases import expand
    from ..sweep.execute import MEMORY_RESOURCE, serial_events
    from ..sweep.spec import read_spec
    from ..sweep.summary import render_csv, render_figure, render_markdown, status_counts

    from .output import require_module

    require_module("matplotlib", "report", "rankloci sweep (its summary figure)")
    if args.serial and (args.scheduler or args.workers):
        raise UsageError("--serial runs without Dask; it excludes --workers and --scheduler")
    if args.connect_timeout and not args.scheduler:
        raise UsageError("--connect-timeout is the wait for the scheduler of --scheduler")
    if args.scheduler and args.workers:
        raise UsageError("--workers sizes a local cluster; a running scheduler has its own "
                         "workers")
    if args.scheduler:
        scheduler_address(args.scheduler)    # checked even when no case needs the cluster
    spec = read_spec(args.spec)
    timeout = spec.timeout if args.timeout is None else args.timeout
    memory = spec.memory if args.memory is None else args.memory
    out = _output_dir(args.output)
    cases, sources, skipped = expand(spec)  # bad input ends here, before anything is written
    if not cases:
        raise UsageError(f"{spec.file}: the spec gives no case ("
                         + "; ".join(skipped[:3]) + (" ..." if len(skipped) > 3 else "") + ")")
    case_dir = out / "cases"
    records = {}
    for case in cases:
        got = _finished_record(case_dir / f"{case.id}.json", case, timeout, memory)
        if got is not None:
            records[case.id] = got
    pending = [c for c in cases if c.id not in records]
    progress = _Progress(len(cases), len(pending), args.quiet)
    for note in skipped:
        progress.line(f"note: {note}")
    executor, where = _executor(args, pending, memory) if pending else (None, "")
    try:                                    # the first write: the spec and the cluster are good
        case_dir.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        if executor:
            executor.close()
        raise UsageError(f"-o {args.output!r}: cannot write there: {e.strerror or e}") from None
    for stale in case_dir.iterdir():       # temporary files of a run killed while writing
        if _OWN_TEMP.fullmatch(stale.name) and stale.is_file() and not stale.is_symlink():
            stale.unlink(missing_ok=True)
    progress.line(f"sweep {spec.file}: {len(cases)} case{'' if len(cases) == 1 else 's'}, "
                  f"{len(records)} finished before, {len(pending)} to run"
                  + (f" {where}" if pending else ""))
    if executor:
        link = executor.dashboard_link
        if link:
            progress.line(f"Dask dashboard: {link}")
        elif executor.cluster is not None and not args.no_dashboard:
            from ..extras import install_command

            progress.line(f"note: no Dask dashboard: it needs bokeh ({install_command('sweep')})")
        if memory and not executor.memory_offers:
            progress.line(f"note: the Dask workers declare no {MEMORY_RESOURCE} resource: the "
                          f"scheduler does not know that each case may use {memory} MiB")
    t0 = time.monotonic()
    try:
        events = (executor.events(pending, sources, timeout=timeout, memory=memory)
                  if executor else serial_events(pending, sources, timeout=timeout,
                                                 memory=memory))
        with _interrupts_remembered() as interrupted:
            for event in _until(interrupted, events):
                if event[0] == "start":
                    progress.started(event[1], event[2])
                elif event[0] == "done":
                    _, case, result = event
                    data = (result["locus"] or {}) | {"sweep": result["sweep"]}
                    write_atomic(case_dir / f"{case.id}.json", json.dumps(data, indent=2) + "\n")
                    records[case.id] = result["sweep"]
                    progress.finished(case, result["sweep"])
                else:
                    progress.draw()
    except KeyboardInterrupt:
        progress.close()
        if executor:
            executor.stop()
        progress.line(f"interrupted: {len(records)} of {len(cases)} cases are saved in "
                      f"{case_dir}; run the same command again to resume")
        raise
    finally:
        progress.close()
        if executor:
            executor.close()
    ordered = [records[c.id] for c in cases]
    figure = render_figure(ordered)
    figures = []
    if figure:
        name, caption, png = figure
        write_atomic(out / name, png, "-o")
        figures.append((name, caption))
    write_atomic(out / "summary.csv", render_csv(ordered))
    write_atomic(out / "summary.md", render_markdown(
        ordered, title=spec.file, settings=_settings(spec, timeout, memory), figures=figures,
        skipped=skipped))
    counts = status_counts(ordered)
    progress.line(f"sweep done in {time.monotonic() - t0:.1f} s: "
                  + ", ".join(f"{v} {k}" for k, v in counts.items()))
    print(out / "summary.md")
    ok = counts["done"] == len(cases) and not counts["check failed"]
    return 0 if ok else 1
