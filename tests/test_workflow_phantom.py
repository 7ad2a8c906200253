"""Phantom acquisition through the Snakemake command line, as a user runs it."""

from __future__ import annotations

import shutil

import ezc3d
import numpy as np
import pytest
import yaml

from conftest import small_copy, snakemake

pytestmark = pytest.mark.slow
# the tests that share the twin's run (twin_run) on one pytest-xdist worker
TWIN_RUN = pytest.mark.xdist_group("acquired_run")

SMALL = {
    "phantom": {
        "protocol": {"strides": 8, "ramp_strides": 1},
        "calibration": {"strides": 8, "ramp_strides": 1},
    }
}


@pytest.fixture
def small_workflow(workflow_copy):
    (workflow_copy / "small.yaml").write_text(yaml.safe_dump(SMALL))
    return workflow_copy


@pytest.fixture(scope="module")
def twin_run(tmp_path_factory):
    """A workflow copy with the twin's recordings written and acquired (one run for two tests)."""
    root = small_copy(tmp_path_factory.mktemp("acquired_run"), SMALL)
    snakemake(root, "phantom_acquire", "--configfile", "small.yaml")
    return root


@TWIN_RUN
def test_synthetic_then_files_acquisition(twin_run, tmp_path):
    raw = twin_run / "raw" / "phantom"
    names = sorted(p.name for p in raw.glob("*.c3d"))
    assert len(names) == 6
    acquired = twin_run / "results" / "phantom" / "acquired"
    assert len(list(acquired.glob("*_markers.parquet"))) == 6
    assert (twin_run / "results" / "phantom" / "calibration" / "fit.json").is_file()

    lab = tmp_path / "lab"
    shutil.copytree(raw, lab / "phantom", ignore=shutil.ignore_patterns("truth", "twin_*"))
    out = tmp_path / "out"
    args = ["--configfile", "small.yaml", "--config", f"raw_dir={lab}", f"results_dir={out}"]
    run = snakemake(twin_run, "phantom_acquire", *args, "acquisition=files")
    assert "phantom_twin" not in run.stdout + run.stderr
    for name in names:
        stem = name.removesuffix(".c3d")
        for kind in ("markers", "analog"):
            mine = (out / "phantom" / "acquired" / f"{stem}_{kind}.parquet").read_bytes()
            assert len(mine) > 0


def test_twin_does_not_overwrite_lab_recordings(small_workflow):
    raw = small_workflow / "raw" / "phantom"
    raw.mkdir(parents=True)
    text = "trial,file,spring_stiffness_N_per_m,test_order,ramp_strides\n"
    (raw / "manifest.csv").write_text(text)
    run = snakemake(
        small_workflow, "-n", "phantom_acquire", "--configfile", "small.yaml", check=False
    )
    assert run.returncode != 0
    assert "acquisition=files" in run.stdout + run.stderr
    assert (raw / "manifest.csv").read_text() == text


@TWIN_RUN
def test_lab_file_missing_a_marker_fails_clearly(twin_run, tmp_path):
    lab = tmp_path / "lab" / "phantom"
    shutil.copytree(twin_run / "raw" / "phantom", lab, ignore=shutil.ignore_patterns("truth"))
    broken = lab / "k03400.c3d"
    data = ezc3d.c3d(str(broken))
    labels = list(data["parameters"]["POINT"]["LABELS"]["value"])
    labels[labels.index("EX_SPRING_B")] = "SPRING_END"
    data["parameters"]["POINT"]["LABELS"]["value"] = tuple(labels)
    data["data"]["points"] = np.array(data["data"]["points"])
    data.write(str(broken))
    out = tmp_path / "out"
    args = ["--config", f"raw_dir={lab.parent}", f"results_dir={out}", "acquisition=files"]
    run = snakemake(twin_run, "phantom_acquire", "--configfile", "small.yaml", *args, check=False)
    assert run.returncode != 0
    text = run.stdout + run.stderr
    assert "k03400.c3d: field 'POINT:LABELS'" in text and "EX_SPRING_B" in text
    assert not (out / "phantom" / "acquired" / "k03400_markers.parquet").exists()
    assert not (out / "phantom" / "acquired" / "k03400_analog.parquet").exists()
