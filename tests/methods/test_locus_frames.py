"""The locus does not depend on the frame J is expressed in, and reported
directions are the model-frame null vectors."""

import numpy as np
import pytest
import sympy as sp

from rankloci.directions import directions_in_model_frame
from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus
from rankloci.tolerances import RANK_RTOL

SEED = 7


def _equation_sets(locus):
    return {tuple(sorted(sp.sstr(e) for e in c.equations))
            for c in locus.components if c.for_model}


def _vanish_somewhere(comp_a, locus_b, syms):
    """Is comp_a's sample point on some component of locus_b?"""
    x = [comp_a.sample[str(s)] for s in syms]
    for c in locus_b.components:
        if not c.for_model:
            continue
        f = sp.lambdify(syms, list(c.equations))
        if np.max(np.abs(np.array(f(*x), dtype=float))) < 1e-7:
            return True
    return False


@pytest.mark.parametrize("name", ["puma560", "ur5", "planar4r", "planar3r_orient"])
def test_locus_same_in_base_and_middle_frame(name):
    model = load_model(name)
    base = compute_locus(task_matrix(model, frame="base", numeric=True), rng=np.random.default_rng(SEED))
    middle = compute_locus(task_matrix(model, frame="auto", numeric=True), rng=np.random.default_rng(SEED))
    syms = list(model.variables)
    assert len(base.components) == len(middle.components)
    for a, b in ((base, middle), (middle, base)):
        for comp in a.components:
            assert _vanish_somewhere(comp, b, syms), (name, comp.equations)


def test_planar_arm_uses_a_middle_frame_and_a_spatial_arm_does_not():
    """A planar arm's link frames are its base frame turned about z, so vx, vy (and wz) keep
    their rank there and the middle frame is used.  The PUMA 560's are not: with the task
    (vx, vy) its middle frame would mix vz into vx and vy, so the model's frame is kept."""
    planar = task_matrix(load_model("planar4r"), frame="auto")
    assert planar.frame == 2, planar.frame
    puma = task_matrix(load_model("puma560"), task="planar", frame="auto")
    assert puma.frame == load_model("puma560").frame, puma.frame


@pytest.mark.parametrize("name", ["puma560", "planar4r", "planar3r_orient"])
def test_directions_are_left_null_vectors_in_model_frame(name):
    """The locus is computed in a middle frame; the directions reported at the sample points
    must be left null vectors of J in the model's own frame and task rows."""
    model = load_model(name)
    tm = task_matrix(model, frame="auto", numeric=True)
    assert tm.frame != model.frame, "the test needs a locus computed in another frame"
    locus = directions_in_model_frame(compute_locus(tm, rng=np.random.default_rng(SEED)), model, tm)
    J_model = task_matrix(model, numeric=True).matrix
    J = sp.lambdify(model.variables, J_model)
    for comp in locus.components:
        A = np.array(J(*[comp.sample[str(v)] for v in model.variables]), dtype=float)
        smax = np.linalg.svd(A, compute_uv=False)[0]
        for u in comp.direction_at_sample:
            # u^T J = 0 up to the rank tolerance: the sample sits on the locus to
            # ROOT_XTOL, far below RANK_RTOL relative to sigma_max
            assert np.linalg.norm(np.asarray(u) @ A) <= 10 * RANK_RTOL * smax, comp.equations
