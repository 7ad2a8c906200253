"""The sit-to-stand verdict in words (``summary.md``): the readings of the study's law and what
rejects each, the corrected law that sits, the modules on the same task, and the thigh link
under the study's support and the configured one, with the section search. Every number is read
from the tables beside it (``checks.csv``, ``readings.json``, ``corrected_laws.json``,
``spring_damper.json``, ``fe.json``, ``sections.csv``, ``study_comparison.csv``), three
significant digits; a claim that holds under one reading only names the reading."""

from __future__ import annotations

from collections.abc import Mapping

import pandas as pd

from exobench import document as frame
from exobench import studies
from exobench.selection.summary import number, table, unit_text
from exobench.sts.loads import JOINTS

CORRECTED, SAME_TASK = "corrected", "corrected_study_seat"
SOURCE = {
    "acquisition": "model",
    "group": "sts",
    "laws": "motion laws (eqs. 1–4) and their readings, design load, link lengths, an "
    "anthropometric body, a seat, and the thigh link's numbers",
    "blocks": ["sts"],
    "tables": [
        "checks.csv",
        "readings.json",
        "corrected_laws.json",
        "spring_damper.json",
        "fe.json",
        "sections.csv",
        "study_comparison.csv",
    ],
}
WORDS = (
    "no",
    "one",
    "two",
    "three",
    "four",
    "five",
    "six",
    "seven",
    "eight",
    "nine",
    "ten",
    "eleven",
    "twelve",
)
COORDINATE = {"phi1": "φ1", "phi2": "φ2", "phi3": "φ3"}
ODD = {
    "phi1": "hip flexion turns the trunk back",
    "phi2": "knee flexion turns the thigh forward, past the shank",
    "phi3": "the shank tilts back, the feet ahead of the knees",
}


def count(n: int) -> str:
    """A small count in words (a count is no measured number)."""
    return WORDS[n] if 0 <= n < len(WORDS) else str(n)


def row_of(checks: pd.DataFrame, law: str, check: str) -> pd.Series:
    """One check's row."""
    return checks[(checks["law"] == law) & (checks["check"] == check)].iloc[0]


def value(checks: pd.DataFrame, law: str, check: str) -> float:
    """One check's value."""
    return float(row_of(checks, law, check)["value"])


def failed(checks: pd.DataFrame, law: str) -> list[str]:
    """The checks a law violates, in table order."""
    rows = checks[(checks["law"] == law) & (checks["decision"] == "violated")]
    return list(rows["check"])


def _listing(by_category: Mapping) -> str:
    """Failed checks by category, 'words: a, b; balance: c'."""
    return "; ".join(f"{cat}: {', '.join(names)}" for cat, names in by_category.items()) or "none"


def readings_paragraph(checks: pd.DataFrame, verdict: Mapping) -> str:
    """Which readings the words admit, what rejects each, and the cause or the ambiguity."""
    readings = verdict["readings"]
    admitted = verdict["admitted"]
    rejected = [n for n in admitted if readings[n]["status"] == "rejected"]
    others = [n for n, r in readings.items() if not r["admitted"]]
    text = (
        f"The study's text admits {count(len(admitted))} readings of its law: "
        f"{' and '.join(admitted)} (eqs. (1)–(3) as printed; the text puts Dx to the right "
        "and never says which way the subject faces). "
    )
    for name in rejected:
        text += (
            f"Its words, anatomy and balance reject '{name}' by checks another admitted "
            f"reading holds ({_listing(readings[name]['rejected_by'])}). "
        )
    survivors = verdict["survivors"]
    common = verdict["common_failures"]
    if verdict["cause"] is not None and survivors:
        name = survivors[0]
        odd_signs = verdict["cause"]["odd_signs"]
        odd = (
            (
                ", ".join(COORDINATE[c] for c in odd_signs)
                + " ("
                + "; ".join(ODD[c] for c in odd_signs)
                + ")"
            )
            if odd_signs
            else "none"
        )
        text += (
            f"{'Only ' if len(survivors) == 1 else ''}'{', '.join(survivors)}' survives; "
            f"under it the trunk leans {number(value(checks, name, 'lean_direction'))}° "
            f"forward and is back within {number(abs(value(checks, name, 'upright_seated')))}° "
            "of upright when seated, as the study says, and the postures depart from a "
            f"human's only in the sign of {odd}. "
        )
    else:
        text += (
            f"{verdict['ambiguity'].capitalize()}, so no single sign is named as the "
            f"cause; what would settle it: {verdict['settle']}. "
        )
    if common:
        text += (
            "The checks every admitted reading fails are the law's own, whichever way it is "
            "read: "
            + "; ".join(
                f"{c} ("
                + ", ".join(
                    f"{number(value(checks, n, c))}{_unit(checks, n, c)} under '{n}'"
                    for n in admitted
                )
                + f"; expected {row_of(checks, admitted[0], c)['expected']})"
                for c in common
            )
            + ". "
        )
    if others:
        text += (
            "The sign slips a reviewer may raise (φ2 or φ1 reversed), which the printed "
            "equations do not admit, fail too: "
            + "; ".join(f"'{n}' {_listing(readings[n]['failed'])}" for n in others)
            + "."
        )
    return text


def corrected_paragraph(checks: pd.DataFrame, postures: Mapping, modules: Mapping) -> str:
    """The corrected law on the chairs, what it cannot meet and why, and the same-task modules."""
    law = postures[CORRECTED]
    reach = postures["study_loading_at_the_chair"]
    total = len(checks[checks["law"] == CORRECTED])
    held = total - len(failed(checks, CORRECTED))
    fits, study_law = modules["laws"], modules["study_law"]
    same = failed(checks, SAME_TASK)
    chairs = postures["chair_range_mm"]
    heel = -postures["foot_heel_mm"]
    text = (
        "The corrected law (the study's links and timing, the knee and hip turning the human "
        f"way) sits on a {number(law['seat_height_mm'])} mm chair (sts.corrected.seat_height_mm;"
        " seat heights are read as the hip joint's height when seated, not the seat surface's):"
        f" the hip drops {number(law['hip_drop_mm'])} mm from "
        f"{number(law['hip_height_standing_mm'])} mm, the shank tilts "
        f"{number(law['at_seat_deg']['phi3'])}° forward, the smallest tilt that keeps the feet's "
        "centre of pressure on the foot before the seat (the cop_standing check solved for), "
        f"the thigh is {number(law['thigh_from_horizontal_at_seat_deg'])}° from horizontal at "
        f"the seat, the trunk's largest lean before the seat is "
        f"{number(value(checks, CORRECTED, 'lean_direction'))}° (forward +) and "
        + _upright(checks, CORRECTED)
        + "; it holds "
        f"{count(held)} of its {count(total)} checks under the seat model"
        + (f" and fails {', '.join(failed(checks, CORRECTED))}. " if held < total else ". ")
        + "Over the chair range "
        f"{number(chairs[0])}–{number(chairs[1])} mm ({postures['chair_range_source']}), "
        + "; ".join(chair_sentence(checks, f"corrected, {h:g} mm chair", h) for h in chairs)
        + ". "
    )
    blocked = reach["loaded_point_farthest_forward_mm"] < -heel
    text += (
        "Under the study's loading (the whole weight at A, no seat) at that chair, with the "
        f"thigh within {number(reach['thigh_tolerance_deg'])}° of horizontal and the trunk "
        f"leaning at most {number(reach['lean_max_deg'])}°, A stands at best "
        f"{number(reach['loaded_point_farthest_forward_mm'])} mm from the ankle (forward +): "
        + (
            f"behind the heel's edge at {number(-heel)} mm, so balance cannot be met there. "
            if blocked
            else f"on the foot (heel's edge at {number(-heel)} mm). "
        )
    )
    at_bound = [j for j in JOINTS if fits[study_law]["tuned"][j]["at_upper_bounds"]]
    bounds = (
        "; the tuned parameters sit at their upper bounds at the "
        + ", ".join(
            f"{j} ({', '.join(fits[study_law]['tuned'][j]['at_upper_bounds'])})" for j in at_bound
        )
        + f" on the {study_law} law, so its number is a bound's, not an optimum's"
        if at_bound
        else ""
    )
    return text + (
        "On the study's own task (the seat at its "
        f"{number(postures['study_seat_height_mm'])} mm hip height, its timing) the tuned "
        f"modules leave the user {number(_largest_user(fits[SAME_TASK]))} N·m RMS at the worst "
        f"joint on the corrected law against {number(_largest_user(fits[study_law]))} N·m on "
        f"the study's {study_law} law{bounds} (the torques in φ are the same under either "
        "facing: gravity does not change under a reflection); on that higher seat the "
        "corrected law " + (f"fails {', '.join(same)}." if same else "holds every check.")
    )


def _unit(checks: pd.DataFrame, law: str, check: str) -> str:
    """The check's unit as text after a number ('' for a ratio or a count)."""
    unit = row_of(checks, law, check)["unit"]
    return "" if unit == "1" else f" {unit_text(unit)}"


def _upright(checks: pd.DataFrame, law: str) -> str:
    """Whether the trunk ends upright, from the upright_seated check's decision and bound."""
    row = row_of(checks, law, "upright_seated")
    if row["decision"] == "holds":
        return f"it is within {number(row['high'])}° of upright when seated"
    return f"it ends {number(abs(row['value']))}° from upright when seated"


def chair_sentence(checks: pd.DataFrame, name: str, seat_mm: float) -> str:
    """What the corrected law fails at one chair, each check with its value and bound."""
    missed = failed(checks, name)
    if not missed:
        return f"at {number(seat_mm)} mm it holds every check"
    return f"at {number(seat_mm)} mm it fails " + ", ".join(
        f"{c} ({number(value(checks, name, c))}{_unit(checks, name, c)}, expected "
        f"{row_of(checks, name, c)['expected']})"
        for c in missed
    )


def _largest_user(fit: Mapping) -> float:
    """The largest of the joints' RMS user torques with the tuned modules."""
    return max(fit["tuned"][j]["user_rms_Nm"] for j in JOINTS)


def fixed_sentence(fixed: Mapping) -> str:
    """The fully fixed face's corner peak, named singular or converged by its own flags."""
    peaks = " → ".join(number(r["fixed_face_peak_MPa"]) for r in fixed["table"])
    sizes = " → ".join(number(r["corner_element_mm"]) for r in fixed["table"])
    text = (
        f"the peak at the face's corner goes {peaks} MPa as the corner's elements shrink "
        f"{sizes} mm ({number(fixed['peak_last_change_pct'])} % over the last two, tolerance "
        f"{number(fixed['tolerance_pct'])} %, as h to the power −{number(fixed['peak_exponent'])})"
    )
    if fixed["singular_corner"]:
        return text + ": a singular corner that does not converge, no stress"
    if fixed["peak_converges"]:
        return text + ": it converges"
    return text + ": it neither converges nor grows at every refinement"


def search_sentence(search: Mapping, sections: pd.DataFrame) -> str:
    """The search's confirmed links, the study's material first, or that none is confirmed."""
    target = search["targets"]
    text = (
        f"Of {search['screened']} links screened with closed forms over depth, thickness, pin "
        "diameter and material, each material's best go to finite elements ("
        f"{count(len(sections))} in all); the tolerance, {number(search['tolerance_pct'])} %, "
        "is taken against the midpoints of the study's ranges "
        f"({number(target['tip_deflection_mm'])} mm, "
        f"{number(target['compression_peak_MPa'])} MPa). "
    )
    study = sections[sections["material"] == search["study_material"]]
    for label, rows in (
        (f"In the study's {search['study_material']}", study),
        ("In another material", sections[sections["material"] != search["study_material"]]),
    ):
        found = rows[rows["confirmed"]]
        if not len(rows):
            continue
        if not len(found):
            text += f"{label} no confirmed link gives both numbers. "
            continue
        best = found.iloc[0]
        text += (
            f"{label}, {number(best['depth_mm'])} × {number(best['thickness_mm'])} mm "
            f"({best['material']}) with {number(best['pin_diameter_mm'])} mm pins deflects "
            f"{number(best['fe_deflection_mm'])} mm and peaks at "
            f"{number(best['fe_compression_peak_MPa'])} MPa in compression, but at "
            f"{number(best['fe_loaded_end_peak_MPa'])} MPa at its loaded end. "
        )
    return text


def fe_paragraph(fe: Mapping, sections: pd.DataFrame) -> str:
    """The two supports, the levers, the section search and what the study's numbers imply."""
    fixed, conv, levers = fe["fixed_support"], fe["convergence"], fe["levers"]
    search, implied = fe["sections"], fe["sections"]["implied"]
    seed = fe["seed_fea"]
    changes = [v for q, v in conv["last_change_pct"].items() if "concentrated" not in q]
    clamp = implied["clamp_stress_for_study_deflection_MPa"]
    local = clamp < seed["bending_peak_MPa"]
    return (
        "Held plane with a parabolic shear (the configured support), the link's reported "
        f"numbers change by at most {number(max(changes))} "
        f"% over the last two refinements (tolerance {number(conv['tolerance_pct'])} %). With "
        "its end face fully fixed, as the study's 'rigidly constrained' end (elements of "
        f"{number(fixed['element_mm'])} mm away from the corners), "
        + fixed_sentence(fixed)
        + "; the deflection it gives changes by "
        f"{number(fixed['deflection_last_change_pct'])} %. Eq. (5)'s lever is "
        f"{number(levers['eq5_lever_mm'])} mm ({number(levers['eq5_moment_Nm'])} N·m); the "
        f"configured bar, built in at its end, has {number(levers['configured_lever_mm'])} mm "
        f"({number(levers['configured_moment_Nm'])} N·m). "
        + search_sentence(search, sections)
        + "Whatever the section, a tip-loaded cantilever "
        "has deflection / clamp bending stress = L²/(3Ec): reading the study's numbers as one "
        f"load case on a prismatic steel cantilever {number(implied['lever_mm'])} mm long "
        f"(E {number(implied['E_MPa'])} MPa), its {number(seed['bending_peak_MPa'])} MPa beside "
        f"{number(implied['study_deflection_mm'])} mm needs a link "
        f"{number(implied['depth_if_peak_were_clamp_stress_mm'])} mm deep, and a link "
        f"{number(implied['depth_mm'])} mm deep deflecting that much carries "
        f"{number(clamp)} MPa at its clamp"
        + (
            ". Under that reading the study's peak is a local one (a hole's edge, its load's "
            "introduction or a fixed corner), not the link's bending stress."
            if local
            else ", no less than the study's peak: under that reading the peak can be the "
            "link's bending stress."
        )
    )


def bounds_section(checks: pd.DataFrame) -> list[str]:
    """Every bound the checks use, with where it comes from (checks.csv's basis)."""
    first = checks.drop_duplicates("check")
    rows = [
        (
            r["check"],
            r["category"],
            r["expected"] + ("" if r["unit"] == "1" else f" {unit_text(r['unit'])}"),
            r["basis"],
        )
        for _, r in first.iterrows()
    ]
    lines = [
        "## Bounds and where they come from",
        "",
        "Each check's bound and its source: the study's words, its loading case, anatomy, "
        "or balance with the chosen foot and the anthropometric table (checks.csv, basis; "
        "the sitting base's front is the toe, its back the hip of each sample).",
        "",
    ]
    return [*lines, *table(["check", "category", "expected", "source of the bound"], rows), ""]


def readings_section(verdict: Mapping) -> list[str]:
    """Each reading's status and its failed checks, listed apart."""
    rows = [
        (
            name,
            "yes" if r["admitted"] else "no",
            r["status"],
            ", ".join(COORDINATE[c] for c in r["odd_signs"]) or "none",
            _listing(r["failed"]),
            _listing(r["rejected_by"]),
            r["basis"],
        )
        for name, r in verdict["readings"].items()
    ]
    lines = [
        "## Every reading of the study's law",
        "",
        "Each reading through the same checks ([readings.json](readings.json)); a reading "
        "is rejected by a check it fails that another admitted reading holds; a check every "
        "admitted reading fails is the law's own. Odd signs: the coordinates whose sense "
        "in the forward frame differs from a human's.",
        "",
    ]
    lines += table(
        [
            "reading",
            "admitted by the words",
            "status",
            "odd signs",
            "failed checks",
            "rejected by",
            "basis",
        ],
        rows,
    )
    users = verdict.get("users", {})
    for name, user in users.items():
        lines += [
            "",
            f"User's law '{name}': "
            + "; ".join(
                f"{n} ({r['status']}): {_listing(r['failed'])}" for n, r in user["readings"].items()
            ),
        ]
    return [*lines, ""]


def checks_section(checks: pd.DataFrame) -> list[str]:
    """Every check of every law with its expected range and decision."""
    rows = []
    for _, r in checks.iterrows():
        unit = "" if r["unit"] == "1" else f" {unit_text(r['unit'])}"
        rows.append(
            (
                r["law"],
                r["category"],
                r["quantity"],
                f"{number(r['value'])}{unit}",
                r["expected"],
                r["decision"],
            )
        )
    lines = [
        "## Every check of every law",
        "",
        "Positions in each law's forward frame (x the way the user faces); the basis of "
        "each check is in [checks.csv](checks.csv).",
        "",
    ]
    lines += table(["law", "category", "quantity", "value", "expected", "decision"], rows)
    return [*lines, ""]


def modules_section(modules: Mapping) -> list[str]:
    """Required and user torques per joint, configured and tuned, on each law."""
    rows = []
    for law, fit in modules["laws"].items():
        for joint in JOINTS:
            tuned = fit["tuned"][joint]
            rows.append(
                (
                    law,
                    joint,
                    number(tuned["required_peak_Nm"]),
                    number(tuned["required_rms_Nm"]),
                    number(fit["user_rms_configured_Nm"][joint]),
                    number(tuned["user_rms_Nm"]),
                    ", ".join(tuned["at_upper_bounds"]) or "none",
                )
            )
    lines = [
        "## Loads and modules on each law",
        "",
        "Inverse-dynamic extensor torques under the study's loading (the design load at A, "
        "the whole weight on the legs, no seat) and what the modules leave to the user "
        f"([spring_damper.json](spring_damper.json)); '{SAME_TASK}' is the corrected law on "
        "the study's own seat height and timing, the task the study's law performs.",
        "",
    ]
    lines += table(
        [
            "law",
            "joint",
            "required peak",
            "required RMS",
            "user RMS, configured",
            "user RMS, tuned",
            "tuned parameters at their upper bound",
        ],
        rows,
    )
    return [*lines, ""]


def fe_section(fe: Mapping, sections: pd.DataFrame) -> list[str]:
    """The finite-element model, its convergence, the fully fixed support and the search."""
    conv = fe["convergence"]
    quantities = list(conv["last_change_pct"])
    rows = [
        (
            number(r["element_mm"]),
            number(r["hole_element_mm"]),
            r["dofs"],
            *(number(r[q]) for q in quantities),
        )
        for r in conv["table"]
    ]
    rows.append(
        (
            "change over the last two",
            "",
            "",
            *(f"{number(conv['last_change_pct'][q])} %" for q in quantities),
        )
    )
    model = fe["model"]
    lines = [
        "## The thigh link by finite elements",
        "",
        f"Model ([fe.json](fe.json)): {model['elements']}; {model['state']}; "
        f"{model['support']}; the design load of {number(model['load_N'])} N through the "
        f"hip pin, {number(model['lever_mm'])} mm from the built-in end. Mesh convergence "
        "(element sizes in mm; the concentrated loads' peaks are listed to show that they "
        "do not converge):",
        "",
    ]
    lines += table(["elements", "at the holes", "unknowns", *quantities], rows)
    fixed = fe["fixed_support"]
    lines += [
        "",
        f"The study's support, {fixed['support']}: the bending case refined at the "
        "fixed face's corners (a growing peak is the corner's singularity):",
        "",
    ]
    lines += table(
        [
            "corner elements (mm)",
            "unknowns",
            "peak at the fixed face (MPa)",
            "where",
            "largest deflection (mm)",
        ],
        [
            (
                number(r["corner_element_mm"]),
                r["dofs"],
                number(r["fixed_face_peak_MPa"]),
                r["where"],
                number(r["largest_displacement_mm"]),
            )
            for r in fixed["table"]
        ],
    )
    search = fe["sections"]
    ranges = "; ".join(
        f"{k}: {min(v['values']):g}–{max(v['values']):g}" for k, v in search["ranges"].items()
    )
    materials = "; ".join(
        f"{k} (E {number(v['E_MPa'])} MPa)" for k, v in search["materials"].items()
    )
    lines += [
        "",
        f"The section search ([sections.csv](sections.csv)): {ranges}; {materials} "
        "(each range's and material's source: fe.json, sections, from the config). "
        "Closed forms screen every combination; the best go to finite elements "
        f"(elements of {number(search['element_mm'])} mm):",
        "",
    ]
    lines += table(
        [
            "depth (mm)",
            "thickness (mm)",
            "pin (mm)",
            "material",
            "closed-form deflection (mm)",
            "FE deflection (mm)",
            "closed-form compression (MPa)",
            "FE compression (MPa)",
            "FE loaded-end peak (MPa)",
            "within tolerance",
        ],
        [
            (
                number(r["depth_mm"]),
                number(r["thickness_mm"]),
                number(r["pin_diameter_mm"]),
                r["material"],
                number(r["deflection_mm"]),
                number(r["fe_deflection_mm"]),
                number(r["compression_peak_MPa"]),
                number(r["fe_compression_peak_MPa"]),
                number(r["fe_loaded_end_peak_MPa"]),
                "yes" if r["confirmed"] else "no",
            )
            for _, r in sections.iterrows()
        ],
    )
    return [*lines, ""]


def comparison_section(comparison: pd.DataFrame) -> list[str]:
    """The study's numbers beside the project's, with their roles."""
    rows = [
        (
            r["quantity"],
            f"{r['study_low']:g}"
            if r["study_low"] == r["study_high"]
            else f"{r['study_low']:g}–{r['study_high']:g}",
            f"{number(r['project'])} {r['unit']}",
            r["role"],
            r["role_basis"],
        )
        for _, r in comparison.iterrows()
    ]
    lines = [
        "## The study's numbers beside the project's",
        "",
        "[study_comparison.csv](study_comparison.csv), each row's role by the project's "
        "role rule (exobench.roles); no row here is a prediction.",
        "",
    ]
    return [*lines, *table(["quantity", "study", "project", "role", "why"], rows), ""]


def unexplained(fe: Mapping) -> list[str]:
    """What the model leaves open."""
    seed = fe["seed_fea"]
    return [
        "## Left unexplained",
        "",
        "- Which way the study's subject faces: the verdict on the readings rests on the "
        "checks; a sentence or a figure drawn with the subject would fix it.",
        f"- Where the study's {number(seed['bending_peak_MPa'])} MPa comes from: a hole's "
        "edge, the load's introduction or the fixed corner each can give it on some mesh; "
        "the study reports neither its mesh there nor how its load reached the link.",
        "- The study's link: the search finds sections that give two of its numbers; the "
        "study gives no drawing to tell which, if any, it analysed.",
        "",
    ]


def document(
    checks: pd.DataFrame,
    verdict: Mapping,
    postures: Mapping,
    modules: Mapping,
    fe: Mapping,
    sections: pd.DataFrame,
    comparison: pd.DataFrame,
) -> str:
    """summary.md: source, study, verdict and open questions first; the tables after."""
    sections_md = [
        frame.heading(
            "Sit-to-stand: the study's motion law read every way it admits, a law "
            "that sits, and the thigh link as the study supported it",
            SOURCE,
        ),
        frame.source(SOURCE),
        frame.cited([studies.STS]),
        [
            "## Verdict",
            "",
            readings_paragraph(checks, verdict),
            "",
            corrected_paragraph(checks, postures, modules),
            "",
            fe_paragraph(fe, sections),
            "",
        ],
        unexplained(fe),
        bounds_section(checks),
        readings_section(verdict),
        checks_section(checks),
        modules_section(modules),
        fe_section(fe, sections),
        comparison_section(comparison),
        frame.references([studies.STS]),
    ]
    return frame.document(sections_md)
