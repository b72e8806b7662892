"""The summary renderers: pure functions of the case records, in case order."""

from __future__ import annotations

import csv
import io

from rankloci.sweep.summary import COLUMNS, render_csv, render_figure, render_markdown

PNG = b"\x89PNG\r\n\x1a\n"


def _record(l1, l2, status="done", components=1, seconds=1.0):
    return {"case": f"arm l1={l1} l2={l2}", "model": "arm", "joints": 2, "matrix": "2x2",
            "status": status, "components": components if status == "done" else None,
            "special": 0, "kinds": "", "check": "pass" if status == "done" else "",
            "seconds": seconds, "note": "" if status == "done" else "over 5 s",
            "parameters": {"l1": l1, "l2": l2}, "augment": []}


GRID = [_record(a, b, components=1 + (a == b)) for a in ("0.5", "1") for b in ("0.5", "1")]


def test_csv_has_one_row_per_case_in_order_and_quotes_commas():
    recs = GRID + [dict(_record("2", "2"), case="arm + sum(q1, q2)")]
    rows = list(csv.DictReader(io.StringIO(render_csv(recs))))
    assert tuple(rows[0]) == COLUMNS
    assert [r["case"] for r in rows] == [r["case"] for r in recs]
    assert [r["components"] for r in rows] == ["2", "1", "1", "2", "1"]


def test_only_the_seconds_column_depends_on_the_timings():
    slow = [dict(r, seconds=r["seconds"] * 7) for r in GRID]
    a = render_markdown(GRID, title="t.toml", settings="s.")
    b = render_markdown(slow, title="t.toml", settings="s.")
    diff = [(x, y) for x, y in zip(a.splitlines(), b.splitlines()) if x != y]
    assert len(diff) == 4 and all(x.replace("1.00", "7.00") == y for x, y in diff)


def test_markdown_counts_the_statuses_and_lists_files_without_cases():
    recs = GRID[:3] + [_record("1", "1", status="timeout")]
    md = render_markdown(recs, title="t.toml", settings="s.", skipped=["y.urdf: no chain"])
    assert "4 cases: 3 done (0 failing the self-check), 1 out of time, 0 out of memory" in md
    assert "- y.urdf: no chain" in md


def test_a_two_parameter_grid_gives_the_components_figure_else_time_against_joints():
    name, caption, png = render_figure(GRID)
    assert name == "components.png" and png.startswith(PNG) and "two-parameter grid" in caption
    assert render_figure(GRID) == (name, caption, png)          # the same records, same bytes
    one = [dict(r, parameters={"l1": r["parameters"]["l1"]}) for r in GRID[:2]]
    name, _, png = render_figure(one)
    assert name == "time.png" and png.startswith(PNG)
    assert render_figure([]) is None
