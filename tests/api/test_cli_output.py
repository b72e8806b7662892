"""The command line's side of the logging bridge, and the report extra's message."""

from __future__ import annotations

import io
import logging
import sys

import pytest

from rankloci.api.progress import log_progress, logger
from rankloci.cli import main
from rankloci.cli import output


class _Terminal(io.StringIO):
    def isatty(self):
        return True


@pytest.fixture
def attached():
    output.progress_printer(False)
    yield output._handler()
    output.detach_progress()


def test_lines_on_a_pipe(attached, monkeypatch):
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    log_progress("branch 1: 6x6 matrix")
    assert err.getvalue() == "rankloci: branch 1: 6x6 matrix\n"


def test_status_line_on_a_terminal_after_the_delay(attached, monkeypatch):
    err = _Terminal()
    monkeypatch.setattr(sys, "stderr", err)
    now = [100.0]
    attached.clock = lambda: now[0]
    log_progress("first")                          # starts the clock, draws nothing yet
    assert err.getvalue() == ""
    now[0] += output.STATUS_DELAY + 0.5
    log_progress("branch 7: 6x7 matrix")
    text = err.getvalue()
    assert text.startswith("\r\x1b[Krankloci: ") and text.endswith("\r")
    assert "1.5 s, 2 steps | branch 7: 6x7 matrix" in text and "\n" not in text
    output.clear_status()
    assert err.getvalue().endswith("\r\x1b[K") and not attached.shown


def test_quiet_attaches_nothing_and_main_detaches(capsys):
    assert output.progress_printer(True) is None and output._handler() is None
    assert main(["locus", "planar2r", "--numeric"]) == 0
    assert "rankloci: planar2r: 2x2 matrix" in capsys.readouterr().err
    assert output._handler() is None and logger.level == logging.NOTSET


def test_report_without_matplotlib_says_what_to_install(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "matplotlib", None)   # find_spec then says: not installed
    out = tmp_path / "r"
    assert main(["report", "planar2r", "-o", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err == ("rankloci: error: rankloci report needs matplotlib, which is not installed: "
                   "pip install \"matplotlib<4,>=3.8\"\n")
    assert not out.exists()
    import rankloci

    with pytest.raises(ImportError, match=r'pip install "matplotlib<4,>=3.8"'):
        rankloci.report("planar2r")
