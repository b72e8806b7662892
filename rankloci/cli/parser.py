"""The argument parser of the ``rankloci`` command line.

Only argument definitions live here: what each subcommand accepts and the
help examples (the argument types that check a value before any work is done
are in :mod:`rankloci.cli.arguments`).  Which function runs a subcommand is decided in
:mod:`rankloci.cli.commands`.
"""

from __future__ import annotations

import argparse

from ..errors import UsageError
from ..process_limits import DEFAULT_MEMORY_MB
from .arguments import (ArgumentParser, frame_arg, jobs_arg, memory_arg, rank_rtol_arg,
                        seed_arg, task_arg, timeout_arg)
from ..tolerances import RANK_RTOL

__all__ = ["UsageError", "build_parser", "OLD_OPTIONS"]


#: Options renamed to one spelling across the subcommands: old spelling -> new.  The old
#: one still works, with a note on stderr (:func:`rankloci.cli.main`).
OLD_OPTIONS = {"--numeric-parameters": "--numeric"}


class _OldSpelling(argparse.Action):
    """A flag's old spelling: stores True, as the new one does, and remembers that it was used."""

    def __init__(self, option_strings, dest, **kwargs):
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS,
                         help=argparse.SUPPRESS)

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, True)
        used = list(getattr(namespace, "old_options", ()))
        if option_string not in used:
            used.append(option_string)
        namespace.old_options = used


def _numeric_flag(p, help_text):
    """``--numeric``, and its old spelling ``--numeric-parameters`` (hidden from the help)."""
    p.add_argument("--numeric", dest="numeric", action="store_true", help=help_text)
    p.add_argument("--numeric-parameters", dest="numeric", action=_OldSpelling)


def _rank_rtol_option(p, what):
    p.add_argument("--rank-rtol", dest="rank_rtol", type=rank_rtol_arg, default=RANK_RTOL,
                   metavar="R",
                   help=f"rank threshold of {what}: J is rank deficient at a point where "
                        f"sigma_min <= R * sigma_max (default {RANK_RTOL:g}; strictly between "
                        "0 and 1)")


def _jobs_option(p):
    p.add_argument("--jobs", type=jobs_arg, default=None, metavar="N",
                   help="processes for the parts of the computation that are independent "
                        "(default: every core this process may use); the locus is the same "
                        "for any N")


EPILOG_JACOBIAN = """examples:
  rankloci jacobian planar2r
  rankloci jacobian puma560 --frame tool --format latex
  rankloci jacobian ssrms --augment q3 --numeric --format json
  rankloci jacobian examples/arm.urdf --tip tool0 --task position

Paths in these examples are files of rankloci's source tree (examples/).
"""

EPILOG_LOCUS = """examples:
  rankloci locus puma560
  rankloci locus ssrms --numeric --format json > ssrms.json
  rankloci locus planar4r --augment "q1 + q2 + q3 + q4" --tree tree.dot
  rankloci locus pa10 --augment "lock(q3)"      # J, J_aug, kinds of J_aug's components
  rankloci locus pa10 --augment "elbow(z)" --format json
  rankloci locus examples/my_matrix.toml --method subdeterminant --show-tree
  rankloci locus examples/arm.urdf --tip tool0 --task position

The locus is printed as components: equations that vanish on each, the solved
form where there is one, dimension, rank drop and the lost task direction.
Paths in these examples are files of rankloci's source tree (examples/).
"""

EPILOG_CHECK = """examples:
  rankloci check planar2r
  rankloci check puma560 --numeric --samples 20 --seed 7
  rankloci locus puma560 --numeric --format json > puma.json
  rankloci check puma560 --locus puma.json --format json
  rankloci locus examples/arm.urdf --tip tool0 --format json > arm.json
  rankloci check examples/arm.urdf --tip tool0 --locus arm.json

Samples points on each component (J must be rank deficient there), random
configurations away from every component (J must be full rank) and minima of
sigma_min/sigma_max (each singular one must lie on a component).  The SVD
decides; where its double-precision ratio lies above 1e-14 a point of a
component is decided again in 50 and 100 digits (singular where the ratio falls
with the digits, regular where it stays).  FSP reducer and maximal-minor
disagreements are listed as findings.
A locus file is checked against the model's own task (a locus computed with
--task or --augment is refused).  Exit 0 when every check passes, 1 when one
fails, 2 on bad input.  Paths in these examples are files of rankloci's source
tree (examples/).
"""

EPILOG_MODELS = """examples:
  rankloci models
  rankloci models --format json
"""

EPILOG_REPORT = """examples:
  rankloci report puma560
  rankloci report planar3r -o out/planar3r --format md --samples 20 --seed 7
  rankloci report ssrms --fragment --format tex,pdf
  rankloci report puma560 --format html
  rankloci report all -o reports --timeout 120

Writes DIR/NAME.md, DIR/NAME.tex and, when latexmk or pdflatex is installed,
DIR/NAME.pdf, with the PNG figures beside them (default DIR: reports/NAME/;
with 'all', one directory per built-in model under -o); --format html adds
DIR/NAME.html, one page that needs no network, in which sliders move the arm
along each component.  The report holds the
model, the symbolic Jacobian, the locus component by component with its
reading, heat maps of sigma_min/sigma_max, the branch tree, the numeric
cross-check, the method comparison and the timings.  Equal seeds give equal
reports, the timing table aside (--no-timings leaves it out).  Exit 0 when
written, 1 when the cross-check fails or LaTeX fails, 2 on bad input.
"""


def _model_args(p):
    p.add_argument("model", metavar="MODEL|FILE",
                   help="a built-in model name (see 'rankloci models') or a .toml/.urdf file")
    p.add_argument("--task", type=task_arg, default=None,
                   help="rows of the 6-row Jacobian: full, position, orientation, planar, or e.g. 0,1,5")
    p.add_argument("--frame", type=frame_arg, default=None,
                   help="frame the Jacobian is expressed in: base, tool, or a link number 0..n")
    p.add_argument("--augment", action="append", metavar="EXPR",
                   help="constraint function g(q) whose gradient is stacked under J (repeatable): "
                        "an expression, or a preset: lock(q3), sum(q1, q2, q3), position(k, x|y|z), "
                        "elbow(z), wrist(x) (points the model names)")
    p.add_argument("--base-link", dest="base_link", help="URDF only: first link of the chain")
    p.add_argument("--tip", dest="tip_link", help="URDF only: last link of the chain")


class _CommandListFormatter(argparse.RawDescriptionHelpFormatter):
    """Measures each item one indent deeper: argparse measures subcommand names at the
    parent's indent but prints them one level in, so a long name (manipulability) would
    otherwise get its help on a line of its own."""

    def add_argument(self, action):
        self._indent()
        super().add_argument(action)
        self._dedent()


def build_parser() -> ArgumentParser:
    """The parser of ``rankloci``; ``args.command`` names the subcommand (None if none)."""
    raw = argparse.RawDescriptionHelpFormatter
    parser = ArgumentParser(
        prog="rankloci",
        description="Closed-form rank-deficiency (singularity) loci of robot Jacobians "
                    "and symbolic matrices.",
        epilog="examples:\n  rankloci models\n  rankloci jacobian puma560\n"
               "\nrun 'rankloci COMMAND --help' for the options of a command.",
        formatter_class=_CommandListFormatter,
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=ArgumentParser)

    p = sub.add_parser("models", help="list the built-in models", epilog=EPILOG_MODELS,
                       formatter_class=raw)
    p.add_argument("--format", choices=("text", "json"), default="text")

    p = sub.add_parser("jacobian", help="print the symbolic Jacobian of a model",
                       epilog=EPILOG_JACOBIAN, formatter_class=raw)
    _model_args(p)
    p.add_argument("--point", type=frame_arg, default="tool",
                   help="reference point: origin of base, tool, or link frame 0..n (default tool)")
    _numeric_flag(p, "replace the geometric parameters by their values")
    p.add_argument("--timeout", type=timeout_arg, default=600.0,
                   help="give up after this many seconds (default 600; 0 = never)")
    p.add_argument("--memory", type=memory_arg, default=DEFAULT_MEMORY_MB, metavar="MIB",
                   help=f"memory limit in MiB (default {DEFAULT_MEMORY_MB}; 0 = none)")
    p.add_argument("--format", choices=("text", "latex", "json"), default="text")

    p = sub.add_parser("locus", help="compute the rank-deficiency (singularity) locus",
                       epilog=EPILOG_LOCUS, formatter_class=raw)
    _model_args(p)
    p.add_argument("--method", choices=("svm", "subdeterminant", "determinant"), default=None,
                   help="svm (default) or subdeterminant; determinant for a square matrix "
                        "(the default when the matrix is square)")
    _numeric_flag(p, "replace the geometric parameters by their values before the algebra")
    p.add_argument("--format", choices=("text", "json", "latex"), default="text")
    p.add_argument("--tree", metavar="FILE", help="write the branch tree to FILE.dot, FILE.json or FILE.txt")
    p.add_argument("--show-tree", action="store_true", help="also draw the branch tree in the terminal")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of the numeric probes (default 0)")
    p.add_argument("--timeout", type=timeout_arg, default=600.0,
                   help="give up after this many seconds (default 600; 0 = never); the limit "
                        "holds within a few seconds whatever the computation is doing")
    p.add_argument("--memory", type=memory_arg, default=DEFAULT_MEMORY_MB, metavar="MIB",
                   help=f"memory limit of the computation in MiB (default {DEFAULT_MEMORY_MB}; "
                        "0 = none); running out is one error line and exit 1")
    p.add_argument("--no-verify", dest="verify", action="store_false",
                   help="skip the self-check (dimension bound and numeric probe at the model's "
                        "values) that runs before the locus is shown, and the recomputation it "
                        "triggers when it fails")
    p.add_argument("--quiet", action="store_true", help="no progress messages on stderr")
    _rank_rtol_option(p, "the numeric self-check")
    _jobs_option(p)
    p.set_defaults(frame_default="auto")

    p = sub.add_parser("check", help="cross-check a locus numerically against the SVD of J",
                       epilog=EPILOG_CHECK, formatter_class=raw)
    p.add_argument("model", metavar="MODEL|FILE",
                   help="a built-in model name (see 'rankloci models') or a .toml/.urdf file")
    p.add_argument("--locus", metavar="LOCUS.json",
                   help="check this locus file (schema rankloci.locus/1 or /2) instead of computing the locus")
    p.add_argument("--base-link", dest="base_link", help="URDF only: first link of the chain")
    p.add_argument("--tip", dest="tip_link", help="URDF only: last link of the chain")
    p.add_argument("--samples", type=int, default=10,
                   help="points per component, off-locus points and probe starts (default 10)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of the random points (default 0)")
    p.add_argument("--format", choices=("text", "json"), default="text")
    _numeric_flag(p, "replace the geometric parameters by their values before the algebra")
    p.add_argument("--timeout", type=timeout_arg, default=600.0,
                   help="give up after this many seconds (default 600; 0 = never)")
    p.add_argument("--memory", type=memory_arg, default=DEFAULT_MEMORY_MB, metavar="MIB",
                   help=f"memory limit in MiB (default {DEFAULT_MEMORY_MB}; 0 = none)")
    p.add_argument("--quiet", action="store_true", help="no progress messages on stderr")
    _rank_rtol_option(p, "the numeric check (and of the self-check of a locus it computes)")
    _jobs_option(p)

    p = sub.add_parser("report", help="write a report (Markdown, LaTeX, PDF, figures) on a model",
                       epilog=EPILOG_REPORT, formatter_class=raw)
    p.add_argument("model", metavar="MODEL|FILE|all",
                   help="a built-in model name, a .toml/.urdf file, or 'all' built-in models")
    p.add_argument("-o", "--output", metavar="DIR",
                   help="directory to write into (default reports/NAME; with 'all', the parent "
                        "directory, default reports)")
    p.add_argument("--format", default="md,tex,pdf", metavar="LIST",
                   help="comma list of md, tex, pdf, html (default md,tex,pdf; pdf only when "
                        "latexmk or pdflatex is installed; html is one self-contained page with "
                        "an interactive view of the arm)")
    p.add_argument("--samples", type=int, default=10,
                   help="cross-check points per component, off-locus points and probe starts "
                        "(default 10)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of every random choice (default 0)")
    p.add_argument("--fragment", action="store_true",
                   help="write the .tex without a preamble, to \\input into a paper")
    _numeric_flag(p, "replace the geometric parameters by their values before the algebra")
    p.add_argument("--timeout", type=timeout_arg, default=600.0,
                   help="seconds per locus computation (default 600; 0 = never); when it runs "
                        "out the report is written without the locus and says so")
    p.add_argument("--memory", type=memory_arg, default=DEFAULT_MEMORY_MB, metavar="MIB",
                   help=f"memory limit in MiB (default {DEFAULT_MEMORY_MB}; 0 = none)")
    _rank_rtol_option(p, "the numeric cross-check and of the locus's self-check")
    _jobs_option(p)
    p.add_argument("--no-timings", dest="no_timings", action="store_true",
                   help="leave out the timing table (then equal seeds give identical files)")
    p.add_argument("--timestamp", action="store_true",
                   help="print the date and time of writing under the title (off by default, "
                        "so that reports are reproducible)")
    p.add_argument("--base-link", dest="base_link", help="URDF only: first link of the chain")
    p.add_argument("--tip", dest="tip_link", help="URDF only: last link of the chain")
    p.add_argument("--quiet", action="store_true", help="no progress messages on stderr")

    from .sweep import EPILOG_SWEEP, add_sweep_arguments

    p = sub.add_parser("sweep", help="compute many loci (models x parameter grid x constraints) "
                                     "on Dask", epilog=EPILOG_SWEEP, formatter_class=raw)
    add_sweep_arguments(p)

    from .near import add_parsers as add_near_parsers

    add_near_parsers(sub, raw)
    return parser
