"""The top-level API: lazy imports, what each call returns, and its errors."""

from __future__ import annotations

import json
import logging
import subprocess
import sys

import pytest
import sympy as sp

import rankloci
from rankloci.errors import LocusTimeout, ModelError


def _run_python(code: str) -> str:
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return out.stdout.strip()


def test_import_loads_nothing_heavy():
    """``import rankloci`` imports neither sympy nor numpy nor any submodule but its version."""
    loaded = json.loads(_run_python(
        "import sys, json, rankloci; "
        "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
        "('sympy', 'numpy', 'networkx', 'flint', 'scipy', 'matplotlib', 'rankloci'))))"))
    assert loaded == ["rankloci", "rankloci.version"]


def test_names_and_submodules_are_reachable_without_imports():
    names = json.loads(_run_python(
        "import json, rankloci; "
        "print(json.dumps([rankloci.io.__name__, rankloci.methods.__name__, "
        "rankloci.LocusTimeout.__module__, rankloci.Locus.__name__, "
        "rankloci.Component.__name__, callable(rankloci.locus), callable(rankloci.jacobian), "
        "callable(rankloci.report), callable(rankloci.from_rtb)]))"))
    assert names == ["rankloci.io", "rankloci.methods", "rankloci.errors", "Locus", "Component",
                     True, True, True, True]
    with pytest.raises(AttributeError, match="no attribute 'nonsense'"):
        rankloci.nonsense  # noqa: B018


def test_no_submodule_is_named_like_a_public_function():
    """The functions stay functions when every submodule is loaded: no name is shared."""
    import importlib
    import pkgutil

    names = {m.name for m in pkgutil.iter_modules(rankloci.__path__)}
    assert names.isdisjoint(rankloci.__all__)
    for name in ("loci", "jacobians", "reporting"):
        importlib.import_module(f"rankloci.{name}")
    for name in ("locus", "jacobian", "report"):
        assert callable(getattr(rankloci, name))
    from rankloci.loci import Locus
    assert rankloci.Locus is Locus


def test_locus_of_a_sympy_matrix_with_parameters_any_shape():
    """A wide 2x3 matrix with a symbolic parameter: rank drops where both 2x2 minors with
    the last column and the first minor vanish."""
    x, y, k = sp.symbols("x y k")
    M = sp.Matrix([[sp.cos(x), k * y, 1], [sp.sin(x), 1, 0]])
    L = rankloci.locus(M, parameters={k: 2}, variables=[x, y])
    # the minor of columns 2, 3 is -1: never zero, so the matrix always has rank 2
    assert L.shape == (2, 3) and L.components == ()
    tall = rankloci.locus(M.T, parameters={"k": 2})
    assert tall.shape == (3, 2) and tall.components == ()
    square = rankloci.locus(sp.Matrix([[sp.cos(x), k * y], [sp.sin(x), 1]]), parameters={k: 2})
    assert [sp.sstr(c.equations[0]) for c in square.components] == ["k*y*sin(x) - cos(x)"]
    assert square.seconds > 0 and square.complete is True
    assert [str(v) for v in square.variables] == ["x", "y"]


def test_matrix_symbols_without_values_are_refused_by_name():
    x, k = sp.symbols("x k")
    with pytest.raises(ModelError, match="'k' is neither a variable nor a parameter"):
        rankloci.locus(sp.Matrix([[sp.cos(x), k]]), variables=[x])
    with pytest.raises(ValueError, match="apply to a sympy matrix only"):
        rankloci.locus("planar2r", parameters={"k": 1})
    with pytest.raises(TypeError, match="cannot use a builtins.dict as a model"):
        rankloci.locus({"not": "a model"})
    with pytest.raises(ValueError, match="'puma560' is neither"):
        rankloci.locus("puma560", tip="link6")


def test_matrix_floats_become_exact():
    x = sp.Symbol("x")
    m = rankloci.load_model(sp.Matrix([[sp.cos(x), 0.4318]]))
    assert m.matrix[0, 1] == sp.Rational(2159, 5000)


def test_jacobian_and_locus_of_a_robot_agree_with_the_command_line(capsys):
    from rankloci.cli import main

    J = rankloci.jacobian("puma560", numeric=True)
    assert J.matrix.shape == (6, 6) and J.row_labels == ("vx", "vy", "vz", "wx", "wy", "wz")
    L = rankloci.locus("puma560", numeric=True)
    assert main(["locus", "puma560", "--numeric", "--format", "json", "--quiet"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert [c["equations"] for c in cli["components"]] == \
        [c.to_dict()["equations"] for c in L.components]


def test_augmented_locus_has_its_base_and_kinds():
    L = rankloci.locus("planar3r", augment=["q1 + q2 + q3"], numeric=True)
    assert [c.kind for c in L.components] == ["mixed"]
    assert L.base is not None and L.base.shape == (2, 3)


def test_timeout_raises_locus_timeout():
    with pytest.raises(LocusTimeout):
        rankloci.locus("ssrms", timeout=1e-9, verify=False)


def test_method_is_validated_with_its_choices():
    with pytest.raises(ValueError, match=r"method= must be None or one of \('svm', .*got 'nope'"):
        rankloci.locus("planar2r", method="nope")


def test_progress_goes_to_the_rankloci_logger(caplog):
    with caplog.at_level(logging.INFO, logger="rankloci"):
        # a seed no other test uses: the locus is computed here, not taken from the cache
        rankloci.locus("planar2r", numeric=True, seed=20261207)
    messages = [r.getMessage() for r in caplog.records if r.name == "rankloci"]
    assert messages[0].startswith("planar2r: 2x2 matrix, method determinant")
    assert any("self-check" in m for m in messages)


def test_check_and_is_singular():
    result = rankloci.check("planar2r", samples=3)
    assert result.ok and "result: PASS" in str(result)
    assert result.to_dict()["ok"] is True
    L = rankloci.locus("planar2r", numeric=True)
    bad = rankloci.locus(sp.Matrix([[1, 0], [0, sp.cos(sp.Symbol("q2"))]]),
                         variables=sp.symbols("q1 q2"))
    planar2r = rankloci.load_model("planar2r")
    wrong = rankloci.Locus.from_dict(bad.to_dict(), planar2r)     # cos(q2) = 0: not its locus
    assert not rankloci.check(planar2r, wrong, samples=3).ok
    assert rankloci.is_singular("planar2r", [0.3, 0.0])
    assert rankloci.is_singular("planar2r", {"q1": 0.3, "q2": 3.141592653589793})
    assert not rankloci.is_singular("planar2r", [0.3, 1.0], locus=L)
    with pytest.raises(ValueError, match="no value for 'q2'"):
        rankloci.is_singular("planar2r", {"q1": 0.3}, locus=L)
    with pytest.raises(ValueError, match="3 values"):
        L.contains([0.1, 0.2, 0.3])


def test_report_builds_and_writes(tmp_path):
    built, paths = rankloci.report("planar2r", tmp_path / "out", formats="md", samples=3)
    assert [p.name for p in paths if p.suffix == ".md"] == ["planar2r.md"]
    assert "sin(q2)" in (tmp_path / "out" / "planar2r.md").read_text()   # the component
    assert any(p.suffix == ".png" for p in paths)
    assert built.locus is not None and len(built.locus.components) == 1
    with pytest.raises(ValueError, match="'docx' is not one of"):
        rankloci.report("planar2r", tmp_path, formats=("docx",))


@pytest.mark.parametrize("name", ["load_model", "jacobian", "locus"])
def test_public_calls_annotate_every_parameter_and_the_return(name):
    import inspect

    sig = inspect.signature(getattr(rankloci, name))
    assert sig.return_annotation is not inspect.Signature.empty
    assert [p for p, v in sig.parameters.items() if v.annotation is inspect.Parameter.empty] == []


@pytest.mark.parametrize("call, error", [
    (lambda: rankloci.locus("no_such_model"), "rankloci.errors.ModelError"),
    (lambda: rankloci.locus("puma560", augment=["q1 +"]), "rankloci.errors.ModelError"),
    (lambda: rankloci.locus("planar2r", task="position", method="determinant", numeric=True,
                            augment=["q1"]), "rankloci.errors.LocusError"),
    (lambda: rankloci.locus("planar2r", method="qr"), "rankloci.errors.ArgumentError"),
    (lambda: rankloci.locus("puma560", variables=["q1"]), "rankloci.errors.ArgumentError"),
    (lambda: rankloci.locus(3), "rankloci.errors.ArgumentError"),
    (lambda: rankloci.locus("planar2r", seed="a"), "rankloci.errors.ArgumentError"),
])
def test_locus_raises_what_its_docstring_lists(call, error):
    import inspect
    import re

    # the numpydoc section: unindented lines name the exceptions, until the next heading
    section = re.search(r"^Raises\n-+\n(.*?)\n\S+\n-+\n", inspect.getdoc(rankloci.locus),
                        re.S | re.M).group(1)
    documented = [line for line in section.splitlines() if line and not line[0].isspace()]
    assert error in documented
    with pytest.raises(Exception) as info:
        call()
    raised = type(info.value)
    assert f"{raised.__module__}.{raised.__name__}".removeprefix("builtins.") == error
