"""What to install for an optional part of rankloci.

The optional dependencies are the extras of ``pyproject.toml`` (``report``:
matplotlib, ``sweep``: Dask, ...).  rankloci is installed from its source
tree, not from a package index, so ``pip install "rankloci[report]"`` does
not work; the error messages name the packages of the extra instead, as the
installed metadata lists them.
"""

from __future__ import annotations

__all__ = ["install_command"]


def _requirements(extra: str) -> list[str]:
    """The requirements of ``extra`` in rankloci's installed metadata (empty if unknown)."""
    import importlib.metadata

    try:
        requires = importlib.metadata.requires("rankloci") or []
    except importlib.metadata.PackageNotFoundError:
        return []
    out = []
    for line in requires:
        requirement, _, marker = line.partition(";")
        if marker.replace('"', "'").split() == ["extra", "==", f"'{extra}'"]:
            out.append(requirement.strip())
    return out


def install_command(extra: str) -> str:
    """The pip command that installs the packages of the extra ``extra``.

    Examples
    --------
    >>> install_command("report")
    'pip install "matplotlib<4,>=3.8"'
    """
    requirements = _requirements(extra)
    if not requirements:
        return f'pip install -e ".[{extra}]" in a clone of rankloci'
    return "pip install " + " ".join(f'"{r}"' for r in requirements)
