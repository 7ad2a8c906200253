"""Config validation: schema violations stop the workflow with a message naming the key."""

from __future__ import annotations

import pytest
import yaml
from snakemake.exceptions import WorkflowError
from snakemake.utils import validate

from conftest import REPO, snakemake

SCHEMA = str(REPO / "workflow" / "schemas" / "config.schema.yaml")


def default_config() -> dict:
    return yaml.safe_load((REPO / "config" / "config.yaml").read_text())


def test_default_config_is_valid():
    validate(default_config(), SCHEMA)


@pytest.mark.parametrize(
    ("key", "value"),
    [("seed", -1), ("seed", "abc"), ("acquisition", "lab"), ("raw_dir", "")],
)
def test_invalid_value_names_the_key(key, value):
    config = default_config() | {key: value}
    with pytest.raises(WorkflowError, match=rf"\['{key}'\]"):
        validate(config, SCHEMA)


def test_unknown_key_is_refused():
    config = default_config() | {"acqusition": "files"}
    with pytest.raises(WorkflowError, match="acqusition"):
        validate(config, SCHEMA)


@pytest.mark.parametrize(
    ("override", "key", "rule"),
    [
        ("seed=-3", "seed", "-3 is less than the minimum of 0"),
        ("acquisition=lab", "acquisition", "'lab' is not one of"),
        ("result_dir=x", "<top level>", "'result_dir' was unexpected"),
    ],
)
def test_command_line_violation_stops_snakemake(workflow_copy, override, key, rule):
    """One line naming the key (or the unexpected one) and the rule broken, not the schema."""
    process = snakemake(workflow_copy, "-n", "--config", override, check=False)
    text = process.stdout + process.stderr
    assert process.returncode == 2
    assert f"bad input: config: field '{key}': expected what workflow/schemas/" in text
    assert rule in text
    assert len(text.splitlines()) < 5
