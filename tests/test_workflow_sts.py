"""The sit-to-stand group through the Snakemake command line, as a user runs it."""

from __future__ import annotations

import json

import pyarrow.parquet as pq
import pytest
import yaml

from conftest import copy_workflow, snakemake

# shares a workflow run: one pytest-xdist worker runs the whole group
pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("sts_run")]

BEAM_KEYS = {
    "max_bending_moment_Nm": float,
    "nominal_bending_stress_MPa": float,
    "peak_stress_MPa": float,
    "tip_deflection_mm": float,
    "buckling_load_N": float,
    "safety_factor_yield": float,
    "fatigue_safety_factor": float,
    "seed_fea_consistent": bool,
    "explanation": str,
}
OUTPUTS = (
    "sts/trajectories.parquet",
    "sts/trajectories_smooth.parquet",
    "sts/verification.json",
    "sts/loads.parquet",
    "sts/motion_comparison.json",
    "sts/spring_damper.json",
    "sts/spring_damper.parquet",
    "sts/beam_check.json",
    "figures/sts/paths.png",
    "figures/sts/torques.pdf",
    "figures/sts/modules.png",
    "figures/sts/thigh.png",
)


@pytest.fixture(scope="module")
def sts_run(tmp_path_factory):
    root = copy_workflow(tmp_path_factory.mktemp("sts_run"))
    snakemake(root, "sts")
    return root


def test_sts_target_builds_every_output_with_units(sts_run):
    results = sts_run / "results"
    for name in OUTPUTS:
        assert (results / name).stat().st_size > 0, name
    schema = pq.read_schema(results / "sts" / "trajectories.parquet")
    for column in ("t_s", "xC_mm", "yC_mm", "xB_mm", "yB_mm", "xA_mm", "yA_mm"):
        assert column in schema.names
    assert schema.field("xA_mm").metadata[b"unit"] == b"mm"
    assert schema.field("vxA_mm_per_s").metadata[b"unit"] == b"mm/s"
    assert b"exobench.provenance" in schema.metadata


def test_verification_and_beam_check_meet_the_contract(sts_run):
    results = sts_run / "results" / "sts"
    verification = json.loads((results / "verification.json").read_text())
    assert verification["max_position_deviation_m"] < 1e-9
    assert verification["passed"] is True
    check = json.loads((results / "beam_check.json").read_text())
    for key, kind in BEAM_KEYS.items():
        assert isinstance(check[key], kind), key
    assert check["max_bending_moment_Nm"] == pytest.approx(750.0)
    assert check["seed_fea_consistent"] is False
    fit = json.loads((results / "spring_damper.json").read_text())
    for joint, tuned in fit["tuned"].items():
        assert tuned["user_rms_Nm"] <= fit["user_rms_configured_Nm"][joint] + 1e-9


def test_sts_rerun_is_byte_identical(sts_run):
    results = sts_run / "results"
    before = {name: (results / name).read_bytes() for name in OUTPUTS}
    snakemake(sts_run, "sts", "--forcerun", "sts_kinematics")
    assert {name: (results / name).read_bytes() for name in OUTPUTS} == before


def test_bad_sample_rate_is_refused_without_outputs(workflow_copy):
    config = yaml.safe_load((workflow_copy / "config" / "config.yaml").read_text())
    config["sts"]["sample_rate_Hz"] = 333
    (workflow_copy / "bad.yaml").write_text(yaml.safe_dump(config))
    run = snakemake(workflow_copy, "sts_kinematics", "--configfile", "bad.yaml", check=False)
    assert run.returncode != 0
    assert "sts.sample_rate_Hz" in run.stderr
    assert not (workflow_copy / "results" / "sts" / "trajectories.parquet").exists()


def test_broken_reference_names_file_and_field(workflow_copy):
    reported = workflow_copy / "raw" / "reference" / "seed001_reported.csv"
    broken = reported.read_text().replace("fea_compression_peak_MPa", "fea_compression")
    reported.write_text(broken)
    run = snakemake(workflow_copy, "sts_beam", check=False)
    assert run.returncode != 0
    assert "seed001_reported.csv" in run.stderr
    assert "fea_compression_peak_MPa" in run.stderr
    assert not (workflow_copy / "results" / "sts" / "beam_check.json").exists()
    assert reported.read_text() == broken  # the user's file is left as they wrote it
