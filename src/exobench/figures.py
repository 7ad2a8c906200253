"""Shared figure style and deterministic saving (PNG for the report, PDF for papers)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from exobench.atomic import write_atomic

# Okabe–Ito colour-blind-safe palette, used in stiffness order wherever groups are coloured.
PALETTE = ("#0072B2", "#56B4E9", "#009E73", "#F0E442", "#E69F00", "#D55E00", "#CC79A7", "#000000")
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


def save(fig, path: str | Path) -> None:
    """Save ``fig`` atomically without timestamps; the format follows the file suffix."""
    suffix = Path(path).suffix.lstrip(".")
    metadata = {"png": {"Software": None}, "pdf": {"CreationDate": None, "Producer": None}}

    def write(tmp: Path) -> None:
        with plt.rc_context(STYLE):
            fig.savefig(tmp, format=suffix, metadata=metadata.get(suffix))

    write_atomic(path, write)
