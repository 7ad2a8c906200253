"""``summary.md`` for a skimming reader, and the residual tests in plain words beside it.

Its first screen holds the source, the studies, the verdict, what the run set against what it
recovered (or the claims, with a lab's data) and what is left unexplained; the details follow.
Each section is one small function returning Markdown lines, so a section is added by writing
one more and listing it where the document is put together (the group's rule script).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from exobench import document as frame
from exobench import studies
from exobench.selection import summary
from exobench.selection.summary import interval_text, number, table, unit_text

TESTS_FILE = "residual_tests.md"
AGAINST = {
    "overall": "a residual larger than the noise allows",
    "stated uncertainty": "a held-out miss beyond the number's stated uncertainty",
    "autocorrelation": "a residual correlated in time",
    "trial time": "a residual drifting over the trial",
}


def verdict(report: Mapping, context: str = "") -> list[str]:
    """The engine's verdict on the recordings, in one paragraph (``context``: a sentence that
    puts its pooled number in proportion)."""
    return ["## Verdict", "", f"{report['cause']} {context}".strip(), ""]


def _recovered(report: Mapping) -> dict[str, tuple[float, list | None, str, str, str]]:
    """Every parameter the report sizes (claimed or tentative): estimate, interval, unit, the
    effect it belongs to and the readings it cannot be told from (``summary.other_readings``)."""
    out = {}
    for entry in [*report["effects_found"], *report["tentative"], *report["discovery"]["named"]]:
        name = entry.get("effect", entry.get("term"))
        for p, value in entry["parameters"].items():
            out[p] = (value, entry["ci95"][p], entry["units"][p], name,
                      summary.other_readings(entry, p))  # fmt: skip
    return out


def twin_settings(effects: Mapping, calibrated: Mapping[str, float]) -> list[dict]:
    """The twin's enabled effects, one row per number it was given: effect, parameter, value
    and whether the calibration fitted it ('calibrated' in the config)."""
    rows = []
    for effect, block in effects.items():
        if not block.get("enabled", False):
            continue
        for parameter, value in block.items():
            fitted = value == "calibrated"
            if fitted:
                value = calibrated[parameter]
            if parameter == "enabled" or isinstance(value, bool | str | list):
                continue
            rows.append({"effect": effect, "parameter": parameter, "value": float(value),
                         "calibrated": fitted})  # fmt: skip
    return rows


def effect_name(report: Mapping, effect: str) -> str:
    """An effect or term by the one name it has everywhere (its description's), else its key
    in words."""
    entry = report["registry"].get(effect) or report["discovery"].get("library", {}).get(effect)
    return summary.short_name(entry["description"]) if entry else effect.replace("_", " ")


def _unit(parameter: str, units: Mapping[str, str]) -> str:
    """A parameter's unit: the engine's, else its name's suffix, else none."""
    if parameter in units:
        return units[parameter]
    from exobench.tables import unit_for

    try:
        return unit_for(parameter)
    except KeyError:
        return "1"


def _as_set(value: float, unit: str) -> str:
    """A value as the config gives it ('8', '0.15 mm'), with its unit."""
    return f"{value:g}" + ("" if unit in ("1", "") else f" {unit_text(unit)}")


def set_against_recovered(report: Mapping, settings: Sequence[Mapping],
                          aliases: Mapping[str, str] = {}) -> list[str]:  # fmt: skip
    """The twin's headline: every number set in the twin beside what the engine recovered from
    its recordings (``aliases``: twin parameter -> the engine's name), whether the set value
    lies inside the 95 % interval, and what the engine claimed that was not set."""
    bounds = summary.bounds_of(report)
    units = {p["name"]: p["unit"] for e in report["registry"].values() for p in e["parameters"]}
    recovered = _recovered(report)
    rows, others, used = [], [], set()
    for row in settings:
        name = aliases.get(row["parameter"], row["parameter"])
        unit = _unit(name, units)
        was = (interval_text(row["value"], None, unit) + " (calibrated)" if row["calibrated"]
               else _as_set(row["value"], unit))  # fmt: skip
        if name not in units:
            others.append(f"{row['effect'].replace('_', ' ')} {row['parameter']} {was}")
            continue
        used.add(name)
        if name in recovered:
            value, ci, unit, _, readings = recovered[name]
            inside = "—" if ci is None else ("yes" if ci[0] <= row["value"] <= ci[1] else "no")
            got = interval_text(value, ci, unit, bounds.get(name), row["value"]) + readings
        else:
            inside, got = "—", "not claimed"
        rows.append((effect_name(report, row["effect"]), name, was, got, inside))
    for name, (value, ci, unit, effect, readings) in recovered.items():
        if name not in used:
            got = interval_text(value, ci, unit, bounds.get(name)) + readings
            rows.append((effect_name(report, effect), name, "not set", got, "no"))
    lines = ["## Set in the twin, recovered from its recordings", ""]
    lines += table(["effect", "parameter", "set", "recovered [95 % interval]",
                    "set value inside the interval"], rows)  # fmt: skip
    if others:
        lines += ["", "Also set, outside the engine's registry (nothing recovers them): "
                  + "; ".join(others) + "."]  # fmt: skip
    if any(row[4] == "no" for row in rows):
        lines += ["", "A set value outside its interval is a bias, not noise: the twin holds "
                  "something the engine's model does not describe (such as the settings outside "
                  "its registry) and the estimate absorbs part of it."]  # fmt: skip
    return [*lines, ""]


def claims(report: Mapping) -> list[str]:
    """The effects claimed (beside what is left unexplained, when structure remains) and those
    only held tentatively, with their estimates and intervals; the hypotheses for the lab, and
    the candidate terms not offered for the small share of the residual they remove: the
    headline with a lab's data."""
    found, tentative = report["effects_found"], report["tentative"]
    beside = any(e.get("beside_unexplained") for e in found)
    title = "Causes claimed beside what is left unexplained" if beside else "Causes claimed"
    lines = [f"## {title}", ""]
    bounds = summary.bounds_of(report)
    if found:
        if beside:
            lines += ["Each estimate rests on what its row says. On every observable: it holds "
                      "whichever candidate term is added to the model, its interval stretched "
                      "by the misfit that remains (√(1 + S²), S the largest structure left, in "
                      "noise units) and widened to hold those estimates. On some observables "
                      "alone: the model refitted on the observables that fit, the misfitting "
                      "ones left out. On the check that located it: sized there, before any "
                      "fit.", ""]  # fmt: skip
            rows = [(*row, rests_on(report, entry)) for entry in found
                    for row in summary.effect_rows([entry], bounds)]  # fmt: skip
            lines += table(["effect", "parameter", "estimate [95 % interval]", "rests on"], rows)
        else:
            lines += table(["effect", "parameter", "estimate [95 % interval]"],
                           summary.effect_rows(found, bounds))  # fmt: skip
    else:
        lines.append("None.")
    if tentative:
        lines += ["", "**Fitted but not claimed while structure remains:**", ""]
        lines += table(["effect", "parameter", "estimate [95 % interval]"],
                       summary.effect_rows(tentative, bounds))  # fmt: skip
    library = report["discovery"].get("library", {})
    found_terms = {
        "Hypotheses for the lab to check": report["discovery"]["named"],
        "Terms proposed, not named": report["discovery"].get("proposed", []),
    }
    for label, terms in found_terms.items():
        if terms:
            lines += ["", f"**{label}:**", ""]
            lines += [f"- {summary.term_statement(t, library)}" for t in terms]
    weak = report["discovery"].get("not_offered", [])
    if weak:
        lines += ["", "Not offered as a cause (each leaves most of the residual): " + "; ".join(
            f"{summary.short_name(w['description'])} removes {w['gain_pct']:.0f} % of the "
            "remaining held-out error" for w in weak) + "."]  # fmt: skip
    return [*lines, ""]


def rests_on(report: Mapping, entry: Mapping) -> str:
    """The evidence a claim beside unexplained structure rests on, in words."""
    observables = entry.get("from_observables")
    if observables is None:
        return "every observable"
    if not observables:
        return "the check of the recordings that located it"
    names = report.get("observable_names", {})
    return " and ".join(names.get(o, o) for o in observables) + " alone"


def unexplained(report: Mapping, tests_file: str = TESTS_FILE, direct: Sequence[str] = (),
                implicated: Sequence[str] = ()) -> list[str]:  # fmt: skip
    """What is left unexplained, with a count of the residual tests and a link to them; what
    the direct checks saw that nothing in the model holds (``direct``, sentences); the
    assumption rows a violated check on a misfitting observable's signal implicates
    (``implicated``, sentences); and every trial's estimate of each constant that differs
    between trials."""
    tests = report["unexplained"]["tests"]
    flagged = sum(t["flag"] for t in tests)
    small = sum(not t["flag"] and t["statistic"] > t["threshold"] for t in tests)
    count = (f"[{len(tests)} residual tests]({tests_file}): {flagged} flagged, {small} find a "
             "pattern beyond the noise that is too small to count.")  # fmt: skip
    constants = [e for e in (report.get("stability") or {}).get("constants", []) if e["tested"]]
    if constants:
        count += (f" [{len(constants)} constants]({tests_file}#between-trials) that must hold "
                  "between trials, each refitted per trial: "
                  f"{sum(e['flag'] for e in constants)} differ.")  # fmt: skip
    text = summary.left_unexplained(report).replace(" (see the residual tests)", "")
    if direct:
        said = ("Seen by the direct checks before any fit, and held by nothing in the model: "
                + "; ".join(direct) + ". The estimates that act on the same observables may "
                "have absorbed part of it.")  # fmt: skip
        text = said if text.startswith("Nothing") else f"{text} {said}"
    if implicated:
        text += " By the direct checks on the same signals, " + "; ".join(implicated) + "."
    lines = ["## Left unexplained", "", text, "", count, ""]
    for entry in (e for e in constants if e["flag"]):
        lines += [f"**The {entry['name']} ({entry['parameter']}) per trial:**", ""]
        lines += table(["trial", "units", "estimate [95 % interval]", "departs"],
                       stability_rows(entry))  # fmt: skip
        lines.append("")
    return lines


def stability_rows(entry: Mapping) -> list[tuple]:
    """(trial, units, estimate [95 % interval], whether it departs) of a constant."""
    apart = {d["trial"] for d in entry["departing"]}
    return [(t["trial"], t["units"],
             interval_text(t["estimate"], t["ci95"], entry["unit"]) if t.get("sized", True)
             else "not sized (its interval holds the whole search range)",
             "yes" if t["trial"] in apart else ("at a search bound" if t["at_bound"] else "no"))
            for t in entry["trials"]]  # fmt: skip


def errors(report: Mapping, context: Mapping[str, str] = {},
           resolution: Mapping[str, float] = {}) -> list[str]:  # fmt: skip
    """What the baseline gets wrong: the error per observable before and after, in its unit;
    ``context`` (observable -> sentence) puts a pooled number in proportion; an observable whose
    errors are below its ``resolution`` says so instead of giving them."""
    kind = "held-out " if report["gain"]["held_out"] else "in-sample "
    names = report.get("observable_names", {})
    rows = []
    for name, before, after, unit in summary.rmse_rows(report):
        obs = next((o for o, n in names.items() if n == name), name)
        floor = resolution.get(obs)
        if floor is not None and max(before, after) < floor:
            below = f"below its resolution ({number(floor)})"
            rows.append((name, below, below, unit_text(unit)))
        else:
            rows.append((name, number(before), number(after), unit_text(unit)))
    lines = ["## What the baseline gets wrong", "",
             f"Baseline: the {report['baseline']['model']}.", ""]  # fmt: skip
    lines += table(["observable", f"{kind}RMSE, baseline", f"{kind}RMSE, extended model",
                    "unit"], rows)  # fmt: skip
    notes = [context[o] for o in report.get("observable_order", []) if o in context]
    return [*lines, *(["", *notes] if notes else []), ""]


def _rounded(value: float, rounding: float) -> str:
    """A reported number as written, with its rounding: '8.0 ± 0.05'."""
    digits = max(0, round(-np.log10(2 * rounding)))
    return f"{value:.{digits}f} ± {rounding:g}"


def reported_medians(report: Mapping, study: studies.Study) -> list[str]:
    """The engine on the medians a study reports: every number's held-out error beside its
    rounding, the effects claimed with what they rest on, and those the numbers cannot carry."""
    told = report.get("uncertainty", "its rounding (half its last digit)")
    lines = [f"## The medians {study.key} report", "", report["cause"], "",
             "Each number is predicted by the model fitted to the other numbers (held out). "
             f"Uncertainty: {told}.", ""]  # fmt: skip
    rows = []
    for n in report["numbers"]:
        bound = n.get("stated_uncertainty", n["rounding"])
        times = abs(n["extended_error"]) / bound
        rows.append((f"{n['name']}, {n['spring_stiffness_N_per_m'] / 1e3:g} kN/m",
                     f"{_rounded(n['reported'], n['rounding'])} {n['unit']}",
                     number(n["baseline"]), number(n["extended"]), number(bound),
                     f"{number(n['extended_error'])} ({number(times)}×)"))  # fmt: skip
    lines += table(["number", "reported (± rounding)", "rigid theory", "extended model",
                    "stated uncertainty of the held-out error",
                    "extended error (× stated uncertainty)"], rows)  # fmt: skip
    support = report.get("support", {})
    claimed = []
    for effect, _, text in summary.effect_rows(report["effects_found"] or report["tentative"],
                                               summary.bounds_of(report)):  # fmt: skip
        key = effect.replace(" ", "_")
        count = max((len(s["numbers"]) for s in support.get(key, {}).values()), default=0)
        claimed.append(f"{effect} {text} (rests on {count} numbers)")
    label = "Claimed" if report["effects_found"] else "Tentative, not claimed"
    lines += ["", f"**{label}:** " + ("; ".join(claimed) if claimed else "none") + "."]
    for entry in report.get("not_claimed", []):
        fitted = "; ".join(
            f"{p} {interval_text(v, None, entry['units'][p], entry['bounds'][p])}"
            for p, v in entry["fitted_anyway"].items()
        )
        lines += ["", f"**Not claimed: {entry['effect'].replace('_', ' ')}.** "
                  f"{entry['reason'][0].upper()}{entry['reason'][1:]}. Fitted to that number "
                  f"anyway, beside the selected effects, it comes to {fitted}; the numbers hold "
                  "no evidence for it."]  # fmt: skip
    return [*lines, ""]


def fitted_more_than_once(fits: Mapping[str, Mapping], notes: Mapping[str, str] = {}) -> list[str]:
    """Parameters fitted by more than one fit (recordings, reported medians, calibration): each
    estimate side by side, what separates the fits, and why that matters (said once)."""
    twice = summary.fitted_twice(dict(fits))
    if not twice:
        return []
    labels = list(fits)
    rows = []
    for row in twice:
        cells = []
        for label in labels:
            if label in row["estimates"]:
                value, ci = row["estimates"][label]
                unit = fits[label]["units"].get(row["parameter"], "1")
                cells.append(interval_text(value, ci, unit))
            else:
                cells.append("—")
        rows.append((row["parameter"], *cells, row["reason"]))
    lines = ["## The same parameter, fitted more than one way", "", summary.FITTED_TWICE, ""]
    lines += table(["parameter", *labels, "what separates the fits"], rows)
    extra = [notes[row["parameter"]] for row in twice if row["parameter"] in notes]
    return [*lines, *(["", *extra] if extra else []), ""]


def plain_decision(test: Mapping) -> str:
    """One residual test's outcome in plain words (a test that words its own: its ``plain``)."""
    if "plain" in test:
        return test["plain"]
    stat, limit = number(test["statistic"]), number(test["threshold"])
    if test["flag"]:
        return f"**flagged**: {stat}, above the noise's {limit}, and large enough to count"
    if test["statistic"] <= test["threshold"]:
        return f"within the noise ({stat}; the noise alone reaches {limit})"
    unit = "noise units of change over a trial" if test["correlates_with"] == "trial time" else (
        "noise units")  # fmt: skip
    return (f"a pattern beyond the noise ({stat} > {limit}) but small: {number(test['size'])} "
            f"{unit}, under the {number(test['size_floor'])} that count")  # fmt: skip


def residual_tests(title: str, reports: Sequence[tuple[str, Mapping]]) -> str:
    """The residual tests of each report in plain words: ``residual_tests.md``."""
    lines = [f"# {title}: residual tests", "",
             "After the selected model, the engine tests whether its held-out residuals still "
             "hold a pattern: one that follows the gait phase, the knee angle, its velocity or "
             "the force, one correlated in time, a residual larger than the noise allows, or a "
             "drift over the trial. Each statistic is compared with the same statistic on the "
             "recording's own noise (its threshold); a pattern beyond the noise counts only when "
             "it is large enough to matter (a set share of the observable's spread, or of the "
             "noise for a drift).", ""]  # fmt: skip
    for label, report in reports:
        names = report.get("observable_names", {})
        rows = [(names.get(t["observable"], t["observable"]),
                 AGAINST.get(t["correlates_with"], f"a residual that follows the "
                             f"{t['correlates_with']}"),
                 plain_decision(t)) for t in report["unexplained"]["tests"]]  # fmt: skip
        lines += [f"## {label}", ""]
        lines += table(["observable", "looks for", "outcome"], rows)
        lines.append("")
    between = [(label, e) for label, report in reports
               for e in (report.get("stability") or {}).get("constants", [])]  # fmt: skip
    if between:
        lines += ["## Between trials", "", "Each constant of the rig that must hold from one "
                  "trial to the next (the assumption table's rows of kind `between`) is "
                  "refitted one value per trial, every other parameter shared and refitted "
                  "with them; Welch's test asks whether the trials agree within their standard "
                  "errors "
                  f"(Holm-adjusted over the constants tested, flagged below "
                  f"{next(r['stability']['alpha'] for _, r in reports if r.get('stability')):g})."
                  , ""]  # fmt: skip
        rows = [(label, f"`{e['assumption']}`: {e['name']} ({e['parameter']})",
                 e["decision"] + (f"; {summary.departed_text(e)}" if e["flag"] else "")
                 + "".join(f"; {u['trial']} not sized" + (f" apart from {', '.join(u['with'])}"
                                                           if u["with"] else "")
                           for u in e.get("unsized", [])))
                for label, e in between]  # fmt: skip
        lines += table(["data", "constant", "outcome"], rows)
        lines.append("")
    return frame.document([lines])
