"""Shared fixtures."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.fixture
def write_file(tmp_path):
    """Return ``write(name, text)``: write str (UTF-8) or bytes to ``tmp_path / name``, return the path."""

    def write(name: str, text: str | bytes) -> Path:
        path = tmp_path / name
        if isinstance(text, bytes):
            path.write_bytes(text)
        else:
            path.write_text(text, encoding="utf-8")
        return path

    return write


# tests/locus_helpers.py is imported as a plain module (tests/ has no __init__.py)
import sys as _sys  # noqa: E402

_TESTS_DIR = str(Path(__file__).resolve().parent)
if _TESTS_DIR not in _sys.path:
    _sys.path.insert(0, _TESTS_DIR)


@pytest.fixture(scope="module")
def robots() -> Path:
    """example-robot-data's robots folder: real URDF files written by others."""
    from rankloci.io.urdf_chains import example_robot_data_dir

    d = example_robot_data_dir()
    if d is None:
        pytest.fail("example-robot-data is not installed; it is a declared test dependency "
                    "(its URDFs are the test data)")
    return d
