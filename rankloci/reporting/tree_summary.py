"""The branch tree of a locus cut down for drawing, its leaves read through their outcomes."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

import networkx as nx

from ..loci import Outcome
from ..tolerances import LEAF_MATCH_RTOL

__all__ = ["TreeSummary", "tree_summary", "node_outcome", "is_component_leaf", "component_leaves"]



def node_outcome(data) -> Outcome | None:
    """The :class:`~rankloci.loci.Outcome` of a branch-tree node with attributes ``data``.

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


def component_leaves(tree: nx.DiGraph, points: dict, variables, parameters) -> dict:
    """The component each component leaf of ``tree`` gives: leaf -> 1-based number.

    ``points`` maps each component's number to points of it (arrays over
    ``variables``).  A leaf gives component k when every branch condition from
    the root down to it vanishes (:data:`LEAF_MATCH_RTOL`) at one of k's points;
    leaves that match no component (branches for special parameter values, or
    pieces the final merge put inside another component) are left out.
    """
    import sympy as sp

    from ..errors import ExpressionError
    from ..expr import parse_expression

    names = {v.name: v for v in variables}
    params = {str(k): v for k, v in parameters.items()}
    cache = {}

    def value(cond, q):
        if cond not in cache:
            try:
                # conditions are text that the tree computation wrote: parsed without the
                # size limits of model files, and never evaluated as Python
                e = parse_expression(cond, {**names, **{k: sp.Symbol(k) for k in params}},
                                     bounded=False)
            except ExpressionError:
                cache[cond] = None
                return None
            e = e.subs({sp.Symbol(k): v for k, v in params.items()})
            terms = sp.Add.make_args(sp.expand(e))
            # the scale of the condition: its terms' numeric coefficients (a term's value
            # alone would make a one-term condition such as cos(q5/2) always 1 relative)
            coeffs = []
            for t in terms:
                try:
                    coeffs.append(abs(float(t.as_coeff_Mul()[0])))
                except TypeError:
                    coeffs.append(0.0)
            cache[cond] = (sp.lambdify(list(variables), e, "numpy"),
                           [sp.lambdify(list(variables), t, "numpy") for t in terms],
                           sum(coeffs))
        f = cache[cond]
        if f is None:
            return None
        size = max(sum(abs(float(t(*q))) for t in f[1]), f[2])
        return abs(float(f[0](*q))) / size if size > 0 else 0.0

    roots = [n for n in tree if tree.in_degree(n) == 0]
    out = {}
    for leaf in (n for n in tree if tree.out_degree(n) == 0 and is_component_leaf(tree.nodes[n])):
        path = next((nx.shortest_path(tree, r, leaf) for r in roots if nx.has_path(tree, r, leaf)),
                    [leaf])
        conds = [tree.nodes[n].get("condition") for n in path if tree.nodes[n].get("condition")]
        if not conds or not points:
            continue
        first = next(iter(points.values()))[0]
        conds = [c for c in conds if value(str(c), first) is not None]
        if not conds:
            continue
        for k, qs in sorted(points.items()):
            # a condition that is no expression ("(all configurations)") constrains nothing;
            # a component made of several leaves (q = 0 and q = pi) has points on each
            if any(all(v is None or v <= LEAF_MATCH_RTOL
                       for v in (value(str(c), q) for c in conds)) for q in qs):
                out[leaf] = k
                break
    return out


def tree_summary(tree: nx.DiGraph, max_nodes: int = 30, components=None) -> TreeSummary:
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
        if components is not None:
            return "component" if n in components else "leaf"
        return "component" if is_component_leaf(tree.nodes[n]) else "leaf"

    def label(n):
        return _label(n, tree.nodes[n], leaf=tree.out_degree(n) == 0,
                      component=(components or {}).get(n))

    if tree.number_of_nodes() <= max_nodes:
        G = nx.DiGraph()
        for n in tree.nodes:
            G.add_node(n, label=label(n), role=role(n))
        G.add_edges_from(tree.edges())
        return TreeSummary(G, tree.number_of_nodes(), 0, dict(outcomes))
    keep = {n for n in tree if role(n) == "component"}
    if components:
        # one leaf per component: the first branch that found it
        first = {}
        for n in sorted(keep, key=lambda n: (isinstance(n, str), str(n).zfill(8))):
            first.setdefault(components[n], n)
        keep = set(first.values())
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
        G.add_node(n, label=label(n), role=role(n))
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
            if components is not None:
                continue  # only the paths to the components are drawn; the rest is counted
            what = "\n".join(f"{v} x {k}" for k, v in sorted(leaves.items()))
            head = f"{len(sub)} more {'branch' if len(sub) == 1 else 'branches'}"
            if found:
                head += f", {found} component {'leaf' if found == 1 else 'leaves'}"
            sid = f"s{n}"
            G.add_node(sid, label=f"{head}\n{what}", role="summary")
            G.add_edge(n, sid)
    return TreeSummary(G, tree.number_of_nodes(), collapsed, dict(outcomes))


def _wrapped(text: str, width: int = 26, lines: int = 3) -> str:
    """``text`` wrapped at ``width`` characters, at most ``lines`` lines (then cut with ...)."""
    import textwrap

    text = " ".join(str(text).split())
    out = textwrap.wrap(text, width, break_long_words=True, break_on_hyphens=False) or [""]
    if len(out) > lines:
        out = out[:lines]
        out[-1] = out[-1][:width - 3] + "..."
    return "\n".join(out)


def _label(n, d, *, leaf: bool, component=None) -> str:
    lines = [f"{n}: " + _wrapped(d.get("condition", ""))]
    bits = []
    if "columns" in d:
        bits.append(f"cols {d['columns']}")
    if "k" in d:
        bits.append(f"k={d['k']}")
    if bits:
        lines.append(", ".join(bits))
    if component is not None:
        lines.append(f"component {component}")
    elif leaf:
        lines.append(f"[{_outcome_text(d)}]")
    return "\n".join(lines)
