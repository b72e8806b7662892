"""The package's import graph: no cycles, no import from a higher layer, no private names.

Every ``import`` of a ``rankloci`` module counts, at the top of a module or
inside a function alike (an import deferred for speed is still a dependency);
only the imports under ``if TYPE_CHECKING:``, which never run, do not.
"""

from __future__ import annotations

import ast
from pathlib import Path

import networkx as nx
import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "rankloci"

#: The layers, lowest first.  A module imports only from its own layer or a lower one.  A
#: module belongs to the layer of the longest prefix of its dotted name listed here.
LAYERS = (
    # what any module may use: errors, tolerances, the version, what an optional part needs
    ("rankloci.errors", "rankloci.tolerances", "rankloci.version", "rankloci.extras",
     "rankloci.renamed", "rankloci.parallel"),
    # exact and numeric building blocks, on no model and no locus
    ("rankloci.expr", "rankloci.algebra", "rankloci.process_limits",
     "rankloci.exact.certificate"),
    # models and their matrices, read from files or built by adapters; numerics on them
    ("rankloci.model", "rankloci.io", "rankloci.kinematics", "rankloci.jacobians",
     "rankloci.adapters", "rankloci.limits", "rankloci.numeric", "rankloci.geometry"),
    # the result types
    ("rankloci.loci",),
    # the engine: the branch tree, then the methods that grow it
    ("rankloci.tree",),
    ("rankloci.methods",),
    # checks of a locus, and what a robot does near it
    ("rankloci.exact", "rankloci.certify", "rankloci.verify", "rankloci.augmented",
     "rankloci.directions", "rankloci.numeric.crosscheck", "rankloci.near", "rankloci.compare"),
    # the one pipeline from a model to a certified locus, stage by stage
    ("rankloci.pipeline",),
    # the library's calls: the pipeline's entry points, and what the near-the-locus functions
    # add to it
    ("rankloci.api.arguments", "rankloci.api.deadline", "rankloci.api.models",
     "rankloci.api.progress", "rankloci.api.results", "rankloci.api.symbols",
     "rankloci.api.calls", "rankloci.api.near", "rankloci.api.geometry",
     "rankloci.api.near_study"),
    # renderers of what the calls return
    ("rankloci.render_text", "rankloci.reporting", "rankloci.near.figures"),
    # the library's interface (the report call included), then the command line and sweeps
    ("rankloci.api",),
    ("rankloci.sweep",),
    ("rankloci.cli",),
    ("rankloci",),
)


def _modules() -> dict[str, tuple[Path, bool]]:
    """Dotted name -> (file, is a package's ``__init__``)."""
    out = {}
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        is_package = parts[-1] == "__init__"
        if is_package:
            parts.pop()
        out[".".join(parts)] = (path, is_package)
    return out


def _type_checking_nodes(tree) -> set[int]:
    """ids of the nodes under ``if TYPE_CHECKING:``."""
    skipped = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for child in node.body:
                skipped.update(id(n) for n in ast.walk(child))
    return skipped


def _imports():
    """(importer, imported module, name or None, line) for every import of a rankloci module."""
    modules = _modules()

    def existing(name):
        while name not in modules:
            name = name.rpartition(".")[0]
        return name

    for module, (path, is_package) in sorted(modules.items()):
        tree = ast.parse(path.read_text(), filename=str(path))
        skipped = _type_checking_nodes(tree)
        for node in ast.walk(tree):
            if id(node) in skipped:
                continue
            if isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name.split(".")[0] == "rankloci":
                        yield module, existing(alias.name), None, node.lineno
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = module.split(".")[: None if is_package else -1]
                    base = base[: len(base) - node.level + 1]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                if target.split(".")[0] != "rankloci":
                    continue
                for alias in node.names:
                    full = f"{target}.{alias.name}"
                    if full in modules:
                        yield module, full, None, node.lineno
                    else:
                        yield module, existing(target), alias.name, node.lineno


def _layer(module: str) -> int:
    best, layer = -1, None
    for i, names in enumerate(LAYERS):
        for name in names:
            if (module == name or module.startswith(name + ".")) and len(name) > best:
                best, layer = len(name), i
    assert layer is not None, f"{module} is in no layer: add it to LAYERS"
    return layer


@pytest.fixture(scope="module")
def imports():
    return list(_imports())


def test_the_walk_sees_the_package(imports):
    importers = {m for m, *_ in imports}
    assert len(_modules()) > 100
    assert {"rankloci.api.calls", "rankloci.tree.context", "rankloci.cli.commands"} <= importers
    assert ("rankloci.methods.singular_vector", "rankloci.tree.blocks") in {
        (m, t) for m, t, *_ in imports}


def test_no_import_cycles(imports):
    graph = nx.DiGraph((m, t) for m, t, *_ in imports if m != t)
    cycles = [sorted(c) for c in nx.strongly_connected_components(graph) if len(c) > 1]
    assert not cycles, f"modules that import each other in a loop: {cycles}"


def test_every_module_has_a_layer_and_every_layer_names_modules():
    modules = _modules()
    for module in modules:
        _layer(module)
    stale = [name for names in LAYERS for name in names if name not in modules]
    assert not stale, f"LAYERS names modules that do not exist: {stale}"


def test_no_import_from_a_higher_layer(imports):
    upward = [f"{m}:{line} imports {t} (layer {_layer(t)} above {_layer(m)})"
              for m, t, _, line in imports if _layer(t) > _layer(m)]
    assert not upward, "\n".join(upward)


def test_no_private_name_imported_from_another_module(imports):
    private = [f"{m}:{line} imports {name} from {t}" for m, t, name, line in imports
               if name and name.startswith("_") and not name.startswith("__") and t != m]
    assert not private, "\n".join(private)


def test_every_exception_class_is_a_rankloci_error():
    """Each exception class of the package derives from RanklociError, but the bug report of a
    child process (ChildFailed), which must not pass for bad input."""
    import importlib

    from rankloci.errors import RanklociError

    outside = []
    for module, (path, _) in sorted(_modules().items()):
        tree = ast.parse(path.read_text())
        names = [n.name for n in tree.body if isinstance(n, ast.ClassDef)
                 and any(ast.unparse(b).endswith(("Exception", "Error")) for b in n.bases)]
        if not names:
            continue
        loaded = importlib.import_module(module)
        outside += [f"{module}.{name}" for name in names
                    if not issubclass(getattr(loaded, name), RanklociError)]
    assert outside == ["rankloci.process_limits.ChildFailed"]


def test_the_state_of_a_locus_computation_changes_only_in_its_own_module():
    """Context (tree/context.py) owns its state: no other module assigns to an attribute of a
    ``ctx`` or changes one in place (its methods note, add_exclusions, ... do)."""
    mutators = {"append", "extend", "add", "update", "pop", "clear", "setdefault", "remove",
                "discard", "insert"}
    found = []
    for module, (path, _) in sorted(_modules().items()):
        if module == "rankloci.tree.context":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            targets = []
            if isinstance(node, (ast.Assign, ast.AugAssign, ast.AnnAssign, ast.Delete)):
                targets = getattr(node, "targets", None) or [node.target]
            elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                  and node.func.attr in mutators):
                targets = [node.func.value]
            for target in targets:
                while isinstance(target, ast.Subscript):
                    target = target.value
                if isinstance(target, ast.Attribute):
                    base = target.value
                    while isinstance(base, (ast.Attribute, ast.Subscript)):
                        base = base.value
                    if isinstance(base, ast.Name) and base.id == "ctx":
                        found.append(f"{module}:{node.lineno} {ast.unparse(target)}")
    assert not found, "\n".join(found)
