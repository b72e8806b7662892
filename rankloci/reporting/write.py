"""Reports on disk: :func:`write_report` (Markdown, LaTeX, PDF, HTML and the PNG figures) and
:func:`read_model_notes`.

This is the only module of the report package that touches files; it runs
LaTeX, and the only other program the package runs is graphviz's ``dot``
(:func:`~rankloci.reporting.figures.tree_png`, on bytes in memory).
:func:`write_report` builds the whole report in a temporary directory beside
the target and then moves the files into place, so that a failure leaves
nothing half-written.  The LaTeX command is passed in (or None): nothing here
looks for programs.

Every file a report writes is named ``STEM.ext`` or ``STEM-what.png``, where
``STEM`` is :attr:`Report.name <rankloci.reporting.build.Report.name>` (ASCII
letters, digits, ``_`` and ``-``), and lies directly in the target
directory.  When a report is written again, the figures of the previous one
that it does not produce are removed: only files whose whole name is one a
report on the same ``STEM`` writes, so that reports on other models in the
same directory are left alone.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

from ..errors import RanklociError

__all__ = ["write_report", "report_workdir", "read_model_notes", "ReportError", "FORMATS"]

#: The formats :func:`write_report` writes (the PNG figures come with each; the HTML page
#: does not need them).
FORMATS = ("md", "tex", "pdf", "html")


class ReportError(RanklociError):
    """A report could not be written (LaTeX failed on it): not bad input, a failure."""


def read_model_notes(model) -> str:
    """The ``notes`` of the TOML file a model was read from ("" for other models)."""
    import tomllib

    path = str(getattr(model, "path", "") or "")
    if not path.endswith(".toml"):
        return ""
    try:
        with open(path, "rb") as fh:
            notes = tomllib.load(fh).get("notes", "")
    except (OSError, tomllib.TOMLDecodeError):
        return ""
    return " ".join(notes.split()) if isinstance(notes, str) else ""


#: The names of the figure files of a report after ``STEM-``: an older one that is not
#: produced again is removed.
_FIGURE_SUFFIX = r"(?:sigma-[1-9][0-9]*|robot-[1-9][0-9]*|manipulability|tree|augmented)\.png"

#: What a file name of a report may be: a stem and one extension, nothing that leaves the
#: directory.
_FILE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]*\.[a-z]+")


def _owned_figures(directory: Path, stem: str) -> set[str]:
    """Names of the files in ``directory`` that are figures of a report on ``stem``.

    An exact match of the whole name; ``stem`` is not a pattern.
    """
    owned = re.compile(re.escape(stem) + "-" + _FIGURE_SUFFIX)
    return {p.name for p in directory.iterdir() if owned.fullmatch(p.name) and p.is_file()}


def _checked_name(fname: str) -> str:
    """``fname`` when it is a plain file name of a report; ValueError otherwise."""
    if not _FILE_NAME.fullmatch(fname):
        raise ValueError(f"{fname!r} is not a file name a report may write")
    return fname


def write_report(report, directory, *, formats=FORMATS, fragment: bool = False,
                 latex: tuple | None = None, timings: bool = True,
                 workdir=None) -> list[Path]:
    """Write ``report`` into ``directory`` (created if missing) and return the paths written.

    Parameters
    ----------
    report : Report
        What :func:`~rankloci.reporting.build.build_report` returned.
    directory : path
    formats : sequence of {"md", "tex", "pdf", "html"}
        The PNG figures are always written beside the text.  The HTML page
        (:func:`~rankloci.reporting.html.render_html`) is one self-contained file.
    fragment : bool
        Write the LaTeX body without a preamble (for ``\\input`` into a paper).
    latex : (str, str) or None
        ``("latexmk", path)`` or ``("pdflatex", path)`` to build the PDF; None
        skips the PDF.
    timings : bool
        Include the timing table (it differs from run to run).
    workdir : path, optional
        An empty directory from :func:`report_workdir` to build in, which the
        caller removes (so that it can, even when this process is killed);
        by default one is made and removed here.

    Everything is first built in a temporary directory (:func:`report_workdir`);
    only when all of it succeeded are the files moved into place.
    """
    from .html import render_html
    from .latex import render_latex
    from .markdown import render_markdown

    bad = [f for f in formats if f not in FORMATS]
    if bad:
        raise ValueError(f"formats {bad} are not among {FORMATS}")
    directory = Path(directory)
    if ".." in directory.parts:
        # "a/../b" is b: mkdir(parents=True) would create a on the way
        directory = Path(os.path.realpath(directory))
    own = workdir is None
    tmp = report_workdir(directory) if own else Path(workdir)
    try:
        produced = []
        name = report.name
        _checked_name(f"{name}.md")
        for fig in report.figures:
            (tmp / _checked_name(fig.name)).write_bytes(fig.png)
            produced.append(fig.name)
        if "md" in formats:
            (tmp / f"{name}.md").write_text(render_markdown(report, timings=timings),
                                            encoding="utf-8")
            produced.append(f"{name}.md")
        if "html" in formats:
            (tmp / f"{name}.html").write_text(render_html(report, timings=timings),
                                              encoding="utf-8")
            produced.append(f"{name}.html")
        tex = render_latex(report, fragment=fragment, timings=timings)
        if "tex" in formats:
            (tmp / f"{name}.tex").write_text(tex, encoding="utf-8")
            produced.append(f"{name}.tex")
        if "pdf" in formats and latex is not None:
            _build_pdf(tmp, name, tex if not fragment else render_latex(
                report, fragment=False, timings=timings), latex)
            produced.append(f"{name}.pdf")
        _check_destinations(directory, produced)    # before anything is moved
        directory.mkdir(parents=True, exist_ok=True)
        written = []
        stale = _owned_figures(directory, name) - set(produced)
        for fname in produced:
            os.replace(tmp / fname, directory / fname)
            written.append(directory / fname)
        for fname in sorted(stale):
            (directory / fname).unlink(missing_ok=True)
        return written
    finally:
        if own:
            shutil.rmtree(tmp, ignore_errors=True)


def report_workdir(directory) -> Path:
    """A new empty directory in which :func:`write_report` can build a report for ``directory``.

    It is made inside ``directory`` when that exists, else in its nearest
    existing ancestor, so that a failure creates nothing and the final moves
    stay on one file system (atomic).  Whoever made it removes it.
    """
    directory = Path(directory)
    if ".." in directory.parts:
        directory = Path(os.path.realpath(directory))
    anchor = directory.absolute()
    while not anchor.is_dir():
        anchor = anchor.parent
    return Path(tempfile.mkdtemp(dir=anchor, prefix=f".{directory.name}.tmp-"))


def _check_destinations(directory: Path, names) -> None:
    """Raise OSError when a file of the report would replace anything but a regular file."""
    import errno
    import stat

    for fname in names:
        try:
            mode = os.lstat(directory / fname).st_mode
        except FileNotFoundError:
            continue
        except NotADirectoryError:
            raise NotADirectoryError(errno.ENOTDIR, f"{directory} is not a directory") from None
        if not stat.S_ISREG(mode):
            what = ("a directory" if stat.S_ISDIR(mode) else "a symbolic link"
                    if stat.S_ISLNK(mode) else "not a regular file")
            raise FileExistsError(errno.EEXIST, f"{directory / fname} is {what}; nothing was "
                                                "written")


def _build_pdf(workdir: Path, name: str, document: str, latex: tuple):
    """Compile ``document`` in ``workdir`` to ``name.pdf``; raise ReportError with the log tail."""
    kind, exe = latex
    job = f"{name}-build"
    (workdir / f"{job}.tex").write_text(document, encoding="utf-8")
    env = dict(os.environ, SOURCE_DATE_EPOCH="0", FORCE_SOURCE_DATE="1")
    if kind == "latexmk":
        cmds = [[exe, "-pdf", "-interaction=nonstopmode", "-halt-on-error", "-file-line-error",
                 f"{job}.tex"]]
    else:
        run = [exe, "-interaction=nonstopmode", "-halt-on-error", "-file-line-error", f"{job}.tex"]
        cmds = [run, run]
    for cmd in cmds:
        try:
            proc = subprocess.run(cmd, cwd=workdir, capture_output=True, timeout=600, env=env,
                                  stdin=subprocess.DEVNULL)
        except subprocess.TimeoutExpired:
            raise ReportError(f"{kind} did not finish within 600 s on {name}.tex") from None
        if proc.returncode != 0:
            log = workdir / f"{job}.log"
            tail = log.read_text(errors="replace").splitlines()[-15:] if log.exists() else []
            errors = [ln for ln in tail if ln.startswith("!") or ":" in ln][:3]
            raise ReportError(f"{kind} failed on {name}.tex: "
                              + (" | ".join(errors) or f"exit code {proc.returncode}"))
    os.replace(workdir / f"{job}.pdf", workdir / f"{name}.pdf")
