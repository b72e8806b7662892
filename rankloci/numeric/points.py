"""Configurations as the public functions take them: one joint vector, N of them, or a mapping.

:func:`configurations` turns what a caller passes as ``q`` into an (N, n) float
array, refusing values that are not finite numbers (a NaN compares false with
every tolerance and would silently answer "not on the locus").
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..errors import ArgumentError

__all__ = ["configurations"]


def configurations(q, variables, joint_names=()) -> tuple[np.ndarray, bool]:
    """``q`` as an (N, n) array of joint vectors, and whether it was one configuration.

    Parameters
    ----------
    q : array_like or mapping
        One configuration (n values, in the order of ``variables``), N of them
        (an (N, n) array), or a mapping from a variable (its name, or the
        symbol) or a joint name to its value.
    variables : sequence of sympy.Symbol
    joint_names : sequence of str, optional
        The name of each variable's joint (a URDF joint), accepted as keys of
        a mapping; empty names are ignored.

    Returns
    -------
    (numpy.ndarray, bool)
        The (N, n) array, and True when ``q`` was a single configuration.

    Raises
    ------
    rankloci.errors.ArgumentError
        A missing or unknown name, the wrong number of values, a value that is
        not a finite number (NaN included).

    Examples
    --------
    >>> import sympy as sp
    >>> q1, q2 = sp.symbols("q1 q2")
    >>> configurations([0.1, 0.2], (q1, q2))
    (array([[0.1, 0.2]]), True)
    >>> configurations({"elbow": 0.2, "q1": 0.1}, (q1, q2), ("shoulder", "elbow"))[0]
    array([[0.1, 0.2]])
    >>> configurations([[0.1, float("nan")]], (q1, q2))
    Traceback (most recent call last):
    ...
    rankloci.errors.ArgumentError: q has a value that is not a finite number (nan at row 0, q2)
    """
    names = [str(v) for v in variables]
    if isinstance(q, Mapping):
        aliases = {j: n for j, n in zip(joint_names, names) if j}
        given = {}
        for key, value in q.items():
            name = str(key)
            name = name if name in names else aliases.get(name)
            if name is None:
                known = names + [j for j in aliases if j not in names]
                raise ArgumentError(f"q: {str(key)!r} is not a variable or joint name; the "
                                    f"names are {known}", argument="q", value=q)
            if name in given:
                raise ArgumentError(f"q gives {name!r} twice (by variable and joint name)",
                                    argument="q", value=q)
            given[name] = value
        missing = [n for n in names if n not in given]
        if missing:
            raise ArgumentError(f"q has no value for {missing[0]!r}; the variables are {names}",
                                argument="q", value=q)
        q = [given[n] for n in names]
    try:
        x = np.asarray(q, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentError(f"q must be numbers (one per variable, or an array of shape (N, "
                            f"{len(names)})), got {q!r:.80}", argument="q", value=q) from None
    single = x.ndim <= 1
    X = x.reshape(1, -1) if single else x
    if X.ndim != 2 or X.shape[1] != len(names):
        got = f"{x.size} values" if single else f"an array of shape {x.shape}"
        raise ArgumentError(f"q has {got}; the variables are {names} (one configuration of "
                            f"{len(names)} values, or an array of shape (N, {len(names)}))",
                            argument="q", value=q)
    bad = np.argwhere(~np.isfinite(X))
    if bad.size:
        i, j = bad[0]
        raise ArgumentError(f"q has a value that is not a finite number ({X[i, j]} at row {i}, "
                            f"{names[j]})", argument="q", value=q)
    return X, single
