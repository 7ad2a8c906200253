"""The sit-to-stand group through the Snakemake command line, as a user runs it: its outputs,
checks, finite-element report and summary read from the shared small run (tests/conftest.py),
and its refusals of bad input in a copy of the workflow."""

from __future__ import annotations

import itertools
import json
import re

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
import yaml

from conftest import REPO, SMALL_RUN, snakemake
from exobench import studies
from exobench.selection.summary import number
from exobench.sts import corrected

pytestmark = pytest.mark.slow

BEAM_KEYS = {
    "max_bending_moment_Nm": float,
    "nominal_bending_stress_MPa": float,
    "peak_stress_MPa": float,
    "tip_deflection_mm": float,
    "buckling_load_N": float,
    "safety_factor_yield": float,
    "fatigue_safety_factor": float,
    "seed_fea_consistent": bool,
    "explanation": str,
}
OUTPUTS = (
    "sts/trajectories.parquet",
    "sts/trajectories_smooth.parquet",
    "sts/trajectories_corrected.parquet",
    "sts/trajectories_corrected_study_seat.parquet",
    "sts/corrected_laws.json",
    "sts/readings.json",
    "sts/sections.csv",
    "sts/study_comparison.csv",
    "sts/verification.json",
    "sts/loads.parquet",
    "sts/motion_comparison.json",
    "sts/spring_damper.json",
    "sts/spring_damper.parquet",
    "sts/checks.csv",
    "sts/beam_check.json",
    "sts/fe.json",
    "sts/fe_field.parquet",
    "sts/fe_mesh.parquet",
    "sts/summary.md",
    "figures/sts/paths.png",
    "figures/sts/torques.pdf",
    "figures/sts/modules.png",
    "figures/sts/thigh.png",
    "figures/sts/fe.png",
)
LAWS = ("piecewise", "smooth", "corrected", "corrected_study_seat")  # motion.LAWS
READINGS = tuple(f"{signs}, facing {side}x" for signs in ("as_written", "knee_reversed",
                 "hip_reversed") for side in "+-")  # fmt: skip


@pytest.fixture(scope="module")
def sts(small_run):
    """The small run's sit-to-stand results."""
    return small_run / "results" / "sts"


@SMALL_RUN
def test_sts_target_builds_every_output_with_units(small_run, sts):
    results = small_run / "results"
    for name in OUTPUTS:
        assert (results / name).stat().st_size > 0, name
    schema = pq.read_schema(sts / "trajectories_corrected.parquet")
    for column in ("t_s", "xC_mm", "yC_mm", "xB_mm", "yB_mm", "xA_mm", "yA_mm"):
        assert column in schema.names
    assert schema.field("xA_mm").metadata[b"unit"] == b"mm"
    assert schema.field("vxA_mm_per_s").metadata[b"unit"] == b"mm/s"
    assert b"exobench.provenance" in schema.metadata
    field = pq.read_schema(sts / "fe_field.parquet")
    assert field.field("bending_von_mises_MPa").metadata[b"unit"] == b"MPa"


@SMALL_RUN
def test_verification_and_beam_check_meet_the_contract(sts):
    verification = json.loads((sts / "verification.json").read_text())
    assert set(verification["laws"]) == set(LAWS)
    assert verification["max_position_deviation_m"] < 1e-9
    assert verification["passed"] is True
    check = json.loads((sts / "beam_check.json").read_text())
    for key, kind in BEAM_KEYS.items():
        assert isinstance(check[key], kind), key
    assert check["max_bending_moment_Nm"] == pytest.approx(750.0)
    assert check["seed_fea_consistent"] is False
    fit = json.loads((sts / "spring_damper.json").read_text())
    assert set(fit["laws"]) == {fit["study_law"], "corrected", "corrected_study_seat"}
    for law in fit["laws"].values():
        for joint, tuned in law["tuned"].items():
            assert tuned["user_rms_Nm"] <= law["user_rms_configured_Nm"][joint] + 1e-9


@SMALL_RUN
def test_every_reading_is_checked_and_the_verdict_names_a_cause_only_under_its_survivor(sts):
    table = pd.read_csv(sts / "checks.csv", keep_default_na=False)
    chairs = yaml.safe_load((REPO / "config" / "config.yaml").read_text())["sts"]["corrected"]
    chair_laws = tuple(f"corrected, {h:g} mm chair" for h in chairs["chair_range_mm"])
    names = (*READINGS, "corrected", "corrected_study_seat", *chair_laws)
    assert list(dict.fromkeys(table["law"])) == list(names)
    counts = table.groupby("law")["check"].apply(list)
    assert all(counts[name] == counts["corrected"] for name in names)
    assert set(table["decision"]) <= {"holds", "violated"}
    inside = (table["value"] >= table["low"]) & (table["value"] <= table["high"])
    assert ((table["decision"] == "holds") == inside).all()
    # the corrected law holds the check it is solved for; what it fails, the verdict names
    verdict_text = (sts / "summary.md").read_text().split("## Left unexplained")[0]
    for law in ("corrected", *chair_laws):
        rows = table[table["law"] == law].set_index("check")
        assert rows.loc["cop_standing", "decision"] == "holds"
        assert all(c in verdict_text for c in rows.index[rows["decision"] == "violated"])
    assert (table["basis"] != "").all()
    verdict = json.loads((sts / "readings.json").read_text())
    assert verdict["admitted"] == list(READINGS[:2])
    assert verdict["survivors"] == ["as_written, facing -x"]
    assert verdict["cause"]["odd_signs"] == ["phi3"]
    comparison = pd.read_csv(sts / "study_comparison.csv", keep_default_na=False)
    assert set(comparison["role"]) <= {"setting", "derived", "calibration target", "prediction"}
    assert (comparison["role_basis"] != "").all()
    found = pd.read_csv(sts / "sections.csv")
    assert found["confirmed"].any()


@SMALL_RUN
def test_the_finite_elements_converge_and_name_the_loaded_end_peak(sts):
    fe = json.loads((sts / "fe.json").read_text())
    convergence = fe["convergence"]
    for quantity, converged in convergence["converged"].items():
        assert converged == ("concentrated" not in quantity), quantity
    table = convergence["table"]
    assert len(table) >= 3 and table[-1]["dofs"] > table[0]["dofs"]
    # the concentrated load's peak grows as the mesh refines, on the finest meshes about as the
    # element size halves: no converged value
    peaks = [row["concentrated bending load's peak at the loaded end (MPa)"] for row in table]
    assert all(b > a for a, b in itertools.pairwise(peaks)) and peaks[-1] > 1.5 * peaks[-2]
    finest = fe["finest"]
    assert finest["bending"]["peak"]["where"] == "built-in end, outer fibre"
    assert finest["bending"]["loaded_end_peak"]["where"] == "edge of the hip pin hole"
    assert fe["hypotheses"]["bearing"]["reproduces"] == {
        "bending_peak_at_loaded_end": False,
        "tip_deflection": False,
        "compression_peak": False,
    }
    assert fe["hypotheses"]["concentrated"]["reproduces"]["compression_peak"] is False
    sections = pd.read_csv(sts / "sections.csv")  # each material's best, the study's first
    assert sections["material"].iloc[0] == fe["sections"]["study_material"]
    assert set(sections["material"]) == set(fe["sections"]["materials"])
    rows = {row["quantity"]: row for row in fe["beam_against_fe"]}
    deflection = next(r for q, r in rows.items() if q.startswith("largest deflection"))
    assert abs(deflection["difference_pct"]) < 3.0


def tables_numbers(sts) -> set[str]:
    """Every number of the tables summary.md reads, as the summary writes numbers (three
    significant digits, or as given), with the counts of checks it states."""
    values: list[float] = []

    def walk(item) -> None:
        if isinstance(item, dict):
            for value in item.values():
                walk(value)
        elif isinstance(item, list):
            for value in item:
                walk(value)
        elif isinstance(item, int | float) and not isinstance(item, bool):
            values.append(float(item))

    for name in ("corrected_laws.json", "spring_damper.json", "fe.json", "readings.json"):
        walk(json.loads((sts / name).read_text()))
    for name in ("sections.csv", "study_comparison.csv"):
        found = pd.read_csv(sts / name)
        values += [float(v) for v in found.select_dtypes("number").to_numpy().ravel()]
    checks = pd.read_csv(sts / "checks.csv", keep_default_na=False)
    values += [float(v) for v in checks[["value", "low", "high"]].to_numpy().ravel()]
    values += [float(v) for v in checks.groupby("law")["decision"].apply(
        lambda d: (d == "violated").sum()).tolist()]  # fmt: skip
    values += [float(len(checks[checks["law"] == law])) for law in LAWS]
    out = set()
    for v in values:
        for x in (v, -v):
            out |= {number(x), f"{x:g}"}
    return out


@SMALL_RUN
def test_the_summary_opens_with_its_verdict_and_every_number_comes_from_the_tables(sts):
    text = (sts / "summary.md").read_text()
    lines = text.splitlines()
    screen = "\n".join(lines[:40])
    assert lines[0].startswith("# Sit-to-stand, on the model only")
    assert lines[2].startswith("**Source: the model only.**")
    assert studies.STS.title in screen and studies.reference(studies.STS) in text
    for heading in ("## Verdict", "## Left unexplained"):
        assert heading in screen
    # numbers that name things, not values: equations, sections, times of the cycle, panels
    references = (r"eqs?\. \(\d\)(–\(\d\))?", r"eqs?\. \d(–\d)?", r"\(\d\)",
                  r"Table \d+\.\d+, case \d\w", r"\d+(\.\d+)?(–\d+(\.\d+)?)? s\b",
                  r"φ\d", r"\(\d{4}\)", r"Dempster \d{4}", r"\d+th ed\.", r"Table \d+\.\d+",
                  r"Fig\. \d+(\.\d+)?\w?", r"\d{4}-T\d")  # fmt: skip
    named = re.sub("|".join(references), "", text)
    written = re.findall(r"(?<![\w.])-?\d+(?:\.\d+)?(?:e-?\d+)?(?:–\d+(?:\.\d+)?)?", named)
    known = tables_numbers(sts)
    unknown = []
    for token in written:
        parts = token.split("–") if "–" in token and not token.startswith("-") else [token]
        unknown += [p for p in parts if p not in known]
    assert unknown == [], unknown


def test_bad_sample_rate_is_refused_without_outputs(workflow_copy):
    config = yaml.safe_load((workflow_copy / "config" / "config.yaml").read_text())
    config["sts"]["sample_rate_Hz"] = 333
    (workflow_copy / "bad.yaml").write_text(yaml.safe_dump(config))
    run = snakemake(workflow_copy, "sts_kinematics", "--configfile", "bad.yaml", check=False)
    assert run.returncode != 0
    assert "sts.sample_rate_Hz" in run.stderr
    assert not (workflow_copy / "results" / "sts" / "trajectories.parquet").exists()


def test_broken_reference_names_file_and_field(workflow_copy):
    """The finite-element rule reads the study's numbers first (it needs no other rule)."""
    reported = workflow_copy / "raw" / "reference" / "seed001_reported.csv"
    broken = reported.read_text().replace("fea_compression_peak_MPa", "fea_compression")
    reported.write_text(broken)
    run = snakemake(workflow_copy, "sts_fe", check=False)
    assert run.returncode != 0
    assert "seed001_reported.csv" in run.stderr
    assert "fea_compression_peak_MPa" in run.stderr
    assert not (workflow_copy / "results" / "sts" / "fe.json").exists()
    assert reported.read_text() == broken  # the user's file is left as they wrote it


def test_a_users_law_file_goes_through_the_workflows_checks_and_verdict(workflow_copy):
    """sts.user_laws → sts_checks: the corrected law written as a user's file facing −x with every
    sign turned is the same motion, so it gets the corrected law's checks row for row, survives
    its mirror, and the verdict names no odd sign."""
    config = yaml.safe_load((workflow_copy / "config" / "config.yaml").read_text())
    law = corrected.configured_laws(config["sts"])["corrected"]
    (workflow_copy / "my_law.yaml").write_text(yaml.safe_dump({
        "name": "my law", "knots_s": list(law.knots_s), "seat_s": law.seat_s,
        "angles_deg": {c: np.degrees(law.angles_rad[:, i]).tolist()
                       for i, c in enumerate(("phi1", "phi2", "phi3"))},
        "interpolation": "min_jerk", "facing": -1, "links_mm": dict(law.links_mm),
        "signs": {k: [-v for v in row] for k, row in zip(("CD", "BC", "AB"), law.signs,
                                                        strict=True)},
        "seat_height_mm": law.seat_height_mm}))  # fmt: skip
    config["sts"]["user_laws"] = ["my_law.yaml"]
    (workflow_copy / "mine.yaml").write_text(yaml.safe_dump(config))
    snakemake(workflow_copy, "results/sts/readings.json", "--configfile", "mine.yaml")
    checks = pd.read_csv(workflow_copy / "results" / "sts" / "checks.csv", keep_default_na=False)
    ours, theirs = (checks[checks["law"] == n].reset_index(drop=True)
                    for n in ("my law", "corrected"))  # fmt: skip
    assert list(ours["check"]) == list(theirs["check"]) and len(ours) > 0
    np.testing.assert_allclose(ours["value"], theirs["value"], atol=1e-6)
    assert list(ours["decision"]) == list(theirs["decision"])
    verdict = json.loads((workflow_copy / "results" / "sts" / "readings.json").read_text())
    user = verdict["users"]["my law"]
    assert user["survivors"] == ["my law"] and user["cause"]["odd_signs"] == []
    assert user["readings"]["my law, mirrored"]["failed"]
