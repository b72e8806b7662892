"""The arguments of the public calls, checked before any work starts.

Each check raises :class:`~rankloci.errors.ArgumentError` naming the
argument as the Python API spells it (``seed=``, ``augment=``; never a
command-line flag), the value given and what is accepted.  The checks that
need the model (a frame number, ``task=`` on a matrix) run once it is loaded
(:func:`check_for_model`).
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Mapping

from ..errors import ArgumentError

__all__ = ["check_arguments", "check_for_model", "check_seed", "check_timeout",
           "check_samples", "check_rank_rtol", "check_contains_rtol"]

_IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]{0,31}\Z")


def _fail(argument, value, expected):
    raise ArgumentError(f"{argument}= must be {expected}, got {value!r}", argument=argument,
                        value=value)


def _is_int(value) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _is_bool(value) -> bool:
    import numpy as np

    return isinstance(value, (bool, np.bool_))


def check_seed(seed) -> int:
    """An integer 0 or above (the seed of a ``numpy.random.Generator``).

    Examples
    --------
    >>> check_seed(7)
    7
    >>> check_seed("a")
    Traceback (most recent call last):
    ...
    rankloci.errors.ArgumentError: seed= must be an integer 0 or above, got 'a'
    """
    if not _is_int(seed) or seed < 0:
        _fail("seed", seed, "an integer 0 or above")
    return int(seed)


def check_timeout(timeout):
    """None, or a finite number of seconds 0 or above (None and 0: no limit)."""
    if timeout is not None and (not isinstance(timeout, numbers.Real) or _is_bool(timeout)
                                or not math.isfinite(timeout) or timeout < 0):
        _fail("timeout", timeout, "a finite number of seconds 0 or above (0 or None: no limit)")
    return timeout


def check_samples(samples) -> int:
    """An integer 1 or above."""
    if not _is_int(samples) or samples < 1:
        _fail("samples", samples, "an integer 1 or above")
    return int(samples)


def check_rank_rtol(rank_rtol) -> float:
    """A number strictly between 0 and 1: the relative rank threshold of the numeric checks
    (J is rank deficient where sigma_min <= rank_rtol * sigma_max).

    Examples
    --------
    >>> check_rank_rtol(1e-6)
    1e-06
    >>> check_rank_rtol(2)
    Traceback (most recent call last):
    ...
    rankloci.errors.ArgumentError: rank_rtol= must be a number strictly between 0 and 1 (sigma_min/sigma_max), got 2
    """
    if not isinstance(rank_rtol, numbers.Real) or _is_bool(rank_rtol) \
            or not math.isfinite(rank_rtol) or not 0 < rank_rtol < 1:
        _fail("rank_rtol", rank_rtol, "a number strictly between 0 and 1 (sigma_min/sigma_max)")
    return float(rank_rtol)


def check_contains_rtol(rtol) -> float:
    """A positive finite number: how small a component's scaled equations must be at a
    configuration on it (:meth:`rankloci.loci.Locus.contains`).

    Examples
    --------
    >>> check_contains_rtol(1e-6)
    1e-06
    >>> check_contains_rtol(-1)
    Traceback (most recent call last):
    ...
    rankloci.errors.ArgumentError: rtol= must be a positive finite number (a scaled residual), got -1
    """
    if not isinstance(rtol, numbers.Real) or _is_bool(rtol) or not math.isfinite(rtol) \
            or rtol <= 0:
        _fail("rtol", rtol, "a positive finite number (a scaled residual)")
    return float(rtol)


def _check_names(argument, names):
    for n in names:
        if not _IDENT.match(n):
            raise ArgumentError(f"{argument}=: {n!r} is not a usable symbol name (a letter or _, "
                                f"then letters, digits and _, up to 32 characters)",
                                argument=argument, value=n)


def _check_variables(variables):
    import sympy as sp

    if variables is None:
        return
    if isinstance(variables, (str, bytes)) or not _iterable(variables):
        _fail("variables", variables, "a sequence of sympy symbols or names, such as [x, y]")
    bad = [v for v in variables if not isinstance(v, (sp.Symbol, str))]
    if bad:
        _fail("variables", variables, f"a sequence of sympy symbols or names ({bad[0]!r} is "
              f"a {type(bad[0]).__name__})")
    names = [str(v) for v in variables]
    _check_names("variables", names)
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise ArgumentError(f"variables=: {repeated[0]!r} is listed more than once",
                            argument="variables", value=variables)


def _check_parameters(parameters, variables):
    import sympy as sp

    if parameters is None:
        return
    if not isinstance(parameters, Mapping):
        _fail("parameters", parameters, "a mapping of parameter symbols or names to values, "
              "such as {k: 2}")
    bad = [k for k in parameters if not isinstance(k, (sp.Symbol, str))]
    if bad:
        _fail("parameters", parameters, f"keyed by sympy symbols or names ({bad[0]!r} is a "
              f"{type(bad[0]).__name__})")
    names = [str(k) for k in parameters]
    _check_names("parameters", names)
    both = sorted(set(names) & {str(v) for v in variables or ()})
    if both:
        raise ArgumentError(f"parameters=: {both[0]!r} is listed in variables= too",
                            argument="parameters", value=parameters)


def _iterable(value) -> bool:
    try:
        iter(value)
    except TypeError:
        return False
    return True


def _check_task(task):
    from ..model import TASKS, task_rows

    if task is None:
        return
    expected = (f"one of {sorted(TASKS)} or a sequence of distinct rows 0..5 of "
                f"(vx, vy, vz, wx, wy, wz)")
    if not isinstance(task, str) and (isinstance(task, bytes) or not _iterable(task)):
        _fail("task", task, expected)
    try:
        task_rows(task)
    except (ValueError, TypeError):
        _fail("task", task, expected)


def _check_augment(augment):
    if isinstance(augment, (str, bytes)) or not _iterable(augment) \
            or not all(isinstance(t, str) for t in augment):
        _fail("augment", augment, 'a sequence of strings, such as ["q1 + q2", "lock(q3)"]')


def _check_method(method):
    from ..methods import METHODS

    if method is not None and method not in METHODS:
        _fail("method", method, f"None or one of {METHODS}")


def _check_frame(argument, frame, allowed):
    if not (frame in allowed or _is_int(frame)) or _is_bool(frame):
        _fail(argument, frame, f"one of {allowed} or a link number")


def _check_name(argument, value):
    if value is not None and not isinstance(value, str):
        _fail(argument, value, "None or the name of a link (a string)")


def check_arguments(*, seed=0, timeout=None, variables=None, parameters=None, task=None,
                    augment=(), method=None, numeric=False, verify=True, frame=None,
                    point="tool", tip=None, base_link=None):
    """Check the arguments every call shares, before the model is loaded.

    Raises
    ------
    rankloci.errors.ArgumentError
        For the first argument of the wrong type or value.

    Examples
    --------
    >>> check_arguments(task="position", augment=["q1 + q2"], seed=3)
    >>> check_arguments(method="qr")
    Traceback (most recent call last):
    ...
    rankloci.errors.ArgumentError: method= must be None or one of ('svm', 'subdeterminant', 'determinant'), got 'qr'
    """
    check_seed(seed)
    check_timeout(timeout)
    _check_variables(variables)
    _check_parameters(parameters, variables)
    _check_task(task)
    _check_augment(augment)
    _check_method(method)
    for argument, value in (("numeric", numeric), ("verify", verify)):
        if not _is_bool(value):
            _fail(argument, value, "True or False")
    _check_frame("frame", frame, (None, "auto", "base", "tool"))
    _check_frame("point", point, ("tool",))
    _check_name("tip", tip)
    _check_name("base_link", base_link)


def check_for_model(model, *, task=None, frame=None, point="tool"):
    """Check what depends on the loaded model: ``task``, ``frame`` and ``point``.

    A matrix takes none of them; a robot's link numbers run from 0 to its
    number of joints.
    """
    from ..model import RobotModel

    if not isinstance(model, RobotModel):
        given = [a for a, v, default in (("task", task, None), ("frame", frame, None),
                                         ("point", point, "tool"))
                 if v != default and not (a == "frame" and v == "auto")]
        if given:
            raise ArgumentError(f"{given[0]}= applies to robot models, not to the matrix "
                                f"{model.name!r}", argument=given[0])
        return
    for argument, value in (("frame", frame), ("point", point)):
        if _is_int(value) and not 0 <= value <= model.dof:
            raise ArgumentError(f"{argument}={value!r} is not a link frame of {model.name!r} "
                                f"(0..{model.dof}, or 'base' / 'tool')", argument=argument,
                                value=value)
