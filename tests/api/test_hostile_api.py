"""Hostile input through the Python API: strings are data, never code.

Every string the API accepts (parameter values, matrix entries, variables, ``augment``, the
equations of a locus) is parsed by :func:`rankloci.expr.parse_expression`, the parser of model
files.  Each payload below would create a file named ``PWNED`` if it were evaluated as Python.
The last test reads the package's source: no call may hand a string to ``sympify``, ``eval``,
``exec`` or sympy's ``parse_expr``.
"""

from __future__ import annotations

import ast
import pathlib
import time

import pytest
import sympy as sp

import rankloci
from rankloci.errors import LocusTimeout, RanklociError

PAYLOAD = "__import__('pathlib').Path('PWNED').touch() or 2"


@pytest.fixture
def cwd(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    yield tmp_path
    assert not (tmp_path / "PWNED").exists(), "a string was evaluated as Python"


def test_parameter_string_is_parsed_not_evaluated(cwd):
    x, k = sp.symbols("x k")
    with pytest.raises(RanklociError, match="not allowed"):
        rankloci.locus(sp.Matrix([[sp.cos(x), k], [sp.sin(x), 1]]), parameters={k: PAYLOAD})


def test_parameter_string_of_a_number_is_read_as_a_model_file_would(cwd):
    x, k = sp.symbols("x k")
    J = rankloci.jacobian(sp.Matrix([[sp.cos(x), k]]), parameters={k: "2"})
    assert J.parameters == {k: 2}           # keyed by the caller's own k
    J = rankloci.jacobian(sp.Matrix([[sp.cos(x), k]]), parameters={k: "0.25"})
    assert J.parameters == {k: sp.Rational(1, 4)}


def test_parameter_object_whose_str_is_code_is_refused(cwd):
    """sympify falls back to ``str(value)`` for unknown objects, and evaluates that."""
    class Sneaky:
        def __str__(self):
            return PAYLOAD

    x, k = sp.symbols("x k")
    with pytest.raises(RanklociError, match="Sneaky is not a number"):
        rankloci.jacobian(sp.Matrix([[sp.cos(x), k]]), parameters={k: Sneaky()})


def test_matrix_of_strings_is_parsed_over_the_given_names(cwd):
    from rankloci.api.models import matrix_model

    m = matrix_model([["cos(x)", "k"], ["sin(x)", "1"]], variables=["x"], parameters={"k": 2})
    assert [str(e) for e in m.matrix] == ["cos(x)", "k", "sin(x)", "1"]
    with pytest.raises(RanklociError, match="not allowed"):
        matrix_model([[PAYLOAD]], variables=["x"])
    with pytest.raises(TypeError, match="not a string"):
        matrix_model(PAYLOAD)


def test_augment_string_is_parsed_not_evaluated(cwd):
    with pytest.raises(RanklociError, match="not allowed"):
        rankloci.jacobian("planar2r", augment=[PAYLOAD])


def test_locus_document_strings_are_parsed_not_evaluated(cwd):
    doc = {"schema": "rankloci.locus/2", "model": "m", "variables": ["q1", "q2"],
           "components": [{"equations": [PAYLOAD]}]}
    with pytest.raises(RanklociError, match="not allowed"):
        rankloci.Locus.from_dict(doc)


def test_hand_built_locus_with_string_equations_is_not_evaluated(cwd):
    q1, q2 = sp.symbols("q1 q2", real=True)
    L = rankloci.Locus("m", (q1, q2), {}, (2, 2), "determinant",
                       (rankloci.Component((PAYLOAD,)),))
    with pytest.raises(RanklociError, match="not allowed"):
        L.contains([0.1, 0.2])
    with pytest.raises(RanklociError, match="not allowed"):
        L.components[0].lambdify([q1, q2])


def test_hand_built_locus_with_a_string_parameter_is_not_evaluated(cwd):
    q1, q2, k = sp.symbols("q1 q2 k", real=True)
    L = rankloci.Locus("m", (q1, q2), {k: PAYLOAD}, (2, 2), "determinant",
                       (rankloci.Component((k * sp.sin(q2),)),))
    with pytest.raises(RanklociError, match="not allowed"):
        L.contains([0.1, 0.0])


def test_hand_built_model_with_a_string_parameter_is_refused(cwd):
    import dataclasses

    m = rankloci.load_model("planar2r")
    bad = dataclasses.replace(m, parameters={p: PAYLOAD for p in m.parameters})
    with pytest.raises(ValueError, match="sympy numbers"):
        rankloci.jacobian(bad, numeric=True)


# --- the package's source ------------------------------------------------------------------------

_PACKAGE = pathlib.Path(rankloci.__file__).parent

#: Callables that evaluate a string as Python (or, for sympify, may do so).
_EVALUATING = {"eval", "exec", "compile", "__import__", "parse_expr", "sympify", "S",
               "eval_expr", "runpy", "literal_eval"}


def _evaluating_calls(tree):
    """``(line, name)`` of every call of an evaluating callable, except
    ``sympify(..., strict=True)`` (which refuses strings)."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            module = getattr(node, "module", None) or ""
            names = [a.name for a in node.names]
            if module.startswith("sympy.parsing") or any(n.startswith("sympy.parsing")
                                                         for n in names):
                found.append((node.lineno, "import of sympy.parsing"))
            if any(n in _EVALUATING for n in names):
                found.append((node.lineno, f"import of {names}"))
        if not isinstance(node, ast.Call):
            continue
        f = node.func
        if isinstance(f, ast.Name):
            name = f.id
        elif isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) \
                and f.value.id in ("sp", "sympy", "builtins"):
            name = f.attr
        else:
            continue        # ring.compile(...) and the like are methods of rankloci's own objects
        if name not in _EVALUATING:
            continue
        strict = any(k.arg == "strict" and isinstance(k.value, ast.Constant)
                     and k.value.value is True for k in node.keywords)
        if name == "sympify" and strict:
            continue
        found.append((node.lineno, name))
    return found


def test_no_call_in_the_package_evaluates_a_string():
    offenders = []
    for path in sorted(_PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        offenders += [f"{path.relative_to(_PACKAGE)}:{line}: {name}"
                      for line, name in _evaluating_calls(tree)]
    assert offenders == []


def test_the_source_check_finds_what_it_looks_for():
    code = ("import sympy as sp\nfrom sympy.parsing.sympy_parser import parse_expr\n"
            "sp.sympify(x)\neval(y)\nsp.sympify(z, strict=True)\nring.compile(p)\n"
            "sp.S('1')\n")
    assert [name for _, name in _evaluating_calls(ast.parse(code))] == [
        "import of sympy.parsing", "import of ['parse_expr']", "sympify", "eval", "S"]


# --- time limits ---------------------------------------------------------------------------------

@pytest.mark.parametrize("timeout", [float("nan"), float("inf"), -1.0, "5", True])
def test_timeout_that_is_no_number_of_seconds_is_refused(timeout):
    """nan compared with the clock is never reached: it silently meant no limit."""
    with pytest.raises(ValueError, match="timeout= must be a finite number"):
        rankloci.locus("planar2r", timeout=timeout)
    with pytest.raises(ValueError, match="timeout= must be a finite number"):
        rankloci.check("planar2r", timeout=timeout, samples=1)


def _ends_within(limit, call):
    """The LocusTimeout ``call`` raises, and the seconds it took."""
    t0 = time.monotonic()
    with pytest.raises(LocusTimeout) as info:
        call()
    return info.value, time.monotonic() - t0


# generous for a loaded 2-core machine; without the bound both calls ran for minutes
_SLACK_S = 3.0


def test_timeout_bounds_building_a_huge_matrix():
    """The expansion of (x+y+z+k+1)**64 is one long sympy step that polls no deadline."""
    x, y, z, k = sp.symbols("x y z k")
    M = sp.Matrix([[(x + y + z + k + 1) ** 64, 1], [1, x]])
    e, took = _ends_within(1, lambda: rankloci.locus(M, timeout=1))
    assert took < 1 + _SLACK_S
    assert "did not finish within 1 s" in str(e)


def test_timeout_bounds_building_the_jacobian_of_a_long_arm():
    from rankloci.io.toml_model import parse_model

    arm = parse_model('name = "arm20"\ntask = "planar"\n' + "".join(
        '[[joint]]\nkind = "revolute"\na = 1\nalpha = 0\nd = 0\n' for _ in range(20)))
    _, took = _ends_within(1, lambda: rankloci.locus(arm, timeout=1))
    assert took < 1 + _SLACK_S
    _, took = _ends_within(1, lambda: rankloci.check(arm, timeout=1, samples=1))
    assert took < 1 + _SLACK_S


def test_time_limit_interrupts_again_code_that_swallows_the_first_interruption():
    from rankloci.api.deadline import time_limit

    swallowed = []

    def stubborn():
        while True:
            try:
                while True:
                    pass
            except Exception as e:       # what careless code does
                swallowed.append(type(e))
                if len(swallowed) == 2:
                    raise

    def limited():
        with time_limit(0.1):
            stubborn()

    _, took = _ends_within(0.1, limited)
    assert len(swallowed) == 2 and took < 0.1 + _SLACK_S


def test_a_call_that_ends_in_time_is_not_interrupted_later():
    L = rankloci.locus("planar2r", timeout=30)
    assert L.complete is True
    time.sleep(0.1)          # nothing pending in this thread once the call returned



def test_time_running_out_while_recomputing_is_a_timeout_not_a_rejection():
    """The first computation fails its certificate, the recomputation runs out of time: the
    error says the time ran out (it said the self-check rejects the locus)."""
    import dataclasses

    import numpy as np

    from rankloci.jacobians import task_matrix
    from rankloci.methods import compute_locus, method_for
    from rankloci.verify import verified_locus

    model = rankloci.load_model("planar3r")
    tm = task_matrix(model, frame="auto")
    calls = []

    def compute(t, seed, **_):
        calls.append(seed)
        if len(calls) > 1:
            raise LocusTimeout("the determinant computation did not finish within its budget")
        found = compute_locus(t, method_for(t.shape), rng=np.random.default_rng(seed))
        wrong = dataclasses.replace(found.components[0], equations=(sp.cos(t.variables[0]),))
        return dataclasses.replace(found, components=(wrong,))    # fails its certificate

    with pytest.raises(LocusTimeout, match="time ran out while the locus was computed again"):
        verified_locus(compute, tm, task_matrix(model), seed=0)
    assert len(calls) == 2
