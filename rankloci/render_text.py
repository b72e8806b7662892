"""Plain-text, JSON and LaTeX renderings of a locus and its branch tree (pure)."""

from __future__ import annotations

import json

import sympy as sp

__all__ = ["locus_text", "locus_json", "locus_latex", "tree_text", "tree_dot", "tree_json",
           "solved_text", "limits_text"]


def _value_text(v) -> str:
    text = sp.sstr(v).replace("pi", "π")
    if not (v / sp.pi).is_rational:
        text += f" (≈ {float(v):.6g})"
    return text


def solved_text(comp) -> str:
    parts = []
    for q, vals in comp.solved.items():
        vs = ", ".join(_value_text(v) for v in vals)
        parts.append(f"{q} ∈ {{{vs}}}" if len(vals) > 1 else f"{q} = {vs}")
    return "; ".join(parts)


def _signed(x, digits) -> str:
    """``x`` with its sign and ``digits`` decimals; a value that rounds to zero has no sign
    (its sign is that of rounding noise, which differs between machines), and a space in
    its place keeps columns aligned."""
    text = f"{float(x):+.{digits}f}"
    return " " + text[1:] if float(text) == 0 else text


def _vector(vec, digits=3) -> str:
    return "[" + ", ".join(_signed(x, digits) for x in vec) + "]"


def limits_text(check) -> str:
    """One line on whether a component meets the joint-limit box (a :class:`LimitCheck`)."""
    if check.meets is True:
        where = ", ".join(f"{k}={_signed(v, 4).strip()}" for k, v in check.sample.items())
        return f"within the joint limits: yes ({check.how}), e.g. at {where}"
    if check.meets is False:
        return f"within the joint limits: no ({check.how}: {check.reason})"
    return f"within the joint limits: not decided ({check.reason})"


def locus_text(locus, *, row_labels=(), within_limits=()) -> str:
    """A human-readable summary of a locus.

    ``within_limits`` holds a :class:`~rankloci.limits.LimitCheck` per component
    (:func:`rankloci.limits.within_limits`); each adds a line to its component.
    """
    rows, cols = locus.shape
    lines = [f"{locus.model}: {rows}x{cols} matrix, method {locus.method}, "
             f"{locus.seconds:.2f} s"]
    if locus.degenerate:
        lines.append("the matrix is rank deficient at every configuration (degenerate design)")
    main = list(locus.components)
    special = list(locus.special)
    lines.append(f"{len(main)} component{'' if len(main) == 1 else 's'} of the "
                 "rank-deficiency locus:")
    checks = dict((ch.component, ch) for ch in within_limits)
    for i, c in enumerate(main, 1):
        lines.extend(_component_lines(i, c, row_labels))
        if i in checks:
            lines.append("     " + limits_text(checks[i]))
        if c.kind:
            lines.append(f"     kind: {_kind_text(c)}")
    if special:
        lines.append("")
        lines.append("only for special parameter values (not this model's):")
        for i, c in enumerate(special, 1):
            lines.extend(_component_lines(i, c, row_labels))
    cert = locus.certificate
    if cert is not None:
        if cert.verdict == "passed":
            lines.append(f"certified complete and sound: {cert.kind}, prime {cert.prime}, "
                         f"{_witness_text(cert)}; error probability below "
                         f"{cert.error_bound:.0e}")
            for part in getattr(cert, "real_parts", ()):
                lines.append(f"  real points of the complex component "
                             f"{part['complex_component']} = 0: where "
                             f"{', '.join(part['sum_of_squares'])} vanish (it is a weighted "
                             f"sum of their squares), {part['real_points']} point"
                             f"{'s' * (part['real_points'] != 1)}, on component"
                             f"{'s' * (len(part['components']) != 1)} "
                             f"{', '.join(map(str, part['components']))}")
        else:
            lines.append(f"certificate {cert.verdict}: " + "; ".join(cert.findings[:3]))
    for note in locus.notes:
        lines.append(f"note: {note}")
    if locus.base is not None:
        kinds = [c.kind for c in main]
        lines.append("")
        lines.append("classification: " + ", ".join(f"{kinds.count(k)} {k}" for k in
                                                      ("kinematic", "algorithmic", "mixed")))
        lines.append("")
        lines.append("locus of J without the constraint rows (the arm's own singularities):")
        base_rows = tuple(row_labels[:locus.base.shape[0]]) if row_labels else ()
        lines.extend("  " + line for line in locus_text(locus.base, row_labels=base_rows).splitlines())
    return "\n".join(lines)


def _witness_text(cert) -> str:
    counts = ", ".join(f"{n} in codimension {c}" for c, n in sorted(cert.witness_points.items()))
    return f"witness points {counts}" if counts else "no witness points"


def _kind_text(c) -> str:
    if c.kind == "kinematic":
        return "kinematic (inside the locus of J: the arm itself is singular here)"
    if c.kind == "algorithmic":
        return "algorithmic (J has full rank on the whole component: the constraints cause it)"
    nums = [str(m["base_component"]) for m in c.meets]
    which = f"component {nums[0]}" if len(nums) == 1 else f"components {', '.join(nums)}"
    return f"mixed (J has full rank at its generic points; it meets {which} of J's locus, below)"


def _component_lines(i, c, row_labels):
    eqs = ",  ".join(f"{sp.sstr(e)} = 0" for e in c.equations) or "(no equation)"
    out = [f"{i:>3}. {eqs}"]
    if c.solved:
        out.append(f"     solved: {solved_text(c)}")
    free = " ".join(map(str, c.free)) or "none"
    out.append(f"     dimension {c.dimension}, rank drop {c.rank_drop}, free: {free}")
    if c.parameter_conditions:
        out.append("     parameters: " + ", ".join(f"{sp.sstr(e)} = 0" for e in c.parameter_conditions))
    if c.excluding:
        out.append("     closure of the part where: " + ",  ".join(f"{sp.sstr(e)} != 0" for e in c.excluding))
    for vec in c.direction:
        out.append("     lost direction: (" + ", ".join(sp.sstr(x) for x in vec) + ")")
    for vec in c.direction_at_sample:
        lab = f" over ({', '.join(row_labels)})" if row_labels and len(row_labels) == len(vec) else ""
        out.append(f"     at the sample point: {_vector(vec)}{lab}")
    sample = ", ".join(f"{k}={_signed(v, 4).strip()}" for k, v in c.sample.items())
    out.append(f"     sample point: {sample}")
    return out


def locus_json(locus, *, within_limits=(), **extra) -> str:
    """The locus as JSON (:meth:`Locus.to_dict`), with ``extra`` top-level entries.

    Each :class:`~rankloci.limits.LimitCheck` of ``within_limits`` becomes the
    ``"within_limits"`` entry of its component (``meets``, ``sample``, ``how``,
    ``reason``).  For a URDF chain, ``"joint_names"`` maps each variable to
    its URDF joint (:attr:`Locus.joint_names`).
    """
    data = locus.to_dict()
    for check in within_limits:
        data["components"][check.component - 1]["within_limits"] = check.to_dict()
    if locus.joint_names:
        data["joint_names"] = {str(v): j for v, j in zip(locus.variables, locus.joint_names)}
    data.update(extra)
    return json.dumps(data, indent=2)


def locus_latex(locus) -> str:
    """The components as an amsmath ``align*`` block per component."""
    out = [f"% rank-deficiency locus of {locus.model} ({locus.shape[0]}x{locus.shape[1]}), "
           f"method {locus.method}"]
    for i, c in enumerate(locus.all_components, 1):
        tag = " (special parameters)" if not c.for_model else ""
        tag += f", {c.kind}" if c.kind else ""
        out.append(f"% component {i}: dimension {c.dimension}, rank drop {c.rank_drop}{tag}")
        out.append(r"\begin{align*}")
        eqs = [sp.latex(e) + " &= 0" for e in c.equations]
        eqs += [sp.latex(e) + r" &\neq 0" for e in c.excluding]
        out.append(" \\\\\n".join(eqs))
        out.append(r"\end{align*}")
    return "\n".join(out)


def _node_label(data) -> str:
    bits = [data.get("condition", "")]
    if "columns" in data:
        bits.append(f"cols {data['columns']}")
    if "k" in data:
        bits.append(f"k={data['k']}")
    if "shape" in data:
        bits.append(data["shape"])
    bits.append(f"[{data.get('outcome', '')}]")
    return "  ".join(b for b in bits if b)


def tree_text(tree) -> str:
    import networkx as nx

    lines = []
    labelled = nx.relabel_nodes(tree, {n: f"{n}: {_node_label(d)}" for n, d in tree.nodes(data=True)})
    nx.write_network_text(labelled, path=lines.append, ascii_only=False)
    return "\n".join(line.rstrip("\n") for line in lines)


def tree_dot(tree) -> str:
    def esc(s):
        return s.replace("\\", "\\\\").replace('"', '\\"')

    out = ["digraph branch_tree {", '  node [shape=box, fontname="Helvetica"];']
    for n, d in tree.nodes(data=True):
        out.append(f'  n{n} [label="{esc(_node_label(d))}"];')
    for a, b in tree.edges():
        out.append(f"  n{a} -> n{b};")
    out.append("}")
    return "\n".join(out)


def tree_json(tree) -> str:
    import networkx as nx

    return json.dumps(nx.node_link_data(tree, edges="edges"), indent=2, default=str)
