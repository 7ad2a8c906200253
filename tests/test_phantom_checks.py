"""Direct checks of the rig's assumptions on hand-made recordings whose violation the test sets:
each check names its own row and no other, and holds on a rig that keeps the contract."""

from __future__ import annotations

import os

import numpy as np
import pandas as pd
import pytest

from exobench.phantom.model import checks
from exobench.phantom.rig import Rig
from exobench.selection import checks as direct_checks

SEED = int(os.environ.get("EXOBENCH_CHECKS_SEED", "5"))
SETTINGS = {"length_tolerance_mm": 5.0, "knee_axis_tolerance_mm": 1.0,
            "ankle_offset_tolerance_mm": 5.0, "bar_angle_tolerance_deg": 1.0,
            "swing_moment_tolerance_Nm": 0.05, "crosstalk_tolerance": 0.01,
            "window_pct": [0.0, 22.5], "swing_pct": [55.0, 95.0]}  # fmt: skip
RATE = 1000


def trial(rng, spring: float, lengths=(0.299, 0.304), ankle_x=0.0, bar=0.0, knee_marker=0.0,
          crosstalk=0.0, stiffness: float | None = None, strides: int = 10) -> dict:  # fmt: skip
    """One trial's tables as the chain writes them: a knee flexing and extending each 2 s
    stride, the ankle on a vertical line ``ankle_x`` anterior of the hip, noise on every
    channel; the knee markers ``knee_marker`` m anterior of the joint on the thigh."""
    n = 2 * RATE
    phase = np.arange(n) / n
    theta = 0.3 + 0.5 * np.sin(2 * np.pi * phase) ** 2
    t = np.arange(strides * n) / RATE
    theta = np.tile(theta, strides)
    l1, l2 = lengths
    # the thigh's angle from the downward vertical with the ankle on x = ankle_x below the hip
    reach = np.sqrt(l1**2 + l2**2 + 2 * l1 * l2 * np.cos(theta))
    lean = np.arcsin(np.clip(ankle_x / reach, -1, 1))
    phi = np.arccos((l1**2 + reach**2 - l2**2) / (2 * l1 * reach)) + lean
    hip = np.array([0.0, 0.9])
    knee = hip + l1 * np.stack([np.sin(phi), -np.cos(phi)], axis=1)
    knee_seen = knee + knee_marker * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    ankle = np.stack([np.full_like(theta, ankle_x), 0.9 - reach * np.cos(lean)], axis=1)
    ankle += rng.normal(0, 2e-5, ankle.shape)
    angles = pd.DataFrame({"t_s": t, "phantom_knee_angle_rad": theta,
                           **{f"{j}_{a}_m": p[:, i] for j, p in
                              (("hip", np.tile(hip, (t.size, 1))), ("knee", knee_seen),
                               ("ankle", ankle)) for i, a in enumerate("xy")}})  # fmt: skip
    engaged = np.tile(phase < 0.35, strides)
    spring_force = np.where(engaged, 3 + 80 * np.tile(np.sin(np.pi * phase / 0.35), strides), 3.0)
    ankle_force = 40 + 30 * np.sin(2 * np.pi * t / 2.0) + rng.normal(0, 0.5, t.size)
    shares = np.array([0.30, 0.33, 0.37])
    cells = shares[:, None] * ankle_force + rng.normal(0, 0.3, (3, t.size))
    cells[0] += crosstalk * spring_force
    # only the columns the rule reads (a column the checks use and the list lacks fails here)
    kinetics = pd.DataFrame({
        "stride": np.repeat(np.arange(strides), n), "t_s": t,
        "gait_cycle_pct": np.tile(phase * 100, strides),
        "knee_moment_Nm": np.where(engaged, 10.0, 0.0) + rng.normal(0, 0.02, t.size),
        "phantom_knee_angle_rad": theta, "exo_knee_angle_rad": theta + bar,
        "spring_force_N": spring_force + rng.normal(0, 0.3, t.size),
        "ankle_force_y_N": cells.sum(axis=0),
        **{f"LC_ANKLE_{i}_N": cells[i - 1] for i in (1, 2, 3)},
    })[checks.KINETICS_COLUMNS]  # fmt: skip
    strides_table = pd.DataFrame({"stride": np.arange(strides), "included": True})
    metrics = pd.DataFrame(
        {
            "included": True,
            "exo_stiffness_Nm_per_rad": np.full(strides, stiffness if stiffness else spring / 100),
        }
    )
    return {"trial": f"k{spring:.0f}", "spring": spring, "kinetics": kinetics,
            "strides": strides_table, "angles": angles, "metrics": metrics}  # fmt: skip


VIOLATIONS = {
    "segment_lengths": {"lengths": (0.299 * 1.06, 0.304 * 1.06)},
    "ankle_path": {"ankle_x": 0.02},
    "bars": {"bar": np.deg2rad(3.0)},
    "knee_markers": {"knee_marker": 0.02},
    "channels_apart": {"crosstalk": 0.05},
    "spring": {},  # two trials' rates swapped in the manifest
}


def study(rng, **violation) -> list[dict]:
    springs = (3400.0, 9200.0, 21700.0)
    parts = [trial(rng, k, **violation) for k in springs]
    return parts


def test_a_rig_that_keeps_the_contract_passes_every_check():
    table = checks.checks(study(np.random.default_rng(SEED)), Rig(), SETTINGS)
    assert len(table) >= 12 and not (table["decision"] == "violated").any(), table
    assert direct_checks.warning(table) == []


def test_swapped_manifest_rates_lead_summary_md_with_a_warning_naming_the_trials():
    parts = study(np.random.default_rng(SEED))
    parts[0]["spring"], parts[2]["spring"] = parts[2]["spring"], parts[0]["spring"]
    (line, _) = direct_checks.warning(checks.checks(parts, Rig(), SETTINGS))
    assert line.startswith("**Warning:**") and "out of the manifest's order" in line
    assert f"{parts[0]['trial']} and {parts[2]['trial']}" in line


@pytest.mark.parametrize("count", [2, 3])
def test_the_spring_order_check_prints_the_value_it_decided_on(count):
    """Kendall's τ of the manifest's rates against the measured stiffness: 1 in order, −1 with
    two trials swapped (never a hard-coded 1 beside a violation)."""
    parts = study(np.random.default_rng(SEED))[:count]
    (held,) = checks.spring_order(parts)
    assert held["measured"] == 1.0 and held["decision"] == "holds"
    parts[0]["spring"], parts[-1]["spring"] = parts[-1]["spring"], parts[0]["spring"]
    (broken,) = checks.spring_order(parts)
    assert broken["decision"] == "violated" and broken["measured"] == -1.0


@pytest.mark.parametrize("row", sorted(VIOLATIONS))
def test_a_violated_assumption_is_found_by_its_own_check_and_no_other(row):
    rng = np.random.default_rng([SEED, len(row)])
    print(f"seed {SEED} (EXOBENCH_CHECKS_SEED), row {row}")
    parts = study(rng, **VIOLATIONS[row])
    if row == "spring":  # the manifest swaps the stiffest and the softest spring
        parts[0]["spring"], parts[2]["spring"] = parts[2]["spring"], parts[0]["spring"]
    table = checks.checks(parts, Rig(), SETTINGS)
    assert direct_checks.violated(table) == [row], table[["assumption", "quantity", "decision"]]
