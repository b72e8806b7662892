"""The one pipeline from a model to a certified locus: read -> J -> engine -> certify -> result.

Each stage is a function of the previous stage's value, and each value is a small frozen
dataclass:

=============  ====================================  =======================================
stage          function                              value
=============  ====================================  =======================================
read           :func:`read`                          :class:`Request`: the model, options
J              :func:`matrices`                      :class:`Matrices`: J (or J_aug) and the
                                                     matrix the checks evaluate
engine         :func:`engine`                        :class:`Engine`: the engine's locus and
                                                     the tree it grew
certify        :func:`certify`                       :class:`Certified`: the locus as the
                                                     certificate and its recomputations left
                                                     it, and what they found
result         :func:`result`                        :class:`~rankloci.loci.Locus`, with the
                                                     notes of every stage in order
=============  ====================================  =======================================

The certify stage calls the engine again when the certificate fails (with the numeric check's
hints, resuming from the tree the engine returned, with the parameter values substituted,
another seed, another method): :func:`~rankloci.verify.verified_locus` decides which.

What is not a value of the computation (where progress goes, when to stop, the clock, the
worker processes) travels beside it in a :class:`Run`.

:func:`rankloci.api.calls.certified_locus` (and through it every command and the Python API)
runs the stages from ``read``; the commands that build their own matrix (``rankloci locus``
with ``--frame`` or ``--point``, sweeps) start at ``matrices`` with it.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from typing import Callable

from .tolerances import RANK_RTOL

__all__ = ["Run", "Request", "Matrices", "Engine", "Certified", "read", "matrices", "engine",
           "certify", "result", "model_locus"]


@dataclass(frozen=True)
class Run:
    """How a computation runs, which does not change its result.

    Attributes
    ----------
    progress : callable or None
        Called with one-line progress messages.
    should_stop : callable or None
        Polled; True once the time is up (:class:`~rankloci.errors.LocusTimeout`).
    clock : callable
        Fills ``Locus.seconds``.
    workers : rankloci.parallel.Workers or None
        Processes for the independent parts (None: one after another, here).
    """

    progress: Callable[[str], None] | None = None
    should_stop: Callable[[], bool] | None = None
    clock: Callable[[], float] = time.perf_counter
    workers: object = None


@dataclass(frozen=True)
class Request:
    """The read stage: a loaded model and the options of its locus.

    ``extra`` holds the parsed constraint rows of ``augment``; ``rank_rtol`` is the rank
    threshold of the numeric self-check (sigma_min <= rank_rtol * sigma_max).
    """

    model: object
    task: object = None
    augment: tuple = ()
    extra: tuple = ()
    method: str | None = None
    seed: int = 0
    numeric: bool = False
    verify: bool = True
    frame: object = "auto"
    rank_rtol: float = RANK_RTOL


@dataclass(frozen=True)
class Matrices:
    """The J stage: the matrix whose locus is computed, its method, and the matrix the checks
    evaluate (the same rows in the same frame, parameters symbolic; None without checks)."""

    request: Request
    tm: object
    method: str
    reference: object = None


@dataclass(frozen=True)
class Engine:
    """The engine stage: the locus the engine computed for the J stage's matrices, and the
    tree it grew for it (:class:`~rankloci.methods.GrownTree`; None when there is none), to
    resume from."""

    matrices: Matrices
    locus: object
    grown: object = None


@dataclass(frozen=True)
class Certified:
    """The certify stage: the locus with its certificate (recomputed when the first failed it)
    and what the checks found (:class:`~rankloci.verify.Verification`; None without them)."""

    matrices: Matrices
    locus: object
    verification: object = None


def read(model, *, task=None, augment=(), method=None, seed=0, numeric=False, verify=True,
         frame="auto", rank_rtol=RANK_RTOL) -> Request:
    """The read stage: ``model`` (a loaded :class:`~rankloci.model.RobotModel` or
    :class:`~rankloci.model.MatrixModel`) and its options, the constraint rows parsed."""
    from .augmented import parse_augment

    augment = tuple(augment)
    return Request(model, task=tuple(task) if isinstance(task, list) else task,
                   augment=augment, extra=parse_augment(model, augment), method=method,
                   seed=seed, numeric=bool(numeric), verify=bool(verify), frame=frame,
                   rank_rtol=float(rank_rtol))


def matrices(request: Request, run: Run, tm=None, method: str | None = None) -> Matrices:
    """The J stage: the task matrix of the request (or ``tm``, built by the caller with the
    request's task and constraint rows), its method, and the checks' reference matrix.

    The reference is in ``tm``'s frame about ``tm``'s point: the model's own frame would be
    as good, but its symbolic Jacobian can take minutes (romeo_laas_small's 9-joint gripper
    chain, whose axes do not snap: over 5 minutes, against 1 s for the middle link's frame).
    """
    from .jacobians import task_matrix
    from .methods import method_for
    from .model import RobotModel

    model = request.model
    if tm is None:
        frame = request.frame if isinstance(model, RobotModel) else None
        tm = task_matrix(model, task=request.task, frame=frame, augment=request.extra,
                         numeric=request.numeric)
        method = method if method is not None else method_for(tm.shape, request.method)
        if run.progress:
            run.progress(f"{tm.name}: {tm.shape[0]}x{tm.shape[1]} matrix, method {method}, "
                         f"seed {request.seed}")
    method = method if method is not None else method_for(tm.shape, request.method)
    reference = None
    if request.verify:
        where = {} if tm.frame is None else {"frame": tm.frame, "point": tm.point}
        reference = task_matrix(model, task=request.task, augment=request.extra, **where)
        if run.progress:
            run.progress("self-check: the locus is checked numerically before it is shown")
    return Matrices(request, tm, method, reference)


def engine(stage: Matrices, run: Run, tm=None, seed: int | None = None, *, hints=(),
           method: str | None = None, grown=None) -> Engine:
    """The engine stage: the loci of J_aug and J, J_aug's components classified
    (:func:`~rankloci.augmented.augmented_locus_and_tree`).

    ``tm``, ``seed`` and ``method`` default to the stage's; the certify stage asks for other
    ones when it recomputes, with ``hints`` and the ``grown`` tree of an earlier computation.
    """
    from .augmented import augmented_locus_and_tree

    locus, tree = augmented_locus_and_tree(
        stage.request.model, stage.tm if tm is None else tm, method or stage.method,
        seed=stage.request.seed if seed is None else seed, progress=run.progress,
        should_stop=run.should_stop, clock=run.clock, hints=hints, grown=grown,
        workers=run.workers)
    return Engine(stage, locus, tree)


def certify(computed: Engine, run: Run) -> Certified:
    """The certify stage: the engine's locus certified, and computed again by the engine
    until it passes (:func:`~rankloci.verify.verified_locus` decides with what); without
    checks, the engine's locus as it is."""
    from .verify import verified_locus

    stage = computed.matrices
    if not stage.request.verify:
        return Certified(stage, computed.locus)
    first = [computed]

    def compute(t, s, hints=(), method=None, grown=None):
        # the first attempt is the engine stage's own computation
        if first and t is stage.tm and s == stage.request.seed and not hints \
                and method is None and grown is None:
            got = first.pop()
        else:
            got = engine(stage, run, t, s, hints=hints, method=method, grown=grown)
        return got.locus, got.grown

    locus, verification = verified_locus(
        compute, stage.tm, stage.reference, seed=stage.request.seed, progress=run.progress,
        should_stop=run.should_stop, method=stage.method, workers=run.workers,
        rank_rtol=stage.request.rank_rtol, with_notes=False)
    return Certified(stage, locus, verification)


def result(stage: Certified):
    """The result stage: the certified locus with every note, in this order: the model's
    (what reading its file changed), its matrix's, the computation's (the engine's and the
    certificate's recovery), the checks' verdict
    (:attr:`~rankloci.verify.Verification.notes`), and the frame J was computed in."""
    model, tm = stage.matrices.request.model, stage.matrices.tm
    checks = stage.verification.notes if stage.verification is not None else ()
    notes = (tuple(getattr(model, "notes", ())) + tuple(tm.notes or ()) + stage.locus.notes
             + tuple(checks))
    if tm.frame is not None and (tm.frame, tm.point) != (getattr(model, "frame", None), "tool"):
        where = f"link frame {tm.frame}" if isinstance(tm.frame, int) else f"the {tm.frame} frame"
        about = f", about the origin of link frame {tm.point}" if isinstance(tm.point, int) else ""
        notes += (f"J was computed in {where}{about} (same rank); symbolic lost directions are "
                  f"expressed there, the directions at the sample points in the model's frame",)
    return dataclasses.replace(stage.locus, notes=notes)


def model_locus(request: Request, run: Run, tm=None, method: str | None = None):
    """The stages from J to the result: the :class:`~rankloci.loci.Locus` of ``request``
    (its matrix ``tm`` when the caller built it, with ``method``)."""
    return result(certify(engine(matrices(request, run, tm, method), run), run))
