"""Exceptions raised by rankloci.

Every error that bad input can cause is a :class:`RanklociError`, and so is
every other failure rankloci raises by design (a limit reached, a report that
LaTeX could not typeset, a sweep's cluster that cannot run it, a term budget
exceeded).  The command line turns one into a single line on stderr and exit
code 2.  The one exception outside it is
:class:`rankloci.process_limits.ChildFailed`: a bug in a child process,
passed on with its traceback.
"""

from __future__ import annotations

__all__ = [
    "RanklociError",
    "ArgumentError",
    "ModelError",
    "ExpressionError",
    "ShapeError",
    "LocusError",
    "LocusTimeout",
    "UsageError",
    "shortened",
]


class RanklociError(Exception):
    """Base class of every error rankloci raises by design (bad input first of all)."""


class ArgumentError(RanklociError, ValueError, TypeError):
    """An argument of a library call has a value or a type it does not take.

    The message names the argument, the value given and what is accepted.
    It is also a :class:`ValueError` and a :class:`TypeError`, so code that
    caught those from earlier versions keeps working.

    Parameters
    ----------
    message : str
        What is wrong, in the words of the Python API (``seed=``, not ``--seed``).
    argument : str, optional
        The name of the argument.
    value : optional
        The value given.

    Examples
    --------
    >>> e = ArgumentError("seed must be an integer 0 or above, got 'a'", argument="seed",
    ...                   value="a")
    >>> isinstance(e, RanklociError) and isinstance(e, ValueError), e.argument
    (True, 'seed')
    """

    def __init__(self, message: str, *, argument: str | None = None, value: object = None):
        self.argument = argument
        self.value = value
        super().__init__(message)


class ExpressionError(RanklociError):
    """An expression string could not be parsed, or uses a forbidden construct."""

    def __init__(self, text: str, reason: str):
        self.text = text
        self.reason = reason
        super().__init__(f"cannot parse {text!r}: {reason}")


class ModelError(RanklociError):
    """A model file is malformed.

    Parameters
    ----------
    message : str
        What is wrong.
    file : str, optional
        File name (without directories) the error was found in.
    joint : int, optional
        1-based joint index.
    field : str, optional
        Name of the offending field.
    """

    def __init__(self, message: str, *, file: str | None = None,
                 joint: int | None = None, field: str | None = None):
        self.message = message
        self.file = file
        self.joint = joint
        self.field = field
        super().__init__(message)

    def located(self, *, file: str | None = None, joint: int | None = None,
                field: str | None = None) -> "ModelError":
        """Return a copy with missing location fields filled in."""
        return ModelError(self.message,
                          file=self.file or file,
                          joint=self.joint if self.joint is not None else joint,
                          field=self.field or field)

    def __str__(self) -> str:
        parts = []
        if self.file:
            parts.append(self.file)
        if self.joint is not None:
            parts.append(f"joint {self.joint}")
        if self.field:
            parts.append(f"field {self.field!r}")
        parts.append(self.message)
        return ": ".join(parts)


class ShapeError(RanklociError):
    """A matrix or vector has the wrong shape."""


class LocusError(RanklociError):
    """A locus computation cannot be carried out on this input."""


class LocusTimeout(LocusError):
    """The computation was stopped because its time budget ran out."""


class UsageError(RanklociError):
    """The command line itself is wrong: an unknown option, a bad value, a missing file name."""


#: Characters of a message shown whole: a progress line on stderr, the error line of a run that
#: ran out of its limits.  The equations of a component found on a long chain can run to
#: megabytes of digits, which a line of progress does not need.
MESSAGE_MAX = 300


def shortened(message: str, limit: int = MESSAGE_MAX) -> str:
    """``message`` cut to ``limit`` characters, saying how many were left out.

    Examples
    --------
    >>> shortened("x" * 10, 4)
    'xxxx ... (6 more characters)'
    >>> shortened("short")
    'short'
    """
    if len(message) <= limit:
        return message
    return f"{message[:limit]} ... ({len(message) - limit} more characters)"
