"""Real lab recordings: glitches repaired or their strides excluded, never the whole study; a
lab's own labels, rates and units read as the contract's.

The glitch test draws glitch type, channel, position and size at random (seed printed; rerun
others with ``EXOBENCH_GLITCH_SEEDS=3,4``) into the twin's recordings and reads the truth only
in the final assertions.
"""

from __future__ import annotations

import os

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from exobench.phantom.chain import filtering
from exobench.phantom.chain.metrics import METRIC_COLUMNS
from exobench.phantom.rig import LOAD_CELLS, MARKERS, Rig
from exobench.phantom.twin import twin
from lab_helpers import CALIBRATED, LAB_LABELS, lab_trial, write_lab_c3d, write_manifest
from phantom_helpers import analyse_recordings, mean_cycle, settings, workflow_config

pytestmark = pytest.mark.slow

SEEDS = [int(s) for s in os.environ.get("EXOBENCH_GLITCH_SEEDS", "0,1").split(",")]
# label swaps happen between markers that come close to each other
NEIGHBOURS = [("PH_HIP_MED", "PH_HIP_LAT"), ("PH_KNEE_MED", "PH_KNEE_LAT"),
              ("PH_ANK_MED", "PH_ANK_LAT"), ("EX_SPRING_A", "EX_SPRING_B"),
              ("EX_THIGH_DIST", "EX_SHANK_PROX"), ("PH_KNEE_LAT", "EX_THIGH_DIST")]  # fmt: skip
KINDS = ("spike", "ghost", "short dropout", "long dropout", "swap")


def study_config(springs, strides: int, noise: bool = True) -> dict:
    config = workflow_config()
    config["phantom"]["protocol"].update(
        strides=strides, ramp_strides=1, springs_N_per_m=springs, test_order_N_per_m=springs
    )
    for effect in ("marker_noise", "load_cell_noise", "occlusion"):
        config["phantom"]["twin"]["effects"][effect]["enabled"] = noise
    return config


def simulate(config) -> list:
    return list(twin.simulate_trials(mean_cycle(), Rig(), settings(config), CALIBRATED))


def inject(trial, rng, count: int, max_gap: int) -> list[dict]:
    """``count`` glitches at random in one trial's recordings (in place), one per second-long
    slot so that each is told apart: what, where and how large."""
    frames = trial.markers_mm["PH_HIP_MED"].shape[0]
    slots = rng.permutation(np.arange(1, frames // 100 - 1))[:count]
    out = []
    for slot in slots:
        kind, frame = str(rng.choice(KINDS)), int(slot * 100 + rng.integers(0, 50))
        if kind == "spike":  # 1–3 samples, 100–3000 N of either sign, on one load cell
            channel = str(rng.choice([*LOAD_CELLS, "LC_SPRING"]))
            start, width = frame * 10 + int(rng.integers(0, 10)), int(rng.integers(1, 4))
            size = rng.choice([-1.0, 1.0]) * np.exp(rng.uniform(np.log(100), np.log(3000)))
            trial.analogs[channel][start : start + width] += size
            out.append({"kind": kind, "channels": [channel], "start_s": start / 1000,
                        "end_s": (start + width) / 1000, "size": size})  # fmt: skip
            continue
        label = str(rng.choice(MARKERS))
        if kind == "ghost":  # 1–5 frames, 20–200 mm off in a random direction
            length = int(rng.integers(1, 6))
            offset = rng.normal(size=3)
            offset *= np.exp(rng.uniform(np.log(20), np.log(200))) / np.linalg.norm(offset)
            trial.markers_mm[label][frame : frame + length] += offset
            size, channels = float(np.linalg.norm(offset)), [label]
        elif kind == "swap":  # two neighbouring markers' labels exchanged for 1–30 frames
            channels = list(NEIGHBOURS[rng.integers(len(NEIGHBOURS))])
            length = int(rng.integers(1, 31))
            first, second = (trial.markers_mm[c] for c in channels)
            held = first[frame : frame + length].copy()
            first[frame : frame + length] = second[frame : frame + length]
            second[frame : frame + length] = held
            size = length
        else:  # occlusion shorter or longer than the fill limit
            length = int(rng.integers(1, max_gap + 1) if kind == "short dropout"
                         else rng.integers(max_gap + 1, 4 * max_gap))  # fmt: skip
            trial.markers_mm[label][frame : frame + length] = np.nan
            size, channels = length, [label]
        out.append({"kind": kind, "channels": channels, "start_s": frame / 100,
                    "end_s": (frame + length) / 100, "size": size})  # fmt: skip
    return out


def filter_reach_s(chain: dict) -> float:
    """How far the 6 Hz zero-phase filter carries a change: the time after which its impulse
    response stays below 1e-6 of its peak."""
    impulse = np.zeros((401, 1))
    impulse[200] = 1.0
    cutoff, order = chain["filter_cutoff_Hz"], chain["filter_order"]
    response = np.abs(filtering.butterworth_zero_phase(impulse, 100.0, cutoff, order)[:, 0])
    return float(np.abs(np.flatnonzero(response > 1e-6 * response.max()) - 200).max() / 100)


@pytest.mark.parametrize("seed", SEEDS)
def test_glitches_are_repaired_or_their_strides_excluded(tmp_path, seed):
    print(f"EXOBENCH_GLITCH_SEEDS={seed}")
    rng = np.random.default_rng([seed, 28])
    config = study_config([6100, 21700], strides=24)
    chain = config["phantom"]["chain"]
    trials = simulate(config)
    twin.write_recordings(trials, tmp_path / "clean", {"rule": "test"}, ramp_strides=1)
    injected = {t.name: inject(t, rng, 8, chain["max_gap_frames"]) for t in trials}
    twin.write_recordings(trials, tmp_path / "glitched", {"rule": "test"}, ramp_strides=1)
    clean = analyse_recordings(tmp_path / "clean", config)  # the run completes, no InputError
    glitched = analyse_recordings(tmp_path / "glitched", config)

    reach = filter_reach_s(chain)
    for trial, glitches in injected.items():
        assert clean[trial]["qc"]["kind"].eq("dropout").all()  # clean: nothing else flagged
        qc = glitched[trial]["qc"]
        for glitch in glitches:
            for channel in glitch["channels"]:
                overlaps = (qc["start_s"] < glitch["end_s"] + 1e-9) & (
                    qc["end_s"] > glitch["start_s"] - 1e-9
                )
                rows = qc[(qc["channel"] == channel) & overlaps]
                excluded = rows["stride_excluded"] & rows["exclusion_reason"].ne("")
                dealt = rows["repair"].eq("filled") | excluded
                assert dealt.any(), (seed, trial, glitch, rows.to_dict("records"))
        strides = clean[trial]["strides"]
        touched = np.zeros(len(strides), bool)
        for glitch in glitches:
            touched |= (strides["start_s"] - reach < glitch["end_s"]).to_numpy() & (
                glitch["start_s"] < strides["end_s"] + reach
            ).to_numpy()
        before = clean[trial]["metrics"][~touched]
        after = glitched[trial]["metrics"][~touched]
        assert after["included"].tolist() == before["included"].tolist()
        kept = before["included"].to_numpy()
        assert kept.sum() >= 3, (seed, trial, "too few untouched strides to compare")
        columns = list(METRIC_COLUMNS)
        # to a millionth of each metric's size (a net work can be near zero), as the filter's
        # reach is where its response has fallen to a millionth
        scale = before.loc[kept, columns].abs().max()
        change = (after.loc[kept, columns] - before.loc[kept, columns]).abs()
        # a slope the validity rule refused (NaN) must be refused in both
        both_refused = before.loc[kept, columns].isna() & after.loc[kept, columns].isna()
        held = (change <= 1e-6 * scale) | both_refused
        assert held.all().all(), (seed, trial, (change / scale).max())


@pytest.fixture(scope="module")
def motion():
    """The twin's noise-free recordings of two springs (22 strides), as the lab and the canonical
    recorders both take them."""
    config = study_config([6100, 18000], strides=22, noise=False)
    return config, simulate(config)


def record(folder, trials, rates, labels, units, seed):
    rng = np.random.default_rng(seed)
    rows = []
    for order, trial in enumerate(trials, start=1):
        markers, analogs = lab_trial(trial.markers_mm, trial.analogs, *rates, 2.0, rng, (0.15, 0.5))
        write_lab_c3d(folder / f"{trial.name}.c3d", markers, analogs, *rates, labels, units)
        rows.append((trial.name, f"{trial.name}.c3d", trial.spring_stiffness_N_per_m, order, 1))
    write_manifest(folder, rows)
    return folder


def metrics_of(results) -> pd.DataFrame:
    return pd.concat([r["metrics"] for r in results.values()]).set_index(["trial", "stride"])


@pytest.mark.parametrize("rates", [(120.0, 1200.0), (200.0, 2000.0)])
def test_a_lab_style_recording_matches_the_canonical_one_within_noise(tmp_path, motion, rates):
    config, trials = motion
    canonical = [record(tmp_path / name, trials, (100.0, 1000.0), {}, "mm", seed)
                 for name, seed in (("a", 1), ("b", 2))]  # fmt: skip
    lab = record(tmp_path / "lab", trials, rates, LAB_LABELS, "m", 3)
    first, second = (metrics_of(analyse_recordings(folder, config)) for folder in canonical)
    results = analyse_recordings(lab, config, LAB_LABELS)
    theirs = metrics_of(results)
    assert all(r["qc"].empty for r in results.values())  # nothing to repair
    assert theirs["included"].equals(first["included"])
    both = first["included"] & second["included"]
    columns = list(METRIC_COLUMNS)
    noise = ((second.loc[both, columns] - first.loc[both, columns]) ** 2).mean()
    departure = ((theirs.loc[both, columns] - first.loc[both, columns]) ** 2).mean()
    # within noise: the lab's differences from the canonical recording are no larger than two
    # canonical recordings' (F test on the mean squares, 0.1 % false alarm over all metrics)
    limit = stats.f.ppf(1 - 0.001 / len(columns), both.sum(), both.sum())
    ratio = departure / noise
    print(ratio.round(2).to_dict())
    assert (ratio < limit).all(), ratio[ratio >= limit]
