"""The argument types of the ``rankloci`` command line: each checks a value before any work.

A bad value is an :class:`argparse.ArgumentTypeError`, which
:class:`ArgumentParser` turns into a :class:`~rankloci.errors.UsageError`.
"""

from __future__ import annotations

import argparse

from ..errors import UsageError
from ..process_limits import MAX_MEMORY_MB, MAX_TIMEOUT_S

__all__ = ["ArgumentParser", "frame_arg", "timeout_arg", "memory_arg", "seed_arg", "jobs_arg",
           "task_arg", "rank_rtol_arg"]


class ArgumentParser(argparse.ArgumentParser):
    """An argument parser whose errors are a :class:`UsageError`, not an exit."""

    def error(self, message):
        raise UsageError(message)


def frame_arg(text: str):
    """``base``, ``tool`` or a link number, as ``--frame`` and ``--point`` take it.

    Examples
    --------
    >>> frame_arg("tool"), frame_arg("3")
    ('tool', 3)
    """
    if text in ("base", "tool"):
        return text
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not 'base', 'tool' or a link number") from None


def timeout_arg(text: str) -> float:
    """Seconds of a time limit: a finite number 0 or above (0 = no limit).

    Examples
    --------
    >>> timeout_arg("2.5")
    2.5
    >>> timeout_arg("nan")
    Traceback (most recent call last):
        ...
    argparse.ArgumentTypeError: 'nan' is not a number of seconds 0 or above (0 = no limit)
    """
    import math

    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(
            f"{text[:20]!r} is not a number of seconds 0 or above (0 = no limit)")
    if value > MAX_TIMEOUT_S:
        raise argparse.ArgumentTypeError(
            f"{text[:20]!r} is more than {MAX_TIMEOUT_S} seconds (0 = no limit)")
    return value


def memory_arg(text: str) -> int:
    """A memory limit in MiB: an integer 0 or above (0 = no limit).

    Examples
    --------
    >>> memory_arg("4096")
    4096
    """
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(
            f"{text[:20]!r} is not a number of MiB 0 or above (0 = no limit)")
    if value > MAX_MEMORY_MB:
        raise argparse.ArgumentTypeError(
            f"{text[:20]!r} is more than {MAX_MEMORY_MB} MiB (0 = no limit)")
    return value


def _integer_at_least(text: str, least: int) -> int:
    """``text`` as an integer ``least`` or above, or the ArgumentTypeError naming it."""
    try:
        value = int(text)
    except ValueError:
        value = least - 1
    if value < least:
        raise argparse.ArgumentTypeError(f"{text[:20]!r} is not an integer {least} or above")
    return value


def seed_arg(text: str) -> int:
    """A seed of :func:`numpy.random.default_rng`: an integer 0 or above.

    Examples
    --------
    >>> seed_arg("7")
    7
    >>> seed_arg("-1")
    Traceback (most recent call last):
        ...
    argparse.ArgumentTypeError: '-1' is not an integer 0 or above
    """
    return _integer_at_least(text, 0)


def jobs_arg(text: str) -> int:
    """A number of processes for one computation: an integer 1 or above.

    Examples
    --------
    >>> jobs_arg("2")
    2
    >>> jobs_arg("0")
    Traceback (most recent call last):
        ...
    argparse.ArgumentTypeError: '0' is not an integer 1 or above
    """
    return _integer_at_least(text, 1)


def rank_rtol_arg(text: str) -> float:
    """A number strictly between 0 and 1, as ``--rank-rtol`` takes it.

    Examples
    --------
    >>> rank_rtol_arg("1e-6")
    1e-06
    >>> rank_rtol_arg("0")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: '0' is not a number strictly between 0 and 1 (sigma_min/sigma_max)
    """
    import math

    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and 0 < value < 1):
        raise argparse.ArgumentTypeError(f"{text!r} is not a number strictly between 0 and 1 "
                                         "(sigma_min/sigma_max)")
    return value


def task_arg(text: str):
    """A task name, or a comma-separated list of rows of the 6-row Jacobian.

    Examples
    --------
    >>> task_arg("planar"), task_arg("0,1,5")
    ('planar', [0, 1, 5])
    """
    from ..model import TASKS, task_rows

    if text in TASKS:
        return text
    try:
        rows = [int(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not one of {', '.join(TASKS)} or a comma-separated row list like 0,1,5"
        ) from None
    try:
        return list(task_rows(rows))
    except ValueError as e:  # task_rows names the bad row
        raise argparse.ArgumentTypeError(str(e)) from None
