"""Cross-field checks of the workflow config, run when the DAG is built (before any job).

The JSON schema checks each key alone; these check keys against each other. Every failure is
an :class:`InputError` on the file ``config`` whose field names the keys involved.
"""

from __future__ import annotations

from collections.abc import Mapping

from exobench.emulator import gait
from exobench.errors import InputError
from exobench.phantom.rig import ANALOG_RATE_HZ
from exobench.sts import motion

SCHEMA = "workflow/schemas/config.schema.yaml"

SOURCE = "config"


def check_phantom(block: Mapping) -> None:
    """Phantom protocol: test order a permutation of the springs, strides > 2 × ramp (recordings
    and calibration), windows."""
    protocol = block["protocol"]
    springs, order = list(protocol["springs_N_per_m"]), list(protocol["test_order_N_per_m"])
    if len(set(springs)) != len(springs) or sorted(order) != sorted(springs):
        raise InputError(
            SOURCE,
            "phantom.protocol.test_order_N_per_m, phantom.protocol.springs_N_per_m",
            f"test order a permutation of the springs {springs}",
            order,
        )
    for key in ("protocol", "calibration"):
        strides, ramps = int(block[key]["strides"]), int(block[key]["ramp_strides"])
        if strides <= 2 * ramps:
            raise InputError(
                SOURCE,
                f"phantom.{key}.strides, phantom.{key}.ramp_strides",
                f"strides > 2 × ramp_strides = {2 * ramps} (ramp strides are dropped at both ends)",
                strides,
            )
    on, off = float(protocol["clutch_on_pct"]), float(protocol["clutch_off_pct"])
    samples = float(protocol["stride_time_s"]) * ANALOG_RATE_HZ
    if not 0.0 <= on < off <= 100.0 or (off - on) / 100.0 * samples < 3.0:
        raise InputError(
            SOURCE,
            "phantom.protocol.clutch_on_pct, phantom.protocol.clutch_off_pct",
            "0 ≤ clutch_on_pct < clutch_off_pct ≤ 100 (% of the stride), at least 3 samples "
            "apart (the stiffness is a slope over the window)",
            [on, off],
        )
    window, stride = float(protocol["work_window_s"]), float(protocol["stride_time_s"])
    if not 0.0 < window <= stride:
        raise InputError(
            SOURCE,
            "phantom.protocol.work_window_s, phantom.protocol.stride_time_s",
            f"a work window inside the stride: 0 < work_window_s ≤ {stride:g} s",
            window,
        )
    low, high = (float(v) for v in block["discrepancy"]["window_pct"])
    if not on <= low < high <= off:
        raise InputError(
            SOURCE,
            "phantom.discrepancy.window_pct, phantom.protocol.clutch_on_pct/clutch_off_pct",
            f"an engaged window inside the clutch window [{on:g}, {off:g}] %",
            [low, high],
        )


def check_names(key: str, names: Mapping) -> None:
    """A map of contract names to a lab's names gives each contract name a name of its own."""
    taken = [name for name in names.values() if list(names.values()).count(name) > 1]
    if taken:
        raise InputError(SOURCE, key, "a different lab name for every contract name",
                         sorted(set(taken)))  # fmt: skip


def check_emulator(block: Mapping, synthetic: bool) -> None:
    """Emulator protocol: a gait shape for every speed the twin simulates."""
    if not synthetic:
        return
    for speed in block["protocol"]["speeds_m_per_s"]:
        try:
            gait.shape_for(block["gait"]["shapes"], float(speed))
        except KeyError:
            raise InputError(
                SOURCE,
                "emulator.protocol.speeds_m_per_s, emulator.gait.shapes",
                "a gait shape for every speed of the protocol",
                speed,
            ) from None


def refuse_schema_violation(error: BaseException) -> None:
    """Raise a schema violation as one InputError naming the key and the rule it breaks.

    Snakemake's own message prints the whole schema after the violation; an error without a
    schema violation behind it is raised as it is.
    """
    violation = error.__context__
    if not (hasattr(violation, "absolute_path") and hasattr(violation, "message")):
        raise error
    key = ".".join(str(part) for part in violation.absolute_path) or "<top level>"
    raise InputError(SOURCE, key, f"what {SCHEMA} allows ({violation.message})")


def check_sts(block: Mapping) -> None:
    """Sit-to-stand: a sample rate whose time grid holds the stage change (its own check)."""
    motion.time_grid(float(block["sample_rate_Hz"]))


def check(config: Mapping) -> None:
    """All cross-field checks of a schema-valid config."""
    check_phantom(config["phantom"])
    check_names("phantom.rig.labels", config["phantom"]["rig"].get("labels", {}))
    check_emulator(config["emulator"], config["acquisition"] == "synthetic")
    check_names("emulator.columns", config["emulator"].get("columns", {}))
    check_sts(config["sts"])
