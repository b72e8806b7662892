"""Every constant that can change a result is stated in rankloci/tolerances.py, with its reason.

A module-level UPPER_CASE name bound to a number anywhere else in the package
must be on the short list below, each entry saying why it decides no result:
it bounds the input (a bigger input is refused, a smaller one is read the
same), sizes a cache or a batch (the same values, computed faster), times
the process, or lays out the text of a report.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "rankloci"

#: Module (or module prefix, ending in "/") -> why its numeric constants decide no result.
ALLOWED_MODULES = {
    "cli/": "the command line: input sizes it accepts, its clock and its messages",
    "sweep/": "sweeps: bounds of a spec, the cluster's timing and retries",
    "reporting/": "the report's layout and its own figures' numerics, which render a locus "
                  "already computed (to move into the library with the report's numerics)",
    "process_limits.py": "process management: memory and time limits, polling",
    "api/deadline.py": "the watchdog's timing",
    "errors.py": "the length of a message",
    "expr.py": "bounds of an expression a model file may hold (a bigger one is refused)",
    "io/toml_model.py": "bounds of a model file (a bigger one is refused)",
    "io/urdf.py": "bounds of a URDF file (a bigger one is refused)",
    "loci.py": "bounds of a locus document read back (a bigger one is refused)",
}

#: "module:NAME" -> why that one constant decides no result.
ALLOWED_NAMES = {
    "algebra/ring.py:MAX_ANGLE_MULTIPLE": "bounds the input: a larger multiple is refused",
    "algebra/ring.py:MAX_SURD": "bounds the input: a larger square root is refused",
    "algebra/ring.py:MAX_ENTRY_TERMS": "bounds the input: a larger entry is refused",
    "algebra/ring.py:COMPILE_MEMO_TERMS": "size of a memo of evaluators (speed only)",
    "algebra/ring.py:SMALL_GATHER": "how an evaluation is batched (speed only)",
    "algebra/ring.py:MANY_GATHER": "how an evaluation is batched (speed only)",
    "numeric/functions.py:CHUNK_TERMS": "how a sum is compiled in pieces (same values)",
    "tree/context.py:MEMO_MAX_TERMS": "size of the determinant and factor memos (speed only)",
    "exact/witness.py:SLICE_MEMO_SIZE": "size of the memo of coordinate slices (speed only: "
                                        "a slice's random stream is its own)",
    "tree/probe.py:_MATRIX_CACHE": "size of a cache (speed only)",
    "tree/probe.py:_POLY_CACHE": "size of a cache (speed only)",
    "api/calls.py:_MAX_CACHED": "loci kept by is_singular (speed only)",
    "parallel.py:WORKER_MIN_VARIABLES": "which parts run in a worker: the locus is the same "
                                         "for any jobs (tests/test_parallel.py)",
    "parallel.py:POLL_SECONDS": "process timing: how often a wait looks at the time limit",
    "parallel.py:PARENT_CHECK_SECONDS": "process timing: how often a worker looks for its parent",
    "limits.py:_TURN": "2 pi, a mathematical constant",
    "near/discontinuity.py:DEFAULT_MIXING_GAIN": "the documented default of a user option",
    "near/manipulability.py:MAX_POLYTOPE_COLUMNS": "bounds the input: a wider matrix is refused",
}


def _numeric_constants():
    """(module path relative to the package, name, line) of module-level numeric constants."""
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).as_posix()
        for node in ast.parse(path.read_text()).body:
            if isinstance(node, ast.Assign):
                targets, value = node.targets, node.value
            elif isinstance(node, ast.AnnAssign) and node.value is not None:
                targets, value = [node.target], node.value
            else:
                continue
            for target in targets:
                if not (isinstance(target, ast.Name)
                        and re.fullmatch(r"_?[A-Z][A-Z0-9_]*", target.id)):
                    continue
                numbers = [n for n in ast.walk(value) if isinstance(n, ast.Constant)
                           and isinstance(n.value, (int, float)) and not isinstance(n.value, bool)]
                # a number, or arithmetic on numbers and names; not a table or a call
                if numbers and not any(isinstance(n, (ast.Call, ast.Dict, ast.List, ast.Set,
                                                      ast.Tuple)) for n in ast.walk(value)):
                    yield rel, target.id, node.lineno


def _allowed(rel: str, name: str) -> bool:
    return (f"{rel}:{name}" in ALLOWED_NAMES
            or any(rel == m or (m.endswith("/") and rel.startswith(m)) for m in ALLOWED_MODULES))


def test_the_scan_finds_constants():
    found = {(rel, name) for rel, name, _ in _numeric_constants()}
    assert ("tolerances.py", "RANK_RTOL") in found
    assert ("tolerances.py", "NEWTON_SETTLED") in found          # 2.0 ** -120
    assert ("process_limits.py", "MAX_MEMORY_MB") in found       # 2 ** 24


def test_result_changing_constants_live_in_tolerances():
    stray = [f"rankloci/{rel}:{line} {name}" for rel, name, line in _numeric_constants()
             if rel != "tolerances.py" and not _allowed(rel, name)]
    assert not stray, ("define these in rankloci/tolerances.py, with their reason, or say in "
                       "this test why they decide no result:\n" + "\n".join(stray))


def test_every_allowed_name_still_exists():
    found = {f"{rel}:{name}" for rel, name, _ in _numeric_constants()}
    assert not set(ALLOWED_NAMES) - found
    for module in ALLOWED_MODULES:
        assert (PACKAGE / module).exists(), module


def test_each_tolerance_is_stated_once_with_a_reason():
    text = (PACKAGE / "tolerances.py").read_text()
    lines = text.splitlines()
    names = re.findall(r"^([A-Z][A-Z0-9_]*) = ", text, re.M)
    assert len(names) == len(set(names)), "a tolerance is defined twice"
    for i, line in enumerate(lines):
        m = re.match(r"^([A-Z][A-Z0-9_]*) = ", line)
        if not m:
            continue
        # its reason: a "#:" comment above it (shared by a group of adjacent definitions) or
        # a comment on its line
        j = i - 1
        while j >= 0 and re.match(r"^[A-Z][A-Z0-9_]* = ", lines[j]):
            j -= 1
        assert "#" in line or (j >= 0 and lines[j].startswith("#")), f"{m.group(1)} has no reason"
