"""Shared figure style, publication polish and deterministic saving (PNG for the report, PDF for
papers, a caption file beside them)."""

from __future__ import annotations

import re
import string
import textwrap
from collections.abc import Mapping
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib import ticker
from matplotlib.transforms import Bbox

from exobench.atomic import write_atomic, write_text

# Okabe–Ito colour-blind-safe palette, used in stiffness order wherever groups are coloured.
PALETTE = ("#0072B2", "#56B4E9", "#009E73", "#F0E442", "#E69F00", "#D55E00", "#CC79A7", "#000000")
# Components of the power partition (seed 000 figure 4 roles: knee blue, exoskeleton red,
# interface yellow, frame green, spring purple), in Okabe–Ito colours.
COMPONENT_COLOURS = {
    "knee": "#0072B2",
    "exoskeleton": "#D55E00",
    "interface": "#E69F00",
    "frame": "#009E73",
    "spring": "#CC79A7",
}
PANEL_LETTER = re.compile(r"^\([a-z]\)")
# Candidate offsets (points) of a label from its anchor, tried in order by place_labels.
LABEL_OFFSETS = ((6, 6), (6, -14), (-6, 6), (-6, -14), (12, 14), (12, -22), (-12, 14), (-12, -22))


def ordered_colours(count: int) -> list:
    """Colour-blind-safe sequential colours (viridis), light to dark with rising stiffness."""
    cmap = matplotlib.colormaps["viridis"]
    return [cmap(0.9 - 0.8 * i / max(count - 1, 1)) for i in range(count)]


STYLE = {
    "figure.dpi": 100,
    "savefig.dpi": 150,
    "font.size": 9,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "svg.hashsalt": "exobench",
    "pdf.fonttype": 42,
}


def new_figure(ncols: int = 1, nrows: int = 1, width: float = 6.0, height: float = 3.5):
    """A figure and axes in the project style, laid out without overlapping text."""
    with plt.rc_context(STYLE):
        return plt.subplots(
            nrows, ncols, figsize=(width, height), layout="constrained", squeeze=False
        )


def new_mosaic(layout, width: float = 6.0, height: float = 3.5):
    """A figure and its named panels (``layout`` as for ``Figure.subplot_mosaic``, panels
    created row by row) in the project style, laid out without overlapping text."""
    with plt.rc_context(STYLE):
        fig = plt.figure(figsize=(width, height), layout="constrained")
        return fig, fig.subplot_mosaic(layout)


def grid_layout(names, ncols: int) -> list[list[str]]:
    """A ``subplot_mosaic`` layout of panels ``names`` in rows of ``ncols``, the last row's
    panels centred (no empty panel left over): each panel two half-columns wide."""
    names = list(names)
    rows = []
    for start in range(0, len(names), ncols):
        row = [name for name in names[start : start + ncols] for _ in range(2)]
        pad = 2 * ncols - len(row)
        rows.append(["."] * (pad // 2) + row + ["."] * (pad - pad // 2))
    return rows


def plain_number(value: float) -> str:
    """A tick value as a plain decimal (40, 0.05, 13000), never 4×10¹ or 1e-04."""
    return np.format_float_positional(float(f"{value:.6g}"), trim="-")


class PlainLogFormatter(ticker.LogFormatter):
    """Log-axis tick labels chosen as matplotlib chooses them, written as plain decimals."""

    def _num_to_string(self, x, vmin, vmax):  # the one hook LogFormatter leaves for the text
        return plain_number(x)


def panels(fig) -> list:
    """The figure's visible panels (axes), colour bars left out, in drawing order."""
    return [ax for ax in fig.axes if ax.get_visible() and not hasattr(ax, "_colorbar")]


def plain_ticks(ax) -> None:
    """Tick labels as plain numbers: no offset (+1e3), no scientific notation, none on log axes."""
    for axis in (ax.xaxis, ax.yaxis):
        if axis.get_scale() == "log":
            axis.set_major_formatter(PlainLogFormatter())
            axis.set_minor_formatter(PlainLogFormatter(labelOnlyBase=False))
        elif isinstance(axis.get_major_formatter(), ticker.ScalarFormatter):
            axis.get_major_formatter().set_useOffset(False)
            axis.get_major_formatter().set_scientific(False)


def letter_panels(fig) -> None:
    """Panel letters (a), (b), … when a figure has more than one panel, at the start of each
    panel's title where it is (left-aligned or centred; a panel without a title gets a left one);
    a panel that has its letter keeps it."""
    axes = panels(fig)
    if len(axes) < 2:
        return
    for letter, ax in zip(string.ascii_lowercase, axes, strict=False):
        if panel_letter(ax):
            continue
        left, centre = ax.get_title(loc="left"), ax.get_title()
        loc = "center" if centre and not left else "left"
        size = (ax.title if loc == "center" else ax._left_title).get_fontsize()
        ax.set_title(f"({letter}) {left or centre}".rstrip(), loc=loc, fontsize=size)


def panel_letter(ax) -> str | None:
    """The panel's letter, '(a)', from the start of its title; None without one."""
    for title in (ax.get_title(loc="left"), ax.get_title()):
        found = PANEL_LETTER.match(title)
        if found:
            return found.group(0)
    return None


def finish(fig):
    """Publication polish every saved figure gets: plain tick labels and panel letters
    (idempotent, so a test may apply it before :func:`save` does)."""
    for ax in fig.axes:
        plain_ticks(ax)
    letter_panels(fig)
    return fig


def texts(fig) -> list:
    """Every visible, non-empty text of the figure outside hidden panels."""
    found = fig.findobj(matplotlib.text.Text)
    return [
        t
        for t in found
        if t.get_visible() and t.get_text().strip() and (t.axes is None or t.axes.get_visible())
    ]


def place_labels(ax, labels, **style) -> list:
    """Annotate each (text, (x, y)) joined to its anchor by a thin line, at the first of
    :data:`LABEL_OFFSETS` — tried in the order that points away from the nearest other anchor —
    whose box stays inside the axes and overlaps no text drawn so far and no anchor (the
    renderer's extents of the laid-out figure); at the best-pointing offset when none is free."""
    fig = ax.figure
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    taken = [t.get_window_extent(renderer) for t in texts(fig)]
    points = np.array([ax.transData.transform(xy) for _, xy in labels]).reshape(-1, 2)
    anchors = [Bbox.from_bounds(x - 6, y - 6, 12, 12) for x, y in points]  # a marker's size
    placed = []
    for index, (text, xy) in enumerate(labels):
        offsets = away_first(points, index)
        note = None
        for offset in offsets:
            candidate = label(ax, text, xy, offset, style)
            candidate.update_positions(renderer)
            box = matplotlib.text.Text.get_window_extent(candidate, renderer)  # text, not leader
            if inside(box, ax.bbox) and not any(box.overlaps(t) for t in taken + anchors):
                note = candidate
                break
            candidate.remove()
        note = note or label(ax, text, xy, offsets[0], style)
        taken.append(note.get_window_extent(renderer))
        placed.append(note)
    return placed


def away_first(points: np.ndarray, index: int) -> list:
    """:data:`LABEL_OFFSETS` ordered by how well each points away from the anchor nearest to
    anchor ``index`` (display coordinates); in their own order for a lone anchor."""
    others = np.delete(points, index, axis=0)
    if not len(others):
        return list(LABEL_OFFSETS)
    nearest = others[np.argmin(np.hypot(*(others - points[index]).T))]
    away = points[index] - nearest
    cosine = [np.dot(o, away) / (np.hypot(*o) * max(np.hypot(*away), 1e-9)) for o in LABEL_OFFSETS]
    return [LABEL_OFFSETS[i] for i in np.argsort(-np.round(cosine, 6), kind="stable")]


def label(ax, text: str, xy, offset, style):
    """An annotation of ``xy`` with ``text`` ``offset`` points away, aligned away from it and
    joined to it by a thin line."""
    align = "left" if offset[0] >= 0 else "right"
    leader = {"arrowstyle": "-", "lw": 0.4, "color": "0.5", "shrinkA": 0, "shrinkB": 2}
    return ax.annotate(
        text, xy, xytext=offset, textcoords="offset points", ha=align, arrowprops=leader, **style
    )


def inside(box, frame) -> bool:
    """Whether display box ``box`` lies within ``frame``."""
    return frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1


def lay_out(fig) -> None:
    """Run the figure's layout engine once, as its PNG's save would (Agg at the saving
    resolution), and remove it: each save then draws the figure once (``savefig`` draws a figure
    that has an engine twice, the first time only to lay it out) and every format gets the PNG's
    layout (a PNG, or a PNG first, the bytes of matplotlib's own save)."""
    engine = fig.get_layout_engine()
    if engine is None or not fig.axes:  # as Figure.draw: no axes, no layout
        return
    with plt.rc_context(STYLE):
        dpi, saving = fig.dpi, plt.rcParams["savefig.dpi"]
        fig.set_dpi(fig.dpi if saving == "figure" else saving)
        try:
            engine.execute(fig)
        finally:
            fig.set_dpi(dpi)
    without_layout_engine(fig)


def without_layout_engine(fig) -> None:
    """Leave the figure without a layout engine (``set_layout_engine(None)`` reads rcParams)."""
    with plt.rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
        fig.set_layout_engine(None)


def save(fig, *paths: str | Path) -> None:
    """Polish ``fig`` (:func:`finish`), lay it out once (:func:`lay_out`) and save it to each
    path atomically without timestamps, the format following the file suffix."""
    finish(fig)
    lay_out(fig)
    metadata = {"png": {"Software": None}, "pdf": {"CreationDate": None, "Producer": None}}
    for path in paths:
        suffix = Path(path).suffix.lstrip(".")

        def write(tmp: Path, suffix=suffix) -> None:
            with plt.rc_context(STYLE):
                fig.savefig(tmp, format=suffix, metadata=metadata.get(suffix))

        write_atomic(path, write)
        # savefig restores the engine it took away: through rcParams, which may name one
        without_layout_engine(fig)


def caption_text(*paragraphs: str) -> str:
    """A caption file's text: paragraphs wrapped at 100 columns, separated by a blank line (valid
    Markdown and reStructuredText, so the report includes the same file)."""
    wrap = textwrap.TextWrapper(100, break_long_words=False, break_on_hyphens=False)
    return "\n\n".join(wrap.fill(p.strip()) for p in paragraphs if p and p.strip()) + "\n"


def write_caption(path: str | Path, *paragraphs: str) -> None:
    """Write a figure's caption beside it (atomically, byte-deterministic)."""
    write_text(path, caption_text(*paragraphs))


def publish(output, names, drawn: Mapping) -> None:
    """Save every named figure of ``drawn`` (name → (figure, caption paragraphs)) to the rule's
    outputs ``<name>_png``, ``<name>_pdf`` and ``<name>_caption``, then close it; a name the
    rule declares and the group does not draw, or one it draws and the rule does not declare,
    raises."""
    unknown, undeclared = set(names) - set(drawn), set(drawn) - set(names)
    if unknown or undeclared:
        raise KeyError(
            f"figures declared by the rule but not drawn: {sorted(unknown)}; drawn but not "
            f"declared: {sorted(undeclared)} (known: {sorted(drawn)})"
        )
    for name in names:
        fig, caption = drawn[name]
        save(fig, output[f"{name}_png"], output[f"{name}_pdf"])
        write_caption(output[f"{name}_caption"], *caption)
        plt.close(fig)
