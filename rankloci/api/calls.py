"""The library's public calls: what each subcommand of the command line does, as a function.

The command line (:mod:`rankloci.cli.commands`) runs the same code through
:func:`model_locus` and :func:`check_model`, inside a child process with its
limits; here it runs in the caller's process, and progress goes to the
``rankloci`` logger (:mod:`.progress`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..tolerances import LOCUS_CONTAINS_RTOL, RANK_RTOL
from .arguments import (check_arguments, check_contains_rtol, check_for_model, check_rank_rtol,
                        check_samples, check_timeout)
from .deadline import stop_after
from .models import as_model
from .progress import log_progress

if TYPE_CHECKING:
    from collections.abc import Sequence

    from ..jacobians import TaskMatrix
    from ..loci import Locus
    from ..model import MatrixModel, RobotModel
    from .models import ModelLike, ParameterValues, Variables

__all__ = ["load_model", "jacobian", "locus", "check", "is_singular", "Check",
           "model_locus", "certified_locus", "check_model"]


def load_model(model: ModelLike, *, tip: str | None = None, base_link: str | None = None,
               variables: Variables | None = None,
               parameters: ParameterValues | None = None) -> RobotModel | MatrixModel:
    """Load a model: a built-in name, a file, a sympy matrix, an RTB or a Pinocchio robot.

    Parameters
    ----------
    model : str, os.PathLike, sympy.Matrix, DHRobot, pinocchio.Model, RobotModel or MatrixModel
        See :func:`rankloci.api.models.as_model`.
    tip, base_link : str, optional
        The chain of a URDF file or of a Pinocchio model (its last and first link or frame).
    variables, parameters : optional
        For a sympy matrix: its column variables and the values of its parameters.

    Returns
    -------
    RobotModel or MatrixModel

    Examples
    --------
    >>> import rankloci
    >>> rankloci.load_model("puma560")
    <RobotModel 'puma560': 6 revolute joints, standard DH, parameters a2, a3, d3, d4>
    """
    check_arguments(variables=variables, parameters=parameters, tip=tip, base_link=base_link)
    return as_model(model, variables=variables, parameters=parameters, tip=tip,
                    base_link=base_link)


def jacobian(model: ModelLike, *, task: str | Sequence[int] | None = None,
             frame: str | int | None = None, point: str | int = "tool",
             augment: Sequence[str] = (), numeric: bool = False,
             variables: Variables | None = None, parameters: ParameterValues | None = None,
             tip: str | None = None, base_link: str | None = None) -> TaskMatrix:
    """The symbolic matrix whose rank is studied (the command ``rankloci jacobian``).

    Parameters
    ----------
    model
        Anything :func:`load_model` accepts.
    task : str or sequence of int, optional
        ``"full"``, ``"position"``, ``"orientation"``, ``"planar"`` or rows 0..5 of
        (vx, vy, vz, wx, wy, wz); default: the model's own.
    frame : {"base", "tool"} or int, optional
        Frame the rows are expressed in (a link number 0..n); default: the model's.
    point : "tool" or int
        Reference point of the linear rows: the tool or the origin of a link frame.
    augment : sequence of str
        Constraint functions whose gradients are stacked under J, as ``--augment``
        takes them (``"q1 + q2"``, ``"lock(q3)"``, ``"elbow(z)"``).
    numeric : bool
        Replace the parameters by their values.
    variables, parameters, tip, base_link
        See :func:`load_model`.

    Returns
    -------
    TaskMatrix
        ``.matrix`` is the sympy matrix, ``.row_labels`` names its rows and
        ``.variables`` its columns.

    Examples
    --------
    >>> import rankloci
    >>> J = rankloci.jacobian("planar2r", numeric=True)
    >>> J.matrix.shape, J.row_labels
    ((2, 2), ('vx', 'vy'))
    """
    from ..augmented import parse_augment
    from ..jacobians import task_matrix

    from .symbols import caller_symbols, with_symbols

    check_arguments(task=task, frame=frame, point=point, augment=augment, numeric=numeric,
                    variables=variables, parameters=parameters, tip=tip, base_link=base_link)
    m = load_model(model, tip=tip, base_link=base_link, variables=variables,
                   parameters=parameters)
    check_for_model(m, task=task, frame=frame, point=point)
    tm = task_matrix(m, task=task, frame=frame, point=point,
                     augment=parse_augment(m, augment, flag="augment"), numeric=numeric)
    return with_symbols(tm, caller_symbols(model, variables, parameters))


def model_locus(model, tm, method, *, task=None, extra=(), seed=0, timeout=None, verify=True,
                progress=None, clock=time.perf_counter, should_stop=None, jobs=1,
                rank_rtol=RANK_RTOL):
    """The locus of a task matrix of ``model`` that the caller built: the pipeline
    (:mod:`rankloci.pipeline`) from its J stage.

    What ``rankloci locus`` and a sweep compute once they have the matrix: the loci of J_aug
    and J with J_aug's components classified (the engine stage), the certificate and the
    self-check with its recomputations (the certify stage) unless ``verify`` is false, and the
    notes of the model, of the matrix and of its frame (the result stage).

    Parameters
    ----------
    model : RobotModel or MatrixModel
    tm : TaskMatrix
        The matrix, from :func:`~rankloci.jacobians.task_matrix` (any frame).
    method : str
        As :func:`~rankloci.methods.method_for` returned it for ``tm``.
    task, extra
        The task and the parsed constraint rows ``tm`` was built with: the
        self-check evaluates the same matrix (in ``tm``'s frame, with the
        parameters symbolic and their values substituted).
    seed : int
    timeout : float, optional
        Seconds; the computation raises :class:`~rankloci.errors.LocusTimeout` after them.
    verify : bool
    progress : callable, optional
        Called with one-line progress messages.
    clock : callable
        Fills ``Locus.seconds``.
    should_stop : callable, optional
        Used instead of ``timeout`` when given.
    jobs : int
        Processes (:class:`~rankloci.parallel.Workers`); the locus is the same for any.
    rank_rtol : float
        Rank threshold of the numeric self-check (see :func:`locus`).
    """
    from ..parallel import Workers
    from ..pipeline import Request, Run
    from ..pipeline import model_locus as from_matrix

    stop = should_stop if should_stop is not None else stop_after(check_timeout(timeout))
    request = Request(model, task=task, extra=tuple(extra), method=method, seed=seed,
                      verify=bool(verify), frame=tm.frame, rank_rtol=float(rank_rtol))
    with Workers(jobs) as workers:
        run = Run(progress=progress, should_stop=stop, clock=clock, workers=workers)
        return from_matrix(request, run, tm, method)


def certified_locus(model, *, task=None, augment=(), method=None, seed=0, numeric=False,
                    verify=True, frame="auto", should_stop=None, progress=None, jobs=None,
                    rank_rtol=RANK_RTOL):
    """The locus of a loaded model, through the one pipeline every command uses.

    The stages of :mod:`rankloci.pipeline`: read (``model`` and the options) -> J
    (:func:`~rankloci.jacobians.task_matrix`) -> engine
    (:func:`~rankloci.augmented.augmented_locus_and_tree`) -> certificate and recomputation
    (:func:`~rankloci.verify.verified_locus`) -> result (:class:`~rankloci.loci.Locus`, its
    notes assembled).
    ``rankloci locus``, ``check``, ``report``, ``ik``, ``manipulability``, sweeps and the
    Python API all get their locus here, so that the same model, seed and options give the
    same locus everywhere.  Within a process a result is kept (by model and options) and given
    again; a computation that ran out of time is not kept.

    Parameters
    ----------
    model : RobotModel or MatrixModel
    task, augment, method, seed, numeric, verify, frame, rank_rtol
        As for :func:`locus`.
    should_stop : callable, optional
        Polled; True once the time is up (:class:`~rankloci.errors.LocusTimeout`).
    progress : callable, optional
        Called with one-line progress messages.
    jobs : int, optional
        Processes for the independent parts of the computation
        (:mod:`rankloci.parallel`); None: every core.  The locus is the same for any, and
        a kept result is given again whatever ``jobs`` asks.

    Returns
    -------
    (Locus, TaskMatrix)
        The locus and the matrix it was computed from.
    """
    from ..parallel import Workers, check_jobs
    from ..pipeline import Run, certify, engine, matrices, read
    from ..pipeline import result as result_stage

    jobs = check_jobs(jobs)
    key = (model, tuple(task) if isinstance(task, (list, tuple)) else task, tuple(augment),
           method, seed, bool(numeric), bool(verify), frame, float(rank_rtol))
    if key in _PIPELINE:
        return _PIPELINE[key]
    request = read(model, task=task, augment=augment, method=method, seed=seed,
                   numeric=numeric, verify=verify, frame=frame, rank_rtol=rank_rtol)
    with Workers(jobs) as workers:
        run = Run(progress=progress, should_stop=should_stop, workers=workers)
        stage = matrices(request, run)
        result = result_stage(certify(engine(stage, run), run))
    tm = stage.tm
    if len(_PIPELINE) >= _MAX_CACHED:
        _PIPELINE.pop(next(iter(_PIPELINE)))
    _PIPELINE[key] = (result, tm)
    return result, tm


#: Loci of :func:`certified_locus`, by model and options (oldest dropped first).
_PIPELINE: dict = {}


def locus(model: ModelLike, *, variables: Variables | None = None,
          parameters: ParameterValues | None = None, task: str | Sequence[int] | None = None,
          augment: Sequence[str] = (), method: str | None = None, timeout: float | None = None,
          seed: int = 0, numeric: bool = False, verify: bool = True, frame: str | int = "auto",
          tip: str | None = None, base_link: str | None = None, jobs: int | None = None,
          rank_rtol: float = RANK_RTOL) -> Locus:
    """The rank-deficiency locus of a model or a matrix (the command ``rankloci locus``).

    Parameters
    ----------
    model
        Anything :func:`load_model` accepts; a sympy matrix of any shape, with
        ``variables`` and ``parameters`` when it has symbolic parameters.
    variables : sequence of sympy.Symbol, optional
        The matrix's column variables (default: every symbol that is not a parameter).
    parameters : mapping, optional
        Values of the matrix's parameters (they stay symbolic in the analysis).
    task : str or sequence of int, optional
        Rows of the Jacobian of a robot; see :func:`jacobian`.
    augment : sequence of str
        Constraint rows; the components are then classified kinematic,
        algorithmic or mixed, and ``Locus.base`` holds the locus of J alone.
    method : {"svm", "subdeterminant", "determinant"}, optional
        Default: determinant for a square matrix, svm otherwise.
    timeout : float, optional
        Seconds for the whole call, loading the model and building J included;
        :class:`~rankloci.errors.LocusTimeout` is raised after them
        (:func:`rankloci.api.deadline.time_limit`).  One long step inside
        compiled code (a factorisation in FLINT) ends before it is seen; the
        command line, which kills its child, bounds those too.
    seed : int
        Seed of the numeric probes; the same seed gives the same locus.
    numeric : bool
        Substitute the parameter values before the algebra (faster; no special components).
    verify : bool
        Run the self-check (as the command line does) and recompute when it fails;
        ``Locus.complete`` says whether it passed.
    frame : str or int
        The frame the algebra works in; ``"auto"`` picks one where the entries are
        small (same rank).
    tip : str, optional
        For a URDF file or a Pinocchio model: the chain's last link or frame.
    base_link : str, optional
        For a URDF file: the chain's first link.
    jobs : int, optional
        Processes for the independent parts of the computation: the numeric self-check
        beside the certificate, J's locus beside J_aug's, the slices of the certificate's
        recovery (:mod:`rankloci.parallel`).  Default: every core this process may use.
        The locus is the same for any ``jobs``.
    rank_rtol : float
        The numeric self-check's rank threshold: J is rank deficient at a point where
        sigma_min <= ``rank_rtol`` * sigma_max (default
        :data:`~rankloci.tolerances.RANK_RTOL`, 1e-8).  Raise it for a model whose data
        are rounded (a configuration the check finds regular at 1e-7 is then singular),
        lower it to tell nearly singular configurations from singular ones.  It decides
        the self-check only: the components come from exact algebra, and the certificate
        uses no tolerance.

    Returns
    -------
    Locus
        With ``seconds`` measured.  Progress goes to the ``rankloci`` logger.
        For a sympy matrix, in the caller's own symbols (matched by name,
        whatever their assumptions): ``equations[0].subs({x: 0.3})`` works
        with the caller's ``x``.

    Raises
    ------
    rankloci.errors.ModelError
        The model cannot be loaded (an unknown name, a malformed file, a
        symbol that is neither a variable nor a parameter with a value), or
        ``task``, ``frame`` or ``augment`` does not fit it.
    rankloci.errors.LocusError
        The method cannot be used on this matrix (``"determinant"`` on a
        matrix that is not square).
    rankloci.errors.LocusTimeout
        ``timeout`` seconds passed before the locus was complete.
    rankloci.errors.ArgumentError
        An argument of the wrong type or value, checked before any work
        starts: ``seed``, ``timeout``, ``variables``, ``parameters``,
        ``task``, ``augment``, ``method``, ``numeric``, ``verify``,
        ``frame``, ``tip``; ``variables``, ``parameters`` or ``tip`` given
        for a model that does not take them; ``model`` of a type that is
        not a model.  It is also a ``ValueError`` and a ``TypeError``.

    Examples
    --------
    >>> import sympy as sp, rankloci
    >>> x, y, k = sp.symbols("x y k")
    >>> L = rankloci.locus(sp.Matrix([[sp.cos(x), k * y], [sp.sin(x), 1]]), parameters={k: 2})
    >>> [str(c.equations[0]) for c in L.components]
    ['k*y*sin(x) - cos(x)']
    >>> L.contains({"x": 0.7853981633974483, "y": 0.5}), L.contains({"x": 0.0, "y": 0.5})
    (True, False)
    """
    import logging

    from ..augmented import parse_augment
    from .deadline import time_limit
    from .progress import LOGGER_NAME
    from .results import task_note, with_model_notes
    from .symbols import caller_symbols, with_symbols

    from ..parallel import check_jobs

    check_arguments(seed=seed, timeout=timeout, variables=variables, parameters=parameters,
                    task=task, augment=augment, method=method, numeric=numeric, verify=verify,
                    frame=frame, tip=tip, base_link=base_link)
    rank_rtol = check_rank_rtol(rank_rtol)
    jobs = check_jobs(jobs)
    with time_limit(timeout, "the locus computation") as should_stop:
        m = load_model(model, tip=tip, base_link=base_link, variables=variables,
                       parameters=parameters)
        check_for_model(m, task=task, frame=frame)
        parse_augment(m, augment, flag="augment")     # its errors in the API's words
        result = certified_locus(m, task=task, augment=augment, method=method, seed=seed,
                                 numeric=numeric, verify=verify, frame=frame,
                                 should_stop=should_stop, progress=log_progress, jobs=jobs,
                                 rank_rtol=rank_rtol)[0]
    note = task_note(result, m, task)
    if note:
        logging.getLogger(LOGGER_NAME).warning("%s: %s", m.name, note)
    result = with_model_notes(result, m, task)
    return with_symbols(result, caller_symbols(model, variables, parameters))


@dataclass(frozen=True)
class Check:
    """What :func:`check` found: the numeric cross-check and the exact one.

    Attributes
    ----------
    numeric : rankloci.numeric.crosscheck.CheckReport
        Points on each component are singular, points off the locus regular,
        and singular points found by minimisation lie on a component.
    exact : rankloci.exact.singular.SingularResult
        The comparison with Singular's minimal primes (``status`` "agree",
        "disagree" or "skipped").
    """

    numeric: object
    exact: object
    certificate: object = None

    @property
    def ok(self) -> bool:
        """Every numeric check passed, Singular does not disagree, and the certificate does
        not disprove the locus (``certified`` says whether it proves it)."""
        return (self.numeric.ok and self.exact.status != "disagree"
                and (self.certificate is None or self.certificate.verdict != "failed"))

    @property
    def certified(self) -> bool:
        """The certificate proves the locus complete and sound."""
        return self.certificate is not None and self.certificate.verdict == "passed"

    def to_dict(self) -> dict:
        """The JSON document of ``rankloci check --format json``."""
        cert = self.certificate.to_dict() if self.certificate is not None else None
        return {**self.numeric.to_dict(), "singular": self.exact.to_dict(),
                "certificate": cert, "certified": self.certified, "ok": self.ok}

    def __str__(self) -> str:
        from ..numeric.crosscheck import render_check_text

        lines = [render_check_text(self.numeric),
                 f"Singular (minimal associated primes of the maximal minors): "
                 f"{self.exact.status}, {self.exact.reason}"]
        lines += [f"  {f}" for f in self.exact.findings]
        if self.certificate is not None:
            c = self.certificate
            lines.append(f"certificate ({c.kind}, prime {c.prime}): {c.verdict}"
                         + (f", error probability below {c.error_bound:.1e}"
                            if c.verdict == "passed" else ""))
            lines += [f"  {f}" for f in c.findings]
        return "\n".join(lines)


def _complex_only(locus, J):
    """The components without real points a locus's certificate lists, each proved so again
    (one of its equations has no real zero): the certificate may count them as covering
    complex witness points.  The others are left out, and their points stay uncovered."""
    from ..exact.real_points import without_real_points
    from ..loci import Component

    cert = locus.certificate
    N = len(J.variables)
    names = {v.name: v for v in J.variables}
    out = []
    for eqs in (cert.complex_components if cert is not None else ()):
        eqs = tuple(e.xreplace({s: names[s.name] for s in e.free_symbols if s.name in names})
                    for e in eqs)
        if without_real_points(eqs, J.variables, J.angles):
            out.append(Component(eqs, dimension=N - len(eqs)))
    return tuple(out)


def check_model(model, given=None, *, samples=10, seed=0, numeric=False, should_stop=None,
                progress=None, jobs=None, rank_rtol=RANK_RTOL) -> Check:
    """What ``rankloci check`` computes: see :func:`check`."""
    import numpy as np

    from ..exact.singular import singular_cross_check
    from ..jacobians import task_matrix
    from ..numeric.crosscheck import cross_check

    tell = progress or (lambda msg: None)
    checked = given
    if checked is None:
        tell(f"{model.name}: computing the locus (seed {seed})")
        checked = certified_locus(model, seed=seed, numeric=numeric, should_stop=should_stop,
                                  progress=progress, jobs=jobs, rank_rtol=rank_rtol)[0]
    J = task_matrix(model)  # the model's own frame; parameters substituted by cross_check
    # (a locus file of schema /1, or one without "matrix", has no shape: 0x0)
    if given is not None and any(given.shape) and tuple(given.shape) != tuple(J.shape):
        from ..errors import LocusError

        raise LocusError(f"the locus is of a {given.shape[0]}x{given.shape[1]} matrix and "
                         f"{model.name}'s task matrix is {J.shape[0]}x{J.shape[1]}: a locus is "
                         "checked against the model's own task, and this one was computed for "
                         "other rows (a task or constraint rows the model does not have)")
    certificate = checked.certificate if given is None else None
    if certificate is None:
        from ..certify import certify_locus

        tell(f"{model.name}: certificate of the locus (witness points modulo a prime)")
        certificate = certify_locus(checked, J, seed=seed, should_stop=should_stop,
                                    progress=progress, complex_only=_complex_only(checked, J))
    n = len(checked.components)
    tell(f"{model.name}: checking {n} component{'' if n == 1 else 's'}, {samples} samples, "
         f"seed {seed}")
    report = cross_check(checked, J.matrix, J.variables, angles=J.angles,
                         parameters=J.parameters, samples=samples,
                         rng=np.random.default_rng(seed), seed=seed, rank_rtol=rank_rtol)
    exact = singular_cross_check(task_matrix(model, frame="auto", numeric=True), checked,
                                 rng=np.random.default_rng(seed), parameters=J.parameters)
    return Check(report, exact, certificate)


def check(model, locus=None, *, samples=10, seed=0, numeric=False, timeout=None,
          variables=None, parameters=None, tip=None, base_link=None, jobs=None,
          rank_rtol=RANK_RTOL) -> Check:
    """Check a locus numerically and exactly (the command ``rankloci check``).

    Parameters
    ----------
    model
        Anything :func:`load_model` accepts.
    locus : Locus, optional
        The locus to check (computed from ``model`` when omitted).
    samples : int
        Points per component, off-locus points and minimisation starts.
    seed : int
    numeric : bool
        Compute the locus with the parameter values substituted.
    timeout : float, optional
        Seconds allowed to the whole call (as for :func:`locus`).
    variables, parameters, tip, base_link
        See :func:`load_model`.
    jobs : int, optional
        Processes for the locus computation (see :func:`locus`); default every core.
    rank_rtol : float
        The numeric check's rank threshold: J is rank deficient at a point where
        sigma_min <= ``rank_rtol`` * sigma_max (default
        :data:`~rankloci.tolerances.RANK_RTOL`); recorded in
        ``to_dict()["thresholds"]["RANK_RTOL"]``.

    Returns
    -------
    Check
        ``ok`` is true when every check passed; ``str()`` gives the report of the
        command line.

    Examples
    --------
    >>> import rankloci
    >>> rankloci.check("planar2r", samples=3).ok
    True
    """
    from .deadline import time_limit
    from .symbols import with_symbols

    from ..parallel import check_jobs

    check_samples(samples)
    check_arguments(seed=seed, numeric=numeric, timeout=timeout, variables=variables,
                    parameters=parameters, tip=tip, base_link=base_link)
    rank_rtol = check_rank_rtol(rank_rtol)
    jobs = check_jobs(jobs)
    with time_limit(timeout, "the check") as should_stop:
        m = load_model(model, tip=tip, base_link=base_link, variables=variables,
                       parameters=parameters)
        if locus is not None:    # a locus in the caller's symbols: the model's own, by name
            locus = with_symbols(locus, {s.name: s for s in (*m.variables, *m.parameters)})
        return check_model(m, locus, samples=samples, seed=seed, numeric=numeric,
                           should_stop=should_stop, progress=log_progress, jobs=jobs,
                           rank_rtol=rank_rtol)


def is_singular(model, q, *, locus=None, rtol=LOCUS_CONTAINS_RTOL, **options):
    """Is the configuration ``q`` on the locus of ``model``?

    Decided by the locus (:meth:`~rankloci.loci.Locus.contains`, which
    respects each component's ``excluding``), not by an SVD at ``q``.

    Parameters
    ----------
    model
        Anything :func:`load_model` accepts.
    q : array_like or mapping
        Values of the variables, in order or by name (or by URDF joint name);
        an (N, n) array for N configurations.
    locus : Locus, optional
        The locus of ``model``; computed with ``options`` (see :func:`locus`)
        when omitted, and then kept for later calls on the same model.
    rtol : float
        ``q`` is on a component when each of its equations, scaled by the sum of the absolute
        values of its coefficients, is at most ``rtol`` there
        (:meth:`~rankloci.loci.Locus.contains`; default
        :data:`~rankloci.tolerances.LOCUS_CONTAINS_RTOL`).  Raise it for configurations
        measured or rounded to a few digits.

    Examples
    --------
    >>> import rankloci
    >>> rankloci.is_singular("planar2r", [0.3, 0.0]), rankloci.is_singular("planar2r", [0.3, 1.0])
    (True, False)
    >>> rankloci.is_singular("planar2r", [[0.3, 0.0], [0.3, 1.0]])
    array([ True, False])

    Returns
    -------
    bool or numpy.ndarray
        One bool, or a boolean array of shape (N,) for an (N, n) array.
    """
    rtol = check_contains_rtol(rtol)
    if locus is None:
        m = load_model(model, tip=options.pop("tip", None),
                       base_link=options.pop("base_link", None),
                       variables=options.pop("variables", None),
                       parameters=options.pop("parameters", None))
        key = (m, tuple(sorted((k, repr(v)) for k, v in options.items())))
        if key not in _LOCI:
            if len(_LOCI) >= _MAX_CACHED:
                _LOCI.pop(next(iter(_LOCI)))
            _LOCI[key] = globals()["locus"](m, **options)
        locus = _LOCI[key]
    return locus.contains(q, rtol=rtol)


#: Loci computed by :func:`is_singular`, by model and options (oldest dropped first).
_LOCI: dict = {}
_MAX_CACHED = 16
