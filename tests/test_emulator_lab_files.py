"""What another lab's emulator files may hold (issue 54, item 5): MATLAB .mat recordings in
either layout, a v7.3 file refused, gaps in motion capture masked and gaps in the brace
excluding their steps. The recordings are written here from docs/rig.md §3 and the physics (a
knee cycle, an encoder of 5000 counts per turn, the spring law while the spring is active,
motion capture with its own zero, gain, clock and noise), not by the twin."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import scipy.io

from emulator_helpers import DEFAULT, analysis_settings, emulator_config, random_seed
from exobench.emulator.chain import analysis, energy
from exobench.emulator.model import discrepancy
from exobench.emulator.recordings import acquire
from exobench.errors import InputError
from test_emulator_heer_definitions import knee, mocap

DURATION_S = 15.0
KAPPA = 3.5
READING = DEFAULT["emulator"]["analysis"]  # gap fraction and rate ranges, as the rule reads
GAPS = READING["max_gap_fraction"]
BRACE_RATES = READING["brace_rate_range_Hz"]
MOCAP_RATES = READING["mocap_rate_range_Hz"]
BRACE_CHANNELS = ["brace_angle_deg", "brace_torque_Nm", "desired_torque_Nm", "motor_angle_deg"]
# the lab's own variable names for the named layout (mapped by emulator.columns)
LAB_NAMES = {"time_s": "Time", "brace_angle_deg": "KneeEncoder", "knee_flexion_deg": "KneeFlex"}


def brace_table(t, angle, phase) -> pd.DataFrame:
    """A brace recording of the knee angle: the spring κ·max(0, 40° − θ) active from late swing
    (75 % of the cycle) to the peak extension (97 %), recorded and desired alike, an encoder of
    5000 counts per turn and the motor angle through A = 0.92 and b(τ) ≈ C·τ."""
    active = (phase >= 0.75) & (phase < 0.97)
    torque = KAPPA * np.radians(np.clip(40.0 - angle, 0.0, None)) * active
    return pd.DataFrame(
        {
            "time_s": t,
            "brace_angle_deg": np.round(angle / 0.072) * 0.072,
            "brace_torque_Nm": torque,
            "desired_torque_Nm": torque,
            "motor_angle_deg": angle / 0.92 + 7.0 * torque,
        }
    )


def recording(seed_name: str, artefact_deg: float = 1.0):
    """Brace (:func:`brace_table`) and motion-capture tables of one trial; motion capture with a
    soft-tissue artefact of ``artefact_deg`` at the second harmonic."""
    rng = np.random.default_rng(random_seed(seed_name))
    t, angle, phase, _ = knee(DURATION_S, rng)
    stamps, knee_deg = mocap(t, angle, phase, rng, artefact_deg)
    return brace_table(t, angle, phase), pd.DataFrame(
        {"time_s": stamps, "knee_flexion_deg": knee_deg}
    )


def read_both(brace_path, mocap_path, names=None, channels=None):
    """The brace and motion-capture files read as the rule emulator_trial reads them."""
    return acquire.read_trial(brace_path, mocap_path, DURATION_S, READING, names, channels)


def test_a_mat_file_in_either_layout_reads_as_the_same_channels_in_csv(tmp_path):
    brace, knee_table = recording("mat layouts")
    brace.to_csv(tmp_path / "brace.csv", index=False)
    knee_table.to_csv(tmp_path / "mocap.csv", index=False)
    from_csv = read_both(tmp_path / "brace.csv", tmp_path / "mocap.csv")
    # named variables, column vectors, under the lab's names
    for table, name in ((brace, "brace_named.mat"), (knee_table, "mocap_named.mat")):
        scipy.io.savemat(
            tmp_path / name,
            {LAB_NAMES.get(c, c): table[c].to_numpy()[:, None] for c in table.columns},
        )
    named = read_both(tmp_path / "brace_named.mat", tmp_path / "mocap_named.mat", LAB_NAMES)
    # one array [time; channels]: the brace's as rows (channels × samples), motion capture's
    # transposed (samples × channels), channel order from the config, not the contract's
    order = {"brace": BRACE_CHANNELS[::-1], "mocap": ["knee_flexion_deg"]}
    scipy.io.savemat(
        tmp_path / "brace_array.mat",
        {"rec": brace[["time_s", *order["brace"]]].to_numpy().T, "note": "lab v5 export"},
    )
    scipy.io.savemat(tmp_path / "mocap_array.mat", {"data": knee_table.to_numpy()})
    arrays = read_both(tmp_path / "brace_array.mat", tmp_path / "mocap_array.mat", None, order)
    for read in (named, arrays):
        for got, want in zip(read, from_csv, strict=True):
            pd.testing.assert_frame_equal(got, want)
    # and so the same outputs: one analysis of the .mat trial against the CSV's
    settings = analysis_settings(emulator_config())
    _, steps_mat, qc_mat = analysis.analyse("t", *arrays, KAPPA, settings)
    _, steps_csv, qc_csv = analysis.analyse("t", *from_csv, KAPPA, settings)
    pd.testing.assert_frame_equal(steps_mat, steps_csv)
    assert qc_mat == qc_csv and len(steps_csv) >= 8


def test_a_mat_array_without_the_configured_shape_is_refused_naming_file_and_variables(tmp_path):
    brace, _ = recording("mat wrong shape")
    path = tmp_path / "brace.mat"
    # time and three channels: 4 columns, the config naming 3 channels (no motor angle) or 4
    scipy.io.savemat(path, {"rec": brace.iloc[:, :4].to_numpy()})
    with pytest.raises(InputError) as raised:
        acquire.read_brace(
            path,
            DURATION_S,
            max_gap_fraction=GAPS,
            rate_range_Hz=BRACE_RATES,
            channels=BRACE_CHANNELS[:3],
        )
    assert raised.value.file == str(path) and raised.value.field == "emulator.mat_channels"
    with pytest.raises(InputError) as raised:
        acquire.read_brace(
            path,
            DURATION_S,
            max_gap_fraction=GAPS,
            rate_range_Hz=BRACE_RATES,
            channels=BRACE_CHANNELS,
        )
    assert raised.value.field == "<variables>"  # none has 1 + 4 rows or columns
    assert "[time; channels] with 5 rows or columns" in str(raised.value)


@pytest.mark.parametrize("superblock", [True, False])
def test_a_v73_mat_file_is_refused_naming_the_file_and_how_to_save_it(superblock, tmp_path):
    # MATLAB's 128-byte text header (version 0x0200, 'IM'), then the HDF5 superblock at byte
    # 512; without the superblock scipy itself refuses the header
    header = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Sun Nov 29 2026 HDF5 schema"
    header = header.ljust(116, b" ") + bytes(8) + b"\x00\x02IM"
    tail = b"\x89HDF\r\n\x1a\n" + bytes(56) if superblock else b""
    path = tmp_path / "v12_k35_brace.mat"
    path.write_bytes(header.ljust(512, b"\x00") + tail)
    with pytest.raises(InputError) as raised:
        acquire.read_brace(path, DURATION_S, max_gap_fraction=GAPS, rate_range_Hz=BRACE_RATES)
    message = str(raised.value)
    assert "v12_k35_brace.mat" in message
    assert "save(..., '-v7')" in message and "v7.3" in message


def test_masked_motion_capture_gaps_keep_the_alignment_within_the_gap_free_intervals(tmp_path):
    # no soft-tissue artefact: zero and gain then rest on every frame and their intervals are
    # narrow (with one they rest on the steps' variation alone)
    brace, knee_table = recording("mocap gaps", artefact_deg=0.0)
    settings = analysis_settings(emulator_config())
    _, _, sound = analysis.analyse("t", brace, knee_table, KAPPA, settings)
    # three gaps of 50–200 ms written as empty cells, read back as NaN (masked, not refused)
    rng = np.random.default_rng(random_seed("mocap gap places"))
    gapped = knee_table.copy()
    starts = rng.choice(np.arange(100, len(gapped) - 100, 300), 3, replace=False)
    lengths = rng.integers(5, 21, 3)  # frames at 100 Hz: 50–200 ms
    for start, length in zip(starts, lengths, strict=True):
        gapped.loc[start : start + length - 1, "knee_flexion_deg"] = np.nan
    path = tmp_path / "mocap.csv"
    gapped.to_csv(path, index=False)
    read = acquire.read_mocap(path, DURATION_S, max_gap_fraction=GAPS, rate_range_Hz=MOCAP_RATES)
    assert read["knee_flexion_deg"].isna().sum() == lengths.sum()
    _, _, masked = analysis.analyse("t", brace, read, KAPPA, settings)
    found, interval = masked["alignment"], sound["alignment"]
    print("masked:", found["mocap_zero_deg"], found["mocap_gain"], "gap-free:",
          interval["mocap_zero_deg"], interval["mocap_gain"],
          interval["mocap_zero_ci95_deg"], interval["mocap_gain_ci95"])  # fmt: skip
    low, high = interval["mocap_zero_ci95_deg"]
    assert low <= found["mocap_zero_deg"] <= high
    low, high = interval["mocap_gain_ci95"]
    assert low <= found["mocap_gain"] <= high
    assert masked["count_drops"] == [] and not masked["encoder_fault"]
    # a mostly empty motion capture is refused, naming file and field
    gapped.loc[: int(0.5 * len(gapped)), "knee_flexion_deg"] = np.nan
    gapped.to_csv(path, index=False)
    with pytest.raises(InputError) as raised:
        acquire.read_mocap(path, DURATION_S, max_gap_fraction=GAPS, rate_range_Hz=MOCAP_RATES)
    assert raised.value.file == str(path) and raised.value.field == "knee_flexion_deg"


def test_a_brace_gap_excludes_its_step_with_the_reason_and_leaves_the_others_alone(tmp_path):
    brace, knee_table = recording("brace gap")
    settings = analysis_settings(emulator_config())
    _, sound, _ = analysis.analyse("t", brace, knee_table, KAPPA, settings)
    # the energy of each step from the physics: −∫τ dθ over the active samples
    t = brace["time_s"].to_numpy()
    hs = np.searchsorted(t, sound["heel_strike_s"].to_numpy())
    hs = np.append(hs, hs[-1] + round(1000 * sound["stride_time_s"].iloc[-1]))
    torque, angle = brace["brace_torque_Nm"].to_numpy(), brace["brace_angle_deg"].to_numpy()
    physics = energy.per_step(energy.interval_energy_J(torque, angle, torque != 0), hs)
    np.testing.assert_allclose(sound["energy_J"], physics, rtol=1e-9)
    # 120 ms of torque lost in the active part of step 3, 80 ms of encoder in step 6
    gapped = brace.copy()
    middle = int(np.flatnonzero(torque[hs[3] : hs[4]])[0]) + hs[3] + 40
    gapped.loc[middle : middle + 119, "brace_torque_Nm"] = np.nan
    gapped.loc[hs[6] + 300 : hs[6] + 379, "brace_angle_deg"] = np.nan
    path = tmp_path / "brace.csv"
    gapped.to_csv(path, index=False)
    read = acquire.read_brace(path, DURATION_S, max_gap_fraction=GAPS, rate_range_Hz=BRACE_RATES)
    samples, steps, qc = analysis.analyse("t", read, knee_table, KAPPA, settings)
    excluded = {e["step"]: e["reason"] for e in qc["excluded_steps"]}
    print(excluded)
    assert set(excluded) == {3, 6}
    assert "gap in brace_torque_Nm from" in excluded[3] and "(120 samples)" in excluded[3]
    assert "gap in brace_angle_deg from" in excluded[6] and "(80 samples)" in excluded[6]
    kept = sound[~sound["step"].isin([3, 6])].reset_index(drop=True)
    np.testing.assert_array_equal(steps["step"], kept["step"])
    np.testing.assert_allclose(steps["energy_J"], kept["energy_J"], rtol=1e-9)
    assert qc["n_steps"] == len(kept)
    assert qc["mean_energy_J"] == pytest.approx(kept["energy_J"].mean(), rel=1e-12)
    # the engine's windows keep clear of the bridged samples: none in steps 3 or 6, nor in the
    # steps before them (a window's rows run past its closing heel strike)
    cfg = emulator_config()
    data, _ = discrepancy.observations(
        [("t", KAPPA, samples, qc)], settings["equilibrium_deg"],
        settings["direction_blend_deg_per_s"], cfg["transmission"], 2,
        cfg["controller"]["torque_filter_Hz"],
    )  # fmt: skip
    assert data.units > 0 and not set(data.order.tolist()) & {2, 3, 5, 6}
    # a brace channel mostly empty is still refused, naming file and field
    gapped.loc[: int(0.4 * len(gapped)), "brace_torque_Nm"] = np.nan
    gapped.to_csv(path, index=False)
    with pytest.raises(InputError) as raised:
        acquire.read_brace(path, DURATION_S, max_gap_fraction=GAPS, rate_range_Hz=BRACE_RATES)
    assert raised.value.file == str(path) and raised.value.field == "brace_torque_Nm"
    assert "max_gap_fraction" in str(raised.value)


def test_text_and_infinities_in_a_brace_cell_are_refused_not_taken_for_gaps(tmp_path):
    brace, _ = recording("brace text")
    path = tmp_path / "brace.csv"
    for bad, field in (("1.2x", "brace_torque_Nm"), ("inf", "desired_torque_Nm")):
        written = brace.astype({field: object})
        written.loc[500, field] = bad
        written.to_csv(path, index=False)
        with pytest.raises(InputError) as raised:
            acquire.read_brace(path, DURATION_S, max_gap_fraction=GAPS, rate_range_Hz=BRACE_RATES)
        assert raised.value.field == field, bad
    # time may never have a gap
    written = brace.copy()
    written.loc[500, "time_s"] = np.nan
    written.to_csv(path, index=False)
    with pytest.raises(InputError, match="finite numbers in every row"):
        acquire.read_brace(path, DURATION_S, max_gap_fraction=GAPS, rate_range_Hz=BRACE_RATES)
