"""Time and memory limits that hold: the work runs in a child process killed at the limit."""

from __future__ import annotations

import os
import signal
import sys
import time

import pytest

from rankloci.process_limits import KILL_GRACE, ChildFailed, LimitExceeded, run_limited
from rankloci.errors import LocusTimeout, ModelError

#: Slack for starting and reaping the child on a loaded 2-core machine (the limit itself is
#: timeout + KILL_GRACE).
SLACK = 5.0


def _stuck(progress):
    progress("entering a step that never returns")
    while True:                      # not a sleep: a busy loop Python cannot leave early
        pass


def test_a_step_that_never_returns_is_killed_at_the_limit():
    t0 = time.monotonic()
    with pytest.raises(LimitExceeded, match="did not finish within 0.5 s") as err:
        run_limited(_stuck, timeout=0.5, memory_mb=0)
    assert time.monotonic() - t0 < 0.5 + KILL_GRACE + SLACK
    assert "entering a step that never returns" in str(err.value)


def _stuck_after_a_long_message(progress):
    progress("component found: " + "123456789*sin(q1) + " * 5000)
    while True:
        pass


def test_the_error_line_keeps_the_last_progress_short():
    """A progress message of 100 kB (a component's equations) is cut in the error line."""
    from rankloci.errors import MESSAGE_MAX

    with pytest.raises(LimitExceeded, match="did not finish") as err:
        run_limited(_stuck_after_a_long_message, timeout=0.5, memory_mb=0)
    message = str(err.value)
    assert "component found: 123456789*sin(q1)" in message and "more characters" in message
    assert len(message) < MESSAGE_MAX + 200


def _hungry(progress):
    chunks = []
    while True:
        chunks.append(bytearray(50 * 2 ** 20))


def test_running_out_of_memory_is_a_clean_error():
    with pytest.raises(LimitExceeded, match="out of memory"):
        run_limited(_hungry, timeout=60, memory_mb=1024)


def test_results_progress_and_errors_come_back():
    seen = []

    def work(progress):
        progress("half way")
        return {"answer": 42}

    assert run_limited(work, timeout=60, memory_mb=0, progress=seen.append) == {"answer": 42}
    assert seen == ["half way"]

    def bad_input(progress):
        raise ModelError("no such joint", file="m.toml", joint=3)

    with pytest.raises(Exception, match="m.toml: joint 3: no such joint"):
        run_limited(bad_input, timeout=60, memory_mb=0)

    def timed_out(progress):
        raise LocusTimeout("ran out after 12 branches")

    with pytest.raises(LocusTimeout, match="12 branches"):
        run_limited(timed_out, timeout=60, memory_mb=0)

    def bug(progress):
        return 1 / 0

    with pytest.raises(ChildFailed, match="ZeroDivisionError"):
        run_limited(bug, timeout=60, memory_mb=0)


def _child_state(pid: int) -> str:
    """'gone', or the state letter of /proc/PID/status (Z: dead, not yet reaped)."""
    try:
        with open(f"/proc/{pid}/status") as f:
            return next(line.split()[1] for line in f if line.startswith("State:"))
    except FileNotFoundError:
        return "gone"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG is Linux's")
def test_the_child_dies_with_a_parent_killed_outright(tmp_path):
    # a parent killed by SIGKILL cannot kill its child; the kernel does (a sweep worker, kill -9)
    pidfile = tmp_path / "child.pid"

    def work(progress):
        pidfile.write_text(str(os.getpid()))
        time.sleep(60)

    parent = os.fork()
    if parent == 0:
        try:
            run_limited(work, timeout=100, memory_mb=0)
        finally:
            os._exit(0)
    deadline = time.monotonic() + 30
    while not pidfile.exists() or not pidfile.read_text():
        assert time.monotonic() < deadline, "the child did not start"
        time.sleep(0.05)
    child = int(pidfile.read_text())
    assert _child_state(child) not in ("gone", "Z")
    os.kill(parent, signal.SIGKILL)
    os.waitpid(parent, 0)
    while _child_state(child) not in ("gone", "Z"):
        assert time.monotonic() < deadline, "the child outlived its parent"
        time.sleep(0.05)


def _touch_mib(n: int) -> bytearray:
    """n MiB written to (a zeroed allocation that is never written takes no memory)."""
    block = bytearray(n * 2 ** 20)
    block[::4096] = b"x" * len(block[::4096])
    return block


def _allocates_100_mib(progress):
    block = _touch_mib(100)
    time.sleep(0.5)                  # held long enough for the parent to read it
    return len(block)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc/PID/smaps_rollup")
def test_the_memory_limit_counts_the_childs_own_memory_not_what_its_parent_holds():
    # the parent (this test process) holds 400 MiB of written memory and maps numpy and
    # sympy (over 1 GB of address space): none of it counts against the child's limit
    held = _touch_mib(400)
    usage: dict = {}
    assert run_limited(_allocates_100_mib, timeout=60, memory_mb=300, usage=usage) == 100 * 2 ** 20
    assert 100 <= usage["peak_mib"] < 300
    with pytest.raises(LimitExceeded, match="out of memory.* 60 MiB"):
        run_limited(_allocates_100_mib, timeout=60, memory_mb=60)
    del held
