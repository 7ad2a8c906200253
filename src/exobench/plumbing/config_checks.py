"""Cross-field checks of the workflow config, run when the DAG is built (before any job).

The JSON schema checks each key alone; these check keys against each other (each group's own rules
live in its package's ``config_rules`` module; this one runs them and holds what they share). Every
failure is an :class:`InputError` on the file ``config`` whose field names the keys involved.
"""

from __future__ import annotations

import copy
import sys
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path

import jsonschema
import yaml

from exobench import studies
from exobench.errors import InputError

SCHEMA = "workflow/schemas/config.schema.yaml"
DEFAULTS = "config/config.yaml"

SOURCE = "config"
# A value 1000× off its plausible range is named a unit slip; the units a key's name ends with,
# with the unit a thousand times smaller and larger (as the slip would be typed).
SLIP = 1000.0
UNITS = {
    "_mm": ("mm", "µm", "m"),
    "_m": ("m", "mm", "km"),
    "_kg": ("kg", "g", "t"),
    "_kgm2": ("kg·m²", "g·m²", None),
    "_N": ("N", "mN", "kN"),
    "_Nm": ("N·m", "N·mm", "kN·m"),
    "_N_per_m": ("N/m", "N/km", "kN/m or N/mm"),
    "_Nm_per_rad": ("N·m/rad", "N·mm/rad", "kN·m/rad"),
    "_Nms_per_rad": ("N·m·s/rad", "N·mm·s/rad", "kN·m·s/rad"),
    "_Nm_per_A": ("N·m/A", "mN·m/A", None),
    "_s": ("s", "ms", "ks"),
    "_Hz": ("Hz", "mHz", "kHz"),
    "_V": ("V", "mV", "kV"),
    "_MPa": ("MPa", "kPa", "GPa"),
    "_ohm": ("Ω", "mΩ", "kΩ"),
    "_m_per_s": ("m/s", "mm/s", "km/s"),
}


def check_names(key: str, names: Mapping) -> None:
    """A map of contract names to a lab's names gives each contract name a name of its own."""
    taken = [name for name in names.values() if list(names.values()).count(name) > 1]
    if taken:
        raise InputError(SOURCE, key, "a different lab name for every contract name",
                         sorted(set(taken)))  # fmt: skip


def kept_trials(config: Mapping, group: str, trials: list[str]) -> list[str]:
    """The run's trials less those ``<group>.exclude_trials`` leaves out (each must be a trial)."""
    left_out = config[group].get("exclude_trials") or {}
    unknown = sorted(set(left_out) - set(trials))
    if unknown:
        raise InputError(SOURCE, f"{group}.exclude_trials", f"trials of the run {trials}", unknown)
    return [trial for trial in trials if trial not in left_out]


def validate(config: dict, schema: Mapping) -> dict:
    """``config`` checked against the schema (JSON Schema 2020-12), its defaults filled in place."""
    properties = jsonschema.Draft202012Validator.VALIDATORS["properties"]

    def with_defaults(validator, declared, instance, subschema):
        for name, property_schema in declared.items():
            if isinstance(instance, dict) and "default" in property_schema:
                instance.setdefault(name, copy.deepcopy(property_schema["default"]))
        yield from properties(validator, declared, instance, subschema)

    filling = jsonschema.validators.extend(
        jsonschema.Draft202012Validator, {"properties": with_defaults}
    )
    try:
        filling(schema).validate(config)
    except jsonschema.ValidationError as violation:
        refuse_schema_violation(violation)
    return config


def refuse_schema_violation(violation: jsonschema.ValidationError) -> None:
    """A schema violation as one InputError: the key, the rule broken, a likely 1000× unit slip."""
    key = ".".join(str(part) for part in violation.absolute_path) or "<top level>"
    bound = bound_violation(violation)
    message = (bound or violation).message
    slip = unit_slip(key, bound.instance, bound.schema) if bound is not None else None
    raise InputError(
        SOURCE, key, f"what {SCHEMA} allows ({message})" + (f"; {slip}" if slip else "")
    )


def bound_violation(violation):
    """The range violation (minimum, maximum) behind a violation, also inside oneOf/anyOf
    branches (a number or ``calibrated``), or None."""
    bounds = {"minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"}
    if violation.validator in bounds:
        return violation
    inner = [e for e in getattr(violation, "context", None) or [] if e.validator in bounds]
    return inner[0] if inner else None


def unit_of(key: str) -> tuple[str, str | None, str | None]:
    """The unit a dotted key's name ends with (or its block's, e.g. ``sts.links_mm.l_CD``), with
    the units a thousand times smaller and larger; ``("", None, None)`` when none is named."""
    for part in reversed(key.split(".")):
        suffix = max((s for s in UNITS if part.endswith(s)), key=len, default=None)
        if suffix is not None:
            return UNITS[suffix]
    return "", None, None


def unit_slip(key: str, value, schema: Mapping) -> str | None:
    """The unit slip that explains a value out of its plausible range: the value divided (or
    multiplied) by 1000 in range, named after the key's unit; None otherwise."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    low = schema.get("minimum", schema.get("exclusiveMinimum", float("-inf")))
    high = schema.get("maximum", schema.get("exclusiveMaximum", float("inf")))
    unit, smaller, larger = unit_of(key)
    for scaled, size, typed in ((value / SLIP, "large", smaller), (value * SLIP, "small", larger)):
        if low <= scaled <= high and not low <= value <= high:
            slip = f": {value:g} {typed} typed as {unit}?" if typed else ""
            within = f"{scaled:g} {unit}".strip() + f" is within {low:g} to {high:g}"
            return f"{value:g} looks {SLIP:g}× too {size}{slip} ({within})"
    return None


def load_schema(basedir: str | Path) -> dict:
    """The config schema of the workflow in ``basedir``."""
    return _yaml((Path(basedir) / SCHEMA).read_text(encoding="utf-8"))


def _yaml(text: str):
    """A YAML document read with libyaml's safe loader where PyYAML has it (several times
    faster than the pure-Python one, on every DAG build)."""
    return yaml.load(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))


def coerce(config: dict, schema: Mapping) -> dict:
    """Text values (``--config`` gives nested values as text: ``phantom='{x: true}'``) turned
    into the boolean or number the schema asks for where the text itself is not allowed;
    changed in place and returned."""
    for key, value in list(config.items()) if isinstance(config, dict) else []:
        config[key] = _coerced(value, _property(schema, key))
    return config


def _branches(schema: Mapping) -> list[Mapping]:
    """A schema and the schemas of its oneOf/anyOf branches."""
    return [schema, *schema.get("oneOf", []), *schema.get("anyOf", [])]


def _property(schema: Mapping | None, key: str) -> Mapping | None:
    """The schema of a mapping's entry ``key`` (properties, else additionalProperties)."""
    for branch in _branches(schema or {}):
        if key in branch.get("properties", {}):
            return branch["properties"][key]
        if isinstance(branch.get("additionalProperties"), dict):
            return branch["additionalProperties"]
    return None


def _coerced(value, schema: Mapping | None):
    """``value`` with its text leaves coerced to what ``schema`` asks for."""
    if schema is None:
        return value
    if isinstance(value, dict):
        return coerce(value, schema)
    if isinstance(value, list):
        items = next((b["items"] for b in _branches(schema) if isinstance(b.get("items"), dict)),
                     None)  # fmt: skip
        return [_coerced(item, items) for item in value]
    if not isinstance(value, str) or jsonschema.Draft202012Validator(schema).is_valid(value):
        return value
    return scalar(value)


def scalar(text: str):
    """Text read as a boolean (true/false), a whole number or a number, else left as text."""
    if text.strip().lower() in ("true", "false"):
        return text.strip().lower() == "true"
    for parse in (int, float):
        try:
            return parse(text)
        except ValueError:
            pass
    return text


def check(config: Mapping, groups: Iterable[Callable[[Mapping], None]]) -> None:
    """All cross-field checks of a schema-valid config: each group's own (``groups``: the
    ``config_rules.check`` of every group package, which name their keys)."""
    for group in groups:
        group(config)


def changed_keys(config, defaults, prefix: str = "") -> list[str]:
    """Dotted keys whose value differs from ``defaults`` (the embedded config), leaf by leaf."""
    if isinstance(config, dict) and isinstance(defaults, dict) and config:
        keys = []
        for key, value in config.items():
            keys += changed_keys(value, defaults.get(key), f"{prefix}{key}.")
        return keys
    return [] if config == defaults else [prefix.rstrip(".")]


def not_applying(config: Mapping, defaults: Mapping) -> list[tuple[list[str], str]]:
    """Settings changed from the defaults that this run does not use, grouped by why: twin
    settings when the twins do not run, a lab's label or column map when the twins write the
    recordings, a disabled effect's parameters."""
    synthetic = config["acquisition"] == "synthetic"
    choice = config["phantom"]["compare_seed000"]
    seed000 = synthetic if choice == "auto" else bool(choice)
    changed = changed_keys(config, defaults)
    rules = []
    if not synthetic and not seed000:
        rules.append((("phantom.twin.", "phantom.calibration."),
                      "acquisition is files and the run does not compare with "
                      f"{studies.PHANTOM.key}'s medians (phantom.compare_seed000), so the phantom "
                      "twin and its calibration do not run"))  # fmt: skip
    if not synthetic:
        twin_protocol = ("springs_N_per_m", "test_order_N_per_m", "strides", "ramp_strides")
        rules.append((tuple(f"phantom.protocol.{key}" for key in twin_protocol),
                      "acquisition is files: the manifest gives the trials, their spring rates "
                      "and ramp strides"))  # fmt: skip
        rules.append((("emulator.gait.", "emulator.effects.", "emulator.sensors.",
                       "emulator.protocol.speeds_m_per_s", "emulator.protocol.stiffnesses"),
                      "acquisition is files: the emulator twin does not run (the manifest gives "
                      "the trials)"))  # fmt: skip
    else:
        rules.append((("phantom.rig.labels", "emulator.columns"),
                      "acquisition is synthetic: the twins write the contract's own labels and "
                      "columns; the map is for a lab's files and is not used"))  # fmt: skip
    for group, twin_runs in (("phantom.twin", synthetic or seed000), ("emulator", synthetic)):
        effects = config[group.split(".")[0]]
        effects = effects["twin"]["effects"] if group == "phantom.twin" else effects["effects"]
        for name, entry in effects.items() if twin_runs else []:
            if not entry.get("enabled", True):
                rules.append(((f"{group}.effects.{name}.",),
                              f"{group}.effects.{name}.enabled is false"))  # fmt: skip
    found = []
    for prefixes, why in rules:
        keys = [key for key in changed if key.startswith(prefixes) and not key.endswith(".enabled")]
        if keys:
            found.append((keys, why))
    return found


def warn_not_applying(config: Mapping, basedir: str | Path) -> None:
    """One console line per reason a changed setting does not apply to this run."""
    path = Path(basedir) / DEFAULTS
    defaults = _yaml(path.read_text(encoding="utf-8")) if path.is_file() else None
    if defaults is None:
        return
    for keys, why in not_applying(config, copy.deepcopy(defaults)):
        shown = ", ".join(keys[:6]) + (f" and {len(keys) - 6} more" if len(keys) > 6 else "")
        print(f"warning: config: {shown}: not used: {why}", file=sys.stderr)
