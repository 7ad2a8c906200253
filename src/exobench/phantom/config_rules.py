"""The phantom group's cross-field config checks (run with the others when the DAG is built)."""

from __future__ import annotations

from collections.abc import Mapping

from exobench.errors import InputError
from exobench.phantom.rig import ANALOG_RATE_HZ
from exobench.plumbing.config_checks import SOURCE, check_names


def check(config: Mapping) -> None:
    """The phantom block's keys against each other, and the lab's label map."""
    check_phantom(config["phantom"])
    check_names("phantom.rig.labels", config["phantom"]["rig"].get("labels", {}))


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
