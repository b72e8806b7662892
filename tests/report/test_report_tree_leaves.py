"""Branch-tree leaves that are halves of a component (q5 = 0 and q5 = pi) are that component's."""

from __future__ import annotations

import numpy as np

import rankloci
from rankloci.io import load_model
from rankloci.jacobians import task_matrix
from rankloci.reporting.tree_summary import component_leaves, tree_summary


def test_both_halves_of_the_puma_wrist_are_component_leaves():
    tm = task_matrix(load_model("puma560"))
    locus = rankloci.locus("puma560")
    names = [v.name for v in tm.variables]
    points = {k: [np.array([c.sample[n] for n in names])]
              for k, c in enumerate(locus.components, start=1)}
    wrist = next(k for k, c in enumerate(locus.components, start=1)
                 if [str(e) for e in c.equations] == ["sin(q5)"])
    for value in (0.0, np.pi):    # a point on each half
        points[wrist].append(np.array([value if n == "q5" else locus.components[wrist - 1]
                                       .sample[n] for n in names]))
    leaves = component_leaves(locus.tree, points, tm.variables, dict(tm.parameters))
    conditions = {str(locus.tree.nodes[n].get("condition")): k for n, k in leaves.items()}
    assert conditions["sin(q5/2)"] == wrist and conditions["cos(q5/2)"] == wrist
    # a parameter's branch (a2 = 0) is no component of this model: it stays a grey leaf
    assert "a2" not in conditions
    summary = tree_summary(locus.tree, components=leaves)
    grey = [d["label"] for _, d in summary.graph.nodes(data=True) if d["role"] == "leaf"]
    assert not any("q5/2" in label for label in grey), grey
