"""The verdict for a reader: a discrepancy report in a few lines of words and tables.

The same text serves three views: ``summary.md`` beside the report's JSON, the figure's title
block and the HTML report. Everything in it is read from the report (and, where one parameter
is fitted two ways, from the other fit), so its numbers are the JSON's.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence


def unit_text(unit: str) -> str:
    """A unit key as text (N·m for Nm, N·m·s for Nm_s; 'log' is a relative error in log units)."""
    return "log units" if unit == "log" else unit.replace("Nm", "N·m").replace("_", "·")


def pattern(correlates_with: str) -> str:
    """How a residual departs from noise, in words, from the test that flagged it."""
    return {"overall": "is larger than the noise allows",
            "autocorrelation": "is correlated in time",
            "trial time": "drifts over the trial"}.get(
        correlates_with, f"follows {correlates_with}")  # fmt: skip


def interval_text(value: float, interval: Sequence[float] | None, unit: str) -> str:
    """'65.6 [65.3, 65.9] N·m/rad': an estimate with its 95 % interval and unit."""
    ci = "" if interval is None else f" [{interval[0]:.3g}, {interval[1]:.3g}]"
    return f"{value:.3g}{ci}" + ("" if unit in ("1", "") else f" {unit_text(unit)}")


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


def effect_rows(entries: Sequence[Mapping]) -> list[tuple[str, str, str]]:
    """(effect or term, parameter meaning, estimate [95 % interval] unit) per parameter."""
    rows = []
    for entry in entries:
        name = entry.get("effect", entry.get("term"))
        intervals, units = entry.get("ci95") or {}, entry.get("units") or {}
        for parameter, value in entry["parameters"].items():
            rows.append((name.replace("_", " "), parameter,
                         interval_text(value, intervals.get(parameter),
                                       units.get(parameter, "1"))))  # fmt: skip
    return rows


def left_unexplained(report: Mapping) -> str:
    """What is left unexplained, in words (or that nothing is, and why)."""
    verdict = report["unexplained"]
    if not verdict["flag"]:
        return (
            "Nothing: every residual test is within its noise threshold, or the structure it "
            "finds is below its size floor (see the residual tests)."
        )
    names = report.get("observable_names", {})
    name = names.get(verdict["observable"], verdict["observable"])
    return (
        f"The held-out residual of the {name} {pattern(verdict['correlates_with'])} (statistic "
        f"{verdict['statistic']:.3g} against its noise threshold {verdict['threshold']:.3g}); "
        "nothing the engine may name accounts for it."
    )


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
        causes = "; ".join(f"{e} {text}" for e, _, text in effect_rows(entries))
        lines.append(f"{label}: {causes}")
    for term in report["discovery"]["named"]:
        lines.append(f"hypothesis: {term['description']}")
    lines.append("unexplained: " + ("nothing" if not report["unexplained"]["flag"] else
                                    left_unexplained(report).split(" (statistic")[0]))  # fmt: skip
    return lines


def fitted_twice(fits: Mapping[str, Mapping]) -> list[dict]:
    """Parameters estimated by more than one fit: each fit's estimate and interval, and why the
    numbers may differ (the effects one model holds and the other lacks; whether the 95 %
    intervals overlap). ``fits``: label -> {"parameters", "ci95" (or None), "effects"}."""
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
        reason = "Each fit sizes this parameter inside its own model and data"
        if differs:
            reason += (f"; the models differ ({differs}), and what an effect explains in one "
                       "model this parameter must explain in another")  # fmt: skip
        if overlap is not None:
            reason += f"; their 95 % intervals {'overlap' if overlap else 'do not overlap'}"
        reason += "."
        out.append({
            "parameter": parameter,
            "estimates": {label: (fit["parameters"][parameter],
                                  fit["ci95"].get(parameter) if fit["ci95"] else None)
                          for label, fit in having.items()},
            "reason": reason,
        })  # fmt: skip
    return out


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


def _table(header: Sequence[str], rows: Sequence[Sequence]) -> list[str]:
    """A Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]


def report_section(title: str, report: Mapping) -> list[str]:
    """One report's verdict as Markdown: the sentence, the error before and after, the causes
    with intervals, the hypotheses, what is left and every residual test's decision."""
    baseline = report["baseline"]["model"]
    kind = "held-out " if report["gain"]["held_out"] else "in-sample "
    lines = [f"## {title}", "", report["cause"], "", f"### What the {baseline} gets wrong", ""]
    lines += _table(
        ["observable", f"{kind}RMSE, baseline", f"{kind}RMSE, extended model", "unit"],
        [(n, f"{b:.3g}", f"{a:.3g}", unit_text(u)) for n, b, a, u in rmse_rows(report)],
    )
    found = report["effects_found"]
    entries = found or report["tentative"]
    heading = "Causes claimed" if found else "Causes tentative (not claimed: structure remains)"
    lines += ["", f"### {heading}", ""]
    if entries:
        lines += _table(["effect", "parameter", "estimate [95 % interval]"], effect_rows(entries))
    else:
        lines.append("None.")
    for kind_, terms in (
        ("Hypotheses for the lab to check", report["discovery"]["named"]),
        ("Terms proposed, not named", report["discovery"]["proposed"]),
    ):
        if terms:
            lines += ["", f"### {kind_}", "", *(f"- {t['statement']}" for t in terms)]
    lines += ["", "### Left unexplained", "", left_unexplained(report), "", "### Residual tests",
              ""]  # fmt: skip
    names = report.get("observable_names", {})
    lines += _table(
        ["observable", "against", "decision"],
        [(names.get(t["observable"], t["observable"]), t["correlates_with"], t["decision"])
         for t in report["unexplained"]["tests"]],
    )  # fmt: skip
    return [*lines, ""]


def markdown(sections: Sequence[tuple[str, Mapping]], fits: Mapping[str, Mapping] = (),
             heading: str = "Verdict") -> str:  # fmt: skip
    """``summary.md``: each report's section, then the parameters fitted more than one way."""
    lines = [f"# {heading}", ""]
    for title, report in sections:
        lines += report_section(title, report)
    twice = fitted_twice(dict(fits)) if fits else []
    if twice:
        lines += ["## The same parameter, fitted more than one way", ""]
        labels = list(dict(fits))
        rows = []
        for row in twice:
            cells = []
            for label in labels:
                if label in row["estimates"]:
                    value, ci = row["estimates"][label]
                    cells.append(interval_text(value, ci, dict(fits)[label]["units"].get(
                        row["parameter"], "1")))  # fmt: skip
                else:
                    cells.append("—")
            rows.append((row["parameter"], *cells))
        lines += _table(["parameter", *labels], rows)
        lines += ["", *(f"- `{row['parameter']}`: {row['reason']}" for row in twice), ""]
    return "\n".join(lines) + "\n"
