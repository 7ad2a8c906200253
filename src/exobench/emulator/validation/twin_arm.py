"""Validation of the shared discrepancy engine on emulator recordings with effects drawn at random.

Each case draws a hidden truth from the emulator registry — no effect, one, or two — with sizes
log-uniform from a third of the documented detectable range up to its top (so that detection
limits show) and a random sign where the effect has one. The emulator twin writes docs/rig.md §3
recordings (manifest, 1 kHz brace CSVs, 100 Hz motion-capture CSVs; a torque-sensor offset is
added to the brace CSV's torque, as a miscalibrated load cell would); they are read back through
the analysis chain as a lab's (acquisition checks → events, activity, energy → sensor alignment
and count drops → session QC) and the engine, told nothing, reports. Rows compare its report
with the truth; :func:`summary` gives per parameter the detection rate, 95 % interval coverage,
false claims and detection limit, and the false-positive rate of the no-effect cases.
"""

from __future__ import annotations

import copy
import tempfile
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import emulator, selection
from exobench.emulator.chain import analysis, triangulation
from exobench.emulator.model import discrepancy, effects
from exobench.emulator.recordings import acquire
from exobench.emulator.twin import twin
from exobench.errors import InputError

# twin switches of the effects the registry describes; every other effect of the twin is off
SWITCHES = ("cuff_compliance", "transmission_friction", "encoder_count_drop", "mocap_alignment",
            "soft_tissue_artefact", "clutch_departure")  # fmt: skip
MOCAP = {"mocap_zero": "zero_deg", "mocap_gain": "gain", "mocap_clock": "clock_offset_s"}


def base_config(emulator_block: Mapping) -> dict:
    """The emulator block the validation's twin runs: the protocol of its ``validation`` block."""
    cfg = copy.deepcopy(dict(emulator_block))
    block = cfg["validation"]
    cfg["protocol"] = {k: block[k] for k in ("speeds_m_per_s", "stiffnesses_Nm_per_rad",
                                              "duration_s")}  # fmt: skip
    return cfg


def draw_case(rng: np.random.Generator, protocol: Mapping) -> dict:
    """A hidden truth: effect -> {parameter: value}, and where a count drop happens."""
    chosen = selection.drawn_effects(effects.REGISTRY, rng)
    hidden = {name: magnitudes(effects.REGISTRY[name], rng) for name in chosen}
    drop = {
        "trial": twin.trial_name(
            float(rng.choice(protocol["speeds_m_per_s"])),
            float(max(protocol["stiffnesses_Nm_per_rad"])),
        ),
        # a quarter of the drops predate the trial (a constant offset of that trial)
        "time_s": 0.0
        if rng.random() < 0.25
        else float(rng.uniform(1.0, protocol["duration_s"] - 1.0)),
    }
    return {"hidden": hidden, "drop": drop}


def magnitudes(effect: selection.Effect, rng, widen: float = 3.0) -> dict[str, float]:
    """Values of an effect's parameters: sizes log-uniform from ``widen`` times below the
    documented detectable range (the emulator registry gives it as sizes) up to its top, with a
    random sign where the effect has one (the cuff's compliance and time constant have none),
    in whole steps of the parameter's resolution where it has one (a controller acts on whole
    samples), never below the range's bottom."""
    out = {}
    for p in effect.parameters:
        low, high = sorted(float(s) for s in p.detectable)
        size = float(np.exp(rng.uniform(np.log(low / widen), np.log(high))))
        if p.resolution:
            steps = max(round(size / p.resolution), np.ceil(low / widen / p.resolution - 1e-9), 1)
            size = float(steps) * p.resolution
        signed = not p.log
        out[p.name] = p.value_at(size, float(rng.choice([-1.0, 1.0])) if signed else 1.0)
    return out


def twin_config(base: Mapping, case: Mapping) -> dict:
    """Emulator block whose twin has exactly the hidden effects (plus sensor noise)."""
    cfg = copy.deepcopy(dict(base))
    for name in SWITCHES:
        cfg["effects"][name]["enabled"] = False
    hidden = case["hidden"]
    if "cuff_compliance" in hidden:
        cfg["effects"]["cuff_compliance"].update(enabled=True, **hidden["cuff_compliance"])
    if "clutch_late_release" in hidden:
        cfg["effects"]["clutch_departure"].update(enabled=True, **hidden["clutch_late_release"])
    if "transmission_friction" in hidden:
        cfg["effects"]["transmission_friction"].update(
            enabled=True, **hidden["transmission_friction"]
        )
    if "encoder_count_drop" in hidden:
        cfg["effects"]["encoder_count_drop"].update(
            enabled=True, trials=[case["drop"]["trial"]], time_s=case["drop"]["time_s"],
            size_deg=hidden["encoder_count_drop"]["drop_deg"],
        )  # fmt: skip
    alignment = {name: hidden[effect][name] for effect, name in MOCAP.items() if effect in hidden}
    if alignment:
        cfg["effects"]["mocap_alignment"].update(
            {"enabled": True, "zero_deg": 0.0, "gain": 1.0, "clock_offset_s": 0.0, **alignment}
        )
    return cfg


def recordings(folder: Path, cfg: Mapping, case: Mapping, seed: int) -> Path:
    """The twin's docs/rig.md §3 files of a case (a torque-sensor offset added to the brace CSV)."""
    recs = twin.run(cfg, seed)
    offset = case["hidden"].get("torque_offset", {}).get("torque_offset_Nm", 0.0)
    for rec in recs:
        rec.brace["brace_torque_Nm"] = rec.brace["brace_torque_Nm"] + offset
    twin.write_recordings(recs, folder)
    return folder / "manifest.csv"


def chain_parts(manifest_path: Path, cfg: Mapping, seed: int) -> list[tuple]:
    """Read the files back as a lab's and run the per-trial analysis and the session QC."""
    settings = emulator.analysis_settings({"emulator": cfg, "seed": seed})
    duration = float(cfg["protocol"]["duration_s"])
    manifest = acquire.read_manifest(manifest_path)
    folder = manifest_path.parent
    trials = {}
    for row in manifest.itertuples():
        brace, mocap = acquire.read_trial(
            folder / row.file, folder / row.mocap_file, duration, settings
        )
        stiffness = float(row.stiffness_Nm_per_rad)
        samples, _, qc = analysis.analyse(row.trial, brace, mocap, stiffness, settings)
        trials[row.trial] = (stiffness, samples, qc)
    qc = triangulation.session(
        {n: v[2] for n, v in trials.items()},
        settings["fault_threshold_deg"],
        cfg["transmission_calibrated"],
    )
    return [(n, k, s, qc["trials"][n]) for n, (k, s, _) in trials.items()]


def run_case(index: int, base: Mapping, engine: Mapping, seed: int) -> tuple[dict, dict]:
    """Draw, simulate, analyse one case: (truth, report)."""
    case_seed = int(seed) * 100_003 + index
    case = draw_case(np.random.default_rng([case_seed, 29]), base["protocol"])
    cfg = twin_config(base, case)
    with tempfile.TemporaryDirectory() as tmp:
        manifest = recordings(Path(tmp), cfg, case, case_seed)
        parts = chain_parts(manifest, cfg, case_seed)
    truth = {"case": index, "seed": case_seed, **case}
    controller = cfg["controller"]
    try:
        data, scales = discrepancy.observations(
            parts, controller["equilibrium_deg"], controller["direction_blend_deg_per_s"],
            cfg["transmission"], int(engine["folds"]), controller["torque_filter_Hz"],
        )  # fmt: skip
    except InputError as error:  # too few complete steps: the engine refuses, says why
        return truth, {"effects_found": [], "tentative": [], "unexplained": {"flag": False},
                       "cause": f"refused: {error}"}  # fmt: skip
    report = discrepancy.analyse(data, scales, engine, case_seed, f"validation case {index}")
    return truth, report


def case_rows(truth: Mapping, report: Mapping) -> list[dict]:
    """One row per registry parameter: hidden truth, what the engine claimed, its interval."""
    case = {"case": truth["case"], "seed": truth["seed"]}
    return [
        {**case, "drop_time_s": truth["drop"]["time_s"] if row["hidden"] else np.nan, **row}
        for row in selection.validation_rows(effects.REGISTRY, truth["hidden"], report)
    ]


def summary(rows: pd.DataFrame) -> pd.DataFrame:
    """Per registry parameter and overall: detection rate, 95 % interval coverage of the claimed
    hidden effects, false-claim rate where the effect was not hidden, detection limit (weakest
    size at and beyond which ≥ 80 % were claimed); and the no-effect cases' false-positive rate
    (anything claimed or an unexplained flag)."""
    out = []
    cases = rows.drop_duplicates("case")
    none = cases[cases["hidden_effects"] == "none"]["case"]
    for (name, parameter), group in rows.groupby(["effect", "parameter"], sort=False):
        present = group[group["hidden"]]
        detected = present[present["claimed"]]
        absent = group[~group["hidden"]]
        out.append(
            {
                "effect": name,
                "parameter": parameter,
                "unit": group["unit"].iloc[0],
                "cases_hidden": len(present),
                "detection_rate": _rate(present["claimed"]),
                "intervals": len(detected),
                "coverage_95": _rate(detected["covered"]),
                "false_claim_rate": _rate(absent["claimed"]),
                "detection_limit": (
                    selection.detection_limit(effects.REGISTRY, present) if len(present) else np.nan
                ),
            }
        )
    detected = rows[rows["hidden"] & rows["claimed"]]
    absent = rows[~rows["hidden"]].groupby(["case", "effect"])["claimed"].any()
    out.append(
        {
            "effect": "all",
            "parameter": "",
            "cases_hidden": int(rows[rows["hidden"]]["case"].nunique()),
            "detection_rate": _rate(
                rows[rows["hidden"]].groupby(["case", "effect"])["claimed"].all()
            ),
            "intervals": len(detected),
            "coverage_95": _rate(detected["covered"]),
            "false_claim_rate": _rate(absent),
        }
    )
    none_rows = rows[rows["case"].isin(none)].groupby("case")
    false = none_rows["claimed"].any() | none_rows["unexplained_flag"].any()
    out.append({"effect": "no-effect cases", "parameter": "", "cases_hidden": len(none),
                "false_positive_rate": _rate(false)})  # fmt: skip
    return pd.DataFrame(out)


def _rate(values) -> float:
    values = np.asarray(values, bool)
    return float(values.mean()) if values.size else np.nan


def figure(rows: pd.DataFrame, table: pd.DataFrame):
    """Coverage and detection rate per parameter (the 90–98 % coverage target shaded), and
    detection against effect size over the top of the documented detectable range."""
    from matplotlib import pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    per = table[table["parameter"] != ""]
    x = np.arange(len(per))
    left.axhspan(0.90, 0.98, color="0.88", label="coverage target 90–98 %")
    left.bar(x - 0.2, per["coverage_95"].fillna(0.0), 0.4, label="95 % interval coverage")
    left.bar(x + 0.2, per["detection_rate"].fillna(0.0), 0.4, label="detection rate")
    left.set_xticks(x, [f"{e}\n{p}" for e, p in zip(per["effect"], per["parameter"], strict=True)],
                    rotation=60, ha="right", fontsize=7)  # fmt: skip
    left.set_ylim(0.0, 1.05)
    left.set_ylabel("rate (1)")
    left.legend(fontsize=7, loc="lower left")
    present = rows[rows["hidden"]]
    for (name, parameter), group in present.groupby(["effect", "parameter"], sort=False):
        p = next(q for q in effects.REGISTRY[name].parameters if q.name == parameter)
        top = float(np.max(p.strength(p.detectable)))
        size = p.strength(group["truth"].to_numpy()) / top
        right.scatter(size, group["claimed"].astype(float) + 0.04 * np.random.default_rng(0)
                      .standard_normal(len(group)), s=12, label=f"{name}: {parameter}")  # fmt: skip
    right.set_xscale("log")
    right.set_xlabel("effect size / top of documented detectable range (1)")
    right.set_ylabel("claimed (1 = yes)")
    right.legend(fontsize=6, loc="center right")
    fig.suptitle(f"Emulator engine validation: {rows['case'].nunique()} cases")
    fig.tight_layout()
    return fig
