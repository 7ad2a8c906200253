"""The numbers a figure draws, read back from the matplotlib Figure, and their comparison with
the numbers a test derives from the tables the caption points to (issue 35 §5).

A panel's drawn data: every line and marker series, bar, whisker, band, pie wedge, image and
number written in data coordinates (shaded windows and zero lines, drawn in axes coordinates,
are not data). A test states, per panel, what the tables give; :func:`compare` finds what is
drawn but not in the tables, and what the tables give but is not drawn.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np
from matplotlib.collections import LineCollection, PolyCollection, TriMesh
from matplotlib.patches import Rectangle, Wedge

from exobench import figures

RTOL, ATOL = 1e-7, 1e-9
NUMBER = re.compile(r"^-?\d+(\.\d+)?%?$")


@dataclass
class Panel:
    """What a panel draws (drawn) or what the tables say it should (expected).

    lines: (x, y) per line or marker series; rects: (x, y, width, height) per bar; whiskers:
    ((x0, y0), (x1, y1)) per whisker; bands: (x, low, high) per band (drawn: its outline's
    vertices); wedges: share of the pie per wedge; images: cell values (NaN where masked), or a
    shaded triangulation's vertex values;
    numbers: (x, y, text) per number written at a data position.
    """

    lines: list = field(default_factory=list)
    rects: list = field(default_factory=list)
    whiskers: list = field(default_factory=list)
    bands: list = field(default_factory=list)
    wedges: list = field(default_factory=list)
    images: list = field(default_factory=list)
    numbers: list = field(default_factory=list)

    def line(self, x, y) -> Panel:
        self.lines.append((np.asarray(x, float).ravel(), np.asarray(y, float).ravel()))
        return self

    def errorbar(self, x, y, low, high, line: bool = True, caps: bool = True) -> Panel:
        """An errorbar series: its marker line (unless ``line`` is False, as for bars), the
        caps at both ends (unless ``caps`` is False) and one whisker per point."""
        x, y = np.asarray(x, float), np.asarray(y, float)
        low, high = np.asarray(low, float), np.asarray(high, float)
        if line:
            self.line(x, y)
        if caps:
            self.line(x, low).line(x, high)
        self.whiskers += [((a, b), (a, c)) for a, b, c in zip(x, low, high, strict=True)]
        return self

    def hwhiskers(self, y, low, high) -> Panel:
        """Horizontal whiskers (x from ``low`` to ``high`` at height y)."""
        self.whiskers += [((b, a), (c, a)) for a, b, c in zip(y, low, high, strict=True)]
        return self

    def bars(self, x, height, width: float = 0.8, bottom=0.0) -> Panel:
        x, height = np.asarray(x, float), np.asarray(height, float)
        bottom = np.broadcast_to(np.asarray(bottom, float), x.shape)
        self.rects += [
            (a - width / 2, b, width, h) for a, b, h in zip(x, bottom, height, strict=True)
        ]
        return self

    def band(self, x, low, high) -> Panel:
        self.bands.append(tuple(np.asarray(v, float).ravel() for v in (x, low, high)))
        return self


def in_data(ax, artist) -> bool:
    """Whether an artist is drawn in the panel's data coordinates."""
    transform = artist.get_data_transform() if hasattr(artist, "get_data_transform") else None
    return (transform or artist.get_transform()) == ax.transData


def read(ax) -> Panel:
    """What a panel draws."""
    out = Panel()
    for line in ax.lines:
        if line.get_visible() and line.get_transform() == ax.transData:
            out.line(line.get_xdata(), line.get_ydata())
    for patch in ax.patches:
        if not patch.get_visible() or not in_data(ax, patch):
            continue
        if isinstance(patch, Wedge):
            out.wedges.append((patch.theta2 - patch.theta1) / 360.0)
        elif isinstance(patch, Rectangle):
            out.rects.append((patch.get_x(), patch.get_y(), patch.get_width(), patch.get_height()))
    for collection in ax.collections:
        if not collection.get_visible() or collection.get_transform() != ax.transData:
            continue
        if isinstance(collection, LineCollection):
            out.whiskers += [tuple(map(tuple, seg[[0, -1]])) for seg in collection.get_segments()]
        elif isinstance(collection, PolyCollection):
            out.bands += [path.vertices for path in collection.get_paths()]
        elif isinstance(collection, TriMesh):  # a shaded field: its values at the vertices
            out.images.append(np.asarray(collection.get_array(), dtype=float))
    for image in ax.images:
        cells = np.ma.masked_invalid(np.ma.asarray(image.get_array(), dtype=float))
        out.images.append(cells.filled(np.nan))
    for text in ax.texts:
        if text.get_visible() and text.get_transform() == ax.transData:
            words = text.get_text().strip()
            if NUMBER.match(words.split("/")[0]):
                out.numbers.append((*text.get_position(), words))
    return out


def values(panel: Panel) -> np.ndarray:
    """Every value a panel draws: the lines' and bands' y, the bars' heights and widths, the
    whiskers' ends, the wedges, the image cells and the numbers written."""
    parts = [y for _, y in panel.lines]
    parts += [np.array([w, h]) for _, _, w, h in panel.rects]
    parts += [np.array([a[1], b[1], a[0], b[0]]) for a, b in panel.whiskers]
    parts += [np.asarray(v)[:, 1] for v in panel.bands]
    parts += [np.asarray(panel.wedges, float)]
    parts += [np.ravel(image) for image in panel.images]
    parts += [np.array([float(n.split("/")[0].rstrip("%")) for *_, n in panel.numbers])]
    flat = np.concatenate([np.asarray(p, float).ravel() for p in parts]) if parts else np.zeros(0)
    return flat[np.isfinite(flat)]


def close(a, b) -> bool:
    """Equal arrays of numbers (same shape, NaN equal to NaN)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a.shape == b.shape and bool(np.allclose(a, b, rtol=RTOL, atol=ATOL, equal_nan=True))


def unmatched(drawn: list, expected: list, same) -> tuple[list, list]:
    """Items of ``drawn`` matching no item of ``expected`` and vice versa, one to one."""
    left = list(range(len(drawn)))
    missing = []
    for item in expected:
        found = next((i for i in left if same(drawn[i], item)), None)
        if found is None:
            missing.append(item)
        else:
            left.remove(found)
    return [drawn[i] for i in left], missing


def band_vertices(band) -> np.ndarray:
    """A band's outline as a set of (x, y) points, rows sorted."""
    if isinstance(band, tuple):
        x, low, high = band
        points = np.concatenate([np.c_[x, low], np.c_[x, high]])
    else:
        points = np.asarray(band, float)
    points = np.unique(np.round(points, 9), axis=0)
    return points


def compare(drawn: Panel, expected: Panel, name: str) -> list[str]:
    """What a panel draws that the tables do not give, and what they give that is not drawn."""
    problems = []

    def short(item) -> str:
        text = np.array2string(np.asarray(item, dtype=object), threshold=6, edgeitems=2)
        return text.replace("\n", " ")[:160]

    checks = (
        ("line", drawn.lines, expected.lines, lambda a, b: close(a[0], b[0]) and close(a[1], b[1])),
        ("bar", drawn.rects, expected.rects, close),
        ("whisker", drawn.whiskers, expected.whiskers, close),
        ("band", drawn.bands, expected.bands,
         lambda a, b: close(band_vertices(a), band_vertices(b))),
        ("wedge", drawn.wedges, expected.wedges, close),
        ("image", drawn.images, expected.images, close),
        ("number", drawn.numbers, expected.numbers,
         lambda a, b: close(a[:2], b[:2]) and a[2] == b[2]),
    )  # fmt: skip
    for kind, seen, wanted, same in checks:
        extra, missing = unmatched(seen, wanted, same)
        problems += [f"{name}: {kind} drawn, not in the tables: {short(i)}" for i in extra]
        problems += [f"{name}: {kind} in the tables, not drawn: {short(i)}" for i in missing]
    return problems


def check_figure(fig, expected: list[Panel]) -> list[str]:
    """Every panel of ``fig`` (in order) against what the tables say it draws."""
    axes = figures.panels(fig)
    if len(axes) != len(expected):
        return [f"{len(axes)} panels drawn, {len(expected)} expected"]
    problems = []
    for index, (ax, panel) in enumerate(zip(axes, expected, strict=True)):
        problems += compare(read(ax), panel, f"panel {index + 1}")
    return problems
