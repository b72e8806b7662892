"""Numeric tools: floating-point checks of what the symbolic methods find.

Submodules are imported on their own (``from rankloci.numeric import fsp``);
importing this package loads nothing.
"""
