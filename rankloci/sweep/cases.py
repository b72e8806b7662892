"""The cases of a sweep: every model of the spec at every point of its grid.

:func:`expand` reads the models a spec names (built-in names, TOML and URDF
files, directories, every chain of a URDF file) and crosses each with its
grid.  The order is the spec's: entries in order, the files of a directory
sorted, the chains of a URDF file in the depth-first order of
:func:`rankloci.io.urdf_chains.urdf_chains`, then the parameter grid
(the first parameter varying slowest) and the constraint options.  Every case
carries the text of its model file (by content hash, in ``sources``), so a
worker on another machine needs rankloci but not the files.

Each case has

- an ``id``: a file-name-safe label plus a hash of what the case *is* (model
  text, chain, parameter values, constraint rows); its locus file is
  ``cases/ID.json``;
- a ``hash`` of everything that determines its result (the ``id`` plus
  task, method, parameter substitution, seed and self-check): a finished case
  whose file carries the same hash is not computed again.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import re
from dataclasses import dataclass
from pathlib import Path

import sympy as sp

from .spec import MAX_CASES, SpecError, SweepSpec

__all__ = ["Case", "expand", "expected_cost"]


@dataclass(frozen=True)
class Case:
    """One locus computation of a sweep.

    Attributes
    ----------
    id, label : str
        File stem of its locus file; what the summary calls it.
    model : str
        The model: a built-in name, a file (relative to its directory entry), or a
        URDF chain ``FILE:BASE->TIP``.
    kind : str
        ``"toml"`` or ``"urdf"``: how the source text is parsed.
    source : str
        Content hash of the model text (a key of the ``sources`` of :func:`expand`).
    file : str
        The model file's name (for the model's name and error messages).
    joints : int or None
        Movable joints (None when the model could not be read).
    parameters : tuple of (str, str, sympy.Expr)
        Name, label and exact value of each swept parameter.
    augment : tuple of str
        The extra constraint rows.
    problem : str
        Why the case cannot run (a file of a directory that does not read); else "".
    """

    id: str
    label: str
    model: str
    kind: str
    source: str
    file: str
    joints: int | None
    base_link: str | None = None
    tip: str | None = None
    parameters: tuple = ()
    augment: tuple = ()
    task: object = None
    method: str | None = None
    numeric: bool = True
    seed: int = 0
    verify: bool = True
    problem: str = ""
    hash: str = ""

    @property
    def parameter_values(self) -> dict:
        """``{name: exact value}`` of the swept parameters."""
        return {name: value for name, _, value in self.parameters}


def _digest(data) -> str:
    return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()


def _slug(text: str) -> str:
    slug = re.sub(r"[^A-Za-z0-9_.=+-]+", "_", text).strip("_.")
    return slug[:80] or "case"


def _read_text(path: Path, where: str, file: str) -> str:
    from ..io import toml_model, urdf
    from ..io.files import read_bounded

    limit = (urdf.MAX_FILE_BYTES if path.suffix.lower() == ".urdf"
             else toml_model.MAX_FILE_BYTES)
    try:
        data = read_bounded(path, limit)
    except OSError as e:
        raise SpecError(f"{where}: cannot read {path.name}: {e.strerror}", file=file) from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise SpecError(f"{where}: {path.name} is not UTF-8 text", file=file) from None


class _Models:
    """The (model, text) pairs of one spec entry, read once."""

    def __init__(self, spec: SweepSpec):
        self.spec = spec
        self.sources: dict[str, str] = {}
        self.skipped: list[str] = []

    def add_source(self, text: str) -> str:
        key = hashlib.sha256(text.encode()).hexdigest()
        self.sources[key] = text
        return key

    def of_entry(self, entry):
        """``(display name, kind, source key, file, joints, base, tip, parsed model, problem)``."""
        from ..errors import RanklociError
        from ..io import builtin_models, models_dir
        from ..io.toml_model import parse_model

        file = self.spec.file
        if entry.name is not None:
            if entry.name not in builtin_models():
                raise SpecError(f"{entry.where}: no built-in model {entry.name!r} (built-in "
                                f"models: {', '.join(builtin_models())})", file=file)
            text = _read_text(models_dir() / f"{entry.name}.toml", entry.where, file)
            model = parse_model(text, file=f"{entry.name}.toml")
            yield (entry.name, "toml", self.add_source(text), f"{entry.name}.toml",
                   model.dof if hasattr(model, "dof") else len(model.variables), None, None,
                   model, "")
            return
        if entry.path.is_dir():
            try:
                files = sorted(p for p in entry.path.glob(entry.pattern)
                               if p.is_file() and p.suffix.lower() in (".toml", ".urdf"))
            except (ValueError, NotImplementedError) as e:
                raise SpecError(f"{entry.where}.pattern: {entry.pattern[:60]!r}: {e}",
                                file=file) from None
            if not files:
                raise SpecError(f"{entry.where}: no .toml or .urdf file matches "
                                f"{entry.pattern!r} in {entry.path.name}", file=file)
            for p in files:
                rel = p.relative_to(entry.path).as_posix()
                try:
                    yield from self._of_file(entry, p, rel)
                except RanklociError as e:      # one file of a collection: a failed case
                    yield (rel, p.suffix.lower()[1:], "", p.name, None, None, None, None,
                           " ".join(str(e).split()))
            return
        try:
            yield from self._of_file(entry, entry.path, entry.path.name)
        except SpecError:
            raise
        except RanklociError as e:
            raise SpecError(f"{entry.where}: {' '.join(str(e).split())}", file=file) from None

    def _of_file(self, entry, path: Path, rel: str):
        from ..io.toml_model import parse_model
        from ..io.urdf_chains import urdf_chains

        text = _read_text(path, entry.where, self.spec.file)
        key = self.add_source(text)
        if path.suffix.lower() == ".toml":
            model = parse_model(text, file=path.name)
            joints = model.dof if hasattr(model, "dof") else len(model.variables)
            yield rel, "toml", key, path.name, joints, None, None, model, ""
            return
        if not entry.chains:
            from ..io.urdf import parse_urdf

            model = parse_urdf(text, name=path.stem, file=path.name, base_link=entry.base_link,
                               tip=entry.tip)
            name = rel if entry.base_link is None and entry.tip is None else (
                f"{rel}:{entry.base_link or 'root'}->{entry.tip or 'leaf'}")
            yield name, "urdf", key, path.name, model.dof, entry.base_link, entry.tip, model, ""
            return
        chains, _ = urdf_chains(text, file=path.name, min_joints=entry.min_joints,
                                max_joints=entry.max_joints)
        if not chains:
            bounds = (f"{entry.min_joints} or more" if entry.max_joints is None
                      else f"{entry.min_joints} to {entry.max_joints}")
            self.skipped.append(f"{rel}: no chain with {bounds} movable joints")
        for c in chains:
            yield f"{rel}:{c.base}->{c.tip}", "urdf", key, path.name, c.n, c.base, c.tip, None, ""


def _check_grid(entry, model, name, file):
    """Every swept parameter is one of the model's; the constraint rows parse."""
    from ..augmented import parse_augment
    from ..errors import RanklociError

    if model is None:
        return
    have = {p.name for p in model.parameters}
    for pname, _ in entry.grid.parameters:
        if pname not in have:
            raise SpecError(f"{entry.where}: {name} has no parameter {pname!r} (its parameters: "
                            f"{', '.join(sorted(have)) or 'none'})", file=file)
    for option in entry.grid.augment:
        try:
            parse_augment(model, option)
        except RanklociError as e:
            raise SpecError(f"{entry.where}: {name}: constraint {', '.join(option)!r}: "
                            f"{' '.join(str(e).split())}", file=file) from None


def expand(spec: SweepSpec) -> tuple[list[Case], dict[str, str], list[str]]:
    """The cases of ``spec`` in order, the model texts by content hash, and the files skipped.

    A URDF file whose chains all fall outside the joint-count bounds gives no case; the
    third item says which files and why.

    Raises
    ------
    SpecError
        A model that does not exist or does not read (named explicitly), a
        swept parameter a model does not have, a constraint that does not parse,
        or more than :data:`~rankloci.sweep.spec.MAX_CASES` cases.  A file found
        in a directory that does not read becomes a case with a ``problem``.

    Examples
    --------
    >>> from rankloci.sweep.spec import parse_spec
    >>> spec = parse_spec('models = ["planar2r"]\\n[grid]\\naugment = ["", "q1"]\\n'
    ...                   '[grid.parameters]\\nl1 = [1, 2]\\n')
    >>> [c.label for c in expand(spec)[0]]
    ['planar2r l1=1', 'planar2r l1=1 + q1', 'planar2r l1=2', 'planar2r l1=2 + q1']
    """
    models = _Models(spec)
    cases: list[Case] = []
    seen: set[str] = set()
    for entry in spec.entries:
        task = entry.task if entry.task is not None else spec.task
        grid = entry.grid
        if len(cases) + grid.size > MAX_CASES:
            raise SpecError(f"{entry.where}: the sweep has more than {MAX_CASES} cases",
                            file=spec.file)
        for name, kind, source, file, joints, base, tip, model, problem in models.of_entry(entry):
            _check_grid(entry, model, name, spec.file)
            axes = [[(pname, text, value) for text, value in values]
                    for pname, values in grid.parameters]
            for point in itertools.product(*axes):
                for option in grid.augment:
                    label = " ".join([name] + [f"{p}={t}" for p, t, _ in point])
                    if option:
                        label += " + " + ", ".join(option)
                    identity = {"source": source, "kind": kind, "file": file, "base": base,
                                "tip": tip, "model": name,
                                "parameters": [[p, sp.srepr(v)] for p, _, v in point],
                                "augment": list(option)}
                    ident = _digest(identity)
                    cid = f"{_slug(label)}-{ident[:10]}"
                    if cid in seen and problem:   # a file two entries share that does not read
                        continue
                    if cid in seen:
                        raise SpecError(f"{entry.where}: case {label!r} is listed twice",
                                        file=spec.file)
                    seen.add(cid)
                    settings = {"task": task, "method": spec.method, "numeric": spec.numeric,
                                "seed": spec.seed, "verify": spec.verify}
                    cases.append(Case(
                        id=cid, label=label, model=name, kind=kind, source=source, file=file,
                        joints=joints, base_link=base, tip=tip, parameters=tuple(point),
                        augment=option, task=task, method=spec.method, numeric=spec.numeric,
                        seed=spec.seed, verify=spec.verify, problem=problem,
                        hash=_digest({"identity": ident, **settings})))
                    if len(cases) > MAX_CASES:
                        raise SpecError(f"the sweep has more than {MAX_CASES} cases",
                                        file=spec.file)
    return cases, models.sources, models.skipped


def expected_cost(case: Case) -> tuple:
    """A key that orders cases by their expected time: the largest runs longest.

    The time of a locus grows fastest with the joints (the variables of J), then with
    the constraint rows, then with the parameters left symbolic.  A sweep starts its
    cases in the decreasing order of this key, so that its longest cases do not start
    last and hold up its end.

    Examples
    --------
    >>> from rankloci.sweep.spec import parse_spec
    >>> spec = parse_spec('models = ["planar2r", "puma560", "planar3r"]\\n')
    >>> [c.label for c in sorted(expand(spec)[0], key=expected_cost, reverse=True)]
    ['puma560', 'planar3r', 'planar2r']
    """
    symbolic = 0 if case.numeric else len(case.parameters)
    return (case.joints or 0, len(case.augment), symbolic)
