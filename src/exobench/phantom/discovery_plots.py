"""Figure of the discovered terms: each term's correction against the residual it explains."""

from __future__ import annotations

import textwrap
from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench import figures
from exobench.phantom.effects import OBSERVABLES

BINS = 20  # quantile bins of a term's correction in the figure


def binned(x: np.ndarray, y: np.ndarray, bins: int = BINS) -> tuple[np.ndarray, ...]:
    """Means of x and y and the SD of y in quantile bins of x (bins without samples dropped)."""
    edges = np.quantile(x, np.linspace(0.0, 1.0, bins + 1))
    which = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, bins - 1)
    count = np.bincount(which, minlength=bins)
    keep = count > 0
    mean_x = np.bincount(which, x, bins)[keep] / count[keep]
    mean_y = np.bincount(which, y, bins)[keep] / count[keep]
    square = np.bincount(which, y * y, bins)[keep] / count[keep]
    return mean_x, mean_y, np.sqrt(np.maximum(square - mean_y**2, 0.0))


def terms_figure(table: pd.DataFrame, report: Mapping):
    """Per discovered term (named, else proposed) and the observable its correction is largest
    in: the residual of the model without the term (before) and with it (after) against the
    correction the term makes, binned; a term that explains the residual puts 'before' on the
    diagonal and 'after' on zero."""
    entries = [*report["discovery"]["named"], *report["discovery"]["proposed"]]
    fig, axes = figures.new_figure(max(len(entries), 1), 1, width=3.2 * max(len(entries), 1),
                                   height=3.4)  # fmt: skip
    if not entries:
        ax = axes[0, 0]
        ax.set_axis_off()
        why = (
            "no library term removes the structure left unexplained"
            if report["discovery"]["searched"]
            else "the registry leaves nothing unexplained, the library was not searched"
        )
        ax.text(0.5, 0.5, f"no discovered term: {why}", ha="center", va="center", wrap=True,
                fontsize=8, transform=ax.transAxes)  # fmt: skip
        return fig
    for letter, ax, entry in zip("abcdefgh", axes[0], entries, strict=False):
        rows = table[table["term"] == entry["term"]]
        best, unit = None, None
        for obs, group in rows.groupby("observable"):
            size = float(np.std(group[f"correction_{OBSERVABLES[obs]}"]))
            if best is None or size > best[0]:
                best, unit = (size, obs, group), OBSERVABLES[obs]
        _, obs, group = best
        x = group[f"correction_{unit}"].to_numpy()
        for kind, colour in (("before", "0.5"), ("after", "#0072B2")):
            mx, my, sd = binned(x, group[f"residual_{kind}_{unit}"].to_numpy())
            ax.errorbar(mx, my, yerr=sd, fmt="o", ms=3, color=colour, lw=0.8,
                        label=f"residual {kind} the term")  # fmt: skip
        span = np.array([x.min(), x.max()])
        ax.plot(span, span, "k:", lw=0.8, label="residual = correction")
        ax.axhline(0.0, color="k", lw=0.5)
        ax.set(xlabel=f"correction of the term ({unit})",
               ylabel=f"{obs} residual, measured − model ({unit})")  # fmt: skip
        kind = "named" if entry in report["discovery"]["named"] else "proposed, not named"
        ax.set_title(f"({letter}) " + "\n".join(textwrap.wrap(
            f"{entry['description']} ({kind}; gain {entry['gain']['gain_pct']:.0f} %)", 40)),
            fontsize=7, loc="left")  # fmt: skip
        ax.legend(fontsize=6)
    return fig
