"""Distance from a configuration to the components of a locus, against closed forms."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from locus_helpers import locus_of

from rankloci.near.nearest import ComponentDistance


def wrapped(d):
    return (np.asarray(d) + np.pi) % (2 * np.pi) - np.pi


def to_multiple_of_pi(x):
    """Distance from the angle x to the nearest multiple of pi."""
    return np.abs(wrapped(2 * np.asarray(x)) / 2)


def test_planar4r_distance_to_the_stretched_or_folded_arm():
    """sin q2 = sin q3 = sin q4 = 0, q1 free: the distance is the norm of each q_i's distance to
    the nearest multiple of pi, i = 2, 3, 4."""
    tm, locus = locus_of("planar4r")
    cd = ComponentDistance(locus, tm.angles)
    rng = np.random.default_rng(1)
    for q in rng.uniform(-np.pi, np.pi, size=(12, 4)):
        near = cd.nearest(q)
        assert near.component == 1
        assert near.distance == pytest.approx(np.linalg.norm(to_multiple_of_pi(q[1:])), abs=1e-8)
        assert near.point[0] == pytest.approx(q[0], abs=1e-8), "q1 stays: it is free"


def test_puma560_distance_to_each_component():
    tm, locus = locus_of("puma560")
    cd = ComponentDistance(locus, tm.angles)
    texts = [str(c.equations) for c in locus.components]
    wrist = next(i for i, t in enumerate(texts) if t == "(sin(q5),)")
    elbow = next(i for i, c in enumerate(locus.components) if c.free and
                 sp.Symbol("q3", real=True) not in c.free and len(c.equations) == 1
                 and c.equations[0].free_symbols == {sp.Symbol("q3", real=True)})
    q3 = sp.Symbol("q3", real=True)
    roots = [float(r) for r in sp.solve(sp.expand_trig(locus.components[elbow].equations[0]), q3)]
    assert roots
    rng = np.random.default_rng(2)
    for q in rng.uniform(-np.pi, np.pi, size=(8, 6)):
        d, p = cd.distance(wrist, q)
        assert d == pytest.approx(float(to_multiple_of_pi(q[4])), abs=1e-8)
        d, p = cd.distance(elbow, q)
        expected = min(min(abs(wrapped(q[2] - r)), abs(wrapped(q[2] - r - np.pi))) for r in roots)
        assert d == pytest.approx(expected, abs=1e-8)
        near = cd.nearest(q)
        assert near.distance == pytest.approx(min(near.distances)) and near.distance <= d + 1e-12


def test_warm_starts_give_the_same_distances_along_a_path():
    tm, locus = locus_of("planar4r")
    cold, warm = ComponentDistance(locus, tm.angles), ComponentDistance(locus, tm.angles)
    for s in np.linspace(0, 1, 15):
        q = np.array([0.3, 0.8 - 0.7 * s, 0.5, -0.4 + 0.3 * s])
        assert warm.nearest(q, warm=True).distance == pytest.approx(cold.nearest(q).distance,
                                                                    abs=1e-9)
