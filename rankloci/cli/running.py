"""How a subcommand runs its work: under the command's time and memory limits.

:func:`limited` runs the work in a child process (:mod:`rankloci.process_limits`)
and turns running out of time or memory into one error line;
:func:`command_deadline` is the cooperative deadline the work itself polls.
"""

from __future__ import annotations

import sys
import time

from .output import clear_status

__all__ = ["limited", "command_deadline", "deadline_clock"]


#: The clock ``--timeout`` is measured on, in seconds.  A module-level name so
#: that tests can put a fake clock in its place.
deadline_clock = time.monotonic


def command_deadline(seconds, started=None):
    """A ``should_stop`` that says True once ``seconds`` have passed since ``started`` (a
    :func:`time.monotonic` reading; default now), on :data:`deadline_clock`; None for no
    limit."""
    from ..api.deadline import stop_after

    return stop_after(seconds, started, clock=deadline_clock)



def limited(args, work, progress, what):
    """``run_limited`` with the command's limits; None (after one error line) when they ran out."""
    from ..errors import LocusTimeout
    from ..process_limits import LimitExceeded, run_limited

    try:
        return run_limited(work, timeout=args.timeout, memory_mb=args.memory, progress=progress,
                           started=getattr(args, "started", None))
    except LocusTimeout as e:
        clear_status()
        print(f"rankloci: error: {e}; raise --timeout (now {args.timeout:g} s) or try "
              f"--numeric-parameters", file=sys.stderr)
    except LimitExceeded as e:
        clear_status()
        print(f"rankloci: error: {what} {e}", file=sys.stderr)
    finally:
        clear_status()
    return None
