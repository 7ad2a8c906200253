"""The publication checklist of issue 30, on a figure object and its caption: plain tick labels,
panel letters, no text overlapping another or leaving the figure (the renderer's text extents),
axis ranges fitted to the data, and a caption that explains what the figure draws."""

from __future__ import annotations

import io
import re
import string
from unittest import mock

import numpy as np
from docutils.core import publish_parts
from matplotlib import ticker
from matplotlib.collections import PolyCollection, TriMesh
from matplotlib.container import ErrorbarContainer
from matplotlib.patches import Patch
from matplotlib.text import Text
from matplotlib.transforms import Bbox

import figure_numbers
from exobench import figures

NOT_PLAIN = re.compile(r"×|\\times|\^|\$|\d[eE][+−-]?\d")  # 4×10¹, $10^{1}$, 1e+04
MARKS = re.compile(r"^(\((\d+|\*)\))+$")  # seed 000's significance marks, one line
MIN_DATA_SHARE = 0.5  # the data span at least half of each axis
TOLERANCE_PX = 1.0


def drawn_texts(fig) -> list[tuple[Text, object]]:
    """Every text the renderer draws (visible, not empty) with its display box."""
    texts: list[Text] = []
    original = Text.draw

    def record(self, renderer):
        texts.append(self)
        return original(self, renderer)

    with mock.patch.object(Text, "draw", autospec=True, side_effect=record):
        fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    kept = [t for t in texts if t.get_visible() and t.get_text().strip()]
    return [(t, t.get_window_extent(renderer)) for t in dict.fromkeys(kept)]


def outside_figure(fig, drawn) -> list[str]:
    """Texts cut off by the figure's edge."""
    frame = fig.bbox.padded(TOLERANCE_PX)
    return [
        f"outside the figure: {t.get_text()!r}"
        for t, box in drawn
        if not figures.inside(box, frame)
    ]


def overlapping(drawn) -> list[str]:
    """Pairs of texts whose boxes overlap by more than a pixel both ways."""
    if len(drawn) < 2:
        return []
    boxes = np.array([[b.x0, b.y0, b.x1, b.y1] for _, b in drawn])
    x = np.minimum(boxes[:, None, 2], boxes[None, :, 2]) - np.maximum(
        boxes[:, None, 0], boxes[None, :, 0]
    )
    y = np.minimum(boxes[:, None, 3], boxes[None, :, 3]) - np.maximum(
        boxes[:, None, 1], boxes[None, :, 1]
    )
    hits = np.argwhere(np.triu((x > TOLERANCE_PX) & (y > TOLERANCE_PX), k=1))
    return [f"overlap: {drawn[i][0].get_text()!r} and {drawn[j][0].get_text()!r}" for i, j in hits]


def not_plain(fig, drawn) -> list[str]:
    """Tick labels in scientific or offset notation."""
    ticks = {
        id(label)
        for ax in fig.axes
        for axis in (ax.xaxis, ax.yaxis)
        for label in (*axis.get_ticklabels(), *axis.get_ticklabels(minor=True))
    }
    offsets = {id(axis.get_offset_text()) for ax in fig.axes for axis in (ax.xaxis, ax.yaxis)}
    found = [t.get_text() for t, _ in drawn if id(t) in ticks and NOT_PLAIN.search(t.get_text())]
    found += [t.get_text() for t, _ in drawn if id(t) in offsets]
    return [f"tick label not plain: {text!r}" for text in found]


def letters_missing(fig) -> list[str]:
    """Panels of a multi-panel figure without their letter, (a), (b), … in order."""
    panels = figures.panels(fig)
    if len(panels) < 2:
        return []
    return [
        f"panel {i + 1} lacks ({letter}): {ax.get_title(loc='left') or ax.get_title()!r}"
        for i, (letter, ax) in enumerate(zip(string.ascii_lowercase, panels, strict=False))
        if figures.panel_letter(ax) != f"({letter})"
    ]


def data_artists(ax) -> list:
    """The panel's artists in data coordinates (shaded windows and zero lines, drawn in axes
    coordinates, are not data)."""
    artists = [*ax.lines, *ax.collections, *ax.patches, *ax.images]
    return [
        a
        for a in artists
        if a.get_visible()
        and (a.get_data_transform() if isinstance(a, Patch) else a.get_transform()) == ax.transData
    ]


def extent(artist, renderer):
    """An artist's display box; a shaded triangulation's from its vertices (matplotlib gives it
    none)."""
    if isinstance(artist, TriMesh):
        grid = artist._triangulation
        points = artist.axes.transData.transform(np.column_stack([grid.x, grid.y]))
        return Bbox.from_extents(*points.min(axis=0), *points.max(axis=0))
    return artist.get_window_extent(renderer)


def categorical(axis) -> bool:
    """Whether an axis places categories (a fixed tick per row, labelled in words): its data
    sit on the ticks whatever their number, so they are not checked for the span they fill."""
    labels = [t.get_text() for t in axis.get_ticklabels()]
    return isinstance(axis.get_major_locator(), ticker.FixedLocator) and any(
        re.search(r"[A-Za-z]", label) for label in labels
    )


def unfitted_axes(fig) -> list[str]:
    """Panels whose data span less than :data:`MIN_DATA_SHARE` of an axis (categorical axes
    left out)."""
    renderer = fig.canvas.get_renderer()
    problems = []
    for ax in figures.panels(fig):
        artists = data_artists(ax)
        if not artists or not ax.axison:
            continue
        boxes = np.array([[b.x0, b.y0, b.x1, b.y1] for b in (extent(a, renderer) for a in artists)])
        frame = ax.bbox
        width = (min(boxes[:, 2].max(), frame.x1) - max(boxes[:, 0].min(), frame.x0)) / frame.width
        height = (
            min(boxes[:, 3].max(), frame.y1) - max(boxes[:, 1].min(), frame.y0)
        ) / frame.height
        width = 1.0 if categorical(ax.xaxis) else width
        height = 1.0 if categorical(ax.yaxis) else height
        if min(width, height) < MIN_DATA_SHARE:
            problems.append(
                f"data fill {width:.0%} × {height:.0%} of panel "
                f"{ax.get_title(loc='left') or ax.get_title()!r}"
            )
    return problems


def caption_problems(fig, drawn, caption: str) -> list[str]:
    """A caption that does not render as reStructuredText, or leaves unexplained the panels,
    marks, whiskers or bands the figure draws."""
    problems = []
    errors = io.StringIO()
    publish_parts(
        caption, writer="html", settings_overrides={"warning_stream": errors, "report_level": 2}
    )
    if errors.getvalue():
        problems.append(f"caption does not render: {errors.getvalue()}")
    if len(figures.panels(fig)) > 1 and "(a)" not in caption:
        problems.append("caption names no panel")
    lines = (line for t, _ in drawn for line in t.get_text().splitlines())
    if any(MARKS.match(line) for line in lines) and not ("(*)" in caption and "Dunn" in caption):
        problems.append("significance marks drawn, not explained")
    containers = [c for ax in fig.axes for c in ax.containers]
    bars = [c for c in containers if getattr(c, "errorbar", None) is not None]
    if (bars or any(isinstance(c, ErrorbarContainer) for c in containers)) and (
        "whiskers" not in caption
    ):
        problems.append("error bars drawn, their meaning not stated")
    bands = [c for ax in fig.axes for c in ax.collections if isinstance(c, PolyCollection)]
    if any(c.get_transform() == c.axes.transData for c in bands) and "band" not in caption:
        problems.append("bands drawn, their meaning not stated")
    return problems


def empty_or_constant(fig) -> list[str]:
    """A figure that draws no data (text only), or whose every drawn value is the same (an
    all-zero heatmap, flat lines)."""
    found = np.concatenate([figure_numbers.values(figure_numbers.read(ax)) for ax in
                            figures.panels(fig)] or [np.zeros(0)])  # fmt: skip
    if not found.size:
        return ["empty figure: no data drawn"]
    if np.ptp(found) == 0:
        return [f"constant figure: every drawn value is {found[0]:g}"]
    return []


def check(fig, caption: str) -> list[str]:
    """Everything the checklist finds wrong with a figure (after the polish every save applies)
    and its caption; empty when it passes."""
    figures.finish(fig)
    drawn = drawn_texts(fig)
    return [
        *outside_figure(fig, drawn),
        *overlapping(drawn),
        *not_plain(fig, drawn),
        *letters_missing(fig),
        *unfitted_axes(fig),
        *empty_or_constant(fig),
        *caption_problems(fig, drawn, caption),
    ]


def window_and_strides_missing(fig, counted: bool = True) -> list[str]:
    """Panels whose title does not state its window (% of the cycle, seconds, heel strike to
    heel strike) and, when ``counted``, its strides or steps (n = …)."""
    problems = []
    for ax in figures.panels(fig):
        title = f"{ax.get_title(loc='left')} {ax.get_title()}"
        window = re.search(r"%|\d s\b|heel strike to heel strike", title)
        if not window or (counted and "n = " not in title):
            problems.append(f"panel states no window or strides: {title.strip()!r}")
    return problems
