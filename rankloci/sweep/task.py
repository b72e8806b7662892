"""One case of a sweep, computed under its limits: what each worker runs.

:func:`run_case` computes the locus of a case as ``rankloci locus`` does
(:func:`rankloci.api.calls.model_locus` with ``--frame auto``, the self-check
unless the spec turns it off) in a forked
child under the time and memory limits of
:func:`rankloci.process_limits.run_limited`, so a case that runs out of either
ends as a record saying so, and the worker goes on with the next case.
It returns the case's record: a JSON-ready dict with the locus (or None) and
the row of the summary.  It raises nothing for a failed case: running out of
time or memory, a model that does not read and a bug in the computation are
all results.
"""

from __future__ import annotations

import time

__all__ = ["run_case", "failed_result", "RECORD_SCHEMA", "STATUSES"]

#: ``schema`` of the ``sweep`` part of a case file.
RECORD_SCHEMA = "rankloci.sweep-case/1"

#: What became of a case: the locus was computed, or it ran out of time, or of memory, or
#: it failed (a model that does not read, a method the matrix does not allow, a bug).
STATUSES = ("done", "timeout", "memory", "error")

#: Longest ``note`` of a summary row, in characters.
NOTE_CHARS = 160


def _model(case, text):
    from ..io.toml_model import parse_model

    if case.kind == "urdf":
        from ..io.urdf import parse_urdf

        model = parse_urdf(text, name=case.file.rsplit(".", 1)[0], file=case.file,
                           base_link=case.base_link, tip=case.tip)
    else:
        model = parse_model(text, file=case.file)
    values = case.parameter_values
    if values:
        import dataclasses

        model = dataclasses.replace(model, parameters={
            p: values.get(p.name, v) for p, v in model.parameters.items()})
    return model


def _kinds(locus) -> str:
    from ..augmented import KINDS

    if locus.degenerate:
        return "degenerate"
    counts = [(k, sum(c.kind == k for c in locus.components)) for k in KINDS]
    return ", ".join(f"{n} {k}" for k, n in counts if n)


def _work(case, text, timeout):
    """The child's work: ``tell -> (locus dict, the case's summary fields)``."""

    def work(tell):
        from ..api.calls import model_locus
        from ..augmented import parse_augment
        from ..errors import LocusError
        from ..jacobians import task_matrix
        from ..methods import method_for

        model = _model(case, text)
        extra = parse_augment(model, case.augment)
        tell(f"{case.label}: building the symbolic matrix")
        tm = task_matrix(model, task=case.task, frame="auto", augment=extra,
                         numeric=case.numeric)
        try:
            method = method_for(tm.shape, case.method)
        except LocusError:
            raise LocusError(f"method {case.method} needs a square matrix; this one is "
                             f"{tm.shape[0]}x{tm.shape[1]}") from None
        locus = model_locus(model, tm, method, task=case.task, extra=extra, seed=case.seed,
                            timeout=timeout or None, verify=case.verify, progress=tell)
        data = locus.to_dict() | {"rows": list(tm.row_labels), "seed": case.seed}
        summary = {
            "matrix": f"{tm.shape[0]}x{tm.shape[1]}",
            "components": len(locus.components),
            "special": len(locus.special),
            "kinds": _kinds(locus),
            "check": {True: "pass", False: "fail", None: "not run"}[locus.complete],
        }
        return data, summary

    return work


def _preload() -> None:
    """Import what a case needs before forking, so that each case's child inherits it.

    A worker process would otherwise import sympy, numpy, scipy and the locus machinery
    afresh in every child (about a second per case); loaded once in the worker, the
    children share them.
    """
    from .. import augmented, jacobians, methods, verify  # noqa: F401
    from ..api import calls  # noqa: F401
    from ..io import toml_model, urdf  # noqa: F401
    from ..numeric import crosscheck  # noqa: F401


def _short(text: str) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= NOTE_CHARS else text[: NOTE_CHARS - 3] + "..."


def failed_result(case, message: str, *, timeout: float, memory: int,
                  transient: bool = False) -> dict:
    """The result of a case that failed with ``message`` (status ``error``, no locus).

    ``transient`` marks a failure of the machinery rather than of the case (a worker
    that died): a resumed sweep computes such a case again.  ``worker`` is the address of
    the Dask worker that ran the case (set by the executor; ``""`` in this process).
    """
    record = {
        "schema": RECORD_SCHEMA, "id": case.id, "case": case.label, "model": case.model,
        "hash": case.hash, "joints": case.joints, "matrix": "",
        "parameters": {name: label for name, label, _ in case.parameters},
        "augment": list(case.augment), "task": case.task, "method": case.method,
        "status": "error", "components": None, "special": None, "kinds": "", "check": "",
        "note": _short(message), "message": message,
        "limits": {"timeout": timeout, "memory": memory}, "seconds": 0.0,
        "transient": transient, "worker": "", "peak_mib": None,
    }
    return {"sweep": record, "locus": None}


def run_case(case, text: str | None, *, timeout: float, memory: int) -> dict:
    """The record of one case, computed in a child process under the limits.

    Parameters
    ----------
    case : rankloci.sweep.cases.Case
    text : str or None
        The model file's text (None for a case with a ``problem``).
    timeout : float
        Seconds for the whole case (0: none); the child is killed one second after.
    memory : int
        Limit of the child's own memory in MiB (0: none): the pages it does not share
        with the worker that forked it (:func:`rankloci.process_limits.own_memory_mib`), the
        same whatever process runs the case.

    Returns
    -------
    dict
        ``{"sweep": record, "locus": locus dict or None}``; the record holds the
        summary row (``status`` is one of :data:`STATUSES`), the limits, the
        seconds the case took and the largest own memory read while it ran
        (``peak_mib``, MiB; None without a memory limit).
    """
    from ..process_limits import ChildFailed, LimitExceeded, run_limited
    from ..errors import LocusTimeout, RanklociError

    if case.problem:
        return failed_result(case, case.problem, timeout=timeout, memory=memory)
    record = failed_result(case, "", timeout=timeout, memory=memory)["sweep"]
    _preload()
    start = time.perf_counter()
    locus = None
    usage: dict = {}
    try:
        locus, summary = run_limited(_work(case, text, timeout), timeout=timeout or None,
                                     memory_mb=memory or None, usage=usage)
        record.update(summary, status="done", method=locus["method"])
        if summary["check"] == "fail":
            record["note"] = "the self-check rejects the locus (see its notes)"
    except LocusTimeout as e:
        record.update(status="timeout", note=f"over {timeout:g} s", message=str(e))
    except LimitExceeded as e:
        message = str(e)
        if message.startswith("did not finish"):
            record.update(status="timeout", note=f"over {timeout:g} s")
        elif "out of memory" in message:
            record.update(status="memory", note=f"over {memory} MiB")
        else:
            record.update(note=_short(message))
        record["message"] = message
    except RanklociError as e:
        record.update(note=_short(e), message=str(e))
    except ChildFailed as e:
        last = str(e).strip().splitlines()[-1] if str(e).strip() else "no traceback"
        if memory and "MemoryError" in str(e):     # raised while handling another error
            record.update(status="memory", note=f"over {memory} MiB", message=str(e))
        else:
            record.update(note=_short(f"bug: {last}"), message=str(e))
    record["seconds"] = round(time.perf_counter() - start, 3)
    record["peak_mib"] = usage.get("peak_mib")
    return {"sweep": record, "locus": locus}
