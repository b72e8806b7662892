"""Sphinx configuration of the rankloci documentation.

The API reference is built from the numpydoc docstrings (``numpydoc``); the
quickstart notebook is executed at every build (``myst_nb``, execution forced,
any error fails the build).  ``sphinx-build -W`` turns every warning into an
error.
"""

project = "rankloci"
author = "the rankloci authors"
copyright = "the rankloci authors"

extensions = ["sphinx.ext.autodoc", "numpydoc", "myst_nb"]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
exclude_patterns = ["_build", "jupyter_execute", ".ipynb_checkpoints"]

autodoc_default_options = {"members": False}
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

nb_execution_mode = "force"
nb_execution_raise_on_error = True
nb_execution_timeout = 600
nb_execution_show_tb = True

html_theme = "alabaster"
html_title = "rankloci"
