"""The report's figures are legible: no text cut by the figure's edge, no two labels of one
Axes on top of each other, no text too small to read, and locus lines on a heat map told apart
by colour and drawn thin.  Each report is built once per module and every figure it draws
(heat maps, J beside the augmented J, paths, robots, tree, near-locus figures) is checked
after an Agg draw."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import rankloci.reporting.figures as F
from rankloci.io import load_model
from rankloci.reporting.build import build_report

#: A text may reach this many pixels past the figure's edge: antialiasing of the glyphs
#: spills about one pixel, which is not a clipped label.
EDGE_ALLOWANCE_PX = 1.0
#: Two texts of one Axes may share a strip this many pixels wide: the bounding boxes of
#: glyphs include side bearings and line gaps, so neighbours that read apart touch by 1-2 px.
OVERLAP_ALLOWANCE_PX = 2.0
#: Smallest font size (points) of any text as printed: below 6 pt a page is not readable.
MIN_FONT_PT = 6.0
#: The LaTeX report prints a figure at most 0.85 of the line wide (A4 less 2.5 cm margins:
#: 16 cm) and 0.42 of the text high (24.7 cm), keeping its aspect ratio.
PRINT_WIDTH_IN = 0.85 * 16.0 / 2.54
PRINT_HEIGHT_IN = 0.42 * 24.7 / 2.54
#: Smallest CIE76 colour difference between two locus lines of one heat map.  About 2.3 is
#: the just-noticeable difference; 20 is a difference seen at a glance on a thin line.
MIN_DELTA_E = 20.0

#: Two windows are the same when their edges agree to this fraction of their width: the
#: round-off of finding the centre of a full turn from its ends and back.
SAME_WINDOW_REL = 1e-9

MODELS = ("planar3r", "planar3r_orient", "puma560", "ur5", "ssrms", "stanford")


@pytest.fixture(scope="module")
def drawn():
    """name -> list of (figure file stem, drawn Figure, renderer) for every model in MODELS."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    original = F.figure_png
    out = {}
    try:
        for name in MODELS:
            figs = []

            def record(fig, _figs=figs):
                _figs.append(fig)
                return original(fig)

            F.figure_png = record
            report = build_report(load_model(name), samples=2, exact=False)
            F.figure_png = original
            # the tree may come from graphviz; every other figure is drawn by matplotlib
            files = [f.name for f in report.figures if f.kind != "tree" or len(figs) > 0]
            assert len(figs) >= len(report.figures) - 1
            entries = []
            for k, fig in enumerate(figs):
                canvas = FigureCanvasAgg(fig)
                fig.set_dpi(F.DPI)
                canvas.draw()
                label = files[k] if k < len(files) else f"{name}-figure-{k}"
                entries.append((label, fig, canvas.get_renderer()))
            out[name] = entries
    finally:
        F.figure_png = original
    return out


def _undrawn_tick_labels(artist) -> set:
    """Tick labels matplotlib keeps but does not draw: their ticks lie outside the view."""
    out = set()
    for ax in artist.figure.axes:
        for axis in ax._axis_map.values():
            shown = ax.axison and axis.get_visible()
            drawn = {id(t) for t in axis._update_ticks()} if shown else set()
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                if id(tick) not in drawn:
                    out.update((id(tick.label1), id(tick.label2)))
    return out


def _texts(artist):
    """The texts of ``artist`` (a Figure or an Axes) that are drawn and say something."""
    from matplotlib.text import Text

    undrawn = _undrawn_tick_labels(artist)
    return [t for t in artist.findobj(Text, include_self=False)
            if t.get_visible() and t.get_text().strip() and t.get_alpha() != 0
            and id(t) not in undrawn]


def _extent(t, renderer):
    """The window extent of ``t`` as drawn; a 3-D text is projected as its draw() does."""
    from mpl_toolkits.mplot3d import proj3d
    from mpl_toolkits.mplot3d.art3d import Text3D

    if not isinstance(t, Text3D) or t.axes is None or t.axes.name != "3d":
        return t.get_window_extent(renderer)
    x, y = t.get_position()
    px, py, _ = proj3d.proj_transform(x, y, t._z, t.axes.get_proj())
    saved = t._x, t._y
    t._x, t._y = px, py
    try:
        return t.get_window_extent(renderer)
    finally:
        t._x, t._y = saved


def _clipped(fig, renderer) -> list:
    """(text, extent) of each text of ``fig`` that runs past the figure's edge."""
    box = fig.bbox
    out = []
    for t in _texts(fig):
        e = _extent(t, renderer)
        if (e.x0 < box.x0 - EDGE_ALLOWANCE_PX or e.y0 < box.y0 - EDGE_ALLOWANCE_PX
                or e.x1 > box.x1 + EDGE_ALLOWANCE_PX or e.y1 > box.y1 + EDGE_ALLOWANCE_PX):
            out.append((t.get_text(), tuple(float(v) for v in np.round(e.extents, 1))))
    return out


def _overlapping(fig, renderer) -> list:
    """(text, text) of each pair of texts of one Axes of ``fig`` whose boxes intersect."""
    out = []
    for ax in fig.axes:
        boxes = [(t.get_text(), _extent(t, renderer)) for t in _texts(ax)]
        for (s, a), (u, b) in itertools.combinations(boxes, 2):
            w = min(a.x1, b.x1) - max(a.x0, b.x0)
            h = min(a.y1, b.y1) - max(a.y0, b.y0)
            if w > OVERLAP_ALLOWANCE_PX and h > OVERLAP_ALLOWANCE_PX:
                out.append((s, u))
    return out


def test_the_checks_find_a_clipped_and_an_overlapping_label():
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(3, 2), dpi=F.DPI)
    ax = fig.add_subplot()
    ax.set_axis_off()
    ax.text(0.4, 0.5, "first label", transform=ax.transAxes)
    ax.text(0.45, 0.5, "second label", transform=ax.transAxes)
    fig.text(0.95, 0.5, "cut off")
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    assert [s for s, _ in _clipped(fig, renderer)] == ["cut off"]
    assert _overlapping(fig, renderer) == [("first label", "second label")]


@pytest.mark.slow
@pytest.mark.parametrize("name", MODELS)
def test_no_text_is_cut_by_the_edge_of_the_figure(drawn, name):
    bad = [(label, *c) for label, fig, renderer in drawn[name] for c in _clipped(fig, renderer)]
    assert not bad, bad


@pytest.mark.slow
@pytest.mark.parametrize("name", MODELS)
def test_no_two_labels_of_one_axes_overlap(drawn, name):
    bad = [(label, *c) for label, fig, renderer in drawn[name]
           for c in _overlapping(fig, renderer)]
    assert not bad, bad


@pytest.mark.slow
@pytest.mark.parametrize("name", MODELS)
def test_no_text_is_too_small_to_read(drawn, name):
    bad = []
    for label, fig, _ in drawn[name]:
        if "-tree" in label:        # drawn by graphviz in the report, tall: a page of its own
            continue
        w, h = fig.get_size_inches()
        scale = min(1.0, PRINT_WIDTH_IN / w, PRINT_HEIGHT_IN / h)
        bad += [(label, t.get_text(), round(scale * t.get_fontsize(), 1)) for t in _texts(fig)
                if scale * t.get_fontsize() < MIN_FONT_PT]
    assert not bad, bad


def _lab(rgb) -> np.ndarray:
    """CIE L*a*b* (D65) of an sRGB colour with channels in 0..1."""
    c = np.asarray(rgb, dtype=float)
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    m = np.array([[0.4124564, 0.3575761, 0.1804375],
                  [0.2126729, 0.7151522, 0.0721750],
                  [0.0193339, 0.1191920, 0.9503041]])
    xyz = m @ lin / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > (6 / 29) ** 3, np.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def test_lab_conversion_matches_known_values():
    assert np.allclose(_lab((1.0, 1.0, 1.0)), [100.0, 0.0, 0.0], atol=0.01)
    assert np.allclose(_lab((0.0, 0.0, 0.0)), [0.0, 0.0, 0.0], atol=0.01)
    assert np.allclose(_lab((1.0, 0.0, 0.0)), [53.24, 80.09, 67.20], atol=0.05)


def _locus_lines(ax):
    """(component label, colour, width) of each locus line of a heat map's Axes."""
    from matplotlib.colors import to_rgb

    out = {}
    for line in ax.get_lines():
        lab = line.get_label()
        if lab.startswith("_") or "point" in lab:
            continue
        if line.get_linestyle() in ("None", "none", " ", ""):     # isolated points: no width
            out.setdefault(lab, (to_rgb(line.get_markerfacecolor()), 0.0))
        else:
            out.setdefault(lab, (to_rgb(line.get_color()), line.get_linewidth()))
    return out


@pytest.mark.slow
@pytest.mark.parametrize("name", MODELS)
def test_locus_lines_on_a_heat_map_are_told_apart(drawn, name):
    seen = 0
    for label, fig, _ in drawn[name]:
        if "-sigma-" not in label and "-augmented" not in label:
            continue
        for ax in fig.axes:
            lines = _locus_lines(ax)
            seen += len(lines)
            for comp, (_, width) in lines.items():
                assert width <= F.CURVE_WIDTH, (label, comp, width)
            for (s, (a, _)), (u, (b, _)) in itertools.combinations(lines.items(), 2):
                d = float(np.linalg.norm(_lab(a) - _lab(b)))
                assert d >= MIN_DELTA_E, (label, s, u, round(d, 1))
    if name != "planar3r_orient":
        assert seen >= 1


def test_every_pair_of_locus_colours_is_told_apart():
    # a heat map with up to ten components uses the whole palette
    from matplotlib.colors import to_rgb

    for a, b in itertools.combinations(F.CURVE_COLOURS, 2):
        d = float(np.linalg.norm(_lab(to_rgb(a)) - _lab(to_rgb(b))))
        assert d >= MIN_DELTA_E, (a, b, round(d, 1))


@pytest.mark.slow
def test_both_panels_of_the_augmented_figure_cover_the_same_window(drawn):
    # the panels share their axes: a smaller window on one leaves a white band in it
    figs = [fig for label, fig, _ in drawn["planar3r_orient"] if "-augmented" in label]
    assert len(figs) == 1
    extents = [ax.images[0].get_extent() for ax in figs[0].axes if ax.images]
    assert len(extents) == 2
    a, b = np.asarray(extents)
    width = max(a[1] - a[0], a[3] - a[2])
    assert np.max(np.abs(a - b)) <= SAME_WINDOW_REL * width, extents


def _data_boxes(fig, renderer) -> list:
    """The window box of the data each Axes of ``fig`` plots: of a 3-D Axes, the box of its
    cube of limits as projected (the data lie inside it); of a 2-D Axes, of its lines,
    collections and images."""
    from matplotlib.transforms import Bbox
    from mpl_toolkits.mplot3d import proj3d

    out = []
    for ax in fig.axes:
        if ax.name == "3d":
            corners = np.array(list(itertools.product(ax.get_xlim3d(), ax.get_ylim3d(),
                                                      ax.get_zlim3d())))
            x, y, _ = proj3d.proj_transform(*corners.T, ax.get_proj())
            out.append(Bbox.union([Bbox.from_extents(*ax.transData.transform((a, b)),
                                                     *ax.transData.transform((a, b)))
                                   for a, b in zip(x, y)]))
        else:
            artists = [*ax.get_lines(), *ax.collections, *ax.images]
            out += [a.get_window_extent(renderer) for a in artists if a.get_visible()]
    return out


def _legends_over_data(fig, renderer) -> list:
    """The texts of each legend of ``fig`` whose box meets the box of some plotted data."""
    out = []
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    legends += list(fig.legends)
    boxes = _data_boxes(fig, renderer)
    for legend in legends:
        e = legend.get_window_extent(renderer)
        for b in boxes:
            w = min(e.x1, b.x1) - max(e.x0, b.x0)
            h = min(e.y1, b.y1) - max(e.y0, b.y0)
            if w > OVERLAP_ALLOWANCE_PX and h > OVERLAP_ALLOWANCE_PX:
                out.append(tuple(t.get_text() for t in legend.get_texts()))
                break
    return out


@pytest.mark.parametrize("three", [False, True])
def test_the_legend_check_finds_a_legend_over_the_data(three):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from rankloci.near.figures import plot_manipulability

    fig = Figure(figsize=(3.4, 3.4), dpi=F.DPI)
    J = np.array([[1.0, 0.4, 0.2], [0.3, 1.0, 0.5], [0.1, 0.2, 0.9]])[:3 if three else 2]
    plot_manipulability(J, ax=fig.add_subplot(projection="3d" if three else None))
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    assert _legends_over_data(fig, canvas.get_renderer())      # its legend is inside


@pytest.mark.slow
@pytest.mark.parametrize("name", MODELS)
def test_near_manipulability_legends_leave_the_plots_free(drawn, name):
    figs = [(label, fig, r) for label, fig, r in drawn[name] if "-near-manipulability" in label]
    assert len(figs) == 1
    for label, fig, renderer in figs:
        assert sum(ax.get_legend() is not None for ax in fig.axes) >= 2
        assert not _legends_over_data(fig, renderer), label


#: Smallest CIE76 difference between a locus line and the heat-map colour beneath any point
#: of it: the same margin as between two lines (a thin line must stand out from its ground).
MIN_DELTA_E_GROUND = 20.0


def _ground_colours(ax, xy) -> np.ndarray:
    """The RGB colours of the heat map of ``ax`` at the points ``xy`` (n, 2), as drawn."""
    image = ax.images[0]
    x0, x1, y0, y1 = image.get_extent()
    values = np.ma.getdata(image.get_array())
    ny, nx = values.shape
    cols = np.clip(((xy[:, 0] - x0) / (x1 - x0) * nx).astype(int), 0, nx - 1)
    rows = np.clip(((xy[:, 1] - y0) / (y1 - y0) * ny).astype(int), 0, ny - 1)
    return image.cmap(image.norm(values[rows, cols]))[:, :3]


def _ground_contrast(ax) -> dict:
    """Component label -> the smallest CIE76 difference between its line's colour and the
    heat-map colours beneath the points of that line."""
    from matplotlib.colors import to_rgb

    out = {}
    for line in ax.get_lines():
        lab = line.get_label()
        if "point" in lab or not len(line.get_xydata()):
            continue
        dotted = line.get_linestyle() in ("None", "none", " ", "")
        colour = _lab(to_rgb(line.get_markerfacecolor() if dotted else line.get_color()))
        ground = np.array([_lab(c) for c in _ground_colours(ax, np.asarray(line.get_xydata()))])
        d = float(np.min(np.linalg.norm(ground - colour, axis=1)))
        key = lab if not lab.startswith("_") else f"segment of {line.get_color()}"
        out[key] = min(d, out.get(key, np.inf))
    return out


def test_the_ground_check_finds_a_line_the_colour_of_its_ground():
    from matplotlib.figure import Figure

    ax = Figure().add_subplot()
    ax.imshow(np.linspace(0, 1, 100).reshape(10, 10), cmap="viridis", extent=(0, 1, 0, 1),
              origin="lower")
    ax.plot([0.05, 0.05], [0.05, 0.95], color="#ffffff", label="component 1")
    ax.plot([0.05, 0.05], [0.05, 0.95], color="#440154", label="component 2")  # viridis at 0
    found = _ground_contrast(ax)
    assert found["component 1"] >= MIN_DELTA_E_GROUND > found["component 2"]


@pytest.mark.slow
@pytest.mark.parametrize("name", MODELS)
def test_locus_lines_stand_out_from_the_heat_map_beneath(drawn, name):
    seen = 0
    for label, fig, _ in drawn[name]:
        if "-sigma-" not in label and "-augmented" not in label:
            continue
        for ax in fig.axes:
            if not ax.images:
                continue
            found = _ground_contrast(ax)
            seen += len(found)
            bad = {k: round(v, 1) for k, v in found.items() if v < MIN_DELTA_E_GROUND}
            assert not bad, (label, bad)
    if name != "planar3r_orient":
        assert seen >= 1


def test_every_locus_colour_stands_out_from_the_whole_colormap():
    # a line may cross any value of the heat map: each colour of the palette keeps the margin
    # from every colour of viridis
    from matplotlib import colormaps
    from matplotlib.colors import to_rgb

    ramp = np.array([_lab(c[:3]) for c in colormaps["viridis"](np.linspace(0, 1, 256))])
    for c in F.CURVE_COLOURS:
        d = float(np.min(np.linalg.norm(ramp - _lab(to_rgb(c)), axis=1)))
        assert d >= MIN_DELTA_E_GROUND, (c, round(d, 1))
