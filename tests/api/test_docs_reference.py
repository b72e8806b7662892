"""The documentation covers the public API, and the quickstart notebook runs outside Jupyter."""

import ast
import builtins
import importlib
import json
import re
from pathlib import Path

import pytest

import rankloci

DOCS = Path(__file__).parents[2] / "docs"

# ".. autofunction:: rankloci.api.locus" (reST) and "```{autofunction} rankloci.api.locus" (MyST)
_DIRECTIVE = re.compile(r"^(?:\.\. |```\{)(?:auto)?(?:function|class|exception|data)(?:::|\})"
                        r"[ \t]*(rankloci(?:\.\w+)+)", re.M)


def documented_targets(docs: Path = DOCS) -> set[str]:
    """The dotted names that a directive of docs/*.rst or docs/*.md documents."""
    texts = [p.read_text() for p in sorted(docs.glob("*.rst")) + sorted(docs.glob("*.md"))]
    return {m.group(1) for text in texts for m in _DIRECTIVE.finditer(text)}


def _resolve(dotted: str):
    """The object a dotted name refers to: the longest importable module, then attributes."""
    parts = dotted.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        for attr in parts[k:]:
            obj = getattr(obj, attr)
        return obj
    raise ImportError(dotted)


def test_the_directive_pattern_reads_both_markups(tmp_path):
    (tmp_path / "a.rst").write_text(".. autofunction:: rankloci.api.locus\n\n"
                                    ".. data:: rankloci.__version__\n")
    (tmp_path / "b.md").write_text("```{autoclass} rankloci.loci.Locus\n```\n")
    assert documented_targets(tmp_path) == {"rankloci.api.locus", "rankloci.__version__",
                                            "rankloci.loci.Locus"}


def test_every_public_name_is_in_the_api_reference():
    import inspect

    # rankloci.report wraps rankloci.api.report (its attributes are the figures' modules)
    documented = {id(inspect.unwrap(_resolve(t))) for t in documented_targets()}
    missing = [name for name in rankloci.__all__
               if id(inspect.unwrap(getattr(rankloci, name))) not in documented]
    assert missing == [], f"not documented in docs/: {missing}"


def test_every_documented_name_exists():
    for target in documented_targets():
        _resolve(target)   # raises AttributeError or ImportError for a stale name


def _names(tree: ast.AST) -> tuple[set[str], set[str]]:
    """(names bound anywhere, names read anywhere) in ``tree``, scopes ignored."""
    bound, read = set(), set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            (read if isinstance(node.ctx, ast.Load) else bound).add(node.id)
        elif isinstance(node, ast.alias):
            bound.add((node.asname or node.name).split(".")[0])
        elif isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            bound.add(node.name)
        elif isinstance(node, ast.arg):
            bound.add(node.arg)
    return bound, read


@pytest.mark.parametrize("notebook", sorted(DOCS.glob("*.ipynb")), ids=lambda p: p.name)
def test_notebook_uses_only_names_it_defines(notebook):
    """Run as a plain script (``jupyter nbconvert --to script``), a notebook has no IPython
    builtins such as ``display``: every name it reads must be imported or assigned in it."""
    cells = json.loads(notebook.read_text())["cells"]
    code = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")
    bound, read = _names(ast.parse(code))
    assert sorted(read - bound - set(dir(builtins))) == []


def test_the_limits_page_states_the_bounds_in_the_code():
    rows = re.findall(r"^\| [^|]+ \| (\d+) \| `(rankloci(?:\.\w+)+)` \|$",
                      (DOCS / "guide" / "limits.md").read_text(), re.M)
    assert len(rows) >= 10
    for value, constant in rows:
        assert _resolve(constant) == int(value), constant


@pytest.mark.slow
def test_the_quickstart_runs_as_a_script(tmp_path):
    """A new user's path: the quickstart's code cells, one after another in a plain Python
    process (no Jupyter), from a Robotics Toolbox robot to its locus and a figure."""
    import os
    import subprocess
    import sys

    cells = json.loads((DOCS / "quickstart.ipynb").read_text())["cells"]
    script = tmp_path / "quickstart.py"
    script.write_text("\n\n".join("".join(c["source"]) for c in cells
                                  if c["cell_type"] == "code") + "\n")
    env = dict(os.environ, MPLBACKEND="Agg")
    run = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    assert "(2, 3, 3)" in run.stdout                      # J.evaluate at two configurations
    assert "[0.3, 0.5, 0.0] True" in run.stdout           # the stretched elbow is singular
