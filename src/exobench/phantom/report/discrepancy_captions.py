"""Captions of the model-discrepancy figures: what each panel draws, over which window and how
many strides (read from the tables the figures draw)."""

from __future__ import annotations

from collections.abc import Mapping

import pandas as pd

from exobench.phantom.study.statistics import SPRING
from exobench.studies import PHANTOM


def sample(predictions: pd.DataFrame) -> str:
    """The engine's strides and window as a caption states them."""
    strides = predictions.groupby(SPRING)["stride"].nunique()
    low, high = int(strides.min()), int(strides.max())
    count = f"{low}" if low == high else f"{low}–{high}"
    return (
        f"{count} strides per spring (the engine's sample, at most "
        "``phantom.discrepancy.max_strides_per_trial`` spread over each trial), each over "
        f"t = {predictions['t_s'].min():g}–{predictions['t_s'].max():g} s from the stride's "
        "start (the engaged window ``phantom.discrepancy.window_pct`` with its margins)"
    )


def discrepancy(predictions: pd.DataFrame, recordings: Mapping, reported: Mapping | None) -> tuple:
    """Caption of ``discrepancy.png``: measured vs rigid theory vs the selected model."""
    return (
        f"What the simulation gets wrong: the measured knee moment against {PHANTOM.key}'s rigid "
        "theory (eqs. 2.1–2.2, baseline) and the model the discrepancy engine selected "
        f"(extended), on {sample(predictions)}.",
        "Panel (a): peak knee moment per spring, each stride's largest moment in that window, "
        "median "
        "over the strides (log scale)"
        + (
            f"; squares: the model selected for the medians {PHANTOM.key} report "
            "(``discrepancy_reported.json``)"
            if reported is not None
            else ""
        )
        + ". This is not the peak stance moment of figure 6 and ``summary.csv`` (largest "
        "moment over the work window, every included stride).",
        "Panels (b) and (c): mean knee moment against mean phantom knee angle over that window "
        "for the "
        "softest and the stiffest spring.",
        "Panel (d): every parameter the recordings' model claims (or holds tentatively): dot, "
        "its estimate; whiskers, its 95 % interval; both relative to the estimate (log scale; "
        "the values are in the labels); squares: the estimate of the same parameter from "
        f"{PHANTOM.key}'s medians.",
        "The title block is the verdict of ``summary.md``: the error the extended model cuts "
        "most, the causes with their intervals and what is left unexplained. "
        "``discrepancy.json`` (and ``discrepancy_reported.json``, for "
        f"{PHANTOM.key}'s medians) list every candidate with its held-out error, the effects "
        "with 95 % intervals, the unexplained verdict, the cause and the gain; the predictions "
        "are in ``discrepancy_predictions.parquet``.",
    )


def terms(report: Mapping) -> tuple:
    """Caption of ``discrepancy_terms.png``: the residual each discovered term explains."""
    entries = [*report["discovery"]["named"], *report["discovery"]["proposed"]]
    panels = "(a)" if len(entries) < 2 else f"(a)–({chr(96 + len(entries))})"
    return (
        "Discovered terms: corrections outside the effect registry that the recordings earn, "
        "each a hypothesis for the lab to check (``discrepancy.json``, key ``discovery``).",
        f"Panels {panels}: per term, in the observable where its correction is largest, the "
        "residual "
        "(measured − model) of the report's model without the term (grey) and with it (blue) "
        "against the correction the term makes; points: means in 20 quantile bins of the "
        "correction over every counted sample of the analysed strides, whiskers: ± 1 SD in the "
        "bin. A term that explains the residual puts grey on the dotted diagonal and blue on "
        "zero."
        if entries
        else "No term is shown: "
        + (
            "no library term removes the structure left unexplained."
            if report["discovery"]["searched"]
            else "the registry leaves nothing unexplained, so the library was not searched."
        ),
        "The library is searched only when the registry leaves structure unexplained; a term "
        "is named only when the model with it leaves nothing flagged and its 95 % interval "
        "excludes the neutral value (else it is shown as proposed). The samples are in "
        "``discrepancy_terms.parquet``.",
    )
