"""Readings before causes: the study's law read facing +x and −x through the same checks, the
verdict that names no single sign while two readings survive, the corrected law that sits, and
a user's own law file through the same checks and verdict."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import REPO
from exobench.errors import InputError
from exobench.sts import body, checks, corrected, kinematics, laws, readings, summary

CONFIG = yaml.safe_load((REPO / "config" / "config.yaml").read_text())["sts"]
BODY = body.Body.from_config(CONFIG["body"], CONFIG["links_mm"])
SETTINGS = checks.Settings.from_config(CONFIG["checks"])
ADMITTED = ("as_written, facing +x", "as_written, facing -x")
# a reflection x -> -x changes none of these: the path's shape, the lean's size, the thigh's angle
MIRROR_BLIND = ("hip_path_inflections", "hip_path_curvature", "lean_size", "thigh_at_seat")


def table_of(named: dict[str, laws.Law]) -> pd.DataFrame:
    """Every check of every law, sampled at 200 Hz."""
    return pd.concat(
        [
            checks.law_checks(law, laws.sample(law, laws.time_grid(law, 200.0)), BODY, SETTINGS)[0]
            for law in named.values()
        ],
        ignore_index=True,
    )


def study_lean_deg(t: float, facing: int) -> float:
    """The trunk's lean forward from the vertical by eqs. (3)–(4) typed out here: the trunk's
    angle φ2 + φ3 − φ1 towards +x, turned the way the subject faces."""
    phi1, phi2, phi3 = (0.4 * math.pi * t, 0.25 * math.pi * t, 0.06 * math.pi * t)
    return facing * math.degrees(phi2 + phi3 - phi1)


def test_mirrored_readings_are_checked_apart_and_no_sign_is_named_while_two_survive():
    study = laws.readings(CONFIG)
    admitted = {name: study[name] for name in ADMITTED}
    table = table_of({name: law for name, (law, _, _) in admitted.items()})
    for name, facing in zip(ADMITTED, (1, -1), strict=True):
        lean = table[(table["law"] == name) & (table["check"] == "lean_direction")]["value"]
        assert float(lean.iloc[0]) == pytest.approx(study_lean_deg(1.5, facing), abs=1e-6)
    # with only the checks a reflection cannot change, both facings survive: no single sign
    blind = readings.verdict(table[table["check"].isin(MIRROR_BLIND)], admitted)
    assert blind["survivors"] == list(ADMITTED)
    assert blind["cause"] is None and "odd signs" in blind["ambiguity"]
    assert blind["settle"] and "faces" in blind["settle"]
    assert (
        blind["readings"][ADMITTED[0]]["odd_signs"] != blind["readings"][ADMITTED[1]]["odd_signs"]
    )
    # with every check, each reading's failures are listed apart; only the one that fails what
    # the other holds is rejected, and the cause is named under the surviving one alone
    full = readings.verdict(table, admitted)
    plus, minus = (full["readings"][n] for n in ADMITTED)
    assert plus["failed"] != minus["failed"]
    assert "lean_direction" in plus["rejected_by"]["words"]
    assert "knee_side" in plus["rejected_by"]["anatomy"]
    assert minus["status"] == "survives" and minus["rejected_by"] == {}
    assert full["survivors"] == [ADMITTED[1]]
    assert full["cause"]["odd_signs"] == ["phi3"]  # the shank, not φ2
    assert "hip_path_curvature" in full["common_failures"]


def test_the_sign_slips_a_reviewer_raises_are_checked_but_not_admitted():
    study = laws.readings(CONFIG)
    table = table_of({name: law for name, (law, _, _) in study.items()})
    verdict = readings.verdict(table, study)
    assert verdict["admitted"] == [n for n in study if n.startswith("as_written")]
    for name, reading in verdict["readings"].items():
        if not name.startswith("as_written"):
            assert reading["status"] == "not admitted" and reading["failed"].get("words")
    knee = verdict["readings"]["knee_reversed, facing +x"]["failed"]
    assert "thigh_at_seat" in knee["loading"]  # Fig. 6's horizontal thigh rejects it


@pytest.mark.parametrize("seat_mm", [430.0, 455.0, 480.0])
def test_the_corrected_law_sits_on_the_smallest_tilt_its_centre_of_pressure_allows(seat_mm):
    """Over the configured chair range: the hip at the seat, the centre of pressure on the heel's
    edge (the check solved for, not a margin), and every check it fails named by the summary."""
    sts = {**CONFIG, "corrected": {**CONFIG["corrected"], "seat_height_mm": seat_mm}}
    law = corrected.configured_laws(sts)["corrected"]
    low, high = CONFIG["corrected"]["chair_range_mm"]
    # the hip at the seat, from the chain typed out (forward +x, angles from the vertical:
    # shank φ3, thigh φ3 − φ2, trunk φ3 − φ2 + φ1)
    _, phi2, phi3 = law.angles_rad[law.seat_index]
    l_cd, l_bc = CONFIG["links_mm"]["l_CD"], CONFIG["links_mm"]["l_BC"]
    hip_y = l_cd * math.cos(phi3) + l_bc * math.cos(phi3 - phi2)
    assert low - 1e-9 <= hip_y <= high + 1e-9 and hip_y == pytest.approx(seat_mm)
    trunk = [math.degrees(p3 - p2 + p1) for p1, p2, p3 in law.angles_rad]
    assert trunk[law.seat_index] > 0.0 and trunk[-1] == pytest.approx(0.0, abs=1e-9)
    heel, rate = CONFIG["checks"]["foot"]["ankle_from_heel_mm"], CONFIG["sample_rate_Hz"]
    assert corrected.heel_clearance_mm(law, BODY, heel, rate) == pytest.approx(0.0, abs=1e-3)
    sampled = laws.sample(law, laws.time_grid(law, rate))
    table = checks.law_checks(law, sampled, BODY, SETTINGS)[0]
    assert table.set_index("check").loc["cop_standing", "decision"] == "holds"
    said = summary.chair_sentence(table, law.name, seat_mm)
    missed = list(table.loc[table["decision"] == "violated", "check"])
    assert all(name in said for name in missed) and ("holds every check" in said) == (not missed)
    with pytest.raises(InputError, match="chair_range_mm"):
        corrected.configured_laws({**sts, "corrected": {**sts["corrected"], "seat_height_mm": 600}})


def test_the_centre_of_pressure_is_taken_about_the_floor():
    """Raising the ankle by h moves the centre of pressure by −h Σf ẍ / Σf (g + ÿ) (the segments'
    accelerations by central differences, as the model takes them)."""
    law = corrected.configured_laws(CONFIG)["corrected"]
    t = laws.time_grid(law, 200.0)
    points = kinematics.closed_loop(law.chain, laws.sample(law, t)).position_m
    floor = body.centre_of_pressure(BODY, t, points)
    ankle = body.centre_of_pressure(replace(BODY, ankle_height_m=0.0), t, points)
    r = body.segment_centres(BODY, points)
    acc = np.gradient(np.gradient(r, t, axis=0), t, axis=0)
    shift = (
        -BODY.ankle_height_m
        * (acc[..., 0] @ BODY.fractions)
        / ((9.81 + acc[..., 1]) @ BODY.fractions)
    )
    assert BODY.ankle_height_m == pytest.approx(0.039 * (0.46 + 0.5) / (0.246 + 0.245))
    np.testing.assert_allclose(floor - ankle, shift, atol=1e-12)
    assert np.abs(shift).max() > 1e-3  # the floor moves it by more than a millimetre


def test_the_verdicts_sentences_follow_their_flags():
    """Each sentence built from its flag: the opposite flag gives the opposite sentence."""
    fixed = {"table": [{"fixed_face_peak_MPa": p, "corner_element_mm": h}
                       for p, h in ((100.0, 4.0), (101.0, 1.0), (101.5, 0.25))],
             "peak_last_change_pct": 0.5, "tolerance_pct": 2.0, "peak_exponent": 0.01}  # fmt: skip
    assert "it converges" in summary.fixed_sentence(
        {**fixed, "singular_corner": False, "peak_converges": True}
    )
    assert "singular" in summary.fixed_sentence(
        {**fixed, "singular_corner": True, "peak_converges": False}
    )
    search = {"screened": 10, "tolerance_pct": 10.0, "study_material": "steel",
              "targets": {"tip_deflection_mm": 0.31, "compression_peak_MPa": 26.5}}  # fmt: skip
    rows = pd.DataFrame([{"material": m, "confirmed": c, "depth_mm": 100.0, "thickness_mm": 10.0,
                          "pin_diameter_mm": 10.0, "fe_deflection_mm": 0.3,
                          "fe_compression_peak_MPa": 25.0, "fe_loaded_end_peak_MPa": 26.0}
                         for m, c in (("steel", False), ("aluminium", True))])  # fmt: skip
    text = summary.search_sentence(search, rows)
    assert "In the study's steel no confirmed link" in text and "(aluminium)" in text
    rows["confirmed"] = [True, False]
    text = summary.search_sentence(search, rows)
    assert "(steel)" in text and "In another material no confirmed link" in text
    law = corrected.configured_laws(CONFIG)["corrected"]
    table = table_of({"corrected": law})
    table["decision"] = "holds"
    assert summary.chair_sentence(table, "corrected", 450.0).endswith("holds every check")
    table.loc[table["check"] == "lean_size", "decision"] = "violated"
    assert "fails lean_size" in summary.chair_sentence(table, "corrected", 450.0)


def test_the_study_loading_cannot_balance_at_a_chair():
    """With the whole weight at A, the thigh within 15° of horizontal and a slight lean, A stays
    behind the heel at a chair's height: a grid over shank tilts typed out here agrees."""
    law = corrected.configured_laws(CONFIG)["corrected"]
    reach = corrected.loaded_point_reach(law.chain, 450.0, 15.0, 30.0)
    tilt = np.linspace(0.0, math.pi / 2, 20001)
    rise = (0.45 - 0.46 * np.cos(tilt)) / 0.5
    ok = np.abs(rise) <= math.sin(math.radians(15.0))
    x_a = 0.46 * np.sin(tilt) - 0.5 * np.sqrt(1 - rise**2) + 0.16 * math.sin(math.radians(30.0))
    assert reach["loaded_point_farthest_forward_mm"] == pytest.approx(1000 * x_a[ok].max(), abs=0.1)
    assert (
        reach["loaded_point_farthest_forward_mm"] < -CONFIG["checks"]["foot"]["ankle_from_heel_mm"]
    )


def test_a_users_law_file_goes_through_the_same_checks_and_verdict(tmp_path):
    """The corrected law written as a user's file facing −x with every sign turned: the same
    motion, so the same checks hold; its verdict names no odd sign; a bad field is named."""
    law = corrected.configured_laws(CONFIG)["corrected"]
    path = tmp_path / "my_law.yaml"
    path.write_text(
        yaml.safe_dump(
            {
                "name": "my law",
                "knots_s": list(law.knots_s),
                "seat_s": law.seat_s,
                "angles_deg": {
                    c: np.degrees(law.angles_rad[:, i]).tolist()
                    for i, c in enumerate(("phi1", "phi2", "phi3"))
                },
                "interpolation": "min_jerk",
                "facing": -1,
                "links_mm": dict(law.links_mm),
                "signs": {
                    k: [-v for v in row]
                    for k, row in zip(("CD", "BC", "AB"), law.signs, strict=True)
                },
                "seat_height_mm": law.seat_height_mm,
            }
        )
    )
    mine = laws.load(path)
    mirror = replace(mine, name="my law, mirrored", facing=1)
    table = table_of({"mine": mine, "mirror": mirror, "corrected": law})
    ours, theirs = (
        table[table["law"] == n].reset_index(drop=True) for n in ("my law", "corrected")
    )
    np.testing.assert_allclose(ours["value"], theirs["value"], atol=1e-9)
    verdict = readings.verdict(
        table,
        {"my law": (mine, "the file", True), "my law, mirrored": (mirror, "its mirror", False)},
    )
    assert verdict["survivors"] == ["my law"] and verdict["cause"]["odd_signs"] == []
    assert verdict["readings"]["my law, mirrored"]["failed"]  # the mirror leans back, etc.
    path.write_text(path.read_text().replace("facing: -1", "facing: 2"))
    with pytest.raises(InputError, match=r"my_law\.yaml.*'facing'"):
        laws.load(path)


@pytest.mark.parametrize(
    ("field", "bad"),
    [("angles_deg", [1, 2]), ("facing", "left"), ("links_mm", {"l_CD": "x", "l_BC": 1, "l_AB": 1}),
     ("knots_s", [0, "one"]), ("seat_height_mm", "high")],
)  # fmt: skip
def test_a_bad_law_file_names_the_file_and_the_field(tmp_path, field, bad):
    law = {"name": "bad", "knots_s": [0.0, 1.0], "seat_s": 1.0,
           "angles_deg": {"phi1": [0, 1], "phi2": [0, 1], "phi3": [0, 1]},
           "interpolation": "linear", "facing": 1,
           "links_mm": {"l_CD": 460, "l_BC": 500, "l_AB": 160},
           "signs": {"CD": [0, 0, 1], "BC": [0, 1, 1], "AB": [-1, 1, 1]}}  # fmt: skip
    path = tmp_path / "bad_law.yaml"
    path.write_text(yaml.safe_dump({**law, field: bad}))
    with pytest.raises(InputError, match=rf"bad_law\.yaml.*'{field}"):
        laws.load(path)
