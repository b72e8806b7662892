"""Discontinuity indices and rate mixing, on small systems and along paths of the planar 4R arm.

The 4R arm is the built-in planar4r: Ha and Lee's four-link planar arm (their Fig. 9) with unit
link lengths l1 = l2 = l3 = l4 = 1, since the text of the paper gives no lengths.  Its locus
(computed by rankloci) is sin q2 = sin q3 = sin q4 = 0: the arm stretched or folded.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from rankloci.io import load_model
from rankloci.near.discontinuity import (discontinuity_index, minor_index, mixed_rates,
                                         mixing_ratio, null_basis, subspace_index)
from rankloci.near.min_inf_norm import ha_lee
from rankloci.near.path import Kinematics, joint_rates_along
from rankloci.tolerances import REGULAR_MIN_RATIO


def _a_form(A, sat):
    """min over k in sat of |det [A_1, a_k]| / sqrt(det A A'): Ha and Lee's index written with A."""
    free = [j for j in range(A.shape[1]) if j not in sat]
    scale = np.sqrt(np.linalg.det(A @ A.T))
    return min(abs(np.linalg.det(A[:, free + [k]])) for k in sat) / scale


def test_index_with_n_equals_the_form_with_a_and_bounds_gravagnes():
    rng = np.random.default_rng(3)
    for _ in range(100):
        m = int(rng.integers(1, 5))
        A = rng.normal(size=(m, m + int(rng.integers(1, 4))))
        s = ha_lee(A, rng.normal(size=m))
        d = discontinuity_index(A, s.saturated)
        assert d == pytest.approx(_a_form(A, list(s.saturated)), rel=1e-9, abs=1e-12)
        # Gravagne's index minimises over every face, a superset of Ha and Lee's faces
        assert subspace_index(A) <= d + 1e-12
        assert 0.0 <= d <= 1.0 + 1e-12
        sv = np.linalg.svd(A, compute_uv=False)
        assert minor_index(A, s.saturated) == pytest.approx(d * np.prod(sv / sv[0]), rel=1e-9,
                                                            abs=1e-14)


def test_index_does_not_depend_on_the_null_space_basis():
    rng = np.random.default_rng(4)
    A = rng.normal(size=(2, 5))
    N = null_basis(A)
    Q = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    for rows in itertools.combinations(range(5), 3):
        assert abs(np.linalg.det(N[list(rows)])) == pytest.approx(
            abs(np.linalg.det((N @ Q)[list(rows)])), rel=1e-10, abs=1e-14)


def test_index_is_zero_exactly_where_the_optimum_is_not_unique():
    # first example: unique optimum, index > 0; second: (0, 1, 1, -1) and (1, 0.5, 1, -1)
    # are both optimal, and the index is 0
    A1 = np.array([[0.7, 0.1, -1.6], [2.0, -0.2, 0.6]])
    assert discontinuity_index(A1, ha_lee(A1, [-1.0, 0.2]).saturated) > 0.05
    A2 = np.array([[1.0, 2.0, 3.0, 4.0], [1.0, 2.0, 3.0, 5.0]])
    assert discontinuity_index(A2, ha_lee(A2, [1.0, 0.0]).saturated) < 1e-12


def test_mixed_rates_solve_the_system_for_every_ratio():
    rng = np.random.default_rng(5)
    A = rng.normal(size=(3, 6))
    y = rng.normal(size=3)
    x_inf = ha_lee(A, y).x
    x_2 = np.linalg.pinv(A) @ y
    for r in (0.0, 0.3, 1.0, float(mixing_ratio(0.1))):
        np.testing.assert_allclose(A @ mixed_rates(x_inf, x_2, r), y, atol=1e-12)
    assert float(mixing_ratio(0.0)) == 0.0 and float(mixing_ratio(10.0)) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="gain"):
        mixing_ratio(0.1, gain=0.0)


@pytest.fixture(scope="module")
def planar4r():
    return Kinematics(load_model("planar4r"))


def test_planar4r_line_gravagnes_index_falls_where_ha_and_lees_does_not(planar4r):
    """The analogue of Ha and Lee's figures 9 to 11 on a line of our own choosing.

    The paper's trajectory and link lengths are only in its figures; here the tool moves 2
    units in -x from q0 = (0.62, 0.23, 1.0, 0.46).  Gravagne's index (every face) falls to
    almost 0 where two columns of J turn parallel, a face the solution does not touch;
    Ha and Lee's index (the faces holding the solution) stays well above it there.
    """
    q0 = np.array([0.62, 0.23, 1.0, 0.46])
    x0 = planar4r.position(q0)
    path = joint_rates_along(planar4r, q0, [x0, x0 - [2.0, 0.0]], norm="inf", steps=200)
    assert path.stopped == "" and path.lp_fallbacks == 0
    assert path.error.max() < 1e-3, "the tool follows the line"
    J = [planar4r.jacobian(q) for q in path.q]
    gravagne = np.array([subspace_index(A) for A in J])
    np.testing.assert_allclose(path.subspace_index, gravagne, rtol=1e-12)
    assert np.all(gravagne <= path.index + 1e-12)
    i = int(np.argmin(gravagne))
    assert gravagne[i] < 2e-3 and path.index[i] > 0.1
    assert path.mixing[i] > 0.85, "the mixing ratio stays near 1 there (Fig. 11), not 0 (Fig. 10)"
    for k in range(0, len(path.t), 10):  # each step's rates realise the path's velocity
        v = J[k] @ path.rates_inf[k]
        np.testing.assert_allclose(J[k] @ path.rates_2[k], v, atol=1e-9)


def test_planar4r_rates_blow_up_and_the_index_drops_near_the_locus(planar4r):
    """Radially outward to 3.999 of the reach 4: the arm nears sin q2 = sin q3 = sin q4 = 0."""
    from rankloci.jacobians import task_matrix
    from rankloci.methods import compute_locus, method_for
    from rankloci.near.nearest import ComponentDistance

    tm = task_matrix(load_model("planar4r"), frame="auto", numeric=True)
    locus = compute_locus(tm, method_for(tm.shape), rng=np.random.default_rng(0))
    assert len(locus.components) == 1
    cd = ComponentDistance(locus, tm.angles)
    q0 = np.array([0.2, 0.6, 0.6, 0.6])
    x0 = planar4r.position(q0)
    path = joint_rates_along(planar4r, q0, [x0, 3.999 * x0 / np.linalg.norm(x0)], norm="inf",
                             steps=200)
    dist = np.array([cd.nearest(q, warm=True).distance for q in path.q])
    rate = np.abs(path.rates_inf).max(axis=1)
    assert dist[-1] < 0.2 * dist[0], "the path nears the component rankloci computed"
    assert rate[-1] > 10 * rate[0], "the minimum infinity-norm joint rates blow up"
    assert path.sigma_ratio[-1] < 0.05 * path.sigma_ratio[0]
    assert path.minor_index[-1] < 0.02 * path.minor_index[0], "the index with J drops to ~0"
    assert path.index[-1] < 0.5 * path.index[0], "the discontinuity index drops along this path"
    # near the end the index falls to ~0 and the rates jump between solutions (sign flips
    # from one step to the next), which they never do over the first 80 % of the path
    flips = np.any(np.diff(np.sign(path.rates_inf), axis=0) != 0, axis=1)
    assert not flips[:160].any() and flips[180:].sum() >= 5
    assert path.index[:160].min() > 0.1 and path.index.min() < 0.01
    # along the approach rate * sigma_min stays bounded: the blow-up is 1/sigma_min
    smin = np.array([np.linalg.svd(planar4r.jacobian(q), compute_uv=False)[-1] for q in path.q])
    assert np.max(rate * smin) < 3 * np.median(rate * smin)


def test_planar4r_equal_bends_the_index_stays_bounded_while_the_form_with_j_vanishes(planar4r):
    """q = (0.3, e, e, e), e -> 0, tip velocity outward: N's minors converge to a nonzero limit.

    The orthonormal-basis index measures non-uniqueness only; it need not drop at the locus.
    The index formed with J carries prod sigma_i / sigma_max and does.
    """
    d, dm = [], []
    for e in (0.1, 0.01, 0.001):
        q = np.array([0.3, e, e, e])
        J = planar4r.jacobian(q)
        p = planar4r.position(q)
        s = ha_lee(J, p / np.linalg.norm(p))
        d.append(discontinuity_index(J, s.saturated))
        dm.append(minor_index(J, s.saturated))
    assert min(d) > 0.2
    assert dm[-1] < 1e-3 and dm[-1] < dm[0] / 50


def test_a_path_into_the_locus_stops_and_says_where(planar4r):
    q0 = np.array([0.2, 0.6, 0.6, 0.6])
    x0 = planar4r.position(q0)
    path = joint_rates_along(planar4r, q0, [x0, 4.2 * x0 / np.linalg.norm(x0)], norm="2", steps=100)
    assert path.stopped.startswith("stopped at t = ")
    assert path.t[-1] < 1.0 and np.all(path.sigma_ratio > REGULAR_MIN_RATIO)


def test_restricted_joints_do_not_move_and_the_tool_still_follows(planar4r):
    q0 = np.array([0.62, 0.23, 1.0, 0.46])
    x0 = planar4r.position(q0)
    for norm in ("2", "inf", "mixed"):
        path = joint_rates_along(planar4r, q0, [x0, x0 + [-0.5, -0.3]], norm=norm, steps=100,
                                 restricted=(0,))
        assert np.all(path.rates[:, 0] == 0.0) and np.all(path.q[:, 0] == q0[0])
        assert path.error.max() < 1e-3
        # the FSP least-norm point is the pseudo-inverse solution of the remaining columns
        for k in range(0, len(path.t), 25):
            J = planar4r.jacobian(path.q[k])[:, 1:]
            v = J @ path.rates_2[k, 1:]
            np.testing.assert_allclose(path.rates_2[k, 1:], np.linalg.pinv(J) @ v, atol=1e-12)
            assert np.abs(path.rates_inf[k, 1:]).max() <= np.abs(path.rates_2[k, 1:]).max() + 1e-12


def test_path_arguments_are_checked(planar4r):
    q0 = np.zeros(4) + 0.3
    with pytest.raises(ValueError, match="2, inf, mixed"):
        joint_rates_along(planar4r, q0, [[0, 0], [1, 1]], norm="1")
    with pytest.raises(ValueError, match="steps"):
        joint_rates_along(planar4r, q0, [[0, 0], [1, 1]], steps=0)
