"""Real points isolated in a complex component are found, reported and certified.

``[[x, -y], [y, x]]`` is singular on the complex curve x**2 + y**2 = 0, whose only real point
is the origin.  The locus must report that point (and nothing else real), its certificate must
pass, and a wrong claim about the real points must be refused.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy as sp

import rankloci
from rankloci.cli import main
from rankloci.exact.real_points import real_part_of, sum_of_squares
from rankloci.exact.witness import certify_components
from rankloci.loci import Component
from rankloci.tolerances import RANK_RTOL

x, y = sp.symbols("x y", real=True)

#: (TOML matrix rows, the real singular points: every combination of the listed values)
CASES = {
    "rotation": ([["x", "-y"], ["y", "x"]], {"x": [0.0], "y": [0.0]}),
    "sines": ([["sin(x)", "-sin(y)"], ["sin(y)", "sin(x)"]],
              {"x": [0.0, np.pi], "y": [0.0, np.pi]}),
    "tall": ([["x", "y"], ["-y", "x"], ["0", "0"]], {"x": [0.0], "y": [0.0]}),
    "one entry": ([["x**2 + y**2"]], {"x": [0.0], "y": [0.0]}),
}


def _write(tmp_path, name, rows):
    path = tmp_path / f"{name.replace(' ', '_')}.toml"
    text = ", ".join("[" + ", ".join(f'"{e}"' for e in row) + "]" for row in rows)
    path.write_text(f'variables = ["x", "y"]\nmatrix = [{text}]\n', encoding="utf-8")
    return path


def _ratio(M, point):
    """sigma_min / sigma_max of M at ``point`` (0 where M vanishes)."""
    A = np.array(M.subs({x: point[0], y: point[1]}).evalf(), dtype=float)
    s = np.linalg.svd(A, compute_uv=False)
    return 0.0 if s[0] == 0 else s[-1] / s[0]


@pytest.mark.parametrize("name", CASES)
def test_real_points_of_a_complex_component_are_reported_and_certified(name, tmp_path, capsys):
    rows, expected = CASES[name]
    path = _write(tmp_path, name, rows)
    assert main(["locus", str(path), "--quiet", "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["complete"] is True
    cert = doc["certificate"]
    assert cert["verdict"] == "passed"
    # the JSON says what was done: the complex component, its squares, its real points
    (part,) = cert["real_parts"]
    assert part["complex_component"] in ("x**2 + y**2", "sin(x)**2 + sin(y)**2")
    assert part["real_points"] == len(expected["x"]) * len(expected["y"])
    assert all(c["real_points_of"] == [part["complex_component"]] for c in doc["components"])
    assert any("the real points of the complex component" in n for n in doc["notes"])

    M = sp.Matrix(rows).subs({sp.Symbol("x"): x, sp.Symbol("y"): y})
    locus = rankloci.locus(M, variables=(x, y))
    assert locus.complete is True
    points = [(a, b) for a in expected["x"] for b in expected["y"]]
    rng = np.random.default_rng(7)
    for p in points:
        # sound: the reported real points are rank deficient, here J vanishes
        assert np.abs(np.array(M.subs({x: p[0], y: p[1]}).evalf(), dtype=float)).max() < 1e-12
        assert locus.contains(list(p))
        # nothing real is missing: points near them are regular and off the locus
        for r in (1e-1, 1e-3):
            for angle in rng.uniform(0, 2 * np.pi, 4):
                near = (p[0] + r * np.cos(angle), p[1] + r * np.sin(angle))
                assert _ratio(M, near) > RANK_RTOL
                assert not locus.contains(list(near))
    # and random points are regular and off the locus
    for q in rng.uniform(-np.pi, np.pi, (8, 2)):
        assert _ratio(M, q) > RANK_RTOL and not locus.contains(list(q))


def test_the_locus_file_of_real_points_is_checked_again(tmp_path, capsys):
    path = _write(tmp_path, "rotation", CASES["rotation"][0])
    assert main(["locus", str(path), "--quiet", "--format", "json"]) == 0
    saved = tmp_path / "locus.json"
    saved.write_text(capsys.readouterr().out, encoding="utf-8")
    assert main(["check", str(path), "--locus", str(saved), "--quiet", "--format", "json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["certificate"]["verdict"] == "passed"


def test_a_complex_component_without_real_points_gives_no_real_component():
    locus = rankloci.locus(sp.Matrix([[x ** 2 + y ** 2 + 1]]), variables=(x, y))
    assert locus.complete is True and locus.components == ()
    assert locus.certificate.complex_components == ((x ** 2 + y ** 2 + 1,),)


ROTATION = sp.Matrix([[x, -y], [y, x]])
SINES = sp.Matrix([[sp.sin(x), -sp.sin(y)], [sp.sin(y), sp.sin(x)]])


def _claim(equations, solved, rank_drop=2, of=x ** 2 + y ** 2):
    return Component(tuple(equations), solved=solved, dimension=0, rank_drop=rank_drop,
                     real_points_of=(of,))


def test_the_right_real_points_pass():
    cert = certify_components(ROTATION, (x, y), (), [_claim((x, y), {x: (0,), y: (0,)})])
    assert cert.verdict == "passed"
    assert cert.real_parts[0]["sum_of_squares"] == ["x", "y"]


def test_a_wrong_real_point_is_refused():
    """(1, 0) is regular, and the origin is then on no reported component."""
    cert = certify_components(ROTATION, (x, y), (), [_claim((x - 1, y), {x: (1,), y: (0,)})])
    assert cert.verdict == "failed"
    assert any("real points of x**2 + y**2 = 0 lie on no reported component" in f
               for f in cert.findings)
    assert any("regular" in f for f in cert.findings)


def test_a_missing_real_point_is_refused():
    """sin(x)**2 + sin(y)**2 has four real zeros; a component with two of them is short."""
    short = _claim((sp.sin(x), sp.sin(y / 2)), {x: (0, sp.pi), y: (0,)},
                   of=sp.sin(x) ** 2 + sp.sin(y) ** 2)
    cert = certify_components(SINES, (x, y), (x, y), [short])
    assert cert.verdict == "failed"
    assert any("2 of the 4 real points" in f for f in cert.findings)


def test_a_hypersurface_that_changes_sign_is_not_taken_for_real_points():
    """x**2 - y**2 = 0 is two real lines: claiming its only real point is the origin is
    refused, and the lines' witness points stay uncovered."""
    M = sp.Matrix([[x ** 2 - y ** 2]])
    cert = certify_components(M, (x, y), (), [_claim((x, y), {x: (0,), y: (0,)}, rank_drop=1,
                                                     of=x ** 2 - y ** 2)])
    assert cert.verdict == "failed"
    assert any("not proved to have real points of lower dimension" in f
               for f in cert.findings)
    assert real_part_of(x ** 2 - y ** 2, (x, y), ()) is None


def test_sums_of_squares_are_exact_identities():
    gens = (x, y)
    for f in (x ** 2 + 2 * x * y + 2 * y ** 2, x ** 4 + x ** 2 * y ** 2 + 3, (x - 2 * y) ** 2):
        sos = sum_of_squares(sp.Poly(f, *gens))
        assert sos is not None and all(d > 0 for d, _ in sos)
        assert sp.expand(sum(d * s.as_expr() ** 2 for d, s in sos) - f) == 0
    assert sum_of_squares(sp.Poly(x * y, *gens)) is None
    assert sum_of_squares(sp.Poly(x ** 2 - 2 * x * y, *gens)) is None


def test_the_text_output_says_how_the_real_points_were_proved(tmp_path, capsys):
    path = _write(tmp_path, "rotation", CASES["rotation"][0])
    assert main(["locus", str(path), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "certified complete and sound" in out
    assert "real points of the complex component x**2 + y**2 = 0: where x, y vanish" in out
