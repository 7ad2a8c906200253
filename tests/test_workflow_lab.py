"""A lab's recordings through the workflow, as docs/phantom.md "Bringing your own rig" tells a new
user: renamed labels, its own camera and analog rates, metres, and the glitches real recorders
make — run to figures, each glitch named in the QC table; W.S.B. et al.'s steps left out; a
manifest in kN/m refused."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import SMALL, copy_workflow, snakemake
from exobench import tables
from exobench.phantom.rig import Rig
from exobench.phantom.twin import twin
from lab_helpers import CALIBRATED, LAB_LABELS, lab_trial, write_lab_c3d, write_manifest
from phantom_helpers import mean_cycle, settings, workflow_config

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("lab_run")]

# trial -> (camera rate, analog rate): every file states its own
RATES = {"k03400": (100.0, 1000.0), "k09200": (200.0, 2000.0), "k21700": (120.0, 1200.0)}
SPIKE = ("k09200", "LC_ANKLE_2", 7.0405)  # one sample of +1500 N, in stride 3
GHOST = ("k21700", "EX_SHANK_DIST", 9.5)  # one frame 80 mm off, in stride 4
TRANSIENTS = ("k21700", "LC_SPRING", (4.31, 12.62, 17.25))  # 3 ms of ±2000 N each


def stretched_spring(markers: dict, target_mm: float) -> float:
    """The spring end's path stretched along the spring so that its largest move between two
    frames is ``target_mm`` (a spring that recoils faster at the clutch release than the
    twin's); the stretch factor."""
    anchor, end = markers["EX_SPRING_A"], markers["EX_SPRING_B"]
    length = np.linalg.norm(end - anchor, axis=1)
    direction = (end - anchor) / length[:, None]
    extension = (length - length.min())[:, None] * direction

    def largest(factor):
        return np.linalg.norm(np.diff(end + (factor - 1) * extension, axis=0), axis=1).max()

    low, high = 1.0, 10.0
    for _ in range(50):
        low, high = ((low + high) / 2, high) if largest((low + high) / 2) < target_mm else (
            low, (low + high) / 2)  # fmt: skip
    markers["EX_SPRING_B"] = end + (low - 1) * extension
    return low


def write_lab(folder) -> None:
    config = workflow_config()
    springs = [3400, 9200, 21700]
    config["phantom"]["protocol"].update(strides=24, ramp_strides=1, springs_N_per_m=springs,
                                         test_order_N_per_m=springs)  # fmt: skip
    config["phantom"]["twin"]["clutch_release_s"] = 0.005  # a fast clutch: the spring recoils
    for effect in ("marker_noise", "load_cell_noise", "occlusion"):
        config["phantom"]["twin"]["effects"][effect]["enabled"] = False
    rng = np.random.default_rng(28)
    rows = []
    for order, trial in enumerate(twin.simulate_trials(mean_cycle(), Rig(), settings(config),
                                                       CALIBRATED), start=1):  # fmt: skip
        rates = RATES[trial.name]
        markers, analogs = lab_trial(trial.markers_mm, trial.analogs, *rates, 2.0, rng, (0.15, 0.5))
        if trial.name == "k03400":
            stretched_spring(markers, 20.75)
        if trial.name == SPIKE[0]:
            analogs[SPIKE[1]][round(SPIKE[2] * rates[1])] += 1500.0
        if trial.name == GHOST[0]:
            markers[GHOST[1]][round(GHOST[2] * rates[0])] += np.array([80.0, 0.0, 0.0])
            for time, sign in zip(TRANSIENTS[2], (1, -1, 1), strict=True):
                start = round(time * rates[1])
                analogs[TRANSIENTS[1]][start : start + round(0.003 * rates[1])] = sign * 2000.0
        file = f"session1_{trial.name}.c3d"  # the lab's own file names
        write_lab_c3d(folder / file, markers, analogs, *rates, LAB_LABELS, "m")
        rows.append((trial.name, file, trial.spring_stiffness_N_per_m, order, 1))
    write_manifest(folder, rows)


@pytest.fixture(scope="module")
def lab_run(tmp_path_factory):
    """The lab's folder and the workflow run on it (phantom target, acquisition=files)."""
    base = tmp_path_factory.mktemp("lab_run")
    root = copy_workflow(base / "wf")
    write_lab(base / "lab" / "phantom")
    # the user's own config: their labels, and a small engine for speed (no term search: the
    # engine's discovery is tested on its own, here only the run's reach and refusals)
    engine = {**SMALL["discrepancy"], "max_terms": 0}
    own = {"phantom": {"rig": {"labels": LAB_LABELS}}, "discrepancy": engine}
    (base / "lab.yaml").write_text(yaml.safe_dump(own))
    config = ["--config", f"raw_dir={base / 'lab'}", f"results_dir={base / 'out'}",
              "acquisition=files"]  # fmt: skip
    run = snakemake(root, "phantom", "--configfile", str(base / "lab.yaml"), *config)
    return {"base": base, "root": root, "results": base / "out", "run": run, "config": config}


def qc_table(lab_run, trial) -> pd.DataFrame:
    return tables.read_table(lab_run["results"] / "phantom" / "qc" / f"{trial}.parquet").data


def test_the_lab_run_reaches_the_figures_without_seed_000s_steps(lab_run):
    results = lab_run["results"]
    figures = results / "figures" / "phantom"
    for name in ("fig05_kinematics", "fig10_work", "qc", "discrepancy"):
        assert (figures / f"{name}.png").is_file(), name
    text = lab_run["run"].stdout + lab_run["run"].stderr
    assert "phantom_calibrate" not in text and "phantom_compare" not in text
    assert not (results / "phantom" / "calibration").exists()
    assert not (results / "phantom" / "paper_comparison.csv").exists()
    metrics = tables.read_table(results / "phantom" / "metrics.parquet").data
    assert sorted(metrics["trial"].unique()) == sorted(RATES)
    assert metrics.groupby("trial")["included"].sum().min() >= 18  # of 22 between the ramps


def test_each_glitch_is_named_in_the_qc_table(lab_run):
    trial, channel, time = SPIKE
    spike = qc_table(lab_run, trial)
    row = spike[spike["channel"] == channel].iloc[0]
    assert "spike" in row["kind"] and "out of range" in row["kind"]
    assert row["start_s"] == pytest.approx(time, abs=1e-3) and row["repair"] == "filled"
    assert row["deviation_N"] == pytest.approx(1500.0, rel=0.05)
    assert set(spike["channel"]) == {channel}  # the other cells moved by a real force, not a spike

    trial, label, time = GHOST
    ghosts = qc_table(lab_run, trial)
    row = ghosts[ghosts["channel"] == label].iloc[0]
    assert row["start_s"] == pytest.approx(time, abs=0.01) and row["repair"] == "filled"
    assert row["deviation_mm"] == pytest.approx(80.0, rel=0.1)
    transients = ghosts[ghosts["channel"] == TRANSIENTS[1]]
    assert transients["start_s"].round(2).tolist() == list(TRANSIENTS[2])
    assert transients["repair"].eq("filled").all()
    assert set(ghosts["channel"]) == {label, TRANSIENTS[1]}
    # the spring end that moves more than 20 mm in one 10 ms frame at the release is physics
    assert qc_table(lab_run, "k03400").empty


def test_each_trials_log_has_its_qc_line(lab_run):
    logs = sorted((lab_run["results"] / "logs" / "phantom_chain").glob("*.log"))
    log = "\n".join(path.read_text() for path in logs)
    lines = [line for line in log.splitlines() if re.search(r"k\d{5}: \d+ of \d+ strides", line)]
    assert len(lines) == len(RATES)
    assert any("1 spike and out of range on LC_ANKLE_2 (1 filled)" in line for line in lines), lines


def test_a_manifest_in_kN_per_m_is_refused_naming_the_column(lab_run, tmp_path):
    raw = tmp_path / "raw" / "phantom"
    raw.mkdir(parents=True)
    manifest = pd.read_csv(lab_run["base"] / "lab" / "phantom" / "manifest.csv")
    for file in manifest["file"]:
        (raw / file).symlink_to(lab_run["base"] / "lab" / "phantom" / file)
    rate = "spring_stiffness_N_per_m"
    manifest.assign(**{rate: manifest[rate] / 1000}).to_csv(raw / "manifest.csv", index=False)
    config = [f"raw_dir={raw.parent}", f"results_dir={tmp_path / 'out'}", "acquisition=files"]
    run = snakemake(lab_run["root"], "-n", "phantom", "--config", *config, check=False)
    assert run.returncode != 0
    text = run.stdout + run.stderr
    assert f"field '{rate}'" in text and "1000× too small" in text and "manifest.csv" in text


def _metres_under_mm(data) -> None:
    data["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]  # the lab's file holds metres


def _kN_under_N(data) -> None:
    labels = [str(x).strip() for x in data["parameters"]["ANALOG"]["LABELS"]["value"]]
    analogs = np.array(data["data"]["analogs"])
    for cell in ("LC_ANKLE_1", "LC_ANKLE_2", "LC_ANKLE_3"):
        analogs[0, labels.index(LAB_LABELS[cell])] *= 0.001
    data["data"]["analogs"] = analogs


@pytest.mark.parametrize(
    ("edit", "field", "slip"),
    [
        (_metres_under_mm, "POINT:UNITS", "markers look to be in metres while POINT:UNITS says mm"),
        (_kN_under_N, "ANALOG:UNITS of Force.Fz1, Force.Fz2, Force.Fz3",
         "the ankle load cells look to be in kN"),
    ],
)  # fmt: skip
def test_a_lab_unit_slip_ends_the_run_with_a_bad_input_line(lab_run, tmp_path, edit, field, slip):
    import ezc3d

    raw = tmp_path / "raw" / "phantom"
    raw.mkdir(parents=True)
    manifest = pd.read_csv(lab_run["base"] / "lab" / "phantom" / "manifest.csv").iloc[:1]
    data = ezc3d.c3d(str(lab_run["base"] / "lab" / "phantom" / manifest["file"].iloc[0]))
    edit(data)
    data.write(str(raw / manifest["file"].iloc[0]))
    manifest.to_csv(raw / "manifest.csv", index=False)
    out = tmp_path / "out"
    target = out / "phantom" / "acquired" / f"{manifest['trial'].iloc[0]}_markers.parquet"
    config = [f"raw_dir={raw.parent}", f"results_dir={out}", "acquisition=files"]
    run = snakemake(lab_run["root"], str(target), "--configfile", str(lab_run["base"] / "lab.yaml"),
                    "--config", *config, check=False)  # fmt: skip
    text = run.stdout + run.stderr
    assert run.returncode != 0
    line = next(line for line in text.splitlines() if "bad input:" in line)
    assert manifest["file"].iloc[0] in line and f"field '{field}'" in line and slip in line
    # no partial outputs: the trial's job left none (the reference cycle before it is whole)
    assert [p.relative_to(out) for p in (out / "phantom").rglob("*.parquet")] == [
        Path("phantom/reference/mean_cycle.parquet")
    ]
