"""The report package renders: its modules call no linear algebra and no optimiser.

Least squares, SVDs, QR factorizations and minimisations belong in the library
(:mod:`rankloci.geometry`, :mod:`rankloci.numeric.landscape`, ...), where the
Python API can use them; ``rankloci/reporting/`` formats, lays out, writes
files and draws what they return.  An ``ast`` walk over each module finds
``numpy.linalg``, ``scipy.linalg`` and ``scipy.optimize`` however they are
imported or reached, and any name ``lstsq`` or ``svd``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

REPORTING = Path(__file__).resolve().parent.parent / "rankloci" / "reporting"

#: Modules whose import, or any attribute of which, is linear algebra or optimisation.
FORBIDDEN_MODULES = ("numpy.linalg", "scipy.linalg", "scipy.optimize")

#: Names that are linear algebra wherever they come from.
FORBIDDEN_NAMES = ("lstsq", "svd")


def _dotted(node) -> str | None:
    """``a.b.c`` for a chain of attributes on a name, else None."""
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name):
        return None
    parts.append(node.id)
    return ".".join(reversed(parts))


def computations(source: str) -> list[tuple[int, str]]:
    """(line, what) for each use of linear algebra or an optimiser in ``source``."""
    tree = ast.parse(source)
    # what each local name stands for: "np" -> "numpy", "sl" -> "scipy.linalg", ...
    aliases: dict[str, str] = {}
    found = []

    def forbidden(full: str) -> bool:
        return any(full == m or full.startswith(m + ".") for m in FORBIDDEN_MODULES) or (
            full.rsplit(".", 1)[-1] in FORBIDDEN_NAMES)

    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                local = a.asname or a.name.split(".")[0]
                aliases[local] = a.name if a.asname else local
                if forbidden(a.name):
                    found.append((node.lineno, f"import {a.name}"))
        elif isinstance(node, ast.ImportFrom) and node.module:
            for a in node.names:
                full = f"{node.module}.{a.name}"
                aliases[a.asname or a.name] = full
                if forbidden(full):
                    found.append((node.lineno, f"from {node.module} import {a.name}"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute):
            dotted = _dotted(node)
            if dotted is None:
                if node.attr in FORBIDDEN_NAMES:
                    found.append((node.lineno, f"….{node.attr}"))
                continue
            head, _, rest = dotted.partition(".")
            full = aliases.get(head, head) + ("." + rest if rest else "")
            if forbidden(full):
                found.append((node.lineno, dotted))
        elif isinstance(node, ast.Name) and node.id in FORBIDDEN_NAMES:
            found.append((node.lineno, node.id))
    return sorted(set(found))


def _modules():
    return sorted(p for p in REPORTING.rglob("*.py"))


@pytest.mark.parametrize("path", _modules(), ids=lambda p: p.relative_to(REPORTING).as_posix())
def test_the_report_module_does_no_linear_algebra(path):
    rel = path.relative_to(REPORTING).as_posix()
    found = computations(path.read_text())
    assert not found, (f"rankloci/reporting/{rel} computes; move this into the library and "
                       "render its result:\n" + "\n".join(f"  line {n}: {w}" for n, w in found))


@pytest.mark.parametrize("source, expected", [
    ("import numpy as np\nnp.linalg.norm(x)", "np.linalg.norm"),
    ("import numpy\nnumpy.linalg.svd(x)", "numpy.linalg.svd"),
    ("from numpy import linalg\nlinalg.qr(x)", "linalg.qr"),
    ("from numpy.linalg import norm", "from numpy.linalg import norm"),
    ("import numpy.linalg as la\nla.det(x)", "la.det"),
    ("import scipy.linalg\nscipy.linalg.qr(G)", "import scipy.linalg"),
    ("from scipy.optimize import least_squares", "from scipy.optimize import least_squares"),
    ("from scipy import optimize\noptimize.minimize_scalar(f)", "optimize.minimize_scalar"),
    ("x = solver.lstsq(A, b)", "solver.lstsq"),
    ("def f(svd):\n    return svd(A)", "svd"),
])
def test_the_walk_finds_each_way_of_computing(source, expected):
    assert expected in [w for _, w in computations(source)]


@pytest.mark.parametrize("source", [
    "import numpy as np\nnp.abs(x).max()",
    "from ..geometry import facts_at\nfacts_at(m, q, None)",
    "import scipy.stats\nscipy.stats.norm(0, 1)",
])
def test_the_walk_passes_what_only_formats_or_calls_the_library(source):
    assert computations(source) == []
