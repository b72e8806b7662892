"""Old names of arguments, still accepted for a while.

One spelling per option: where an argument was renamed, the old keyword
keeps working, with a :class:`DeprecationWarning` that names the new one.
"""

from __future__ import annotations

import warnings

from .errors import ArgumentError

__all__ = ["renamed_argument"]


def renamed_argument(new_value, old_value, *, new: str, old: str, where: str,
                     stacklevel: int = 3):
    """The value of an argument that was renamed from ``old`` to ``new``.

    ``old_value`` (the old keyword's value, None when not given) is taken
    with a :class:`DeprecationWarning`; giving both names is an
    :class:`~rankloci.errors.ArgumentError`.  ``stacklevel`` points the
    warning at the caller of the function whose argument was renamed.

    Examples
    --------
    >>> renamed_argument("link_7", None, new="tip", old="tip_link", where="read_urdf")
    'link_7'
    >>> import pytest
    >>> with pytest.warns(DeprecationWarning, match="use tip="):
    ...     renamed_argument(None, "link_7", new="tip", old="tip_link", where="read_urdf")
    'link_7'
    """
    if old_value is None:
        return new_value
    if new_value is not None:
        raise ArgumentError(f"{where}: give {new}= only ({old}= is its old name)",
                            argument=old, value=old_value)
    warnings.warn(f"{where}: {old}= is deprecated; use {new}=", DeprecationWarning,
                  stacklevel=stacklevel)
    return old_value
