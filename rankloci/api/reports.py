"""``rankloci report`` as a function: a report on a model, built and optionally written.

It sits above the renderers of :mod:`rankloci.reporting`, which take their loci
from :mod:`rankloci.api.calls`.
"""

from __future__ import annotations

import time

from .arguments import check_arguments, check_samples
from .calls import load_model
from .progress import log_progress

__all__ = ["report", "require_matplotlib"]


def report(model, directory=None, *, formats=("md",), seed=0, samples=10, numeric=False,
           timeout=None, tip=None, base_link=None):
    """Build a report on a model and, given a directory, write it (``rankloci report``).

    Needs matplotlib (the ``report`` extra).

    Parameters
    ----------
    model
        Anything :func:`load_model` accepts.
    directory : path, optional
        Where to write it; without it nothing is written.
    formats : sequence of {"md", "tex", "pdf"}
        The PDF needs ``latexmk`` or ``pdflatex`` on the PATH.
    seed, samples, numeric, timeout
        As for the command line.
    tip, base_link
        See :func:`load_model`.

    Returns
    -------
    (Report, list of pathlib.Path)
        The report's content and the files written.
    """
    import shutil

    require_matplotlib("report")
    from ..reporting import FORMATS, build_report, read_model_notes, write_report

    check_arguments(seed=seed, numeric=numeric, timeout=timeout, tip=tip, base_link=base_link)
    check_samples(samples)
    if isinstance(formats, str):
        formats = (formats,)
    bad = [f for f in formats if f not in FORMATS]
    if bad:
        from ..errors import ArgumentError

        raise ArgumentError(f"formats=: {bad[0]!r} is not one of {FORMATS}", argument="formats",
                            value=formats)
    m = load_model(model, tip=tip, base_link=base_link)
    built = build_report(m, seed=seed, samples=samples, numeric=numeric, timeout=timeout,
                         clock=time.perf_counter, progress=log_progress, dot=shutil.which("dot"),
                         model_notes=read_model_notes(m))
    if directory is None:
        return built, []
    latex = next(((kind, exe) for kind in ("latexmk", "pdflatex")
                  if (exe := shutil.which(kind))), None) if "pdf" in formats else None
    return built, write_report(built, directory, formats=formats, latex=latex)


def require_matplotlib(what: str) -> None:
    """Raise ImportError, saying what to install, when matplotlib is missing."""
    import importlib.util

    from ..extras import install_command

    if importlib.util.find_spec("matplotlib") is None:
        raise ImportError(f"the {what} needs matplotlib: {install_command('report')}")
