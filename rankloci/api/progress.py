"""Progress messages as :mod:`logging` records of the ``rankloci`` logger.

The engine reports its progress through a callable taking one line of text
(``progress=``).  At the library's boundary that callable is
:func:`log_progress`, which logs each line at level INFO on the logger named
``"rankloci"``; a notebook or a script sees them by configuring that logger,
for example ``logging.basicConfig(level=logging.INFO)``.  The command line
attaches its own handler (:func:`rankloci.cli.output.progress_printer`).
"""

from __future__ import annotations

import logging

__all__ = ["LOGGER_NAME", "logger", "log_progress"]

#: Name of the logger every progress message goes to.
LOGGER_NAME = "rankloci"

#: The ``rankloci`` logger.  Like every library logger it has no handler of its own
#: (a :class:`logging.NullHandler`), so nothing is printed unless the application asks.
logger = logging.getLogger(LOGGER_NAME)
logger.addHandler(logging.NullHandler())


def log_progress(message: str) -> None:
    """Log one progress line of the engine at level INFO on the ``rankloci`` logger.

    Examples
    --------
    >>> import logging
    >>> records = []
    >>> handler = logging.Handler()
    >>> handler.emit = records.append
    >>> logger.addHandler(handler); logger.setLevel(logging.INFO)
    >>> log_progress("branch 3: 6x6 matrix")
    >>> logger.removeHandler(handler); logger.setLevel(logging.NOTSET)
    >>> [r.getMessage() for r in records]
    ['branch 3: 6x6 matrix']
    """
    logger.info("%s", message)
