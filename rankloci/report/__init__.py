"""Reports: what rankloci finds about a model, as Markdown, LaTeX and PDF with figures, or as
one HTML page with an interactive view of the arm.

:func:`build_report` computes everything a report shows and returns a frozen
:class:`Report`; :func:`~rankloci.report.markdown.render_markdown` and
:func:`~rankloci.report.latex.render_latex` turn it into text;
:func:`write_report` writes it, with its figures and (given a LaTeX command)
its PDF.  :func:`read_model_notes` reads the free-text notes of a model file,
which the model object does not keep.

The modules, in the order of the data:

- :mod:`~rankloci.report.build`: :func:`build_report` and :class:`Report`;
- :mod:`~rankloci.report.analysis`: the numbers behind figures and comparisons;
- :mod:`~rankloci.report.reading`: plain-language readings of lost directions, verified
  numerically; :mod:`~rankloci.report.geometry` and :mod:`~rankloci.report.interpret`: the
  geometric facts at a configuration and one complete reading of each component;
- :mod:`~rankloci.report.figure_files`, :mod:`~rankloci.report.figures` and
  :mod:`~rankloci.report.robot`: which figures, with which captions; the plotting
  functions (each returns a matplotlib Figure and takes ``ax=``) and their PNG bytes;
- :mod:`~rankloci.report.content` and :mod:`~rankloci.report.findings`: the
  report as blocks (:mod:`~rankloci.report.blocks`);
- :mod:`~rankloci.report.mathfmt`, :mod:`~rankloci.report.matrixfmt` and
  :mod:`~rankloci.report.escape`: LaTeX math and escaped text;
- :mod:`~rankloci.report.markdown` and :mod:`~rankloci.report.latex`: the blocks
  as text; :mod:`~rankloci.report.html`: the blocks as one self-contained HTML page, with
  the arm view (``assets/arm_view.js``) and the bundled math renderer (``assets/katex/``);
- :mod:`~rankloci.report.write`: the only module that touches files.
"""

from .build import ComponentView, Report, build_report
from .escape import file_stem
from .figure_files import FigureFile
from .write import FORMATS, ReportError, read_model_notes, write_report

__all__ = ["Report", "FigureFile", "ComponentView", "build_report", "write_report",
           "read_model_notes", "ReportError", "FORMATS", "file_stem"]
