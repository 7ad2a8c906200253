"""What the phantom analysis assumes about the rig, one row per assumption, and the terms that
relax each (docs/assumptions.md is this table in words; a test keeps the two equal).

The rows, relaxations and families follow :mod:`exobench.selection.assumptions`: the law
families applied to every element (elastic, stiffening, viscous, Coulomb, drifting over the
trial), the fault families applied to every channel (gain, offset, drift, delay, a share of
another channel), a deviation of every value and direction. The engine's term library is
generated from these relaxations (:mod:`exobench.phantom.model.terms`); some of them are the
registry's effects, the physics the study itself names. A row without relaxations is checked
directly on the recordings (:mod:`exobench.phantom.model.checks`).
"""

from __future__ import annotations

from exobench.selection import assumptions as table
from exobench.selection.assumptions import Assumption, Relaxation

# The engine's observables a row can touch (exobench.phantom.model.discrepancy.MEASURED).
OBSERVABLES = ("moment", "exo", "spring", "force", "swing", "swing_force")


MOMENTS = ("moment", "swing")
CHAIN = ("moment", "exo", "spring", "force")


def _drifting(element: str, *requires: str, name: str = "",
              visible: tuple[float, float] = (0.004, 0.015)) -> Relaxation:  # fmt: skip
    """A stiffness that changes linearly over the trial (a stiff element's must change more to
    show)."""
    return Relaxation(
        "drifting", "drift_per_s", "1/s",
        f"the {element}'s stiffness changes linearly over the trial: k(t) = k·(1 + ρ·t), t the "
        "time since the trial's first sample",
        visible, signed=True, requires=requires,
        name=name,
    )  # fmt: skip


def _cell(channel: str, what: str, share_of: str) -> Assumption:
    """An analog channel read as calibrated, on the marker clock, alone."""
    observables = ("force", "swing_force") if channel == "LC_SPRING" else MOMENTS
    spring = channel == "LC_SPRING"
    return Assumption(
        channel, "channel", f"load cell {channel}",
        f"{channel} reads {what} in N as calibrated: no gain error, no offset, no drift, on the "
        "markers' clock, and nothing of another channel",
        observables,
        (
            Relaxation("gain", "gain", "1", f"{channel} records g × its true force", (0.04, 0.12),
                       neutral=1.0, signed=True,
                       registry="load_cell_gain" if spring else None),
            Relaxation("offset", "offset_N", "N", f"{channel} records its true force + o",
                       (2.0, 10.0), signed=True, registry="load_cell_offset" if spring else None),
            Relaxation("drift", "drift_N_per_s", "N/s",
                       f"{channel} records its true force + ḃ·t, t the time since the trial's "
                       "first sample", (0.08, 0.3), signed=True),
            Relaxation("delay", "delay_s", "s",
                       f"{channel}'s sample stamped t holds its true force at t − d (this "
                       "channel alone lags)", (0.008, 0.03)),
            Relaxation("crosstalk", "share", "1",
                       f"{channel} records its true force + s × {share_of}", (0.03, 0.1),
                       signed=True, name=f"{channel} crosstalk from {share_of}"),
        ),
    )  # fmt: skip


def _segment_value(segment: str, quantity: str, what: str, short: str,
                   visible: tuple[float, float] = (0.15, 0.4)) -> Assumption:  # fmt: skip
    """A segment's mass, centre of mass or inertia as the rig states it (an inertia shows
    faintly in a 2 s stride: its visible sizes are larger)."""
    key = f"{segment}_{quantity}"
    return Assumption(
        key, "value", f"the {segment}'s {what}",
        f"the {segment} (phantom with the strapped exoskeleton part) has the rig's {what} "
        f"(phantom.rig.{key}_…)",
        MOMENTS,
        (Relaxation("value", "scale", "1",
                    f"the real {what} is s × the rig's (the inverse dynamics uses the rig's)",
                    visible, neutral=1.0, signed=True),),
        short=f"{segment} {short}",
    )  # fmt: skip


TABLE: tuple[Assumption, ...] = (
    # The load path from the limb to the spring: interface → bars and frame → chain → spring.
    Assumption(
        "interface",
        "law",
        "soft tissue and straps between the phantom and the bars",
        "the bars follow the phantom's segments: the interface is rigid, lossless and the same "
        "all trial",
        CHAIN,
        (
            Relaxation(
                "elastic",
                "k_interface_Nm_per_rad",
                "N·m/rad",
                "the interface deflects δ = M/k between the phantom's and the bars' knee angles",
                (40.0, 150.0),
                neutral=float("inf"),
                registry="interface_compliance",
            ),
            Relaxation(
                "stiffening",
                "stiffening_per_rad2",
                "1/rad²",
                "the interface's moment is M = k·(δ + β·δ³)",
                (100.0, 800.0),
                registry="interface_stiffening",
                requires=("interface.elastic",),
            ),
            Relaxation(
                "viscous",
                "c_interface_Nms_per_rad",
                "N·m·s/rad",
                "the interface's moment is M = k·δ + c·δ̇ (Kelvin–Voigt)",
                (0.3, 1.5),
                registry="interface_damping",
                requires=("interface.elastic",),
            ),
            Relaxation(
                "coulomb",
                "friction_Nm",
                "N·m",
                "a friction moment τ in parallel with the interface's spring: δ sticks "
                "while |M − k·δ| ≤ τ, else M = k·δ + τ·sign(δ̇)",
                (0.15, 0.6),
                requires=("interface.elastic",),
            ),
            _drifting("interface", "interface.elastic"),
            Relaxation(
                "play",
                "play_rad",
                "rad",
                "the bars turn freely by ±p/2 about the phantom's segments before the straps "
                "carry a moment: a dead band of width p in δ about the last loaded position",
                (0.01, 0.04),
                name="interface play (strap slack)",
            ),
        ),
    ),
    Assumption(
        "frame",
        "law",
        "bars, chain and clutch between the bars and the spring",
        "the bars, chain and clutch are rigid: the spring side turns with the bars",
        CHAIN,
        (
            Relaxation(
                "elastic",
                "k_frame_Nm_per_rad",
                "N·m/rad",
                "the frame deflects ε = M/k between the bars' knee angle and the spring side",
                (300.0, 2500.0),
                neutral=float("inf"),
                registry="frame_compliance",
            ),
            Relaxation(
                "stiffening",
                "stiffening_per_rad2",
                "1/rad²",
                "the frame's moment is M = k·(ε + β·ε³)",
                (3e3, 3e4),
                requires=("frame.elastic",),
            ),
            Relaxation(
                "viscous",
                "c_frame_Nms_per_rad",
                "N·m·s/rad",
                "the frame's moment is M = k·ε + c·ε̇ (Kelvin–Voigt)",
                (15.0, 60.0),
                requires=("frame.elastic",),
            ),
            _drifting("frame", "frame.elastic", visible=(0.01, 0.018)),
        ),
    ),
    Assumption(
        "spring",
        "law",
        "the extension spring on the thigh bar",
        "the spring is linear at the manifest's rate, lossless and keeps its rate all trial: "
        "F = F₀ + k·x, x its stretch",
        CHAIN,
        (
            Relaxation(
                "value",
                "scale",
                "1",
                "the spring's real rate is s × the manifest's",
                (0.1, 0.35),
                neutral=1.0,
                signed=True,
                name="spring rate off the manifest's",
            ),
            Relaxation(
                "stiffening",
                "quadratic_per_m",
                "1/m",
                "the spring's force is F = F₀ + k·x·(1 + a·x)",
                (5.0, 20.0),
            ),
            Relaxation(
                "viscous",
                "c_spring_Ns_per_m",
                "N·s/m",
                "the spring's force is F = F₀ + k·x + c·ẋ while taut",
                (40.0, 120.0),
            ),
            Relaxation(
                "coulomb",
                "friction_Nm",
                "N·m",
                "a knee-equivalent friction moment τ on the spring side (chain and "
                "clutch): the spring side sticks while |M − M_s| ≤ τ, M_s the spring "
                "side's elastic moment",
                (0.1, 0.8),
                registry="frame_friction",
                name="spring-side friction (chain and clutch)",
            ),
            _drifting("spring", name="spring rate drift over the trial"),
        ),
    ),
    Assumption(
        "transmission",
        "law",
        "chain and pulley",
        "the chain is taut: from the engagement on, every knee rotation reaches the spring",
        ("moment", "spring", "force"),
        (
            Relaxation(
                "play",
                "play_rad",
                "rad",
                "the spring side starts to turn only after the knee has turned by the play "
                "p since the engagement",
                (0.01, 0.05),
                registry="transmission_play",
            ),
        ),
    ),
    Assumption(
        "clutch",
        "timing",
        "the clutch that engages the spring",
        "the clutch locks at the programmed instant (phantom.protocol.clutch_on_pct)",
        CHAIN,
        (
            Relaxation(
                "delay",
                "delay_s",
                "s",
                "the clutch locks d after the programmed instant",
                (0.015, 0.06),
                registry="clutch_timing",
                name="late clutch",
            ),
        ),
    ),
    Assumption(
        "pulley_radius",
        "value",
        "the spring pulley's radius r",
        "the pulley's radius is the rig's (phantom.rig.pulley_radius_m)",
        CHAIN,
        (
            Relaxation(
                "value",
                "scale",
                "1",
                "the real radius is s × the rig's",
                (0.06, 0.15),
                neutral=1.0,
                signed=True,
            ),
        ),
        short="pulley radius",
    ),
    Assumption(
        "chain_ratio",
        "value",
        "the chain ratio T/t",
        "the chain ratio is the rig's (phantom.rig.chain_ratio)",
        CHAIN,
        (
            Relaxation(
                "value",
                "scale",
                "1",
                "the real ratio is s × the rig's",
                (0.06, 0.15),
                neutral=1.0,
                signed=True,
            ),
        ),
        short="chain ratio",
    ),
    Assumption(
        "tensioner",
        "value",
        "the chain tensioner",
        "the tensioner's stiffness is the rig's (phantom.rig.tensioner_stiffness_Nm_per_rad)",
        CHAIN,
        (
            Relaxation(
                "value",
                "scale",
                "1",
                "the real stiffness is s × the rig's",
                (4.0, 15.0),
                neutral=1.0,
            ),
        ),
        short="tensioner stiffness",
    ),
    # The phantom: hinges, segments, the hexapod's path.
    Assumption(
        "knee",
        "law",
        "the phantom's own knee joint",
        "the phantom's knee is a frictionless, unsprung hinge: the exoskeleton carries the "
        "whole knee moment the inverse dynamics gives",
        MOMENTS,
        (
            Relaxation(
                "elastic",
                "k_Nm_per_rad",
                "N·m/rad",
                "the phantom's knee itself carries an extensor moment k·θ (θ its flexion)",
                (0.3, 1.5),
                name="phantom knee stiffness",
            ),
            Relaxation(
                "viscous",
                "c_Nms_per_rad",
                "N·m·s/rad",
                "the phantom's knee itself carries c·θ̇ (extensor while flexing)",
                (0.03, 0.15),
            ),
            Relaxation(
                "coulomb",
                "friction_Nm",
                "N·m",
                "the phantom's knee itself carries τ·sign(θ̇) (extensor while flexing)",
                (0.08, 0.3),
            ),
        ),
        short="phantom knee",
    ),
    Assumption(
        "hip",
        "law",
        "the phantom's hip joint",
        "the hip is a fixed, frictionless hinge: with it, the planar equations give the "
        "horizontal ankle force the load cells do not measure",
        MOMENTS,
        (
            Relaxation(
                "viscous",
                "c_Nms_per_rad",
                "N·m·s/rad",
                "the hip carries a moment c·φ̇ on the thigh against its rotation φ (from "
                "the vertical)",
                (0.1, 0.5),
            ),
            Relaxation(
                "coulomb",
                "friction_Nm",
                "N·m",
                "the hip carries a moment τ·sign(φ̇) on the thigh against its rotation",
                (0.15, 0.6),
            ),
            Relaxation(
                "elastic",
                "k_Nm_per_rad",
                "N·m/rad",
                "the hip carries a moment −k·φ on the thigh, φ its rotation from the vertical",
                (1.0, 5.0),
                name="phantom hip stiffness",
            ),
        ),
        short="phantom hip",
    ),
    _segment_value("thigh", "mass", "mass", "mass"),
    _segment_value("thigh", "com", "centre-of-mass distance from the hip", "centre of mass"),
    _segment_value("thigh", "inertia", "inertia about its centre of mass", "inertia", (0.4, 0.8)),
    _segment_value("shank", "mass", "mass", "mass"),
    _segment_value("shank", "com", "centre-of-mass distance from the knee", "centre of mass"),
    _segment_value("shank", "inertia", "inertia about its centre of mass", "inertia", (0.4, 0.8)),
    Assumption(
        "bars",
        "direction",
        "the exoskeleton's bars",
        "with nothing deflecting, each bar is parallel to its segment, so the exoskeleton's knee "
        "angle equals the phantom's",
        ("exo",),
        (
            Relaxation(
                "offset",
                "angle_rad",
                "rad",
                "the thigh bar is mounted turned by a (anterior) from its segment's axis, so "
                "the exoskeleton's knee angle reads the phantom's + a",
                (0.03, 0.1),
                signed=True,
                checked=True,
                name="thigh bar mounting angle",
            ),
        ),
        check="bars_parallel",
        short="thigh bar",
    ),
    Assumption(
        "segment_lengths",
        "value",
        "hip to knee and knee to ankle",
        "hip to knee and knee to ankle measure the rig's lengths (phantom.rig.thigh_length_m, "
        "shank_length_m)",
        ("moment", "swing"),
        (
            Relaxation(
                "value",
                "scale",
                "1",
                "the real thigh and shank are both s × the rig's lengths (their centres of "
                "mass stay at the rig's distances from the hip and the knee)",
                (0.04, 0.12),
                neutral=1.0,
                signed=True,
                checked=True,
                name="segment lengths off the rig's",
            ),
        ),
        check="segment_lengths",
    ),
    Assumption(
        "ankle_path",
        "direction",
        "the hexapod's path",
        "the hexapod moves the ankle straight up and down, directly below the hip, in the "
        "sagittal plane",
        ("moment", "swing"),
        (
            Relaxation(
                "offset",
                "offset_mm",
                "mm",
                "the ankle moves up and down along a vertical line o anterior of the hip's",
                (15.0, 50.0),
                signed=True,
                checked=True,
                name="ankle path off the hip's vertical",
            ),
        ),
        check="ankle_path",
    ),
    Assumption(
        "cell_direction",
        "direction",
        "the ankle load cells' axis",
        "the ankle load cells measure the vertical force",
        MOMENTS,
        (
            Relaxation(
                "tilt",
                "tilt_rad",
                "rad",
                "the cells measure along an axis tilted α anterior of vertical: they record "
                "their shares of F_y·cos α + F_x·sin α, F_x the hexapod's horizontal force on "
                "the ankle (anterior +)",
                (0.04, 0.12),
                signed=True,
            ),
        ),
        short="ankle load cells' axis",
    ),
    Assumption(
        "knee_markers",
        "direction",
        "the knee markers",
        "the knee markers sit on the joint's axis: their midpoint is the knee's centre",
        CHAIN,
        (
            Relaxation(
                "offset",
                "offset_mm",
                "mm",
                "the knee markers sit o anterior of the joint's axis (on the thigh)",
                (10.0, 30.0),
                signed=True,
                registry="knee_marker_offset",
                name="knee-marker offset",
            ),
        ),
        check="knee_axis",
    ),
    # Channels.
    *(
        _cell(f"LC_ANKLE_{i}", "its share of the vertical ankle force", "LC_SPRING's force")
        for i in (1, 2, 3)
    ),
    _cell("LC_SPRING", "the spring's tension", "the vertical ankle force"),
    Assumption(
        "clocks",
        "timing",
        "the analog and marker clocks",
        "the analog channels and the markers share one clock",
        (*CHAIN, "swing"),
        (
            Relaxation(
                "delay",
                "analog_delay_s",
                "s",
                "every analog channel's sample stamped t holds its value at t − d (SYNC included)",
                (0.01, 0.04),
                signed=True,
                registry="clock_offset",
                name="analog clock lag",
            ),
            Relaxation(
                "drift",
                "rate_error",
                "1",
                "the analog clock runs (1 + ε) × the markers': the analog sample stamped t holds "
                "its value at t·(1 − ε), t the time since the trial's first sample",
                (5e-5, 2e-4),
                signed=True,
                name="analog clock rate off",
            ),
        ),
        short="analog clock",
    ),
    # What the channels' datasheets state beyond their calibration.
    Assumption(
        "cell_linearity",
        "channel",
        "the load cells' datasheets",
        "every load cell is linear over its range, and the cells' and markers' noise is what "
        "their datasheets state",
        (*MOMENTS, "force", "swing_force"),
        (
            Relaxation(
                "nonlinearity",
                "quadratic_per_kN",
                "1/kN",
                "every load cell records F·(1 + q·|F|), F its true force in kN",
                (0.1, 0.5),
                signed=True,
                name="load cells not linear",
            ),
        ),
        check="noise_levels",
        short="load cells' datasheets",
    ),
    Assumption(
        "channels_apart",
        "channel",
        "the channels' independence",
        "with the clutch open LC_SPRING holds the pretension whatever the ankle does, and the "
        "three ankle cells keep fixed shares of one force",
        (),
        check="channels_apart",
        short="channels",
    ),
    # What must stay the same from one trial (spring) to the next.
    Assumption(
        "straps_between",
        "between",
        "the straps, from one trial to the next",
        "the straps are fastened the same way in every trial, so one interface stiffness holds "
        "for all springs",
        CHAIN,
        (
            Relaxation(
                "between",
                "spread",
                "1",
                "the straps are re-fastened: trial i's interface stiffness is the session's "
                "× (1 + s·z_i), z_i a standard normal draw per trial, the same all trial long",
                (0.1, 0.3),
                requires=("interface.elastic",),
                checked=True,
                name="interface stiffness changed between trials",
                varies="interface.elastic",
            ),
        ),
        check="stability",
        short="straps between trials",
    ),
    Assumption(
        "cells_zero_between",
        "between",
        "LC_SPRING's zero, from one trial to the next",
        "the load cells are zeroed once for the session, so LC_SPRING's offset is the same in "
        "every trial",
        ("force", "swing_force"),
        (
            Relaxation(
                "between",
                "spread_N",
                "N",
                "LC_SPRING is re-zeroed: trial i records its true force + s·z_i (N), z_i a "
                "standard normal draw per trial, the same all trial long",
                (1.0, 4.0),
                checked=True,
                name="LC_SPRING's zero changed between trials",
                varies="LC_SPRING.offset",
            ),
        ),
        check="stability",
        short="LC_SPRING zero between trials",
    ),
    Assumption(
        "clutch_open",
        "law",
        "the exoskeleton with its clutch open",
        "with the clutch open the exoskeleton carries no load, so the net knee moment the "
        "inverse dynamics gives is zero (whatever departs from zero there is the phantom's own "
        "knee, its hip, a segment value or an ankle cell)",
        ("swing",),
        check="swing_moment",
        short="clutch open",
    ),
)


def relaxations() -> dict[str, tuple[Assumption, Relaxation]]:
    """Every relaxation of the phantom's table by its term key (``row.family``)."""
    return table.relaxations(TABLE)


def registry_terms() -> dict[str, str]:
    """The registry effect each relaxation is, by term key (registry relaxations only)."""
    return table.registry_terms(TABLE)


def markdown() -> str:
    """The table in words (docs/assumptions.md)."""
    return table.markdown(
        TABLE,
        "What the phantom analysis assumes, and how each assumption can fail",
        "exobench.phantom.model.assumptions",
        "docs/rig.md and the analysis",
    )
