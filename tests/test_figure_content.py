"""What figures say, on small made-up tables: the checklist refuses a figure with nothing to
show; the QC figure names channels as the lab does, orders trials by spring rate and keys only
the marks it draws; the energy and activity figures name a controller that departs from
Table 6.1."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from matplotlib import pyplot as plt

import figure_checklist as checklist
from conftest import REPO
from exobench import figures
from exobench.emulator.report import plots as emulator_plots
from exobench.phantom.report import plots as phantom_plots


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def test_the_checklist_fails_an_empty_or_constant_figure():
    text_only, axes = figures.new_figure()
    axes[0, 0].set_axis_off()
    axes[0, 0].text(0.5, 0.5, "no discovered term", transform=axes[0, 0].transAxes)
    assert checklist.empty_or_constant(text_only) == ["empty figure: no data drawn"]
    zeros, axes = figures.new_figure()
    axes[0, 0].imshow(np.zeros((12, 10)), aspect="auto")
    assert checklist.empty_or_constant(zeros) == ["constant figure: every drawn value is 0"]
    flat, axes = figures.new_figure(2, 1)
    axes[0, 0].plot([0.0, 1.0, 2.0], [3.0, 3.0, 3.0])
    axes[0, 1].bar([0, 1], [3.0, 3.0], width=3.0)
    assert checklist.empty_or_constant(flat)[0].startswith("constant figure")
    drawn, axes = figures.new_figure()
    axes[0, 0].plot([0.0, 1.0], [3.0, 4.0])
    assert checklist.empty_or_constant(drawn) == []
    assert "empty figure: no data drawn" in checklist.check(text_only, "A caption.\n")


def _events(trial: str, rows) -> pd.DataFrame:
    """A QC table (qc/<trial>.parquet) of (channel, kind, repair) events."""
    return pd.DataFrame(rows, columns=["channel", "kind", "repair"]).assign(trial=trial)


def _strides(reasons) -> pd.DataFrame:
    reasons = pd.Series(reasons, dtype=str)
    return pd.DataFrame({"exclusion_reason": reasons, "included": reasons == ""})


def test_the_qc_figure_speaks_the_labs_labels_by_spring_rate_with_a_key_for_what_it_draws():
    springs = {"first": 21700.0, "second": 3400.0, "third": 9200.0}  # test order: stiff first
    checks = {
        "first": _events("first", [("PH_HIP_MED", "dropout", "filled")]),
        "second": _events("second", [("PH_HIP_MED", "dropout", "filled")]),
        "third": _events("third", [("LC_SPRING", "dropout", "filled")]),
    }
    strides = {t: _strides(["", "", "hexapod ramp stride"]) for t in springs}
    labels = {"PH_HIP_MED": "RHipMed", "LC_SPRING": "SpringForce"}
    fig = phantom_plots.quality_control(checks, strides, springs, labels)
    events, bars = figures.panels(fig)
    rows = [t.get_text() for t in events.get_yticklabels()]
    assert rows == ["3.4 kN/m (second)", "9.2 kN/m (third)", "21.7 kN/m (first)"]
    assert [t.get_text() for t in bars.get_yticklabels()] == rows
    columns = [t.get_text() for t in events.get_xticklabels()]
    assert "RHipMed" in columns and "SpringForce" in columns and "PH_HIP_MED" not in columns
    key = [t.get_text() for t in fig.legends[0].get_texts()]
    assert key == ["events filled by the gap fill"]  # nothing left as a gap, no glitch
    caption = " ".join(phantom_plots.quality_control_caption(checks, strides, 10, springs, labels))
    assert "RHipMed for PH_HIP_MED" in caption and "ordered by spring rate" in caption
    assert "after a slash" not in caption
    # a gap left and a glitch: both keyed, and said
    checks["third"] = _events(
        "third", [("LC_SPRING", "saturated", "left as gap"), ("PH_KNEE_MED", "spike", "filled")]
    )
    fig = phantom_plots.quality_control(checks, strides, springs, labels)
    key = [t.get_text() for t in fig.legends[0].get_texts()]
    assert len(key) == 3 and any("slash" in k for k in key) and any("shade" in k for k in key)
    caption = " ".join(phantom_plots.quality_control_caption(checks, strides, 10, springs, labels))
    assert "after a slash (red)" in caption and "The shade counts" in caption


def test_the_energy_figure_names_a_controller_departing_from_table_6_1():
    conditions = pd.DataFrame({"trial": ["slow", "fast"], "speed_m_per_s": [0.8, 1.2],
                               "stiffness_Nm_per_rad": [2.0, 2.0]})  # fmt: skip
    summary = conditions.assign(
        n_steps=[20, 24],
        mean_energy_J=[0.3, 0.4],
        sd_energy_J=0.01,
        mean_energy_active_J=[0.3, 0.4],
        sd_energy_active_J=0.01,
    )
    energies = np.r_[np.full(20, 0.3), np.full(24, 0.4)]
    steps = pd.DataFrame({"trial": ["slow"] * 20 + ["fast"] * 24, "energy_active_J": energies})
    reported = pd.read_csv(REPO / "raw" / "reference" / "seed002_reported.csv")
    agreeing = {"share_of_steps_disagreeing": 0.0, "phases_disagreeing_pct": []}
    departing = {"share_of_steps_disagreeing": 0.5, "phases_disagreeing_pct": [[60.0, 70.0]]}
    qc = {
        trial: {"encoder_fault": False, "fault_kinds": [], "encoder_offset_deg": None,
                "table61_crosscheck": check}
        for trial, check in (("slow", agreeing), ("fast", departing))
    }  # fmt: skip
    fig, caption = emulator_plots.energy_per_step(summary, steps, conditions, qc, reported)
    legend = figures.panels(fig)[0].get_legend().texts
    notes = " ".join(t.get_text().replace("\n", " ") for t in legend)
    assert "condition 2" in notes and "Table 6.1 in 50 % of steps" in notes
    assert "circled: condition 1" not in notes
    assert "condition 2 (1.2 m/s, κ 2)" in caption[-1] and "60–70 %" in caption[-1]
    qc["fast"]["table61_crosscheck"] = agreeing
    _, caption = emulator_plots.energy_per_step(summary, steps, conditions, qc, reported)
    assert caption[-1].endswith("every step of every condition agrees with it.")
    # the activity figure shades the phases where the recording departs, and names them
    qc["fast"]["table61_crosscheck"] = departing
    cycle = np.arange(1000)
    active = (cycle >= 800) & (cycle < 990)
    samples = {
        trial: pd.DataFrame({"active": np.tile(active, 3), "table61_active": np.tile(active, 3),
                             "clutch_window": np.tile(cycle >= 750, 3),
                             "heel_strike": np.tile(cycle == 0, 3)})
        for trial in conditions["trial"]
    }  # fmt: skip
    fig, caption = emulator_plots.activity_vs_table61(samples, conditions, qc)
    slow, fast = figures.panels(fig)
    assert not slow.patches and len(fast.patches) == 1
    assert fast.patches[0].get_x() == 60.0 and fast.patches[0].get_width() == 10.0
    assert "condition 2 (1.2 m/s, κ 2): activity departs from Table 6.1 in 50 %" in caption[-1]
