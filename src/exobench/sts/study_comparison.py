"""The sit-to-stand study's numbers beside the project's (``study_comparison.csv``), each row
with its role by the project's one role rule (:mod:`exobench.roles`) and the inputs that
determine it."""

from __future__ import annotations

from collections.abc import Mapping

import pandas as pd

from exobench import roles
from exobench.roles import Provenance

COLUMNS = [
    "key",
    "quantity",
    "unit",
    "study_low",
    "study_high",
    "study_source",
    "project",
    "project_source",
    "within_study_range",
]
CHOSEN_SECTION = (
    "the configured section, holes and end margin (sts.thigh_link: chosen, the study gives "
    "no drawing)"
)


def _row(
    key: str,
    quantity: str,
    unit: str,
    study: tuple[float, float],
    study_source: str,
    project: float,
    project_source: str,
    facts: Provenance,
    tolerance: float = 0.0,
) -> dict:
    """One row: study range, project value, within the range widened by ``tolerance``, role."""
    low, high = study
    within = low * (1 - tolerance) <= project <= high * (1 + tolerance)
    return {
        "key": key,
        "quantity": quantity,
        "unit": unit,
        "study_low": low,
        "study_high": high,
        "study_source": study_source,
        "project": float(project),
        "project_source": project_source,
        "within_study_range": bool(within),
        **roles.columns(facts),
    }


def table(
    reported: pd.DataFrame, settings: Mapping, fe: Mapping, sections: pd.DataFrame
) -> pd.DataFrame:
    """Every study number beside the project's, the searched link the first confirmed row."""
    rows = reported.set_index("metric")

    def study(metric: str) -> tuple[float, float]:
        """The study's range of one metric."""
        return float(rows.loc[metric, "low"]), float(rows.loc[metric, "high"])

    def source(metric: str) -> str:
        """Where the study gives one metric."""
        return f"the study, {rows.loc[metric, 'source']}"

    link, material = settings["links_mm"], settings["thigh_link"]["material"]
    bearing, levers = fe["hypotheses"]["bearing"], fe["levers"]
    found = (
        sections[sections["confirmed"]].iloc[0] if sections["confirmed"].any() else sections.iloc[0]
    )
    tol = float(settings["sections"]["tolerance_pct"]) / 100.0
    found_text = (
        f"the searched link {found['depth_mm']:g} × {found['thickness_mm']:g} mm, "
        f"pins {found['pin_diameter_mm']:g} mm, {found['material']} "
        f"({'the study' if found['study_material'] else 'not the study'}'s material; "
        "sections.csv, FE)"
    )
    put_in = "taken from the study into config/config.yaml"
    out = [
        _row(
            "design_load_N",
            "design load at A",
            "N",
            study("design_load_N"),
            source("design_load_N"),
            settings["design_load_N"],
            "sts.design_load_N",
            Provenance(determined_by=(f"sts.design_load_N ({put_in})",)),
        ),
        _row(
            "l_BC_mm",
            "thigh link length BC",
            "mm",
            (500.0, 500.0),
            "the study, §4 (l_BC)",
            link["l_BC"],
            "sts.links_mm.l_BC",
            Provenance(determined_by=(f"sts.links_mm.l_BC ({put_in})",)),
        ),
        _row(
            "bending_moment_eq5_Nm",
            "bending moment, thigh horizontal, eq. (5) lever F·l_BC",
            "N·m",
            study("bending_moment_horizontal_thigh_Nm"),
            source("bending_moment_horizontal_thigh_Nm"),
            levers["eq5_moment_Nm"],
            "fe.json levers",
            Provenance(derived_from=("design_load_N", "l_BC_mm")),
        ),
        _row(
            "bending_moment_configured_Nm",
            "bending moment at the built-in end of the configured bar (lever l_BC + end margin)",
            "N·m",
            study("bending_moment_horizontal_thigh_Nm"),
            source("bending_moment_horizontal_thigh_Nm"),
            levers["configured_moment_Nm"],
            "fe.json levers",
            Provenance(
                determined_by=(
                    "sts.thigh_link.end_margin_mm (chosen: the clamp at the bar's end, "
                    f"{levers['configured_lever_mm'] - levers['eq5_lever_mm']:g} mm behind the "
                    "knee pin)",
                    "sts.design_load_N",
                )
            ),
        ),
        _row(
            "yield_MPa",
            "yield strength, steel St. 3",
            "MPa",
            study("yield_strength_MPa"),
            source("yield_strength_MPa"),
            material["yield_MPa"],
            "sts.thigh_link.material",
            Provenance(determined_by=(f"sts.thigh_link.material.yield_MPa ({put_in})",)),
        ),
        _row(
            "allowable_MPa",
            "allowable stress, steel St. 3",
            "MPa",
            study("allowable_stress_MPa"),
            source("allowable_stress_MPa"),
            material["allowable_MPa"],
            "sts.thigh_link.material",
            Provenance(determined_by=(f"sts.thigh_link.material.allowable_MPa ({put_in})",)),
        ),
        _row(
            "configured_loaded_end_peak_MPa",
            "bending peak at the loaded end, configured link",
            "MPa",
            study("fea_bending_von_mises_peak_MPa"),
            source("fea_bending_von_mises_peak_MPa"),
            bearing["loaded_end_peak_MPa"],
            "fe.json (finest mesh, pin bearing)",
            Provenance(determined_by=(CHOSEN_SECTION,)),
        ),
        _row(
            "configured_deflection_mm",
            "tip deflection, configured link",
            "mm",
            study("fea_tip_deflection_mm"),
            source("fea_tip_deflection_mm"),
            bearing["tip_deflection_mm"],
            "fe.json (finest mesh)",
            Provenance(determined_by=(CHOSEN_SECTION,)),
        ),
        _row(
            "configured_compression_peak_MPa",
            "compression peak, configured link",
            "MPa",
            study("fea_compression_peak_MPa"),
            source("fea_compression_peak_MPa"),
            bearing["compression_peak_MPa"],
            "fe.json (finest mesh, pin bearing)",
            Provenance(determined_by=(CHOSEN_SECTION,)),
        ),
        _row(
            "searched_deflection_mm",
            "tip deflection, searched link",
            "mm",
            study("fea_tip_deflection_mm"),
            source("fea_tip_deflection_mm"),
            found["fe_deflection_mm"],
            found_text,
            Provenance(
                matched_by=(
                    "the section search (depth, thickness, pin, material) screened to this number",
                )
            ),
            tol,
        ),
        _row(
            "searched_compression_peak_MPa",
            "compression peak, searched link",
            "MPa",
            study("fea_compression_peak_MPa"),
            source("fea_compression_peak_MPa"),
            found["fe_compression_peak_MPa"],
            found_text,
            Provenance(matched_by=("the section search screened to this number",)),
            tol,
        ),
        _row(
            "searched_loaded_end_peak_MPa",
            "bending peak at the loaded end, searched link",
            "MPa",
            study("fea_bending_von_mises_peak_MPa"),
            source("fea_bending_von_mises_peak_MPa"),
            found["fe_loaded_end_peak_MPa"],
            found_text,
            Provenance(
                determined_by=(
                    "the searched section (fitted to the deflection and compression peak, not to "
                    "this number)",
                )
            ),
        ),
        _row(
            "safety_factor_yield",
            "safety factor on yield, configured link",
            "1",
            study("fea_safety_factor_yield"),
            source("fea_safety_factor_yield"),
            material["yield_MPa"] / fe["finest"]["bending"]["peak"]["MPa"],
            "yield over fe.json's largest bending peak",
            Provenance(determined_by=(CHOSEN_SECTION, "sts.thigh_link.material.yield_MPa")),
        ),
    ]
    frame = pd.DataFrame(out)
    roles.check(frame, "key", "results/sts/study_comparison.csv")
    return frame[COLUMNS + roles.ROLE_COLUMNS]
