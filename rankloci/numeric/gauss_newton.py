"""Minimum-norm Gauss-Newton from many starts at once."""

from __future__ import annotations

import numpy as np
from ..tolerances import (GN_DIFFERENCE_STEP, GN_MAX_ITER, GN_MIN_STEP, GN_RESIDUAL_FLOOR,
                          GN_STALL_STEPS, LINE_LEVELS)

__all__ = ["gauss_newton", "gauss_newton_rows"]

_HALVINGS = 0.5 ** np.arange(LINE_LEVELS)


def gauss_newton(residual, x0, *, max_iter: int = GN_MAX_ITER, h: float = GN_DIFFERENCE_STEP):
    """:func:`gauss_newton_rows` from one start; returns the final point or None."""
    x = gauss_newton_rows(residual, np.asarray(x0, dtype=float)[None, :], max_iter=max_iter, h=h)[0]
    return x if np.all(np.isfinite(x)) else None


def gauss_newton_rows(residual, X0, *, max_iter: int = GN_MAX_ITER, h: float = GN_DIFFERENCE_STEP):
    """Minimum-norm Gauss-Newton from several starts at once (the rows of ``X0``).

    ``residual`` maps rows of unknowns (shape (B, n)) to rows of residuals,
    so that every start, and every column of the forward-difference
    Jacobians, is evaluated in one call.  Each step solves J dx = -r in the
    least-squares, minimum-norm sense, with step halving while the residual
    grows (LINE_LEVELS halvings evaluated per call).  A start stops when its
    residual is below GN_RESIDUAL_FLOOR, when a step cannot reduce it, or when
    it has not halved in GN_STALL_STEPS steps (no convergence in sight).  Returns
    the final rows (NaN where not finite).
    """
    X = np.array(X0, dtype=float)
    S, n = X.shape
    if n == 0:
        return X           # nothing left to move: the caller checks the residual
    R = residual(X)
    norm = np.linalg.norm(R, axis=1)
    norm[~np.isfinite(norm)] = np.inf
    active = np.isfinite(norm)
    shifts = np.vstack([np.zeros(n), h * np.eye(n)])
    history = [norm.copy()]
    for it in range(max_iter):
        active &= norm >= GN_RESIDUAL_FLOOR
        if it >= GN_STALL_STEPS:
            active &= norm <= 0.5 * history[it - GN_STALL_STEPS]
        if not active.any():
            break
        idx = np.flatnonzero(active)
        P = (X[idx, None, :] + shifts[None, :, :]).reshape(-1, n)
        RR = residual(P).reshape(len(idx), n + 1, -1)
        J = np.transpose((RR[:, 1:, :] - RR[:, :1, :]) / h, (0, 2, 1))
        if not np.all(np.isfinite(J)):
            ok = np.all(np.isfinite(J), axis=(1, 2))
            active[idx[~ok]] = False
            idx, J = idx[ok], J[ok]
            if not len(idx):
                continue
        dX = -np.einsum("anm,am->an", np.linalg.pinv(J), R[idx])
        step = np.ones(len(idx))
        pending = np.ones(len(idx), dtype=bool)
        while pending.any():
            # the next LINE_LEVELS halvings of every pending step in one call: a call costs
            # about as much for a few points as for one, and a step is halved 4 times on
            # average (tiago's thumb chain: 110000 calls of 3 points, 100 us each)
            k = np.flatnonzero(pending)
            scales = step[k, None] * _HALVINGS[None, :]                # (row, level)
            Xn = X[idx[k], None, :] + scales[:, :, None] * dX[k, None, :]
            Rn = residual(Xn.reshape(-1, n)).reshape(len(k), LINE_LEVELS, -1)
            nn = np.linalg.norm(Rn, axis=2)
            # steps of GN_MIN_STEP and below are not tried (the row is stuck)
            better = np.isfinite(nn) & (nn < norm[idx[k], None]) & (scales > GN_MIN_STEP)
            # the first (longest) improving step of each row, as sequential halving takes it
            first = np.argmax(better, axis=1)
            won = better[np.arange(len(k)), first]
            rows, kw, fw = idx[k[won]], k[won], first[won]
            X[rows] = Xn[won, fw]
            R[rows] = Rn[won, fw]
            norm[rows] = nn[won, fw]
            pending[kw] = False
            lost = k[~won]
            step[lost] *= _HALVINGS[-1] / 2
            stuck = lost[step[lost] <= GN_MIN_STEP]
            pending[stuck] = False
            active[idx[stuck]] = False
        history.append(norm.copy())
    return X
