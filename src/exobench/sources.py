"""Where a run's data come from, in the words every summary opens with: the digital twin and the
settings it simulated, or the lab's manifest. Light (no scientific imports): the workflow's
common rules use it while the DAG is built."""

from __future__ import annotations

from collections.abc import Mapping

# The settings file a run starts from; --configfile and --config may change any key on top.
CONFIG_FILE = "config/config.yaml"


def kind(source: Mapping) -> str:
    """The source in a few words, for a title: the twin's simulated recordings, the lab's, or
    (a model-only group) the model."""
    if source["acquisition"] == "model":
        return "the model only"
    if source["acquisition"] == "synthetic":
        return f"simulated recordings of the {source['group']}'s digital twin"
    return f"the lab's recordings in {source['manifest']}"


def source_line(source: Mapping) -> str:
    """The first line of a summary: the twin with its settings (and calibration), or the lab's
    manifest. ``source``: acquisition ('synthetic' or 'files'), group ('phantom' or 'emulator'),
    twin_blocks (the config keys the twin simulated), manifest (location-independent name),
    calibration (relative to the summary, or None), engine (the engine's report, relative); a
    model-only group ('model') gives the study's laws it runs (laws), its config blocks (blocks)
    and the tables beside the summary (tables)."""
    settings = (f"the run's config ({CONFIG_FILE} with any --configfile or --config on top; its "
                "sha256 is in the provenance file beside this one)")  # fmt: skip
    if source["acquisition"] == "model":
        blocks = " and ".join(f"`{b}`" for b in source["blocks"])
        return (
            "**Source: the model only.** No recordings: every number follows from the study's "
            f"{source['laws']} and from the settings {blocks} of {settings}; the tables beside "
            f"this file ({', '.join(source['tables'])}) hold them."
        )
    engine = f"the engine's estimates are in [{source['engine']}]({source['engine']})"
    return _kind_line(source, settings, engine) + left_out(source)


def left_out(source: Mapping) -> str:
    """The trials the config left out of the analysis, each with its reason ('' for none)."""
    excluded = source.get("excluded") or {}
    if not excluded:
        return ""
    named = "; ".join(f"`{trial}` ({reason})" for trial, reason in sorted(excluded.items()))
    key = f"{source['group']}.exclude_trials"
    return f" Left out of the analysis by `{key}`: {named}; nothing here includes them."


def _kind_line(source: Mapping, settings: str, engine: str) -> str:
    """The twin's or the lab's source sentence."""
    if source["acquisition"] == "synthetic":
        blocks = " and ".join(f"`{b}`" for b in source["twin_blocks"])
        calibration = source.get("calibration")
        fitted = f" and the calibration [{calibration}]({calibration})" if calibration else ""
        return (
            f"**Source: simulated recordings.** The {source['group']}'s digital twin wrote them "
            f"(`acquisition: synthetic`) from the settings {blocks} of {settings}{fitted}; "
            f"{engine}. A value recovered here is the twin's own setting found again: a check "
            "of the method, not a physical finding about a real rig."
        )
    return (
        f"**Source: the lab's recordings** listed in the manifest `{source['manifest']}` "
        f"(`acquisition: files`), analysed with the settings of {settings}; {engine}."
    )
