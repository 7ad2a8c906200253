"""The checks every motion law goes through: a departure drawn into the corrected law (fixed
seeds) is found by its own check, the hip path's curvature is the path's geometry, the centre
of mass and the seat contact follow the body's table."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import REPO
from exobench.sts import body, checks, corrected, laws

CONFIG = yaml.safe_load((REPO / "config" / "config.yaml").read_text())["sts"]
BUILT = corrected.configured_laws(CONFIG)
BODY = body.Body.from_config(CONFIG["body"], CONFIG["links_mm"])
SETTINGS = checks.Settings.from_config(CONFIG["checks"])


def checked(law: laws.Law) -> pd.DataFrame:
    """Every check of a law sampled at 200 Hz, by check."""
    sampled = laws.sample(law, laws.time_grid(law, 200.0))
    return checks.law_checks(law, sampled, BODY, SETTINGS)[0].set_index("check")


@pytest.mark.parametrize("seed", [11, 21, 4242, 31337, 7])  # every kind once
def test_a_departure_drawn_into_the_corrected_law_is_found_by_its_check(seed):
    print(f"seed {seed}")
    rng = np.random.default_rng(seed)
    kind = str(rng.choice(["lean_back", "lean_far", "crouch", "steep_thigh", "none"]))
    size = float(np.radians(rng.uniform(10.0, 25.0)))
    law = BUILT["corrected"]
    angles = law.angles_rad.copy()
    seat = law.seat_index
    if kind == "lean_back":  # the trunk leans back instead: φ1 smaller through the descent
        angles[1 : seat + 1, 0] -= 2 * np.radians(24.3) + size
    elif kind == "lean_far":  # beyond 'slightly'
        angles[1 : seat + 1, 0] += np.radians(30.0) - np.radians(24.3) + size
    elif kind == "crouch":  # the shank tilts further forward at the same hip flexion: the thigh
        angles[seat:, 2] += size  # turns up, away from horizontal
    elif kind == "steep_thigh":
        angles[seat:, 1] -= size
    table = checked(replace(law, angles_rad=angles, seat_height_mm=None))
    base = checked(replace(law, seat_height_mm=None))
    violated = set(table.index[table["decision"] == "violated"]) - set(
        base.index[base["decision"] == "violated"]
    )  # the law's own failures (e.g. the ankle's range) are not the departure's
    expected = {
        "lean_back": "lean_direction",
        "lean_far": "lean_size",
        "crouch": "thigh_at_seat",
        "steep_thigh": "thigh_at_seat",
        "none": None,
    }[kind]
    assert (expected in violated) if expected else not violated, (kind, size, violated)


def test_the_hip_curvature_is_the_paths_geometry():
    """An elliptic arc as the hip's path (independent of the chain): Menger's curvature next to
    its ends is the ellipse's there, κ = ab/(a² sin² u + b² cos² u)^(3/2), whatever the timing
    (the second and the second-last of 51 points equally spaced in arc length)."""
    a, b = 0.4, 0.25
    t = np.linspace(0.0, 1.5, 1501)
    u = 0.2 + 1.1 * (t / 1.5) ** 2  # uneven timing
    frame = pd.DataFrame({"t_s": t, "xB_mm": 1000 * a * np.cos(u), "yB_mm": 1000 * b * np.sin(u)})
    kappa = checks.hip_curvature(frame, 1.5)

    def exact(v: float) -> float:
        return a * b / (a**2 * np.sin(v) ** 2 + b**2 * np.cos(v) ** 2) ** 1.5

    fine = np.linspace(0.2, 1.3, 200001)
    arc = np.concatenate(
        [[0.0], np.cumsum(np.hypot(np.diff(a * np.cos(fine)), np.diff(b * np.sin(fine))))]
    )
    for k, index in ((0, 1), (-1, 49)):
        where = fine[np.searchsorted(arc, arc[-1] * index / 50)]
        assert abs(kappa[k]) == pytest.approx(exact(where), rel=5e-3)
    assert np.all(np.sign(kappa) == np.sign(kappa[0]))


def test_the_centre_of_mass_and_the_seat_follow_the_table():
    """Standing straight, every segment's centre is over the ankle; a posture's centre of mass
    is the mass-weighted mean of the segment centres placed by hand from the table."""
    points = np.array([[0.0, 0.46], [0.0, 0.96], [0.0, 1.12]])
    assert body.centre_of_mass(BODY, points)[0] == pytest.approx(0.0, abs=1e-12)
    shank, thigh = np.array([0.2, 0.4]), np.array([-0.3, 0.45])
    trunk = np.array([np.sin(0.3), np.cos(0.3)])
    pts = np.array([shank, thigh, thigh + 0.16 * trunk])
    table = CONFIG["body"]
    stature = (
        (CONFIG["links_mm"]["l_CD"] + CONFIG["links_mm"]["l_BC"])
        / 1000
        / (table["length_per_stature"]["shank"] + table["length_per_stature"]["thigh"])
    )
    lengths = table["length_per_stature"]
    centres = [
        (1 - table["centre_from_proximal"]["shank"]) * shank,
        thigh + table["centre_from_proximal"]["thigh"] * (shank - thigh),
        thigh + table["centre_from_proximal"]["trunk"] * lengths["trunk"] * stature * trunk,
        thigh + lengths["hip_to_ear"] * stature * trunk,
        thigh + lengths["trunk"] * stature * trunk,
    ]
    m = table["mass_fraction"]
    weights = [2 * m["shank"], 2 * m["thigh"], m["trunk"], m["head_neck"], 2 * m["arm"]]
    expected = sum(w * c for w, c in zip(weights, centres, strict=True)) / sum(weights)
    np.testing.assert_allclose(body.centre_of_mass(BODY, pts), expected, atol=1e-12)
    assert body.contact_index(np.array([0.9, 0.6, 0.45, 0.45]), 0.45) == 2
    assert body.contact_index(np.array([0.9, 0.6]), 0.45) is None


def test_the_joint_ranges_are_the_human_chains_coordinates():
    """On the corrected chain (shank φ3, thigh φ3 − φ2, trunk φ3 − φ2 + φ1 from the vertical) the
    ankle's dorsiflexion is φ3, the knee's flexion φ2 and the hip's φ1: each check's value is the
    coordinate's largest over the cycle, and its bound and source are the configured ones."""
    law = BUILT["corrected"]
    sampled = laws.sample(law, laws.time_grid(law, 200.0))
    table = checks.law_checks(law, sampled, BODY, SETTINGS)[0].set_index("check")
    largest = np.degrees(sampled.q_rad.max(axis=0))
    for joint, column in (("ankle_dorsiflexion", 2), ("knee_flexion", 1), ("hip_flexion", 0)):
        row = table.loc[f"{joint}_range"]
        assert row["value"] == pytest.approx(largest[column], abs=1e-6), joint
        bound = CONFIG["checks"]["range_of_motion"][joint]
        assert row["high"] == bound["max_deg"] and bound["source"] in row["basis"]
        assert row["decision"] == ("holds" if largest[column] <= bound["max_deg"] else "violated")
