"""The emulator's assumption table: readable in docs/, complete against the rig contract
(docs/rig.md §3), and the source of the engine's registry names and term library."""

from __future__ import annotations

import re

from conftest import REPO
from exobench.emulator.model import assumptions, effects, terms
from exobench.selection import assumptions as table
from exobench.selection.families import FAMILIES
from term_helpers import assert_docs_hold

# What docs/rig.md §3 states, by the name it uses, and the row that holds the assumption.
COLUMNS = {
    "time_s": "clocks", "brace_angle_deg": "encoder", "brace_torque_Nm": "torque_sensor",
    "desired_torque_Nm": "spring", "motor_angle_deg": "motor_encoder",
    "clutch_engaged": "clutch_release", "knee_flexion_deg": "mocap",
    "stiffness_Nm_per_rad": "spring", "emulator.controller.torque_filter_Hz": "torque_sensor",
    "emulator.sensors.load_cell_sd_Nm": "torque_linearity",
    "emulator.transmission": "cable_calibration",
    "emulator.transmission_calibrated": "cable_tension_between",
}  # fmt: skip
# Backticked names of §3 that state no assumption: files and formats, the manifest's labels,
# config keys (reading settings), outputs and the rules and tools that read or write them.
NOT_ASSUMED = {
    "manifest.csv", "trial", "file", "mocap_file", "speed_m_per_s", "side", "emulator",
    "emulator.protocol.duration_s", "emulator.columns", "<raw_dir>/emulator/", "null",
    ".mat", "[time; channels]", "-v7", "save", "scipy.io.loadmat", "emulator.mat_channels",
    "brace", "mocap", "emulator.analysis.max_gap_fraction", "emulator.analysis.brace_rate_range_Hz",
    "emulator.analysis.mocap_rate_range_Hz", "emulator_checks", "emulator_discrepancy",
    "excluded_steps", "qc/", "qc/<trial>.json", "steps/", "t_s", "scipy.signal.resample_poly",
    "session", "per_trial", "emulator.controller", "emulator.sensors",
}  # fmt: skip
# Values, laws and timing §3 states in words, and their rows.
STATED = {
    "κ = 0 to 3.5 N·m/rad": "spring",
    "τ = κ · max(0, θ_eq − θ), θ_eq = 40°": "spring",
    "positive in flexion": "spring",
    "engages at peak knee flexion once the knee has passed 40°": "clutch_engage",
    "releases at peak\nextension": "clutch_release",
    "a CSV at 1000 Hz": "loop",
    "on the same clock, a CSV at 100 Hz": "clocks",
    "(encoder)": "encoder",
    "(the controller's)": "spring",
    "(measured: the load cell": "torque_sensor",
}


def rig_section() -> str:
    """docs/rig.md §3, the emulator's contract."""
    text = (REPO / "docs" / "rig.md").read_text(encoding="utf-8")
    return text[text.index("## 3.") :]


def test_docs_hold_the_table_as_the_code_defines_it():
    assert_docs_hold("emulator_assumptions.md", assumptions.markdown(),
                     "exobench.emulator.model.assumptions")  # fmt: skip


def test_every_column_value_law_and_timing_of_rig_md_section_3_has_its_row():
    section = rig_section()
    named = {name.strip() for span in re.findall(r"`([^`]+)`", section)
             for name in span.split(",")}  # fmt: skip
    assert named - NOT_ASSUMED == set(COLUMNS), sorted(named - NOT_ASSUMED ^ set(COLUMNS))
    rows = {row.key for row in assumptions.TABLE}
    assert set(COLUMNS.values()) | set(STATED.values()) <= rows
    for words in STATED:
        assert words in section, words


def test_rows_are_well_formed_and_every_relaxation_is_a_registry_effect_or_a_term():
    keys = [row.key for row in assumptions.TABLE]
    assert len(keys) == len(set(keys))
    registry = set()
    for row in assumptions.TABLE:
        assert row.kind in table.KINDS and set(row.observables) <= set(assumptions.OBSERVABLES)
        assert row.relaxations or row.check, row.key
    for key, (row, r) in assumptions.relaxations().items():
        assert r.family in FAMILIES and 0 < r.visible[0] < r.visible[1], key
        assert all(q in assumptions.relaxations() for q in r.requires), key
        if r.registry:
            registry.add(r.registry)
            assert effects.REGISTRY[r.registry].description == row.description(r)
            assert effects.REGISTRY[r.registry].observables == row.observables
        elif r.checked:
            assert row.check, key  # a direct check sees it
        else:
            assert key in terms.LIBRARY, key
    assert registry == set(effects.REGISTRY)
    names = [row.name(r) for row, r in assumptions.relaxations().values()]
    assert len(names) == len(set(names))
