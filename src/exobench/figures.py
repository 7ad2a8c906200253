"""Shared figure style and deterministic saving (PNG for the report, PDF for papers)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from exobench.atomic import write_atomic

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


def save(fig, *paths: str | Path) -> None:
    """Save ``fig`` to each path atomically without timestamps, the format following the file
    suffix; the constrained layout is computed for the first and kept for the others (the
    figure then has no layout engine, so each later save draws it once, not twice)."""
    metadata = {"png": {"Software": None}, "pdf": {"CreationDate": None, "Producer": None}}
    for path in paths:
        suffix = Path(path).suffix.lstrip(".")

        def write(tmp: Path, suffix=suffix) -> None:
            with plt.rc_context(STYLE):
                fig.savefig(tmp, format=suffix, metadata=metadata.get(suffix))

        write_atomic(path, write)
        with plt.rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
            fig.set_layout_engine(None)  # (None reads these two settings)
