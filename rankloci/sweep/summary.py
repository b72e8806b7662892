"""The summary of a sweep: CSV, Markdown and a figure, from the case records.

The renderers are pure: they take the records in case order and return text
(or PNG bytes); :mod:`rankloci.cli.sweep` writes them.  Only the ``seconds``
column depends on the machine and the run: everything else is the same for
any number of workers and any order of completion.
"""

from __future__ import annotations

import csv
import io

__all__ = ["COLUMNS", "summary_rows", "render_csv", "render_markdown", "render_figure",
           "status_counts"]

#: Columns of summary.csv and summary.md, in order.
COLUMNS = ("case", "model", "joints", "matrix", "status", "components", "special", "kinds",
           "check", "seconds", "note")


def summary_rows(records) -> list[dict]:
    """One row per case record, with the :data:`COLUMNS` as keys (missing values empty)."""
    rows = []
    for r in records:
        row = {k: r.get(k) for k in COLUMNS}
        row["seconds"] = f"{r.get('seconds', 0.0):.2f}"
        rows.append({k: "" if v is None else v for k, v in row.items()})
    return rows


def status_counts(records) -> dict:
    """``{status: count}`` plus the number of failed self-checks under ``"check failed"``."""
    from .task import STATUSES

    out = {s: sum(r["status"] == s for r in records) for s in STATUSES}
    out["check failed"] = sum(r.get("check") == "fail" for r in records)
    return out


def render_csv(records) -> str:
    """summary.csv: a header line and one line per case.

    Examples
    --------
    >>> rec = {"case": "planar2r", "model": "planar2r", "joints": 2, "matrix": "2x2",
    ...        "status": "done", "components": 1, "special": 0, "kinds": "", "check": "pass",
    ...        "seconds": 0.5, "note": ""}
    >>> print(render_csv([rec]), end="")
    case,model,joints,matrix,status,components,special,kinds,check,seconds,note
    planar2r,planar2r,2,2x2,done,1,0,,pass,0.50,
    """
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(summary_rows(records))
    return out.getvalue()


def _cell(value) -> str:
    return str(value).replace("|", "\\|").replace("\n", " ")


def render_markdown(records, *, title: str, settings: str, figures=(), skipped=()) -> str:
    """summary.md: the counts, the settings of the sweep, the table and the figures.

    Parameters
    ----------
    records : list of dict
        The case records, in case order.
    title : str
        The sweep's name (the spec file's).
    settings : str
        One sentence on how the cases were computed (task, method, limits).
    figures : sequence of (str, str)
        ``(file name, caption)`` of the figures beside the summary.
    skipped : sequence of str
        Files of the spec that gave no case, with why.
    """
    counts = status_counts(records)
    n = len(records)
    lines = [f"# Sweep: {title}", "", settings, ""]
    lines.append(f"**{n} case{'' if n == 1 else 's'}: {counts['done']} done "
                 f"({counts['check failed']} failing the self-check), {counts['timeout']} out "
                 f"of time, {counts['memory']} out of memory, {counts['error']} "
                 f"error{'' if counts['error'] == 1 else 's'}.**")
    lines += ["", "'seconds' is the wall time of the case on its worker (the only column that "
                  "depends on the machine); 'components' counts those of the model's own locus, "
                  "'special' those that exist only for other parameter values.", ""]
    lines.append("| " + " | ".join(COLUMNS) + " |")
    lines.append("| " + " | ".join("---" for _ in COLUMNS) + " |")
    for row in summary_rows(records):
        lines.append("| " + " | ".join(_cell(row[k]) for k in COLUMNS) + " |")
    if skipped:
        lines += ["", "Files that give no case:", ""] + [f"- {_cell(s)}" for s in skipped]
    for name, caption in figures:
        lines += ["", f"![{caption}]({name})", "", caption]
    return "\n".join(lines) + "\n"


def _two_parameter_grids(records) -> list:
    """``(title, x name, y name, {(x, y): components})`` per model and constraint option swept
    over exactly two parameters with at least two values each."""
    groups: dict = {}
    for r in records:
        params = r.get("parameters") or {}
        if len(params) != 2:
            continue
        key = (r["model"], tuple(r.get("augment") or ()), tuple(params))
        groups.setdefault(key, []).append(r)
    out = []
    for (model, augment, names), rs in groups.items():
        xs = list(dict.fromkeys(r["parameters"][names[0]] for r in rs))
        ys = list(dict.fromkeys(r["parameters"][names[1]] for r in rs))
        if len(xs) < 2 or len(ys) < 2:
            continue
        cells = {(r["parameters"][names[0]], r["parameters"][names[1]]): r for r in rs}
        title = model + (f" + {', '.join(augment)}" if augment else "")
        out.append((title, names, xs, ys, cells))
    return out


def render_figure(records):
    """``(file name, caption, PNG bytes)`` of the sweep's figure, or None without cases.

    With a model swept over two parameters: the number of components over the
    grid, one panel per model and constraint option (at most 6), cells that did
    not finish marked.  Otherwise: the seconds of each case against its joints.
    """
    # a Figure of its own (no pyplot): the user's backend is left as it is
    from matplotlib.figure import Figure

    if not records:
        return None
    grids = _two_parameter_grids(records)[:6]
    if grids:
        fig = Figure(figsize=(4.2 * len(grids), 3.8))
        axes = fig.subplots(1, len(grids), squeeze=False)
        for ax, (title, names, xs, ys, cells) in zip(axes[0], grids):
            for i, x in enumerate(xs):
                for j, y in enumerate(ys):
                    r = cells.get((x, y))
                    if r is None:
                        continue
                    done = r["status"] == "done"
                    text = str(r["components"]) if done else {"timeout": "T", "memory": "M"}.get(
                        r["status"], "E")
                    ax.scatter([i], [j], s=520, c="#4c72b0" if done else "#dd8452",
                               alpha=0.35 + 0.1 * min(int(r["components"] or 0), 6))
                    ax.annotate(text, (i, j), ha="center", va="center", fontsize=9)
            ax.set_xticks(range(len(xs)), xs, rotation=45)
            ax.set_yticks(range(len(ys)), ys)
            ax.set_xlabel(names[0])
            ax.set_ylabel(names[1])
            ax.set_title(title, fontsize=9)
            ax.margins(0.15)
        caption = ("Number of components of the locus over the two-parameter grid "
                   "(T: out of time, M: out of memory, E: error).")
        name = "components.png"
    else:
        fig = Figure(figsize=(6, 4))
        ax = fig.subplots()
        for status, colour, marker in (("done", "#4c72b0", "o"), ("timeout", "#dd8452", "x"),
                                       ("memory", "#c44e52", "s"), ("error", "#8c8c8c", "^")):
            pts = [(r["joints"], r["seconds"]) for r in records
                   if r["status"] == status and r["joints"] is not None and r["seconds"] > 0]
            if pts:
                ax.scatter(*zip(*pts), c=colour, marker=marker, label=status, alpha=0.7)
        ax.set_xlabel("joints")
        ax.set_ylabel("seconds")
        ax.set_yscale("log")
        ax.legend()
        caption = "Seconds per case against the number of joints."
        name = "time.png"
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100, metadata={"Software": None})
    return name, caption, buf.getvalue()
