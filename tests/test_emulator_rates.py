"""Emulator files at a rate other than Heer's (issue 54): a lab's brace and motion capture are
analysed at their own rates inside emulator.analysis.brace_rate_range_Hz and
mocap_rate_range_Hz, a rate outside is refused naming file and field, and the discrepancy
engine, which counts 1 kHz brace samples, refuses a trial at another rate. The recordings are
written here from docs/rig.md §3 and the physics (the knee cycle, encoder, spring and motion
capture of :mod:`test_emulator_heer_definitions`), not by the twin: one trial sampled at 1 kHz
and the same motion sampled at 500 Hz, its motion capture at 200 Hz holding the 100 Hz frames."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy.stats import t as student

from emulator_helpers import DEFAULT, analysis_settings, emulator_config, random_seed
from exobench.emulator.chain import analysis
from exobench.emulator.model import discrepancy
from exobench.emulator.recordings import acquire
from exobench.errors import InputError
from test_emulator_heer_definitions import CLOCK_S, GAIN, ZERO_DEG, knee
from test_emulator_lab_files import brace_table

DURATION_S = 15.0
KAPPA = 3.5
GAPS = DEFAULT["emulator"]["analysis"]["max_gap_fraction"]
BRACE_RATES = DEFAULT["emulator"]["analysis"]["brace_rate_range_Hz"]
MOCAP_RATES = DEFAULT["emulator"]["analysis"]["mocap_rate_range_Hz"]


def trial(seed_name: str, artefact_deg: float = 1.0, sd_deg: float = 0.8):
    """One trial's brace at 1 kHz (:func:`brace_table`) and its motion capture at 200 Hz (stamps
    every 5 ms): zero + gain·(θ + artefact at harmonic 2)(s − clock) + noise."""
    rng = np.random.default_rng(random_seed(seed_name))
    t, angle, phase, _ = knee(DURATION_S, rng)
    brace = brace_table(t, angle, phase)
    seen = angle + artefact_deg * np.sin(4 * np.pi * phase)
    stamps = t[::5]
    knee_deg = ZERO_DEG + GAIN * np.interp(stamps - CLOCK_S, t, seen)
    knee_deg = knee_deg + sd_deg * rng.standard_normal(len(stamps))
    return brace, pd.DataFrame({"time_s": stamps, "knee_flexion_deg": knee_deg})


def written(tmp_path, name: str, table: pd.DataFrame, every: int):
    """The table with every ``every``-th row, written as a lab's CSV; its path."""
    path = tmp_path / f"{name}.csv"
    table.iloc[::every].to_csv(path, index=False)
    return path


def read(brace_path, mocap_path):
    """The two files read as the rule emulator_trial reads them."""
    return acquire.read_trial(brace_path, mocap_path, DURATION_S, DEFAULT["emulator"]["analysis"])


def ci95(values: np.ndarray) -> tuple[float, float]:
    """mean ± t₀.₉₇₅,ₙ₋₁·sd/√n of the values."""
    half = student.ppf(0.975, len(values) - 1) * np.std(values, ddof=1) / np.sqrt(len(values))
    return float(values.mean() - half), float(values.mean() + half)


@pytest.fixture(scope="module")
def analysed(tmp_path_factory):
    """The trial at 1000 Hz / 100 Hz, 500 Hz / 200 Hz and 500 Hz / 50 Hz, read from CSV and
    analysed."""
    folder = tmp_path_factory.mktemp("rates")
    brace, knee_table = trial("rates trial")
    settings = analysis_settings(emulator_config())
    out = {}
    for label, brace_every, mocap_every in (("nominal", 1, 2), ("own", 2, 1), ("coarse", 2, 4)):
        files = (
            written(folder, f"{label}_brace", brace, brace_every),
            written(folder, f"{label}_mocap", knee_table, mocap_every),
        )
        out[label] = (files, *analysis.analyse(label, *read(*files), KAPPA, settings))
    return out


@pytest.mark.parametrize("label", ["own", "coarse"])
def test_a_trial_at_500_hz_keeps_energy_and_alignment_within_the_1khz_intervals(analysed, label):
    _, samples, steps, qc = analysed[label]
    _, _, nominal_steps, nominal_qc = analysed["nominal"]
    assert np.allclose(np.diff(samples["t_s"]), 0.002)  # analysed at the file's 500 Hz
    assert len(steps) == len(nominal_steps) >= 10
    low, high = ci95(nominal_steps["energy_J"].to_numpy())
    print(
        f"energy per step: 500 Hz {qc['mean_energy_J']:.5f} J, 1 kHz 95 % [{low:.5f}, {high:.5f}]"
    )
    assert low <= qc["mean_energy_J"] <= high
    for key in ("mocap_zero", "mocap_gain"):
        unit = "_deg" if key == "mocap_zero" else ""
        value = qc["alignment"][f"{key}{unit}"]
        low, high = nominal_qc["alignment"][f"{key}_ci95{unit}"]
        print(f"{key} ({label}): {value:.4f}, 1 kHz/100 Hz 95 % [{low:.4f}, {high:.4f}]")
        assert low <= value <= high
    # heel strikes within two samples of the 500 Hz file of the 1 kHz file's: the rule fires
    # at the first sample past the turn, and the backward difference lags half a sample
    late = steps["heel_strike_s"] - nominal_steps["heel_strike_s"]
    print(f"heel strikes at 500 Hz later by {late.min() * 1e3:.1f} to {late.max() * 1e3:.1f} ms")
    assert late.between(0.0, 2 / 500).all()


@pytest.mark.parametrize(
    ("kind", "every", "key"),
    [("brace", 10, "brace_rate_range_Hz"), ("mocap", 40, "mocap_rate_range_Hz")],
)
def test_a_file_outside_the_configured_rates_is_refused_naming_file_and_field(
    kind, every, key, tmp_path
):
    brace, knee_table = trial("rates refused")
    table = brace if kind == "brace" else knee_table
    path = written(tmp_path, kind, table, every)  # brace at 100 Hz, motion capture at 5 Hz
    reader = acquire.read_brace if kind == "brace" else acquire.read_mocap
    rates = BRACE_RATES if kind == "brace" else MOCAP_RATES
    with pytest.raises(InputError) as raised:
        reader(path, DURATION_S, max_gap_fraction=GAPS, rate_range_Hz=rates)
    print(raised.value)
    assert raised.value.file == str(path) and raised.value.field == "time_s"
    assert key in str(raised.value)


def test_an_unevenly_sampled_file_is_refused_at_any_rate(tmp_path):
    brace, _ = trial("rates uneven")
    uneven = brace.drop(index=brace.index[3000:3600])  # 0.6 s missing: 4 % of the rows
    path = tmp_path / "brace.csv"
    uneven.to_csv(path, index=False)
    with pytest.raises(InputError) as raised:
        acquire.read_brace(path, DURATION_S, max_gap_fraction=GAPS, rate_range_Hz=BRACE_RATES)
    assert raised.value.field == "time_s" and "evenly spaced" in str(raised.value)


def test_the_engine_refuses_a_trial_whose_brace_is_not_at_1khz(analysed):
    cfg = emulator_config()
    settings = analysis_settings(cfg)
    arguments = (
        settings["equilibrium_deg"],
        settings["direction_blend_deg_per_s"],
        cfg["transmission"],
        2,
        cfg["controller"]["torque_filter_Hz"],
    )
    _, samples, _, qc = analysed["own"]
    with pytest.raises(InputError) as raised:
        discrepancy.observations([("own", KAPPA, samples, qc)], *arguments)
    message = str(raised.value)
    print(message)
    assert raised.value.field == "t_s" and "trial 'own'" in raised.value.file
    assert "1000 Hz" in message and "resample" in message and "500 Hz" in message
    # the 1 kHz trial passes the rate and goes on to its windows
    _, samples, _, qc = analysed["nominal"]
    discrepancy.require_1kHz("nominal", samples)
