"""The validation figure: the twin arm's coverage and detection, the open-world arm's
outcomes."""

from __future__ import annotations

import numpy as np
import pandas as pd

from exobench import figures
from exobench.phantom.model import effects
from exobench.phantom.validation import openworld
from exobench.phantom.validation.twin_arm import relative_size
from exobench.selection import openworld as scoring


def figure(rows: pd.DataFrame, table: pd.DataFrame, openworld_rows: pd.DataFrame,
           openworld_table: pd.DataFrame):  # fmt: skip
    """Coverage and detection rate per effect (with the 90–98 % target band), detection as a
    function of effect size, per number of strides, and the open-world and combined arms on the
    independent generator's recordings (:func:`exobench.selection.openworld.outcome_panel`)."""
    fig, axes = figures.new_figure(3, 1, width=14.0, height=4.6)
    scoring.outcome_panel(axes[0, 2], openworld.ARM, openworld_rows, openworld_table)
    per = table[table["effect"].isin(list(effects.REGISTRY))].reset_index(drop=True)
    ax = axes[0, 0]
    x = np.arange(len(per))
    ax.axhspan(0.90, 0.98, color="0.9", label="coverage target 90–98 %")
    ax.bar(x - 0.2, per["coverage_95"], width=0.4, color="#0072B2", label="95 % interval coverage")
    ax.bar(x + 0.2, per["detection_rate"], width=0.4, color="#E69F00", label="detection rate")
    ax.plot(x, per["false_claim_rate"], "kx", label="false-claim rate")
    ax.set_xticks(x, [e.replace("_", " ") for e in per["effect"]], rotation=60, ha="right",
                  fontsize=6)  # fmt: skip
    none = table[table["effect"] == "no-effect cases"].iloc[0]
    ax.set(ylim=(0, 1.05), ylabel="share of cases",
           title=f"false positives, no-effect data: {none['false_positive_rate']:.0%}\n"
           f"({int(none['cases_hidden'])} cases)")  # fmt: skip
    ax.legend(fontsize=6, loc="lower left")
    ax = axes[0, 1]
    present = rows[rows["hidden"]]
    colours = figures.ordered_colours(present["strides_per_trial"].nunique())
    for colour, (strides, group) in zip(colours, present.groupby("strides_per_trial"), strict=True):
        size = [
            relative_size(effect, name, value)
            for effect, name, value in zip(group["effect"], group["parameter"], group["truth"],
                                           strict=True)
        ]  # fmt: skip
        jitter = np.linspace(-0.04, 0.04, len(size))
        ax.plot(size, group["claimed"].astype(float) + jitter, "o", ms=3, color=colour,
                label=f"{strides} strides per trial")  # fmt: skip
    ax.set_xscale("log")
    ax.set(xlabel="effect size / top of its documented detectable range",
           ylabel="claimed (1) or not (0)", title="detection against effect size")  # fmt: skip
    ax.legend(fontsize=6)
    return fig
