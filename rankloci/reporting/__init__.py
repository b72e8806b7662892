"""Reports: what rankloci finds about a model, as Markdown, LaTeX and PDF with figures, or as
one HTML page with an interactive view of the arm.

:func:`build_report` computes everything a report shows and returns a frozen
:class:`Report`; :func:`~rankloci.reporting.markdown.render_markdown` and
:func:`~rankloci.reporting.latex.render_latex` turn it into text;
:func:`write_report` writes it, with its figures and (given a LaTeX command)
its PDF.  :func:`read_model_notes` reads the free-text notes of a model file,
which the model object does not keep.

The package renders: the numbers it shows come from the library
(:mod:`rankloci.geometry` for the axes of a pose and the facts of a component,
:mod:`rankloci.directions` for a lost direction, :mod:`rankloci.numeric.landscape`
for slices and paths, :mod:`rankloci.numeric.factored_det` for det J), and
``tests/test_report_renders.py`` keeps linear algebra out of it.  The modules,
in the order of the data:

- :mod:`~rankloci.reporting.build`: :func:`build_report` and :class:`Report`;
- :mod:`~rankloci.reporting.reading`: lost directions in words;
  :mod:`~rankloci.reporting.interpret`: one complete reading of each component, from the
  facts to sentences to the name of the classical case;
- :mod:`~rankloci.reporting.figure_files`, :mod:`~rankloci.reporting.figures`,
  :mod:`~rankloci.reporting.analysis` and :mod:`~rankloci.reporting.robot`: which figures,
  with which captions; the plotting functions (each takes ``ax=`` and returns the Axes it
  drew on) and their PNG bytes; the library's numbers as the drawing code names them;
- :mod:`~rankloci.reporting.content` and :mod:`~rankloci.reporting.findings`: the
  report as blocks (:mod:`~rankloci.reporting.blocks`);
- :mod:`~rankloci.reporting.mathfmt`, :mod:`~rankloci.reporting.matrixfmt` and
  :mod:`~rankloci.reporting.escape`: LaTeX math and escaped text;
- :mod:`~rankloci.reporting.markdown` and :mod:`~rankloci.reporting.latex`: the blocks
  as text; :mod:`~rankloci.reporting.html`: the blocks as one self-contained HTML page, with
  the arm view (``assets/arm_view.js``) and the bundled math renderer (``assets/katex/``);
- :mod:`~rankloci.reporting.write`: the only module that touches files.
"""

from .build import ComponentView, Report, build_report
from .escape import file_stem
from .figure_files import FigureFile
from .write import FORMATS, ReportError, read_model_notes, write_report

__all__ = ["Report", "FigureFile", "ComponentView", "build_report", "write_report",
           "read_model_notes", "ReportError", "FORMATS", "file_stem"]
