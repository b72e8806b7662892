"""The install hints name the packages of each extra, as pyproject.toml declares them."""

import importlib.metadata
import shlex
import tomllib
from pathlib import Path

import pytest
from packaging.requirements import Requirement

from rankloci.extras import install_command

PYPROJECT = tomllib.loads((Path(__file__).parents[1] / "pyproject.toml").read_text())
EXTRAS = PYPROJECT["project"]["optional-dependencies"]


@pytest.mark.parametrize("extra", ["report", "sweep", "rtb", "pinocchio"])
def test_install_command_installs_the_requirements_of_the_extra(extra):
    words = shlex.split(install_command(extra))
    assert words[:2] == ["pip", "install"]
    assert {Requirement(w) for w in words[2:]} == {Requirement(r) for r in EXTRAS[extra]}
    assert "rankloci[" not in install_command(extra)   # not on a package index


def test_install_command_without_metadata_points_to_the_source_tree(monkeypatch):
    def missing(name):
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "requires", missing)
    assert install_command("report") == 'pip install -e ".[report]" in a clone of rankloci'
