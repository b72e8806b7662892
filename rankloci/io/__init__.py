"""Reading models: TOML robot and matrix files, URDF, and the built-in models.

``parse_*`` functions take text and are pure; ``read_*`` functions read a
file and call them.  :func:`load_model` resolves what a user typed on the
command line: a path to a ``.toml`` or ``.urdf`` file, or the name of a
built-in model.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import ModelError

__all__ = ["models_dir", "builtin_models", "load_model"]


def models_dir() -> Path:
    """Directory of the built-in model files.

    In a wheel they are installed as ``rankloci/_models``; in a source tree
    they are ``kinematics_models/`` beside the package.
    """
    pkg = Path(__file__).resolve().parent.parent
    installed = pkg / "_models"
    return installed if installed.is_dir() else pkg.parent / "kinematics_models"


def builtin_models() -> list[str]:
    """Names of the built-in models, sorted."""
    d = models_dir()
    return sorted(p.stem for p in d.glob("*.toml")) if d.is_dir() else []


def load_model(spec: str, *, base_link: str | None = None, tip: str | None = None,
               tip_link: str | None = None):
    """Model from a file path (``.toml`` or ``.urdf``) or a built-in model name.

    ``base_link`` and ``tip`` choose the chain of a URDF file
    (:func:`~rankloci.io.urdf.parse_urdf`); ``tip_link`` is the deprecated
    old name of ``tip``.
    """
    from ..renamed import renamed_argument
    from .toml_model import read_model

    tip = renamed_argument(tip, tip_link, new="tip", old="tip_link", where="load_model")

    path = Path(spec)
    try:
        exists, is_file = path.exists(), path.is_file()
    except OSError as e:          # a name longer than the file system takes
        raise ModelError(f"cannot read: {e.strerror}", file=str(spec)[:80]) from None
    if path.suffix.lower() in (".toml", ".urdf") or exists:
        if not is_file:
            raise ModelError("no such file", file=str(spec))
        if path.suffix.lower() == ".urdf":
            from .urdf import read_urdf
            return read_urdf(path, base_link=base_link, tip=tip)
        if path.suffix.lower() != ".toml":
            raise ModelError("unknown file type (expected .toml or .urdf)", file=path.name)
        return read_model(path)
    names = builtin_models()
    if spec not in names:
        raise ModelError(f"no built-in model or file {spec!r}; built-in models: {', '.join(names)}")
    return read_model(models_dir() / f"{spec}.toml", require_source=True)
