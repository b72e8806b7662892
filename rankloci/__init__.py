"""rankloci: closed-form rank-deficiency loci of robot Jacobians.

The package is imported lazily: importing it costs nothing until a
submodule is used, so the command line starts fast.
"""

__version__ = "0.1.0"
__all__ = ["__version__"]
