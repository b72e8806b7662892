"""The branch tree of a locus cut down for drawing, its leaves read through their outcomes."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

import networkx as nx

from ..locus import Outcome

__all__ = ["TreeSummary", "tree_summary", "node_outcome", "is_component_leaf"]


def node_outcome(data) -> Outcome | None:
    """The :class:`~rankloci.locus.Outcome` of a branch-tree node with attributes ``data``.

    None when the node has no outcome; a text that is no outcome is a ValueError.
    """
    outcome = data.get("outcome")
    return None if outcome is None else Outcome(outcome)


def is_component_leaf(data) -> bool:
    """Does a branch-tree node with attributes ``data`` stop as a component of the locus?

    A node without an outcome is not one.

    Examples
    --------
    >>> is_component_leaf({"outcome": Outcome.ALL_MINORS_VANISH}), is_component_leaf({})
    (True, False)
    """
    outcome = node_outcome(data)
    return outcome is not None and outcome.is_component


def _outcome_text(data) -> str:
    """The outcome of a node as it is shown, "" when it has none."""
    outcome = node_outcome(data)
    return "" if outcome is None else str(outcome)


@dataclass(frozen=True)
class TreeSummary:
    """A branch tree cut down for drawing; ``graph`` nodes carry ``label`` and ``role``."""

    graph: nx.DiGraph
    total_nodes: int
    collapsed: int
    outcomes: dict = field(default_factory=dict)


def tree_summary(tree: nx.DiGraph, max_nodes: int = 45) -> TreeSummary:
    """The branch tree cut down to at most about ``max_nodes`` nodes for drawing.

    A small tree is kept whole.  A larger one keeps the paths from the root to
    the component leaves; every subtree off those paths becomes one dashed node
    that counts its leaves by stop reason.  If that is still too big, the tree
    is cut at the deepest level that fits, each cut subtree again one dashed
    node.  Node roles: ``"component"`` (a leaf that is a component), ``"leaf"``
    (another stop reason), ``"inner"``, ``"summary"``.
    """
    outcomes = Counter(_outcome_text(d) for n, d in tree.nodes(data=True)
                       if tree.out_degree(n) == 0)

    def role(n):
        if tree.out_degree(n):
            return "inner"
        return "component" if is_component_leaf(tree.nodes[n]) else "leaf"

    if tree.number_of_nodes() <= max_nodes:
        G = nx.DiGraph()
        for n, d in tree.nodes(data=True):
            G.add_node(n, label=_label(n, d, leaf=tree.out_degree(n) == 0), role=role(n))
        G.add_edges_from(tree.edges())
        return TreeSummary(G, tree.number_of_nodes(), 0, dict(outcomes))
    keep = {n for n in tree if role(n) == "component"}
    for n in list(keep):
        keep |= nx.ancestors(tree, n)
    keep |= {n for n in tree if tree.in_degree(n) == 0}
    depth = {}
    for r in (n for n in tree if tree.in_degree(n) == 0):
        depth.update(nx.single_source_shortest_path_length(tree, r))
    # the deepest cut that fits: kept nodes down to `cut`, one summary per cut or pruned subtree
    levels = sorted({depth[n] for n in keep}, reverse=True)
    for cut in levels:
        shown = {n for n in keep if depth[n] <= cut}
        summaries = sum(1 for n in shown if any(c not in shown for c in tree.successors(n)))
        if len(shown) + summaries <= max_nodes:
            break
    G = nx.DiGraph()
    collapsed = 0
    for n in sorted(shown):
        G.add_node(n, label=_label(n, tree.nodes[n], leaf=tree.out_degree(n) == 0), role=role(n))
    for n in sorted(shown):
        rest = []
        for c in tree.successors(n):
            if c in shown:
                G.add_edge(n, c)
            else:
                rest.append(c)
        if rest:
            sub = set(rest)
            for c in rest:
                sub |= nx.descendants(tree, c)
            leaves = Counter(_outcome_text(tree.nodes[m]) for m in sub
                             if tree.out_degree(m) == 0)
            found = sum(1 for m in sub if tree.out_degree(m) == 0 and role(m) == "component")
            collapsed += len(sub)
            what = "\n".join(f"{v} x {k}" for k, v in sorted(leaves.items()))
            head = f"{len(sub)} more {'branch' if len(sub) == 1 else 'branches'}"
            if found:
                head += f", {found} component {'leaf' if found == 1 else 'leaves'}"
            sid = f"s{n}"
            G.add_node(sid, label=f"{head}\n{what}", role="summary")
            G.add_edge(n, sid)
    return TreeSummary(G, tree.number_of_nodes(), collapsed, dict(outcomes))


def _short(text: str, width: int = 38) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= width else text[:width - 3] + "..."


def _label(n, d, *, leaf: bool) -> str:
    lines = [f"{n}: {_short(d.get('condition', ''))}"]
    bits = []
    if "columns" in d:
        bits.append(f"cols {d['columns']}")
    if "k" in d:
        bits.append(f"k={d['k']}")
    if bits:
        lines.append(", ".join(bits))
    if leaf:
        lines.append(f"[{_outcome_text(d)}]")
    return "\n".join(lines)
