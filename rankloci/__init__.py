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
- :func:`pose_geometry`, :func:`component_geometry`: the joint axes at a
  configuration or on a component, which of them are parallel, collinear or
  meet there, and what the end-effector cannot do (:mod:`rankloci.geometry`,
  :mod:`rankloci.directions`);
- :func:`from_rtb`, :func:`from_pinocchio`: models from Robotics Toolbox for
  Python and Pinocchio (:mod:`rankloci.adapters`);
- :class:`Locus`, :class:`Component`, :class:`Outcome`: the result types;
  :class:`LocusTimeout` and the other errors (:mod:`rankloci.errors`);
- the submodules (``rankloci.io``, ``rankloci.methods``, ...) are attributes too.
  No submodule is named like a function: the result types are in
  ``rankloci.loci``, the task matrices in ``rankloci.jacobians`` and the
  report's parts in ``rankloci.reporting``, whose submodules are also
  attributes of the function ``rankloci.report``
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

from .version import __version__

#: Public name -> the module that defines it.
_EXPORTS = {
    "load_model": "rankloci.api", "jacobian": "rankloci.api", "locus": "rankloci.api",
    "check": "rankloci.api", "report": "rankloci.api", "is_singular": "rankloci.api",
    "Check": "rankloci.api", "from_rtb": "rankloci.adapters",
    "from_pinocchio": "rankloci.adapters",
    "Locus": "rankloci.loci", "Component": "rankloci.loci", "Outcome": "rankloci.loci",
    "RobotModel": "rankloci.model", "MatrixModel": "rankloci.model",
    "TaskMatrix": "rankloci.jacobians",
    "RanklociError": "rankloci.errors", "ArgumentError": "rankloci.errors",
    "ModelError": "rankloci.errors",
    "ExpressionError": "rankloci.errors", "ShapeError": "rankloci.errors",
    "LocusError": "rankloci.errors", "LocusTimeout": "rankloci.errors",
    "min_inf_norm": "rankloci.near.min_inf_norm", "manipulability": "rankloci.api.near",
    "joint_rates": "rankloci.api.near", "nearest_component": "rankloci.api.near",
    "within_limits": "rankloci.limits", "pose_geometry": "rankloci.api.geometry",
    "component_geometry": "rankloci.api.geometry",
}

#: Submodules reachable as attributes without importing them first.
_SUBMODULES = ("adapters", "algebra", "api", "augmented", "certify", "cli", "directions", "errors",
               "exact", "expr", "extras", "geometry", "io", "jacobians", "kinematics", "limits",
               "loci", "methods", "model", "near", "numeric", "process_limits", "render_text",
               "reporting", "sweep", "tolerances", "tree", "verify", "version")

__all__ = ["__version__", *_EXPORTS]


class _ReportCall:
    """``rankloci.report``: the function, whose attributes are also :mod:`rankloci.reporting`'s.

    ``rankloci.report(...)`` builds a report (:func:`rankloci.api.report`);
    ``rankloci.report.figures`` is the module :mod:`rankloci.reporting.figures`
    (the plotting functions), imported on first use.
    """

    def __init__(self, function):
        functools.update_wrapper(self, function)

    def __call__(self, *args, **kwargs):
        return self.__wrapped__(*args, **kwargs)

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        package = importlib.import_module("rankloci.reporting")
        if hasattr(package, name):
            return getattr(package, name)
        try:
            return importlib.import_module(f"rankloci.reporting.{name}")
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
