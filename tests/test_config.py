"""Config validation: schema violations stop the workflow with a message naming the key."""

from __future__ import annotations

import copy
import re
import shlex

import pytest
import yaml

from conftest import REPO, snakemake
from exobench.errors import InputError
from exobench.plumbing import config_checks


def default_config() -> dict:
    return yaml.safe_load((REPO / "config" / "config.yaml").read_text())


def test_default_config_is_valid():
    config = default_config()
    assert config_checks.validate(copy.deepcopy(config), schema()) == config


def test_a_key_left_out_takes_the_schema_default():
    config = default_config()
    declared = schema()["properties"]["results_dir"]["default"]
    del config["results_dir"]
    assert config_checks.validate(config, schema())["results_dir"] == declared


@pytest.mark.parametrize(
    ("key", "value"),
    [("seed", -1), ("seed", "abc"), ("acquisition", "lab"), ("raw_dir", "")],
)
def test_invalid_value_names_the_key(key, value):
    config = default_config() | {key: value}
    with pytest.raises(InputError, match=rf"field '{key}'"):
        config_checks.validate(config, schema())


def test_unknown_key_is_refused():
    config = default_config() | {"acqusition": "files"}
    with pytest.raises(InputError, match="'acqusition' was unexpected"):
        config_checks.validate(config, schema())


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


def schema() -> dict:
    return yaml.safe_load((REPO / "workflow" / "schemas" / "config.schema.yaml").read_text())


def refusal(config: dict) -> InputError:
    """The InputError the workflow raises for ``config`` (coerced, validated, then named)."""
    config_checks.coerce(config, schema())
    with pytest.raises(InputError) as caught:
        config_checks.validate(config, schema())
    return caught.value


def test_nested_command_line_text_becomes_the_booleans_and_numbers_the_schema_asks():
    # what snakemake --config phantom='{...}' gives: every nested value as text
    config = default_config()
    friction = {"enabled": "false", "friction_Nm": "calibrated"}
    update = {"compare_seed000": "true", "rig": {"thigh_length_m": "0.31", "labels": {"SYNC": "1"}},
              "protocol": {"strides": "40", "springs_N_per_m": ["3400", "6100"]},
              "twin": {"effects": {"frame_friction": friction}}}  # fmt: skip
    config["phantom"] = update
    config_checks.coerce(config, schema())
    assert config["phantom"] == {
        "compare_seed000": True,
        "rig": {"thigh_length_m": 0.31, "labels": {"SYNC": "1"}},  # a label stays text
        "protocol": {"strides": 40, "springs_N_per_m": [3400, 6100]},
        "twin": {"effects": {"frame_friction": {"enabled": False, "friction_Nm": "calibrated"}}},
    }
    assert config_checks.coerce({"phantom": {"compare_seed000": "auto"}}, schema()) == {
        "phantom": {"compare_seed000": "auto"}
    }


@pytest.mark.parametrize(
    ("block", "entry", "key", "slip"),
    [
        ("phantom", {"rig": {"thigh_length_m": "299"}}, "phantom.rig.thigh_length_m",
         "299 looks 1000× too large: 299 mm typed as m? (0.299 m is within 0.05 to 2)"),
        ("phantom", {"twin": {"clutch_release_s": 150}}, "phantom.twin.clutch_release_s",
         "150 ms typed as s?"),
        ("phantom", {"twin": {"effects": {"drive_compliance": {"k_drive_N_per_m": 1e11}}}},
         "phantom.twin.effects.drive_compliance.k_drive_N_per_m", "1000× too large"),
        ("sts", {"links_mm": {"l_CD": 0.46}}, "sts.links_mm.l_CD",
         "0.46 m typed as mm? (460 mm is within 10 to 3000)"),
        ("sts", {"thigh_link": {"material": {"E_MPa": 206}}}, "sts.thigh_link.material.E_MPa",
         "206 GPa typed as MPa?"),
        ("emulator", {"transmission": {"brace_pulley_radius_m": 44}},
         "emulator.transmission.brace_pulley_radius_m", "44 mm typed as m?"),
    ],
)  # fmt: skip
def test_a_setting_1000x_off_is_refused_naming_the_key_and_the_slip(block, entry, key, slip):
    config = default_config()
    config_checks_update(config[block], entry)
    error = refusal(config)
    assert error.field == key and slip in str(error)


def config_checks_update(block: dict, entry: dict) -> None:
    for key, value in entry.items():
        if isinstance(value, dict):
            config_checks_update(block.setdefault(key, {}), value)
        else:
            block[key] = value


def test_a_value_out_of_range_but_not_1000x_off_names_no_slip():
    config = default_config()
    config["phantom"]["rig"]["thigh_length_m"] = 2.5
    error = refusal(config)
    assert "2.5 is greater than the maximum of 2" in str(error) and "looks" not in str(error)


UNIT = re.compile(r"_(m|mm|kg|kgm2|N|Nm|s|s2|Hz|V|deg|rad|rad2|MPa|K|W|A|ohm|pct|min)$")


def numeric_leaves(node, path=""):
    """(key, schema) of every number setting of the schema (oneOf branches and array items)."""
    if not isinstance(node, dict):
        return
    if node.get("type") in ("number", "integer") and path:
        yield path, node
    for key, child in node.get("properties", {}).items():
        yield from numeric_leaves(child, f"{path}.{key}".lstrip("."))
    for child in node.get("oneOf", []) + node.get("anyOf", []):
        yield from numeric_leaves(child, path)
    if isinstance(node.get("items"), dict):
        yield from numeric_leaves(node["items"], path)


def test_every_setting_with_a_physical_unit_has_a_plausible_range():
    low, high = {"minimum", "exclusiveMinimum"}, {"maximum", "exclusiveMaximum"}
    unbounded = [
        key for key, leaf in numeric_leaves(schema())
        if UNIT.search(key.split(".")[-1]) and not (low & set(leaf) and high & set(leaf))
    ]  # fmt: skip
    assert unbounded == []


def test_settings_the_run_does_not_use_are_named_with_why():
    defaults = default_config()
    config = copy.deepcopy(defaults)
    config["acquisition"] = "files"
    config["phantom"]["twin"]["flexion_sd_deg"] = 5.0
    config["phantom"]["protocol"]["strides"] = 40
    config["emulator"]["gait"]["variability"]["stride_time_cv"] = 0.05
    config["phantom"]["chain"]["filter_cutoff_Hz"] = 8.0  # used: no warning
    found = dict((tuple(keys), why) for keys, why in config_checks.not_applying(config, defaults))
    assert (
        "the phantom twin and its calibration do not run" in found[("phantom.twin.flexion_sd_deg",)]
    )
    assert "the manifest gives the trials" in found[("phantom.protocol.strides",)]
    assert "emulator twin does not run" in found[("emulator.gait.variability.stride_time_cv",)]
    assert len(found) == 3
    config["phantom"]["compare_seed000"] = True  # the calibration simulates the twin
    keys = [k for keys, _ in config_checks.not_applying(config, defaults) for k in keys]
    assert "phantom.twin.flexion_sd_deg" not in keys
    synthetic = copy.deepcopy(defaults)
    synthetic["phantom"]["rig"]["labels"] = {"SYNC": "Trigger"}
    synthetic["phantom"]["twin"]["effects"]["clutch_timing"]["delay_s"] = 0.05
    found = config_checks.not_applying(synthetic, defaults)
    assert found == [
        (["phantom.rig.labels.SYNC"], "acquisition is synthetic: the twins write the contract's "
         "own labels and columns; the map is for a lab's files and is not used"),
        (["phantom.twin.effects.clutch_timing.delay_s"],
         "phantom.twin.effects.clutch_timing.enabled is false"),
    ]  # fmt: skip
    assert config_checks.not_applying(defaults, defaults) == []


# docs/settings.md shows these; the test runs each as a dry run
DOCUMENTED = (
    "--config phantom='{compare_seed000: false, protocol: {strides: 40}}'",
    "--config emulator='{effects: {clutch_departure: {enabled: true, release_delay_s: 0.08}}}'",
)


@pytest.mark.parametrize("example", DOCUMENTED)
def test_the_documented_nested_command_line_settings_work(workflow_copy, example):
    assert example in (REPO / "docs" / "settings.md").read_text()
    arguments = shlex.split(example)
    process = snakemake(workflow_copy, "-n", *arguments, check=False)
    text = process.stdout + process.stderr
    assert process.returncode == 0, text
    assert "bad input" not in text and "warning: config" not in text


def test_a_mistyped_unit_on_the_command_line_stops_snakemake(workflow_copy):
    process = snakemake(
        workflow_copy, "-n", "--config", "phantom={rig: {thigh_length_m: 299}}", check=False
    )
    text = process.stdout + process.stderr
    assert process.returncode == 2
    assert (
        "bad input: config: field 'phantom.rig.thigh_length_m': expected what "
        "workflow/schemas/config.schema.yaml allows (299 is greater than the maximum of 2.0); "
        "299 looks 1000× too large: 299 mm typed as m? (0.299 m is within 0.05 to 2)"
    ) in text
    assert not (workflow_copy / "results").exists() or not any(
        (workflow_copy / "results").iterdir()
    )
