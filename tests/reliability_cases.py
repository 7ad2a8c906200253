"""Run every damaged-input case of issue 14 through Snakemake and print case → exit → message.

Usage: ``.venv/bin/python tests/reliability_cases.py [case numbers]`` (all cases: about 5 min
on 2 free cores). Each case gets its own copy of valid recordings; the table says whether the
copy's raw files are unchanged and which tables of the damaged trial are left.
"""

from __future__ import annotations

import copy
import hashlib
import re
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

sys.path.insert(0, str(Path(__file__).parent))

from conftest import copy_workflow, snakemake
from exobench import tables
from reliability_helpers import (
    EMULATOR_DURATION_S,
    PHANTOM_RAMPS,
    PHANTOM_STRIDES,
    edit_c3d,
    saturate,
    write_emulator,
    write_phantom,
)

# The protocol of the valid recordings (reliability_helpers), as a config file.
PROTOCOL = {
    "phantom": {
        "protocol": {"strides": PHANTOM_STRIDES, "ramp_strides": PHANTOM_RAMPS},
        "calibration": {"strides": PHANTOM_STRIDES, "ramp_strides": PHANTOM_RAMPS},
    },
    "emulator": {
        "protocol": {
            "speeds_m_per_s": [0.8],
            "stiffnesses_Nm_per_rad": [0.0, 3.5],
            "duration_s": EMULATOR_DURATION_S,
        }
    },
}


def digest(folder: Path) -> str:
    sha = hashlib.sha256()
    for path in sorted(folder.rglob("*")):
        if path.is_file():
            sha.update(path.as_posix().encode() + path.read_bytes())
    return sha.hexdigest()


def cut_half(path: Path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def short_c3d(path: Path) -> None:
    from exobench.phantom.recordings import c3d

    markers, analog = c3d.read_trial(path)
    c3d.write_trial(
        path,
        {m: markers[[f"{m}_{a}_mm" for a in "xyz"]].to_numpy()[:250] for m in c3d.MARKERS},
        {k: analog[f"{k}_{u}"].to_numpy()[:2500] for k, u in c3d.ANALOG_UNITS.items()},
    )


def scaled(label: str, factor: float, offset: float = 0.0):
    def edit(_points, analogs, labels):
        row = labels.index(label)
        analogs[row] = factor * analogs[row] + offset * analogs[row].max()

    return edit


def jump(points, _analogs, _labels):
    points[0, 3, 500:505] += 80.0


def ghost(points, _analogs, _labels):
    points[:3, 10, 700] += 80.0 / np.sqrt(3)  # EX_SPRING_A 80 mm off for one frame


def spike(_points, analogs, labels):
    analogs[labels.index("LC_ANKLE_1"), 5123] += 1500.0


def c3d_edit(edit):
    return lambda path: edit_c3d(path, path, edit)


def brace_edit(edit):
    def apply(path: Path) -> None:
        frame = edit(pd.read_csv(path))
        frame.to_csv(path, index=False)

    return apply


# (case, group, damage of the first trial's recording or manifest, phantom config, target)
CASES = [
    ("C3D cut in half", "phantom", cut_half, {}, "trial"),
    ("very short C3D (2.5 s)", "phantom", short_c3d, {}, "trial"),
    (
        "load cell saturated for 1 s",
        "phantom",
        c3d_edit(saturate("LC_ANKLE_2", 4200, 5200)),
        {},
        "trial",
    ),
    ("every stride saturated", "phantom", c3d_edit(saturate("LC_ANKLE_2", 0, 12000)), {}, "trial"),
    ("load cell in mN (×1000)", "phantom", c3d_edit(scaled("LC_ANKLE_1", 1000.0)), {}, "trial"),
    (
        "spring force sign reversed",
        "phantom",
        c3d_edit(scaled("LC_SPRING", -1.0, 1.0)),
        {},
        "trial",
    ),
    ("marker jump 80 mm for 5 frames (repaired)", "phantom", c3d_edit(jump), {}, "trial"),
    ("ghost frame 80 mm (repaired)", "phantom", c3d_edit(ghost), {}, "trial"),
    ("1500 N spike, one sample (repaired)", "phantom", c3d_edit(spike), {}, "trial"),
    ("manifest header only", "phantom-manifest", "header", {}, "trial"),
    ("manifest springs in kN/m", "phantom-manifest", "kN/m", {}, "trial"),
    ("manifest 0 bytes", "phantom-manifest", "empty", {}, "trial"),
    (
        "emulator torque in N·mm",
        "emulator",
        brace_edit(lambda f: f.assign(brace_torque_Nm=1000 * f["brace_torque_Nm"])),
        {},
        "trial",
    ),
    (
        "emulator brace file cut to half",
        "emulator",
        brace_edit(lambda f: f.iloc[: len(f) // 2]),
        {},
        "trial",
    ),
    ("emulator manifest header only", "emulator-manifest", "header", {}, "trial"),
    (
        "test order not a permutation",
        "config",
        None,
        {"protocol": {"test_order_N_per_m": [9200, 21700, 13600, 6100, 3400, 3400]}},
        "dry",
    ),
    (
        "strides ≤ 2 × ramp_strides",
        "config",
        None,
        {"protocol": {"strides": 10, "ramp_strides": 5}},
        "dry",
    ),
    (
        "calibration strides ≤ 2 × ramp_strides",
        "config",
        None,
        {"calibration": {"strides": 10, "ramp_strides": 5}},
        "dry",
    ),
    (
        "work window longer than the stride",
        "config",
        None,
        {"protocol": {"work_window_s": 2.5}},
        "dry",
    ),
    (
        "discrepancy window outside the clutch window",
        "config",
        None,
        {"discrepancy": {"window_pct": [0.0, 50.0]}},
        "dry",
    ),
]


def message(text: str) -> str:
    for pattern in (r"bad input: (.*)", r"InputError[^:\n]*: ?(.*)", r"Error.*?: (.*)"):
        found = re.search(pattern, text)
        if found and found.group(1).strip():
            return found.group(1).strip()
    return text.strip().splitlines()[-1] if text.strip() else ""


def run_case(root: Path, valid: Path, work: Path, case) -> tuple[int, str, bool, list]:
    _name, group, damage, extra, kind = case
    raw = work / "raw"
    shutil.copytree(valid, raw)
    results = work / "results"
    config = ["acquisition=files", f"raw_dir={raw}", f"results_dir={results}"]
    kind_group = group.split("-")[0]
    folder = raw / ("emulator" if kind_group == "emulator" else "phantom")
    manifest = folder / "manifest.csv"
    trial = pd.read_csv(manifest)["trial"].iloc[0] if kind_group != "config" else None
    if group.endswith("manifest") and damage == "kN/m":
        table = pd.read_csv(manifest)
        rate = "spring_stiffness_N_per_m"
        table.assign(**{rate: table[rate] / 1000}).to_csv(manifest, index=False)
    elif group.endswith("manifest"):
        text = manifest.read_text().splitlines()[0] + "\n"
        manifest.write_text(text if damage == "header" else "")
    elif damage is not None:
        damage(folder / pd.read_csv(manifest)["file"].iloc[0])
    before = digest(raw)
    if kind == "dry":
        args = ["-n", "phantom"]
    elif kind_group == "emulator":
        args = [str(results / "emulator" / "steps" / f"{trial}.parquet")]
    else:
        args = [str(results / "phantom" / "strides" / f"{trial}.parquet")]
    protocol = copy.deepcopy(PROTOCOL)
    for key, value in extra.items():
        protocol["phantom"].setdefault(key, {}).update(value)
    (work / "config.yaml").write_text(yaml.safe_dump(protocol))
    process = snakemake(
        root, *args, "--configfile", str(work / "config.yaml"), "--config", *config, check=False
    )
    text = process.stdout + process.stderr
    out = message(text)
    strides = results / "phantom" / "strides" / f"{trial}.parquet"
    if process.returncode == 0 and strides.is_file():
        table = tables.read_table(strides).data
        excluded = table[table["exclusion_reason"] != ""]
        out = "; ".join(
            f"stride {s}: {r}"
            for s, r in zip(excluded["stride"], excluded["exclusion_reason"], strict=True)
        )
    leftover = sorted(
        path.parent.name
        for path in results.rglob(f"{trial}*")
        if path.is_file() and not {"logs", "benchmarks"} & set(path.parts)
    )
    if kind == "dry" or process.returncode == 0:
        leftover = []
    return process.returncode, out, digest(raw) == before, leftover


def main() -> None:
    base = Path(tempfile.mkdtemp(prefix="exobench_cases_"))
    root = copy_workflow(base / "wf")
    valid = base / "valid"
    write_phantom(valid / "phantom")
    write_emulator(valid / "emulator")
    print("| case | exit | message or exclusion reason | raw unchanged | trial tables left |")
    print("|---|---|---|---|---|")
    chosen = [int(i) for i in sys.argv[1:]] or range(len(CASES))
    for index in chosen:
        case = CASES[index]
        code, out, unchanged, leftover = run_case(root, valid, base / f"case{index}", case)
        out = out.replace("|", "\\|")
        left = ", ".join(leftover) or "none"
        print(f"| {case[0]} | {code} | {out} | {unchanged} | {left} |", flush=True)
    shutil.rmtree(base)


if __name__ == "__main__":
    main()
