"""Baxter's arm, whose DH table has the special values a1 = a3 (kinematics_models/extra).

With its parameters symbolic the tree assumes generic values; every component shown must
still hold at the model's own values, and none lie inside another there.  The locus is the
one ``rankloci locus`` shows (computed, checked numerically against the DH Jacobian at the
model's values, and recomputed where the check fails); the check must accept it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rankloci.io.toml_model import read_model
from rankloci.jacobians import task_matrix
from rankloci.methods import compute_locus, method_for
from rankloci.verify import dimension_findings, verified_locus

BAXTER = Path(__file__).resolve().parents[2] / "kinematics_models" / "extra" / "baxter_dh.toml"


def test_baxter_locus_at_its_own_parameter_values():
    model = read_model(BAXTER)
    tm = task_matrix(model, frame="auto")
    assert {str(p) for p in tm.parameters} >= {"a1", "a3"}

    def compute(t, seed, hints=()):
        return compute_locus(t, method_for(t.shape), rng=np.random.default_rng(seed),
                             hints=hints)

    locus, verification = verified_locus(compute, tm, task_matrix(model))
    assert verification.complete, verification.problems
    assert locus.components and all(c.for_model for c in locus.components)
    # a rank drop of 1 of a 6 x 7 matrix holds on sets of dimension 5 at least (7 - 2)
    assert all(c.dimension == 5 for c in locus.components if c.rank_drop == 1)
    assert not dimension_findings(locus)
