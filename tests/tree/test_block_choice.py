"""Which square block the singular vector method takes the determinant of."""

from __future__ import annotations

import numpy as np

from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.tree import blocks
from rankloci.tree.branch import Branch
from rankloci.tree.context import Context


def _redundant_context():
    tm = task_matrix(load_model("planar4r"), numeric=True)
    return Context(tm, method="svm", rng=np.random.default_rng(0))


def _counted(ctx):
    calls = []
    det = ctx.det

    def counting(block):
        D = det(block)
        calls.append(len(D))
        return D
    ctx.det = counting
    return calls


def test_candidates_are_compared_and_the_smallest_determinant_wins():
    ctx = _redundant_context()
    calls = _counted(ctx)
    pts = ctx.sampler.points(Branch())
    M = ctx.M if len(ctx.M) <= len(ctx.M[0]) else [list(r) for r in zip(*ctx.M)]
    _, D = blocks.choose_columns(ctx, M, pts, candidates=3)
    assert len(calls) >= 1
    assert len(D) == min(calls)


def test_no_further_candidate_after_a_determinant_past_the_term_limit(monkeypatch):
    """The 8-joint chains' root determinants have millions of terms: once one is past
    CANDIDATE_MAX_TERMS, the others are not formed."""
    ctx = _redundant_context()
    pts = ctx.sampler.points(Branch())
    M = ctx.M if len(ctx.M) <= len(ctx.M[0]) else [list(r) for r in zip(*ctx.M)]
    calls = _counted(ctx)
    blocks.choose_columns(ctx, M, pts, candidates=12)
    assert len(calls) > 1          # without the limit, several candidates are compared
    ctx2 = _redundant_context()
    calls2 = _counted(ctx2)
    monkeypatch.setattr(blocks, "CANDIDATE_MAX_TERMS", min(calls) - 1)
    blocks.choose_columns(ctx2, M, ctx2.sampler.points(Branch()), candidates=12)
    assert len(calls2) == 1
