"""The sit-to-stand verdict in words (``summary.md``): the motion laws' checks, the corrected
laws' gain in loads and modules, and the thigh link by finite elements against the beam
formulas and the study's three numbers. Every number is read from the tables beside it
(``checks.csv``, ``corrected_laws.json``, ``spring_damper.json``, ``fe.json``), three
significant digits."""

from __future__ import annotations

from collections.abc import Mapping

import pandas as pd

from exobench import document as frame
from exobench import studies
from exobench.selection.summary import number, table, unit_text
from exobench.sts.loads import JOINTS

STUDY_LAW, CORRECTED = "piecewise", "corrected"
SOURCE = {
    "acquisition": "model",
    "group": "sts",
    "laws": "motion laws (eqs. 1–4), design load, link lengths and thigh-link numbers",
    "blocks": ["sts"],
    "tables": ["checks.csv", "corrected_laws.json", "spring_damper.json", "fe.json"],
}  # fmt: skip


def value(checks: pd.DataFrame, law: str, check: str) -> float:
    """One check's value."""
    rows = checks[(checks["law"] == law) & (checks["check"] == check)]
    return float(rows["value"].iloc[0])


def bound(checks: pd.DataFrame, check: str, side: str) -> float:
    """One check's low or high bound (the same for every law at an upright posture)."""
    return float(checks.loc[checks["check"] == check, side].iloc[0])


def failed(checks: pd.DataFrame, law: str) -> list[str]:
    """The checks a law violates, in table order."""
    rows = checks[(checks["law"] == law) & (checks["decision"] == "violated")]
    return list(rows["check"])


def laws_paragraph(checks: pd.DataFrame, postures: Mapping, modules: Mapping) -> str:
    """The motion laws' verdict: what the study's laws get wrong, the one sign behind it, what
    the corrected laws hold and what they cost."""
    count = len(checks[checks["law"] == STUDY_LAW])
    study, smooth = failed(checks, STUDY_LAW), failed(checks, "smooth")
    same = "the same" if smooth == study else f"{len(smooth)}"
    fits = modules["laws"]
    law = modules["study_law"]
    return (
        f"The study's motion laws fail {len(study)} of the {count} checks its own words, "
        f"anatomy and balance decide (the minimum-jerk laws through its postures fail {same}): "
        "the trunk "
        f"leans {number(-value(checks, STUDY_LAW, 'lean_direction'))}° back where the study says "
        f"it leans forward; the thigh ends {number(-value(checks, STUDY_LAW, 'knee_side'))} mm "
        "in front of the shank's line, where a knee puts it behind; at the seat (1.5 s) the "
        f"loaded point A stands {number(value(checks, STUDY_LAW, 'A_seat'))} mm in front of the "
        f"ankle, past the foot's {number(bound(checks, 'A_seat', 'high'))} mm, and the ankle "
        f"would need {number(value(checks, STUDY_LAW, 'ankle_seat'))} N·m per newton of body "
        f"weight where a foot gives at most {number(bound(checks, 'ankle_seat', 'high'))}. One "
        "sign causes them: φ2 enters eqs. (2)–(3) as φ2 + φ3, so knee flexion turns the thigh "
        "forward past the shank. The corrected laws (the study's links and timing, the knee and "
        "hip turning the human way, the study's trunk lean turned forward, the seat reached with "
        f"the centre of mass over the foot) hold {count - len(failed(checks, CORRECTED))} of "
        f"the {count}. On them the tuned modules leave the user "
        f"{number(_largest_user(fits[CORRECTED]))} N·m RMS at the worst joint, against "
        f"{number(_largest_user(fits[law]))} N·m on the study's {law} law, with "
        f"{fits[CORRECTED]['parameters_at_upper_bounds']} module parameters at their upper "
        f"bound against {fits[law]['parameters_at_upper_bounds']}; most of that gain is the "
        "shallower motion, not better modules. The price is the seat: with "
        f"the whole body weight at A, {number(postures['hip_drop_mm'])} mm of hip drop is all "
        "that balance allows before the seat must take the weight."
    )


def _largest_user(fit: Mapping) -> float:
    """The largest of the joints' RMS user torques with the tuned modules."""
    return max(fit["tuned"][j]["user_rms_Nm"] for j in JOINTS)


def fe_paragraph(fe: Mapping) -> str:
    """The thigh link by finite elements in one paragraph: the converged field, what the beam
    formulas miss, and the study's three numbers against the loadings."""
    finest, bearing = fe["finest"], fe["hypotheses"]["bearing"]
    concentrated, seed = fe["hypotheses"]["concentrated"], fe["seed_fea"]
    tolerance = fe["convergence"]["tolerance_pct"]
    pin = next(r for r in fe["beam_against_fe"] if r["quantity"].startswith("peak at the loaded"))
    return (
        f"By finite elements (plane stress, quadratic triangles, every reported number within "
        f"{tolerance:g} % over the last two refinements), the configured link under the "
        f"design load peaks at {number(finest['bending']['peak']['MPa'])} MPa "
        f"({finest['bending']['peak']['where']}), deflects "
        f"{number(finest['bending']['max_displacement_mm'])} mm and reaches "
        f"{number(finest['compression']['peak']['MPa'])} MPa in compression "
        f"({finest['compression']['peak']['where']}). The beam formulas get the bending field "
        "and the deflection within a few per cent but miss the pin's load introduction: "
        f"{number(pin['fe'])} MPa at the loaded pin against F/(d·t) = {number(pin['formula'])} "
        f"MPa (a bearing factor of {number(bearing['bearing_factor'])}). The study's "
        f"{number(seed['bending_peak_MPa'])} MPa at the loaded end is no bearing stress of such "
        f"a pin (it gives {number(bearing['loaded_end_peak_MPa'])} MPa; a pin "
        f"{number(bearing['pin_diameter_for_reported_peak_mm'])} mm across would be needed), "
        "but a concentrated force reproduces it with elements of "
        f"{number(concentrated['element_mm_for_reported_peak'])} mm at the hole: that peak "
        f"grows as the element size to the power −{number(concentrated['exponent'])} and never "
        "converges, and the same mesh would show "
        f"{number(concentrated['compression_peak_at_that_size_MPa'])} MPa in compression, not "
        f"{_range(seed['compression_peak_MPa'])}. No loading of one link gives the three "
        f"numbers: on this link the deflection of {_range(seed['tip_deflection_mm'])} mm "
        f"appears at {number(bearing['load_for_reported_deflection_N'])} N and the compression "
        f"peak at {number(bearing['load_for_reported_compression_N'])} N."
    )


def _range(values) -> str:
    """A reported range as the study writes it, '26–27'."""
    low, high = values
    return f"{low:g}–{high:g}" if low != high else f"{low:g}"


def _cell(checks: pd.DataFrame, law: str, check: str) -> str:
    """A check's value with its unit and decision, for a table cell."""
    rows = checks[(checks["law"] == law) & (checks["check"] == check)].iloc[0]
    unit = "" if rows["unit"] == "1" else (" °" if rows["unit"] == "deg" else f" {rows['unit']}")
    return f"{number(rows['value'])}{unit}: {rows['decision']}"


def gains(checks: pd.DataFrame, modules: Mapping) -> list[str]:
    """The headline: every check the study's laws fail beside the corrected laws' value, and
    the modules tuned on each."""
    rows = []
    for check in failed(checks, STUDY_LAW):
        first = checks[(checks["law"] == STUDY_LAW) & (checks["check"] == check)].iloc[0]
        rows.append((first["quantity"], _cell(checks, STUDY_LAW, check),
                     _cell(checks, CORRECTED, check), first["expected"]))  # fmt: skip
    law = modules["study_law"]
    fits = modules["laws"]
    for joint in JOINTS:
        rows.append((f"user's RMS torque at the {joint}, tuned modules",
                     f"{number(fits[law]['tuned'][joint]['user_rms_Nm'])} N·m",
                     f"{number(fits[CORRECTED]['tuned'][joint]['user_rms_Nm'])} N·m",
                     "as small as the modules' bounds allow"))  # fmt: skip
    lines = ["## Gains of the corrected laws", "",
             f"The study's laws in their piecewise form (eq. 4) beside the corrected laws, for "
             f"every check the study's laws fail ([checks.csv](checks.csv)) and for the modules "
             f"tuned on each (the study's {law} law; [spring_damper.json](spring_damper.json)).",
             ""]  # fmt: skip
    lines += table(["quantity", "study's laws", "corrected laws", "expected"], rows)
    return [*lines, ""]


def unexplained(fe: Mapping) -> list[str]:
    """What the model leaves open."""
    seed = fe["seed_fea"]
    concentrated = fe["hypotheses"]["concentrated"]
    return ["## Left unexplained", "",
            f"- Whether the study's {number(seed['bending_peak_MPa'])} MPa is such a concentrated "
            "load's number: a concentrated force reproduces it with elements of "
            f"{number(concentrated['element_mm_for_reported_peak'])} mm at the hole, but the "
            "study reports neither its mesh there nor how its load reached the link.",
            f"- The study's deflection ({_range(seed['tip_deflection_mm'])} mm) and compression "
            f"peak ({_range(seed['compression_peak_MPa'])} MPa): the study gives no drawing of "
            "its link, and no loading of the configured one reproduces them (fe.json, "
            "hypotheses).",
            "- Where a user's weight really acts: the study puts it at A, on the pelvic plate just "
            "above the hip; a deeper seat in balance needs it higher up the trunk or a seat that "
            "takes it earlier, which the study does not describe.", ""]  # fmt: skip


def checks_section(checks: pd.DataFrame) -> list[str]:
    """Every check of every law with its expected range, decision and cause."""
    rows = []
    for _, r in checks.iterrows():
        unit = "" if r["unit"] == "1" else f" {unit_text(r['unit'])}"
        rows.append((r["law"], r["quantity"], f"{number(r['value'])}{unit}", r["expected"],
                     r["decision"], r["cause"] or "—"))  # fmt: skip
    lines = [
        "## Every check of every law",
        "",
        "Forward is the way the knee travels. The basis of each check (the study's words, "
        "anatomy, or balance with a chosen foot) is in [checks.csv](checks.csv).",
        "",
    ]
    lines += table(["law", "quantity", "value", "expected", "decision",
                    "part of eqs. (1)–(4) behind a departure"], rows)  # fmt: skip
    return [*lines, ""]


def modules_section(modules: Mapping) -> list[str]:
    """Required and user torques per joint, configured and tuned, on each law."""
    rows = []
    for law, fit in modules["laws"].items():
        for joint in JOINTS:
            tuned = fit["tuned"][joint]
            rows.append((law, joint, number(tuned["required_peak_Nm"]),
                         number(tuned["required_rms_Nm"]),
                         number(fit["user_rms_configured_Nm"][joint]),
                         number(tuned["user_rms_Nm"]),
                         ", ".join(tuned["at_upper_bounds"]) or "none"))  # fmt: skip
    lines = [
        "## Loads and modules on each law",
        "",
        "Inverse-dynamic extensor torques under the design load at A (N·m) and what the "
        "modules leave to the user ([spring_damper.json](spring_damper.json)). As in the "
        "study's loading, the whole weight stays on the legs while seated (1.5–2 s): no "
        "seat is modelled.",
        "",
    ]
    lines += table(["law", "joint", "required peak", "required RMS", "user RMS, configured",
                    "user RMS, tuned", "tuned parameters at their upper bound"],
                   rows)  # fmt: skip
    return [*lines, ""]


def fe_section(fe: Mapping) -> list[str]:
    """The finite-element model, its convergence, the beam formulas against it, and the study's
    three numbers against each loading."""
    conv = fe["convergence"]
    quantities = list(conv["last_change_pct"])
    rows = [(number(r["element_mm"]), number(r["hole_element_mm"]), r["dofs"],
             *(number(r[q]) for q in quantities)) for r in conv["table"]]  # fmt: skip
    rows.append(("change over the last two", "", "",
                 *(f"{number(conv['last_change_pct'][q])} %" for q in quantities)))  # fmt: skip
    model = fe["model"]
    lines = ["## The thigh link by finite elements", "",
             f"Model ([fe.json](fe.json)): {model['elements']}; {model['state']}; "
             f"{model['support']}; the design load of {number(model['load_N'])} N through the "
             f"hip pin, {number(model['lever_mm'])} mm from the built-in end. Mesh convergence "
             "(element sizes in mm; the concentrated loads' peaks are listed to show that they "
             "do not converge):", ""]  # fmt: skip
    lines += table(["elements", "at the holes", "unknowns", *quantities], rows)
    lines += ["", "The group's closed forms (strength.py, beam.py) for the same bar, support and "
              "load, against the finest mesh:", ""]  # fmt: skip
    lines += table(["quantity", "formula", "finite elements", "formula − FE", "left out"],
                   [(r["quantity"], f"{number(r['formula'])} {r['unit']}",
                     f"{number(r['fe'])} {r['unit']}", f"{number(r['difference_pct'])} %",
                     r["missed"]) for r in fe["beam_against_fe"]])  # fmt: skip
    lines += ["", "The study's three numbers against each loading of the configured link:", ""]
    lines += table(["loading", "bending peak at the loaded end", "tip deflection",
                    "compression peak", "reproduces"], _hypothesis_rows(fe))  # fmt: skip
    return [*lines, ""]


def _hypothesis_rows(fe: Mapping) -> list[tuple]:
    """The study's numbers, the pin's bearing and the concentrated force, one row each."""
    seed, bearing = fe["seed_fea"], fe["hypotheses"]["bearing"]
    concentrated = fe["hypotheses"]["concentrated"]

    def said(reproduced: Mapping) -> str:
        names = [k.replace("_", " ") for k, v in reproduced.items() if v]
        return ", ".join(names) or "none"

    return [
        ("the study (SolidWorks, 1500 N)", f"{number(seed['bending_peak_MPa'])} MPa",
         f"{_range(seed['tip_deflection_mm'])} mm", f"{_range(seed['compression_peak_MPa'])} MPa",
         "—"),
        ("pin bearing (cosine pressure on the half hole)",
         f"{number(bearing['loaded_end_peak_MPa'])} MPa",
         f"{number(bearing['tip_deflection_mm'])} mm",
         f"{number(bearing['compression_peak_MPa'])} MPa", said(bearing["reproduces"])),
        (f"concentrated force, elements of {number(concentrated['element_mm_for_reported_peak'])}"
         " mm at the hole", f"{number(seed['bending_peak_MPa'])} MPa (grows without bound)",
         f"{number(concentrated['tip_deflection_mm'])} mm",
         f"{number(concentrated['compression_peak_at_that_size_MPa'])} MPa",
         said(concentrated["reproduces"])),
    ]  # fmt: skip


def document(checks: pd.DataFrame, postures: Mapping, modules: Mapping, fe: Mapping) -> str:
    """summary.md: source, study, verdict, gains and what is left unexplained on its first
    screen; the checks, loads and the finite-element detail after."""
    sections = [
        frame.heading(
            "Sit-to-stand: what the study's motion laws and thigh-link numbers get wrong", SOURCE
        ),
        frame.source(SOURCE),
        frame.cited([studies.STS]),
        ["## Verdict", "", laws_paragraph(checks, postures, modules), "", fe_paragraph(fe), ""],
        gains(checks, modules),
        unexplained(fe),
        checks_section(checks),
        modules_section(modules),
        fe_section(fe),
        frame.references([studies.STS]),
    ]
    return frame.document(sections)
