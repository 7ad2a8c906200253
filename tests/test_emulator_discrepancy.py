"""Hidden-effect tests of the emulator's discrepancy engine, run through Snakemake as a user would.

Each case writes twin recordings (docs/rig.md §3 files only, no truth, no stamp) with one effect of
the registry at a random magnitude within its documented detectable range (or none, or a torque
disturbance that no registry entry describes), runs the emulator rules with
``acquisition=files`` and compares the engine's findings with the hidden truth only in the final
assertions. The default suite's seed is fixed and printed; ``pytest --explore`` adds a fresh one;
``EXOBENCH_EMULATOR_DISCREPANCY_SEEDS=7,8`` reruns given seeds.
"""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
import yaml

import seeds
from conftest import copy_workflow, snakemake
from emulator_helpers import emulator_config
from exobench.emulator.model import effects
from exobench.emulator.twin import twin
from exobench.plumbing import stamp

pytestmark = pytest.mark.slow

SWITCHES = ("cuff_compliance", "transmission_friction", "encoder_count_drop", "mocap_alignment",
            "soft_tissue_artefact", "clutch_departure")  # fmt: skip
PROTOCOL = {"speeds_m_per_s": [0.8, 1.2], "stiffnesses_Nm_per_rad": [2.0, 3.5], "duration_s": 15.0}
# intervals by the engine's block bootstrap (its Wald fallback is for too few steps to resample)
FAST_ENGINE = {"discrepancy": {"folds": 3, "bootstrap": 100, "null_draws": 100, "max_effects": 3}}


# The default suite's case (its seed fixed by name) and, under --explore, a fresh one.
SEEDS = [
    *(int(s) for s in os.environ.get("EXOBENCH_EMULATOR_DISCREPANCY_SEEDS", "").split(",") if s),
] or [seeds.fixed("emulator discrepancy")]
CASE_SEEDS = [*SEEDS, pytest.param(None, id="fresh", marks=pytest.mark.explore)]
OUTSIDE = "phase_disturbance"  # made by the test: no registry entry describes it


def detectable(effect: str, parameter: str) -> tuple[float, float]:
    """The documented detectable range of a registry parameter."""
    entry = effects.REGISTRY[effect]
    return next(p.detectable for p in entry.parameters if p.name == parameter)


def hidden_effect(case: str, rng: np.random.Generator) -> tuple[dict, dict, dict]:
    """Twin switches, the truth (effect → parameter → value) and CSV edits of one case."""
    sign = rng.choice([-1.0, 1.0])
    draw = {name: rng.uniform(*detectable(case, name)) for name in _names(case)}
    if case == "cuff_compliance":
        twin_cfg = {case: {"enabled": True, "compliance_deg_per_Nm": draw["compliance_deg_per_Nm"],
                           "time_constant_s": draw["time_constant_s"]}}  # fmt: skip
        return twin_cfg, {case: draw}, {}
    if case == "transmission_friction":
        twin_cfg = {case: {"enabled": True, "friction_fraction": draw["friction_fraction"]}}
        return twin_cfg, {case: draw}, {}
    if case == "encoder_count_drop":
        trial = twin.trial_name(rng.choice(PROTOCOL["speeds_m_per_s"]), 3.5)
        # two complete steps on either side (a step ends at a heel strike after the trial's
        # first: up to three 1.25 s strides from the start): with one, the fold holding it has
        # no step to fit the drop on and the engine says the residual is unexplained
        # (docs/emulator.md)
        time_s = rng.uniform(4.0, PROTOCOL["duration_s"] - 4.0)
        twin_cfg = {case: {"enabled": True, "trials": [trial], "size_deg": draw["drop_deg"],
                           "time_s": time_s}}  # fmt: skip
        return twin_cfg, {case: draw}, {}
    if case in ("mocap_zero", "mocap_gain", "mocap_clock"):
        key = {"mocap_zero": "zero_deg", "mocap_gain": "gain", "mocap_clock": "clock_offset_s"}
        parameter = _names(case)[0]
        value = effects.REGISTRY[case].parameters[0].value_at(draw[parameter], sign)
        alignment = {"enabled": True, "zero_deg": 0.0, "gain": 1.0, "clock_offset_s": 0.0}
        alignment[key[case]] = value
        return {"mocap_alignment": alignment}, {case: {parameter: value}}, {}
    if case == "clutch_late_release":  # the controller holds its clutch whole samples longer
        delay = round(draw["release_delay_s"] * 1000.0) / 1000.0
        twin_cfg = {"clutch_departure": {"enabled": True, "release_delay_s": delay}}
        return twin_cfg, {case: {"release_delay_s": delay}}, {}
    if case == "torque_offset":
        value = sign * draw["torque_offset_Nm"]
        return {}, {case: {"torque_offset_Nm": value}}, {"offset": value}
    if case == OUTSIDE:
        return {}, {}, {"disturbance": rng.uniform(0.15, 0.3)}
    return {}, {}, {}


def _names(case: str) -> list[str]:
    entry = effects.REGISTRY.get(case)
    return [p.name for p in entry.parameters] if entry else []


def write_lab_recordings(folder, case: str, seed: int) -> dict:
    """Twin recordings with the case's hidden effect as lab files; returns the truth."""
    rng = np.random.default_rng([seed, 1 + sorted(CASES).index(case)])
    switches, truth, edits = hidden_effect(case, rng)
    cfg = emulator_config(**dict.fromkeys(SWITCHES, False))
    cfg["protocol"] = dict(PROTOCOL)
    for name, block in switches.items():
        cfg["effects"][name].update(block)
    recordings = twin.run(cfg, seed)
    for rec in recordings:
        torque = rec.brace["brace_torque_Nm"].to_numpy()
        if "offset" in edits:
            torque = torque + edits["offset"]
        if "disturbance" in edits:  # a smooth torque that follows the gait phase
            t, hs = rec.brace["time_s"].to_numpy(), np.asarray(rec.truth["heel_strikes_s"])
            k = np.clip(np.searchsorted(hs, t, side="right") - 1, 0, hs.size - 2)
            phase = np.clip((t - hs[k]) / (hs[k + 1] - hs[k]), 0.0, 1.0)
            torque = torque + edits["disturbance"] * np.sin(2.0 * np.pi * phase) ** 2
        rec.brace["brace_torque_Nm"] = torque
    twin.write_recordings(recordings, folder / "emulator")
    for path in (folder / "emulator").glob("truth/*"):
        path.unlink()
    (folder / "emulator" / stamp.STAMP).unlink()
    return truth


CASES = ("none", *effects.REGISTRY, OUTSIDE)


# the cuff's settling time on this short protocol (4 trials of 15 s) is unbiased, but its 95 %
# interval spans about ±50 % (emulator validation), wider for the shortest time constants: it
# is held to twice its own interval, which must lie inside the fit bounds (an informative
# interval, not the whole range); the rest to 25 %
WIDE = {("cuff_compliance", "time_constant_s")}


@pytest.mark.parametrize("seed", CASE_SEEDS)
def test_engine_selects_and_sizes_a_hidden_effect_drawn_from_the_registry(tmp_path, seed):
    seed = seeds.drawn("emulator discrepancy, a registry effect") if seed is None else seed
    case = list(effects.REGISTRY)[np.random.default_rng(seed).integers(len(effects.REGISTRY))]
    print(f"seed {seed}: hidden {case} (rerun with EXOBENCH_EMULATOR_DISCREPANCY_SEEDS={seed})")
    report, truth = _run(tmp_path, case, seed)
    chosen = {e["effect"]: e for e in report["effects_found"] + report["tentative"]}
    assert case in chosen, (report["selected"], report["cause"], truth)
    for name, value in truth[case].items():
        if (case, name) in WIDE:
            low, high = chosen[case]["ci95"][name]
            bounds = next(p for p in effects.REGISTRY[case].parameters if p.name == name)
            assert bounds.low < low and high < bounds.high, (name, chosen[case])
            assert within_twice_the_interval(chosen[case], name, value), (name, truth)
        else:
            assert chosen[case]["parameters"][name] == pytest.approx(value, rel=0.25), (name, truth)


@pytest.mark.parametrize("seed", CASE_SEEDS)
def test_engine_claims_exactly_the_hidden_effect_within_twice_its_interval(tmp_path, seed):
    seed = seeds.drawn("emulator discrepancy, one case") if seed is None else seed
    case = CASES[np.random.default_rng(seed).integers(len(CASES) - 1)]  # not the outside one
    print(f"seed {seed}: hidden {case} (rerun with EXOBENCH_EMULATOR_DISCREPANCY_SEEDS={seed})")
    _check(*_run(tmp_path, case, seed), case)


def test_an_effect_outside_the_registry_is_flagged_and_nothing_claimed(tmp_path):
    seed = SEEDS[0]
    print(f"seed {seed}: hidden {OUTSIDE} (rerun with EXOBENCH_EMULATOR_DISCREPANCY_SEEDS={seed})")
    # the term search kept small: what it finds is the open-world arm's and tests/test_selection's
    _check(*_run(tmp_path, OUTSIDE, seed, {"screen_terms": 3, "max_terms": 1}), OUTSIDE)


def _run(tmp_path, case: str, seed: int, engine=None) -> tuple[dict, dict]:
    """The engine's report on recordings with the case's hidden effect, and the truth
    (``engine``: settings changed from :data:`FAST_ENGINE`'s)."""
    raw, results = tmp_path / "lab", tmp_path / "out"
    truth = write_lab_recordings(raw, case, seed)
    root = copy_workflow(tmp_path / "wf")
    fast = {"discrepancy": {**FAST_ENGINE["discrepancy"], **(engine or {})}}
    config = {**fast, "emulator": {"protocol": PROTOCOL}}
    (root / "fast.yaml").write_text(yaml.safe_dump(config))
    snakemake(root, "emulator_discrepancy", "--configfile", "fast.yaml", "--config",
              f"raw_dir={raw}", f"results_dir={results}", "acquisition=files")  # fmt: skip
    return json.loads((results / "emulator" / "discrepancy.json").read_text()), truth


def _check(report: dict, truth: dict, case: str) -> None:
    found = {f["effect"]: f for f in report["effects_found"]}
    if case == OUTSIDE:
        assert report["unexplained"]["flag"], report["cause"]
        assert report["effects_found"] == []
        return
    assert set(found) == set(truth), (report["selected"], report["cause"], truth)
    assert not report["unexplained"]["flag"], report["cause"]
    for effect, values in truth.items():  # coverage itself is the validation's (many draws)
        for name, value in values.items():
            assert within_twice_the_interval(found[effect], name, value), (effect, name, found)
    if not truth:
        assert report["cause"].startswith("none")


def within_twice_the_interval(finding: dict, name: str, value: float) -> bool:
    """The true value lies within twice the 95 % interval's half on its side of the estimate."""
    low, high = finding["ci95"][name]
    estimate = finding["parameters"][name]
    side = high - estimate if value > estimate else estimate - low
    return abs(value - estimate) <= 2.0 * side
