"""The Python interface: what the command line does, as functions.

- :func:`load_model`: a built-in name, a model file, a sympy matrix, a
  Robotics Toolbox DH robot or a Pinocchio model;
- :func:`jacobian`, :func:`locus`, :func:`check`, :func:`report`: the
  subcommands;
- :func:`is_singular`: whether a configuration lies on the locus.

Progress goes to the ``rankloci`` logger (:mod:`.progress`).  Everything here
is also reachable from the top level: ``rankloci.locus(...)``.
"""

from .calls import Check, check, is_singular, jacobian, load_model, locus
from .models import as_model, matrix_model
from .progress import LOGGER_NAME, log_progress
from .reports import report

__all__ = ["load_model", "jacobian", "locus", "check", "report", "is_singular", "Check",
           "as_model", "matrix_model", "LOGGER_NAME", "log_progress"]
