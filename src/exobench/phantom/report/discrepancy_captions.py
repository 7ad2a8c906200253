"""Captions of the model-discrepancy figures: what each panel draws, over which window and how
many strides, and which table holds the numbers (read from the tables the figures draw)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from exobench.phantom.report import discovery_plots
from exobench.phantom.report.plots import count_text
from exobench.phantom.study.statistics import SPRING
from exobench.selection import summary
from exobench.studies import PHANTOM


def sample(predictions: pd.DataFrame) -> str:
    """The engine's strides and window as a caption states them."""
    strides = discovery_plots.engine_sample(predictions).groupby(SPRING)["stride"].nunique()
    return (
        f"{count_text(strides)[4:]} strides per spring (the engine's sample, at most "
        "``phantom.discrepancy.max_strides_per_trial`` spread over each trial), each over "
        f"t = {discovery_plots.window_text(predictions)} from the stride's start (the engaged "
        "window ``phantom.discrepancy.window_pct`` with its margins)"
    )


def loop_strides(predictions: pd.DataFrame) -> str:
    """Every stride the loop panels draw, per spring, as a caption counts them."""
    springs = sorted(predictions[SPRING].unique())
    counts = predictions.drop_duplicates(["trial", "stride"]).groupby(SPRING).size()
    return ", ".join(f"{counts[s]} at {s / 1e3:g} kN/m" for s in (springs[0], springs[-1]))


def verdict(report: Mapping) -> str:
    """The verdict of ``summary.md`` in one sentence, every effect under the name the figure
    gives it (its description, with the description in full once)."""
    block = summary.title_block(report)
    table = discovery_plots.estimates(report)
    parts = [block[0]]
    for status, rows in table.groupby("status", sort=False):
        listed = "; ".join(
            f"{r.effect}{': ' + r.meaning if r.many and r.meaning else ''} "
            + discovery_plots.value_text(
                r.estimate, None if np.isnan(r.low) else (r.low, r.high), r.unit
            )
            + (f" at its {r.bound} fit bound" if r.bound else "")
            for r in rows.itertuples()
        )
        parts.append(f"{discovery_plots.STATUS[status]['label']}: {listed}")
    parts.append(block[-1])
    described = "; ".join(dict.fromkeys(table["description"]))
    return "; ".join(parts) + (
        f". The effects, as the report describes them: {described}" if described else ""
    )


def special(report: Mapping) -> list[str]:
    """Sentences on the estimates that need one: at a fit bound, without an interval."""
    table = discovery_plots.estimates(report)
    out = []
    bound = table[table["bound"] != ""]
    if len(bound):
        listed = ", ".join(f"{r.effect} (at its {r.bound} fit bound "
                           f"{discovery_plots.plain(r.bound_value)})"
                           for r in bound.itertuples())  # fmt: skip
        out.append(
            f"At a fit bound (red triangle pointing at the bound): {listed}; an estimate there "
            "is where the search stopped, not a measured value, and its interval is cut by the "
            "bound."
        )
    bare = table[table["low"].isna()]
    if len(bare):
        listed = ", ".join(dict.fromkeys(bare["effect"]))
        out.append(f"Without an interval (no whisker): {listed}.")
    return out


def discrepancy(
    predictions: pd.DataFrame,
    recordings: Mapping,
    summary_table: pd.DataFrame,
    protocol: Mapping,
    reported: Mapping | None = None,
    paper: pd.DataFrame | None = None,
) -> tuple:
    """Caption of ``discrepancy.png``: measured vs rigid theory vs the selected model."""
    peak = summary_table[summary_table["metric"] == discovery_plots.PEAK]
    window = discovery_plots.work_window(protocol)
    table = discovery_plots.estimates(recordings)
    errors = discovery_plots.model_errors(predictions)
    return (
        f"What the simulation gets wrong: the measured knee moment against {PHANTOM.key}'s rigid "
        "theory (eqs. 2.1–2.2, baseline) and the model the discrepancy engine selected "
        "(extended). The line on top is the error the extended model cuts most (held-out, "
        "pooled over the springs).",
        f"Panel (a): peak stance moment, each stride's largest knee moment over {window} "
        f"(``peak_moment_Nm``), median over the {count_text(peak['n'])[4:]} included strides of "
        "each spring; whiskers: first and third quartiles. These are the medians and quartiles "
        "of ``summary.csv``, the strides and window of figure 6 (whose bars show the mean)."
        + (
            f" Crosses: the medians {PHANTOM.key} report (``seed000_reported.csv``); squares: the "
            "same quantity predicted by the model the engine fitted to them "
            "(``discrepancy_reported.json``, ``predictions``)."
            if reported is not None
            else ""
        ),
        "Panel (b): root-mean-square difference of each model from the measured knee moment "
        f"per spring, over the engine's sample: {sample(predictions)} "
        "(``discrepancy_predictions.parquet``; in-sample, the models fitted to every stride "
        f"of the sample). Rigid theory {errors['baseline'].min():.3g}–"
        f"{errors['baseline'].max():.3g} N·m, extended model {errors['extended'].min():.3g}–"
        f"{errors['extended'].max():.3g} N·m (log scale).",
        "Panel (c): every parameter the recordings' model claims, holds tentatively or names "
        "as a hypothesis (``discrepancy.json``): marker, its estimate; whiskers, its 95 % "
        "interval; both as the difference from the estimate in % of the estimate's magnitude, "
        "so that parameters of any unit and sign share the axis; the values and units are in "
        "the labels"
        + (
            f"; squares: the estimate of the same parameter from {PHANTOM.key}'s medians"
            if reported is not None
            else ""
        )
        + (". No effect is claimed, held tentatively or named." if table.empty else ".")
        + (" " + " ".join(special(recordings)) if special(recordings) else ""),
        "Panels (d) and (e): knee moment against phantom knee angle over the same window for "
        "the softest and the stiffest spring, over every included stride of the spring, not "
        f"the engine's sample ({loop_strides(predictions)}; the models, fitted to the sample, "
        "predict the other strides): each stride's measured loop (thin grey) and the mean "
        "loop measured (wide grey line), of the rigid theory (dashed) and of the extended "
        "model (blue, drawn on top of the measurement). The mean loop's peak is not the "
        "median of the strides' peaks of panel (a): strides peak at different angles, and "
        "the mean flattens them.",
        f"The verdict (``summary.md``): {verdict(recordings)}. ``discrepancy.json`` lists "
        "every candidate with its held-out error, the effects with 95 % intervals, the "
        "unexplained verdict, the cause and the gain.",
    )


def terms(predictions: pd.DataFrame, report: Mapping) -> tuple:
    """Caption of ``discrepancy_terms.png``: what the extended model leaves, and the residual
    each discovered term explains."""
    discovery = report.get("discovery", {})
    entries = [*discovery.get("named", []), *discovery.get("proposed", [])]
    noise = report.get("noise_scales", {}).get("moment_Nm")
    flagged = report.get("unexplained", {}).get("flag", False)
    left = discovery_plots.residuals(predictions)
    largest = float(np.nanmax(np.abs(left.to_numpy()))) if left.size else float("nan")
    panels = "Panel (b)" if len(entries) == 1 else f"Panels (b)–({chr(97 + len(entries))})"
    return (
        "What the extended model leaves unexplained in the knee moment, and the terms "
        "discovered outside the effect registry (``discrepancy.json``, key ``discovery``).",
        ("Panel (a): knee" if entries else "Knee")
        + " moment measured minus the extended model, mean over the engine's "
        f"strides of each spring per time in the window: {sample(predictions)} "
        "(``discrepancy_predictions.parquet``)"
        + (
            f"; band: ± 1 SD of the knee moment's noise in the disengaged swing ({noise:.3g} "
            "N·m, ``noise_scales``)"
            if noise is not None
            else ""
        )
        + f". The largest mean residual is {largest:.3g} N·m. The residual tests "
        + (
            "flag structure the engine cannot name: " + summary.left_unexplained(report)
            if flagged
            else "find nothing left unexplained (``summary.md``, residual tests)."
        ),
        (
            f"{panels}: per discovered term, in the observable where its correction is "
            "largest, the residual (measured − model) of the report's model without the term "
            "(grey) and with it (blue) against the correction the term makes; points: means in "
            f"{discovery_plots.BINS} quantile bins of the correction over every counted sample "
            "of the analysed strides, whiskers: ± 1 SD in the bin. A term that explains the "
            "residual puts grey on the dotted diagonal and blue on zero. The samples are in "
            "``discrepancy_terms.parquet``."
            if entries
            else "No term was discovered: "
            + (
                "no library term removes the structure left unexplained."
                if discovery.get("searched")
                else "the registry leaves nothing unexplained, so the library was not searched."
            )
        ),
        "The library is searched only when the registry leaves structure unexplained; a term "
        "is named only when the model with it leaves nothing flagged and its 95 % interval "
        "excludes the neutral value (else it is shown as proposed).",
    )
