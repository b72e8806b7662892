"""rankloci: closed-form rank-deficiency loci of robot Jacobians and symbolic matrices.

The package is imported lazily: ``import rankloci`` loads nothing heavy, and
each name below is imported the first time it is used, so the command line
starts fast.

- :func:`load_model`, :func:`jacobian`, :func:`locus`, :func:`check`,
  :func:`report`, :func:`is_singular`: the command line's subcommands as
  functions (:mod:`rankloci.api`);
- :func:`min_inf_norm`, :func:`manipulability`, :func:`joint_rates`,
  :func:`nearest_component`: what a robot does near its locus (:mod:`rankloci.near`);
- :func:`within_limits`: which components meet the joint-limit box (:mod:`rankloci.limits`);
- :func:`from_rtb`, :func:`from_pinocchio`: models from Robotics Toolbox for
  Python and Pinocchio (:mod:`rankloci.adapters`);
- :class:`Locus`, :class:`Component`, :class:`Outcome`: the result types;
  :class:`LocusTimeout` and the other errors (:mod:`rankloci.errors`);
- the submodules (``rankloci.io``, ``rankloci.methods``, ...) are attributes too,
  except that ``rankloci.locus``, ``rankloci.jacobian`` and ``rankloci.report``
  are the functions: import those modules by name (``from rankloci.locus import
  Locus``, ``importlib.import_module("rankloci.report")``); the submodules of
  ``rankloci.report`` are also attributes of the function
  (``rankloci.report.figures.plot_sigma_slice``).

Examples
--------
>>> import rankloci
>>> L = rankloci.locus("puma560", numeric=True)
>>> len(L.components), L.complete
(3, True)
"""

import functools
import importlib
import sys
import types

from .version import __version__

#: Public name -> the module that defines it.
_EXPORTS = {
    "load_model": "rankloci.api", "jacobian": "rankloci.api", "locus": "rankloci.api",
    "check": "rankloci.api", "report": "rankloci.api", "is_singular": "rankloci.api",
    "Check": "rankloci.api", "from_rtb": "rankloci.adapters",
    "from_pinocchio": "rankloci.adapters",
    "Locus": "rankloci.locus", "Component": "rankloci.locus", "Outcome": "rankloci.locus",
    "RobotModel": "rankloci.model", "MatrixModel": "rankloci.model",
    "TaskMatrix": "rankloci.jacobian",
    "RanklociError": "rankloci.errors", "ArgumentError": "rankloci.errors",
    "ModelError": "rankloci.errors",
    "ExpressionError": "rankloci.errors", "ShapeError": "rankloci.errors",
    "LocusError": "rankloci.errors", "LocusTimeout": "rankloci.errors",
    "min_inf_norm": "rankloci.near.min_inf_norm", "manipulability": "rankloci.api.near",
    "joint_rates": "rankloci.api.near", "nearest_component": "rankloci.api.near",
    "within_limits": "rankloci.limits",
}

#: Submodules reachable as attributes without importing them first.
_SUBMODULES = ("adapters", "algebra", "api", "augmented", "cli", "directions", "errors", "exact",
               "expr", "io", "jacobian", "kinematics", "limits", "locus", "methods", "model", "near",
               "numeric", "render_text", "report", "tolerances", "tree", "verify")

__all__ = ["__version__", *_EXPORTS]


#: Functions named like a submodule: the attribute stays the function.
_FUNCTIONS_OVER_MODULES = frozenset({"locus", "jacobian", "report"})


class _Package(types.ModuleType):
    """The package module, whose function attributes are not replaced by submodules.

    Importing ``rankloci.locus`` for the first time sets the package's
    attribute ``locus`` to that module; that one assignment is dropped, so
    ``rankloci.locus`` stays the function (the module is in ``sys.modules``).
    """

    def __setattr__(self, name, value):
        if name in _FUNCTIONS_OVER_MODULES and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package


class _ReportCall:
    """``rankloci.report``: the function, whose attributes are also the package's submodules.

    ``rankloci.report(...)`` builds a report (:func:`rankloci.api.report`);
    ``rankloci.report.figures`` is the module :mod:`rankloci.report.figures`
    (the plotting functions), imported on first use.
    """

    def __init__(self, function):
        functools.update_wrapper(self, function)

    def __call__(self, *args, **kwargs):
        return self.__wrapped__(*args, **kwargs)

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        package = importlib.import_module("rankloci.report")
        if hasattr(package, name):
            return getattr(package, name)
        try:
            return importlib.import_module(f"rankloci.report.{name}")
        except ModuleNotFoundError:
            raise AttributeError(f"rankloci.report has no attribute {name!r}") from None


def __getattr__(name):
    if name == "report":
        value = _ReportCall(importlib.import_module("rankloci.api").report)
        globals()[name] = value
        return value
    if name in _EXPORTS:
        value = getattr(importlib.import_module(_EXPORTS[name]), name)
        globals()[name] = value   # later look-ups do not come here
        return value
    if name in _SUBMODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS) | set(_SUBMODULES))
