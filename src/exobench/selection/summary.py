"""The verdict for a reader: a discrepancy report in a few lines of words and tables.

The same text serves three views: ``summary.md`` beside the report's JSON, the figure's title
block and the HTML report. Everything in it is read from the report (and, where one parameter
is fitted two ways, from the other fit), so its numbers are the JSON's.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np


def unit_text(unit: str) -> str:
    """A unit key as text (N·m for Nm, N·m·s for Nm_s; 'log' is a relative error in log units)."""
    return "log units" if unit == "log" else unit.replace("Nm", "N·m").replace("_", "·")


def number(value: float) -> str:
    """Three significant digits, without an exponent from 0.001 to a million (1050, not
    1.05e+03)."""
    if value == 0 or not 1e-3 <= abs(value) < 1e6:
        return f"{value:.3g}"
    digits = 2 - int(np.floor(np.log10(abs(value))))
    return f"{round(value, digits):.{max(digits, 0)}f}"


def interval_number(x: float, value: float, interval: Sequence[float],
                    apart: float | None = None) -> str:  # fmt: skip
    """One number of an estimate with its interval, with at least three significant digits and
    as many decimals as keep the interval's two ends apart: '298.9' in '299.0 [298.9, 299.1]',
    not '299 [299, 299]' (and, for a value ``apart`` outside the interval, its nearer end apart
    from that value: '[0.9703, 1.0300]' beside a set 0.97, not '[0.970, 1.03]')."""
    largest = max(abs(value), abs(interval[0]), abs(interval[1]))
    width = abs(interval[1] - interval[0])
    if largest == 0 or not np.isfinite(largest):
        return number(x)
    top = int(np.floor(np.log10(largest)))
    fixed = 1e-3 <= largest < 1e6

    def text(v: float, decimals: int) -> str:
        return f"{v:.{max(decimals, 0)}f}" if fixed else f"{v:.{max(decimals + top + 1, 1)}g}"

    decimals = 2 - top if width == 0 else max(2 - top, -int(np.floor(np.log10(width))))
    outside = apart is not None and not interval[0] <= apart <= interval[1]
    near = min(interval, key=lambda end: abs(end - apart)) if outside else None

    def alike(decimals: int) -> bool:
        """Whether the two ends, or ``apart`` and its nearer end, read the same."""
        ends = width > 0 and text(interval[0], decimals) == text(interval[1], decimals)
        return ends or (outside and text(apart, decimals) == text(near, decimals))

    while decimals < 15 and alike(decimals):
        decimals += 1
    return text(x, decimals)


def at_bound(value: float, bounds: Sequence[float] | None) -> str | None:
    """'lower' or 'upper' when a value sits at that search bound (to 1 part in 10⁶), else None."""
    if bounds is None:
        return None
    for side, bound in zip(("lower", "upper"), bounds, strict=True):
        if abs(value - bound) <= 1e-6 * max(abs(bound), 1e-12):
            return side
    return None


def pattern(correlates_with: str) -> str:
    """How a residual departs from noise, in words, from the test that flagged it."""
    return {"overall": "is larger than the noise allows",
            "stated uncertainty": "misses its number by more than its stated uncertainty",
            "autocorrelation": "is correlated in time",
            "trial time": "drifts over the trial"}.get(
        correlates_with, f"follows {correlates_with}")  # fmt: skip


def interval_text(value: float, interval: Sequence[float] | None, unit: str,
                  bounds: Sequence[float] | None = None,
                  apart: float | None = None) -> str:  # fmt: skip
    """'65.6 [65.3, 65.9] N·m/rad': an estimate with its 95 % interval and unit; with the
    parameter's search ``bounds``, an estimate at a bound says so instead of giving an interval
    ('3 (at the upper search bound)'), and an interval reaching one says which (``apart``: a
    value, such as the one a twin set, that the interval's digits must show inside or out,
    :func:`interval_number`)."""
    side = at_bound(value, bounds)
    scale = 1e3 if unit == "N/m" and abs(value) >= 1e3 else 1.0  # spring rates in kN/m
    value, interval = value / scale, None if interval is None else [v / scale for v in interval]
    apart = None if apart is None else apart / scale
    unit = "kN/m" if scale > 1 else unit
    unit = "" if unit in ("1", "") else f" {unit_text(unit)}"
    if side:
        return f"{number(value)}{unit} (at the {side} search bound)"
    if interval is None:
        return f"{number(value)}{unit}"
    low, high = (interval_number(v, value, interval, apart) for v in interval)
    text = f"{interval_number(value, value, interval, apart)} [{low}, {high}]{unit}"
    if interval[1] == interval[0]:
        text += " (an interval of zero width)"
    reached = [s for s in (at_bound(interval[0], bounds), at_bound(interval[1], bounds)) if s]
    return text + (f" (the interval reaches the {reached[0]} search bound)" if reached else "")


def bounds_of(report: Mapping) -> dict[str, list[float]]:
    """Search bounds of every parameter of a report's registry and term library."""
    entries = [*report.get("registry", {}).values(),
               *report.get("discovery", {}).get("library", {}).values()]  # fmt: skip
    return {p["name"]: p["bounds"] for e in entries for p in e["parameters"]}


def rmse_rows(report: Mapping) -> list[tuple[str, float, float, str]]:
    """(observable in words, baseline RMSE, extended-model RMSE, unit) per observable."""
    gain = report["gain"]
    names = report.get("observable_names", {})
    units = report["observables"]
    return [
        (names.get(obs, obs), gain["baseline_rmse"][f"{obs}_{units[obs]}"],
         gain["extended_rmse"][f"{obs}_{units[obs]}"], units[obs])
        for obs in report.get("observable_order", units)
    ]  # fmt: skip


def headline(rows: Sequence[tuple[str, float, float, str]]) -> tuple[str, float, float, str]:
    """The observable whose error the extended model cuts most (relative to the baseline's; the
    first of equals), for the one-line gain."""
    cut = [(before - after) / before if before > 0 else 0.0 for _, before, after, _ in rows]
    return rows[max(range(len(rows)), key=lambda i: (round(cut[i], 3), -i))]


def short_name(description: str) -> str:
    """An effect's name without where it lives: 'interface damping (soft tissue …)' →
    'interface damping'."""
    return description.split(" (")[0]


def effect_rows(entries: Sequence[Mapping], bounds: Mapping[str, Sequence[float]] = {}
                ) -> list[tuple[str, str, str]]:  # fmt: skip
    """(effect or term, parameter, estimate [95 % interval] unit) per parameter; an estimate or
    interval at a search bound (``bounds``: parameter -> [low, high]) says so."""
    rows = []
    for entry in entries:
        name = short_name(entry["description"]) if entry.get("description") else entry.get(
            "effect", entry.get("term")).replace("_", " ")  # fmt: skip
        intervals, units = entry.get("ci95") or {}, entry.get("units") or {}
        for parameter, value in entry["parameters"].items():
            rows.append((name, parameter,
                         interval_text(value, intervals.get(parameter),
                                       units.get(parameter, "1"), bounds.get(parameter))
                         + other_readings(entry, parameter)))  # fmt: skip
    return rows


def other_readings(entry: Mapping, parameter: str) -> str:
    """' (cannot be told from soft-tissue artefact locked to the gait: 1.00 with it)': the
    readings a claimed estimate cannot be told from (its interval holds them), else ''."""
    said = [f"{short_name(r['description'])}: {number(r['parameters'][parameter])} with it"
            for r in entry.get("cannot_tell", []) if parameter in r["parameters"]]  # fmt: skip
    return f" (cannot be told from {'; '.join(said)})" if said else ""


def _difference(entry: Mapping, departed: Mapping) -> str:
    """A departing trial's difference from the others with its 95 % interval: a share for a
    log-scale parameter (e^d − 1), else in the parameter's unit."""
    d, (low, high) = departed["difference"], departed["difference_ci95"]
    if entry["relative"]:
        return (f"{100 * np.expm1(d):+.0f} % [{100 * np.expm1(low):+.0f}, "
                f"{100 * np.expm1(high):+.0f}]")  # fmt: skip
    unit = "" if entry["unit"] in ("1", "") else f" {unit_text(entry['unit'])}"
    return f"{number(d):s} [{number(low)}, {number(high)}]{unit}"


def departed_text(entry: Mapping) -> str:
    """'trial k09200 departs, 51.3 [49.0, 53.7] N·m/rad against 65.2 for the others (−21 %
    [−25, −17])', for every departing trial of a flagged constant."""
    trials = {t["trial"]: t for t in entry["trials"]}
    parts = []
    for d in entry["departing"]:
        own = trials[d["trial"]]
        estimate = interval_text(own["estimate"], own["ci95"], entry["unit"])
        parts.append(f"{d['trial']} {estimate} against {number(d['others'])} for the others "
                     f"({_difference(entry, d)})")  # fmt: skip
    if len(parts) == 1:
        return f"trial {parts[0].replace(' ', ' departs, ', 1)}"
    return "trials " + ", ".join(d["trial"] for d in entry["departing"]) + " depart: " + (
        "; ".join(parts))  # fmt: skip


def between_trials(stability: Mapping) -> str:
    """The constants that differ between trials, in words: which parameter (and the row of the
    assumption table), the test and the trials that depart with their estimates (refitted there
    where the model holds their shifts, :mod:`.between`)."""
    sentences = []
    for entry in (e for e in stability["constants"] if e["flag"]):
        df1, df2 = entry["df"]
        said = ("Refitted in the trials it moved in" if entry.get("refitted")
                else "Left unexplained between trials")  # fmt: skip
        sentences.append(
            f"{said}: the {entry['name']} ({entry['parameter']}; "
            f"`{entry['assumption']}`) differs from trial to trial (Welch's F = "
            f"{entry['statistic']:.3g} on {df1:.0f} and {df2:.3g} degrees of freedom, p = "
            f"{entry['p']:.2g}, Holm-adjusted {entry['p_adjusted']:.2g}); "
            f"{departed_text(entry)}."
        )
    return " ".join(sentences)


def unsized_text(stability: Mapping) -> str:
    """The trials that do not size a constant (its 95 % interval holds the whole search range),
    in words, with the parameters of that trial alone it cannot be told from; else ''."""
    sentences = []
    for entry in stability.get("constants", []):
        for u in entry.get("unsized", []):
            told = (f": it cannot be told from {', '.join(u['with'])}, a parameter of that "
                    "trial alone" if u["with"] else "")  # fmt: skip
            sentences.append(f"Trial {u['trial']} does not size the {entry['name']} "
                             f"({entry['parameter']}; its 95 % interval holds the whole search "
                             f"range){told}, so it is not compared with the others.")  # fmt: skip
    return " ".join(sentences)


def left_unexplained(report: Mapping) -> str:
    """What is left unexplained, in words (or that nothing is, and why): the residual's
    structure, the constants of the rig that differ between trials, and the trials that do not
    size a constant (:func:`unsized_text`)."""
    verdict = report["unexplained"]
    stability = report.get("stability") or {"flag": False}
    between = between_trials(stability) if stability["flag"] else ""
    between = f"{between} {unsized_text(stability)}".strip()
    if not verdict["flag"] and report.get("readings"):
        names = report.get("observable_names", {})
        seen = "; ".join(f"the {names.get(t['observable'], t['observable'])} "
                         f"{pattern(t['correlates_with'])}" for t in verdict["tests"]
                         if t["statistic"] > t["threshold"])  # fmt: skip
        told = "; ".join(
            f"{', '.join(r['moves'])} from {short_name(r['description'])} (with it: "
            + ", ".join(f"{p} {number(m['estimate'])}" for p, m in r["moves"].items())
            + ")"
            for r in report["readings"]
        )
        what = (f"A pattern beyond the noise that the residual tests find too small to count "
                f"({seen})" if seen else "What a direct check of the recordings sees")  # fmt: skip
        return (
            f"{what}, and estimates the data cannot tell from what would account for it: "
            f"{told}. Their intervals hold either reading; which one is right needs a check "
            f"on the rig (see the residual tests). {between}"
        ).strip()
    if not verdict["flag"]:
        if stability["flag"]:
            return ("Within each trial, every residual test is within its noise threshold, or "
                    f"the structure it finds is below its size floor. {between}")  # fmt: skip
        tested = any(e["tested"] for e in stability.get("constants", []))
        return (
            "Nothing: every residual test is within its noise threshold, or the structure it "
            "finds is below its size floor (see the residual tests)"
            + (", and the constants that must hold between trials agree from trial to trial"
               + (" where a trial sizes them. " if between else ".") if tested else ". ")
            + between
        ).strip()  # fmt: skip
    names = report.get("observable_names", {})
    name = names.get(verdict["observable"], verdict["observable"])
    return (
        f"The held-out residual of the {name} {pattern(verdict['correlates_with'])} (statistic "
        f"{verdict['statistic']:.3g} against its noise threshold {verdict['threshold']:.3g}); "
        f"nothing the engine may name accounts for it. {between}"
    ).strip()


def title_block(report: Mapping) -> list[str]:
    """The verdict in at most four short lines: the gain, the causes, what is left."""
    name, before, after, unit = headline(rmse_rows(report))
    kind = "held-out " if report["gain"]["held_out"] else ""
    lines = [f"{report['baseline']['model']}: {kind}{name} RMSE {before:.3g} → {after:.3g} "
             f"{unit_text(unit)}"]  # fmt: skip
    found = report["effects_found"]
    entries = found or report["tentative"]
    if entries:
        label = "claimed" if found else "tentative, not claimed"
        causes = "; ".join(f"{e} {text}" for e, _, text in effect_rows(entries, bounds_of(report)))
        lines.append(f"{label}: {causes}")
    for term in report["discovery"]["named"]:
        lines.append(f"hypothesis: {term['description']}")
    parts = []
    if report["unexplained"]["flag"]:
        parts.append(left_unexplained(report).split(" (statistic")[0])
    elif report.get("readings"):
        parts.append("estimates not told apart")
    for entry in (e for e in (report.get("stability") or {}).get("constants", [])
                  if e["flag"] and not e.get("refitted")):  # fmt: skip
        trials = ", ".join(d["trial"] for d in entry["departing"])
        parts.append(f"the {entry['name']} differs between trials ({trials})")
    for entry in (report.get("stability") or {}).get("constants", []):
        if entry.get("unsized"):
            trials = ", ".join(u["trial"] for u in entry["unsized"])
            parts.append(f"the {entry['name']} not sized in {trials}")
    lines.append("unexplained: " + ("; ".join(parts) or "nothing"))
    return lines


# Why one parameter fitted by several models may differ, said once above their list.
FITTED_TWICE = (
    "Each fit sizes a parameter inside its own model and data: what an effect explains in one "
    "model, the parameter must explain in a model that lacks the effect."
)


def fitted_twice(fits: Mapping[str, Mapping]) -> list[dict]:
    """Parameters estimated by more than one fit: each fit's estimate and interval, and what
    separates the fits (the effects one model holds and the other lacks; whether the 95 %
    intervals overlap; :data:`FITTED_TWICE` says why that matters).
    ``fits``: label -> {"parameters", "ci95" (or None), "effects"}."""
    names = sorted({p for fit in fits.values() for p in fit["parameters"]})
    out = []
    for parameter in names:
        having = {label: fit for label, fit in fits.items() if parameter in fit["parameters"]}
        if len(having) < 2:
            continue
        effects = {label: set(fit["effects"]) for label, fit in having.items()}
        common = set.intersection(*effects.values())
        extra = {label: sorted(e - common) for label, e in effects.items()}
        intervals = [fit["ci95"].get(parameter) for fit in having.values() if fit["ci95"]]
        intervals = [ci for ci in intervals if ci is not None]  # a parameter without one
        overlap = (
            None if len(intervals) < 2
            else max(lo for lo, _ in intervals) <= min(hi for _, hi in intervals)
        )  # fmt: skip
        differs = "; ".join(
            f"{label}: + {', '.join(x.replace('_', ' ') for x in more)}"
            for label, more in extra.items() if more
        )  # fmt: skip
        parts = [f"the models differ ({differs})" if differs else "the models hold the same "
                 "effects"]  # fmt: skip
        if overlap is not None:
            parts.append(f"their 95 % intervals {'overlap' if overlap else 'do not overlap'}")
        reason = "; ".join(parts) + "."
        out.append({
            "parameter": parameter,
            "estimates": {label: (fit["parameters"][parameter],
                                  fit["ci95"].get(parameter) if fit["ci95"] else None)
                          for label, fit in having.items()},
            "reason": reason,
        })  # fmt: skip
    return out


def term_statement(term: Mapping, library: Mapping[str, Mapping]) -> str:
    """A named or proposed term as a hypothesis for the lab, in words: its size with interval
    (or the search bound it sits at), the share of the remaining held-out error it removes (of
    the observables it was found on, where that is not all of them: its ``basis``), and the
    terms that would serve as well. ``library``: the report's term library."""
    spec = {p["name"]: p for p in library[term["term"]]["parameters"]}
    sizes = "; ".join(
        f"{spec[name]['meaning']} "
        + interval_text(value, term["ci95"][name], term["units"][name], spec[name]["bounds"])
        for name, value in term["parameters"].items()
    )
    whose = " of those observables" if term.get("basis") else ""
    text = (f"Hypothesis for the lab to check{term.get('basis', '')}: {term['description']} "
            f"({sizes}; it removes {term['gain']['gain_pct']:.0f} % of the remaining held-out "
            f"error{whose})")  # fmt: skip
    if term.get("alternatives"):
        alike = [short_name(library[a]["description"]) for a in term["alternatives"]]
        text += "; " + " or ".join(alike) + " would explain the data as well"
    return text + "."


def as_fit(report: Mapping) -> dict:
    """A discrepancy report as one fit for :func:`fitted_twice` (its effects found or tentative
    and its named terms)."""
    entries = [*report["effects_found"], *report["tentative"], *report["discovery"]["named"]]
    return {
        "parameters": {k: v for e in entries for k, v in e["parameters"].items()},
        "ci95": {k: v for e in entries for k, v in (e.get("ci95") or {}).items()},
        "units": {k: v for e in entries for k, v in (e.get("units") or {}).items()},
        "effects": [e.get("effect", e.get("term")) for e in entries],
    }


def point_fit(parameters: Mapping[str, float], units: Mapping[str, str],
              effects: Sequence[str]) -> dict:  # fmt: skip
    """A fit known by its estimates only (no intervals, e.g. a calibration) as one fit for
    :func:`fitted_twice`."""
    return {"parameters": dict(parameters), "ci95": None, "units": dict(units),
            "effects": list(effects)}  # fmt: skip


def table(header: Sequence[str], rows: Sequence[Sequence]) -> list[str]:
    """A Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
