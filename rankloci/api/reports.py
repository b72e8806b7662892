"""``rankloci report`` as a function: a report on a model, built and optionally written.

It sits above the renderers of :mod:`rankloci.reporting`, which take their loci
from :mod:`rankloci.api.calls`.
"""

from __future__ import annotations

import time

from ..tolerances import RANK_RTOL
from .arguments import check_arguments, check_rank_rtol, check_samples
from .calls import load_model
from .progress import log_progress

__all__ = ["report", "require_matplotlib"]


def report(model, directory=None, *, formats=("md", "tex", "pdf"), seed=0, samples=10,
           numeric=False, timeout=None, tip=None, base_link=None, fragment=False, timings=True,
           jobs=None, rank_rtol=RANK_RTOL):
    """Build a report on a model and, given a directory, write it (``rankloci report``).

    Needs matplotlib (the ``report`` extra).

    Parameters
    ----------
    model
        Anything :func:`load_model` accepts.
    directory : path, optional
        Where to write it; without it nothing is written.
    formats : str or sequence of {"md", "tex", "pdf", "html"}
        What to write, as ``rankloci report --format md,tex,pdf``; the default,
        md, tex and pdf, is the command's.  The PDF needs ``latexmk`` or
        ``pdflatex`` on the PATH: without either it is skipped with a warning on
        the ``rankloci`` logger, as the command skips it with a note.  ``"html"``
        is one self-contained page with an interactive view of the arm.  A
        string may be one format or a comma list (``"md,tex"``).
    seed, samples, numeric, timeout
        As for the command line.
    tip, base_link
        See :func:`load_model`.
    fragment : bool
        The LaTeX without a preamble, to ``\\input`` into a paper (``--fragment``).
    timings : bool
        Include the timing table (``--no-timings`` leaves it out).
    jobs : int, optional
        Processes for the locus computation (see :func:`locus`); default every core.
    rank_rtol : float
        Rank threshold of the locus's self-check and of the numeric cross-check (see
        :func:`check`).

    Returns
    -------
    (Report, list of pathlib.Path)
        The report's content and the files written.
    """
    import shutil

    require_matplotlib("report")
    from ..parallel import check_jobs
    from ..reporting import FORMATS, build_report, read_model_notes, write_report

    check_arguments(seed=seed, numeric=numeric, timeout=timeout, tip=tip, base_link=base_link)
    check_samples(samples)
    rank_rtol = check_rank_rtol(rank_rtol)
    jobs = check_jobs(jobs)
    if isinstance(formats, str):
        formats = tuple(f.strip() for f in formats.split(",") if f.strip())
    try:
        formats = tuple(formats)
    except TypeError:
        formats = (formats,)
    bad = [f for f in formats if not isinstance(f, str) or f not in FORMATS] or (
        [] if formats else [""])
    if bad:
        from ..errors import ArgumentError

        raise ArgumentError(f"formats=: {bad[0]!r} is not one of {FORMATS}", argument="formats",
                            value=formats)
    m = load_model(model, tip=tip, base_link=base_link)
    built = build_report(m, seed=seed, samples=samples, numeric=numeric, timeout=timeout,
                         clock=time.perf_counter, progress=log_progress, dot=shutil.which("dot"),
                         model_notes=read_model_notes(m), jobs=jobs, rank_rtol=rank_rtol)
    if directory is None:
        return built, []
    latex = next(((kind, exe) for kind in ("latexmk", "pdflatex")
                  if (exe := shutil.which(kind))), None) if "pdf" in formats else None
    if "pdf" in formats and latex is None:
        import logging

        from .progress import LOGGER_NAME

        logging.getLogger(LOGGER_NAME).warning("PDF skipped: neither latexmk nor pdflatex is "
                                               "installed")
    return built, write_report(built, directory, formats=formats, latex=latex,
                               fragment=bool(fragment), timings=bool(timings))


def require_matplotlib(what: str) -> None:
    """Raise ImportError, saying what to install, when matplotlib is missing."""
    import importlib.util

    from ..extras import install_command

    if importlib.util.find_spec("matplotlib") is None:
        raise ImportError(f"the {what} needs matplotlib: {install_command('report')}")
