"""The near-locus path crosses its component with a joint-rate peak at the crossing."""

from __future__ import annotations

import re

import pytest

from rankloci.io import load_model
from rankloci.reporting import build_report


@pytest.mark.slow
@pytest.mark.parametrize("name", ["stanford", "ur5"])
def test_rates_peak_where_the_path_passes_the_component(name):
    path = build_report(load_model(name), seed=0, samples=2, exact=False).near.path
    assert path is not None
    # the closest approach is the middle of the line, where it passes the component ...
    assert abs(path.t - 0.5) <= 0.15, path
    assert path.distance < 0.05
    # ... and the rates there stand well above those at the start
    assert path.rate_max > 5 * path.rate_max_start, path
    stop = re.search(r"stopped at t = ([\d.]+)", path.stopped)
    assert stop is None or float(stop.group(1)) > path.t, path.stopped


@pytest.mark.slow
def test_ur5_path_goes_on_past_the_crossing():
    """The UR5's path used to blow up at t = 0.875, away from its crossing; now it peaks at
    the crossing and runs to its end."""
    path = build_report(load_model("ur5"), seed=0, samples=2, exact=False).near.path
    assert not path.stopped, path.stopped
