"""The near-manipulability figure keeps its text legible once scaled into the PDF."""

from __future__ import annotations

import numpy as np

from rankloci.io import load_model
from rankloci.reporting.near_section import NearPose, near_manipulability_figure

#: Printed width of a figure: 0.85 of the 16 cm line of an A4 page with 2.5 cm margins.
PRINTED_WIDTH_IN = 0.85 * 16.0 / 2.54
#: The smallest text that reads on paper, in points.
LEGIBLE_PT = 6.0


def test_near_manipulability_text_prints_at_a_legible_size():
    model = load_model("puma560")
    q = np.full(6, 0.3)
    poses = [NearPose(k, q + 0.05 * k, 0.05, 0.1, 0.1, np.ones(3), 1.0) for k in range(5)]
    fig = near_manipulability_figure(model, poses)
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()    # tick labels exist once drawn
    width, _ = fig.get_size_inches()
    scale = min(1.0, PRINTED_WIDTH_IN / width)
    sizes = [t.get_fontsize() for t in fig.findobj(lambda a: hasattr(a, "get_fontsize"))
             if t.get_visible() and t.get_text()]
    assert sizes and min(sizes) * scale >= LEGIBLE_PT, (min(sizes), scale)
