"""What the emulator analysis assumes about the rig, one row per assumption, and the ways each can
fail (docs/emulator_assumptions.md is this table in words; a test keeps the two equal and checks
it against docs/rig.md §3).

The rows follow :mod:`exobench.selection.assumptions`, as the phantom's do: the values (the
cable's calibration, the pulleys' ratio, the spring law's rate and equilibrium, the encoder's
counts per turn, the motor's constants), the laws (the Bowden cable, the cuffs, the brace's
hinge against the knee), every channel (brace encoder, motor encoder, motion capture, the
brace's torque sensor, the shared clock), the timing (the control loop, Table 6.1's engagement
and release, Table 5.1's events), what a channel's datasheet states beyond its calibration, and
what must stay the same between trials (straps re-fastened, sensors re-zeroed, the cable
re-tensioned). Some relaxations are the registry's effects (:mod:`.effects`); a row without
relaxations, and a relaxation only a direct check sees, are checked on the recordings.
"""

from __future__ import annotations

from exobench.selection import assumptions as table
from exobench.selection.assumptions import Assumption, Relaxation

# Count drops the session QC locates (emulator.analysis.drop_threshold_sd 2.5) on four 15 s
# trials of the twin, drops at random instants: 100 of 100 a size from 2.4° to 2.8° (40 of 40
# from 3° to 4°), 99 of 100 at 2.2°, 23 of 40 at 2.0°; the engine sizes only a drop the QC
# located. The lower end is also the engine's linear-screen probe and the validation's draws.
DROP_DETECTABLE_DEG = (2.5, 8.0)

# The engine's observables a row can touch (exobench.emulator.model.discrepancy.MEASURED).
OBSERVABLES = ("torque", "encoder", "energy", "desired_impulse")
ANGLES = ("encoder", "torque", "energy")  # what the knee angle's sources reach
DELIVERED = ("torque", "energy")  # what the delivered torque reaches
DESIRED = ("desired_impulse",)  # what the controller's own output reaches


def _between(key: str, what: str, parameter: str, unit: str, law: str,
             visible: tuple[float, float], varies: str, requires: tuple[str, ...] = (),
             observables: tuple[str, ...] = ANGLES,
             alike: tuple[str, ...] = ()) -> Assumption:  # fmt: skip
    """A constant of the rig that must be the same in every trial of a session (``law``: how
    trial i's value departs, z_i a standard normal draw per trial; ``varies``: the relaxation
    whose parameter changes), seen by the engine's parameter stability across trials (and by a
    direct check that cannot tell it from ``alike``: rows, or relaxations by term key)."""
    return Assumption(
        f"{key}_between", "between", f"{what}, from one trial to the next",
        f"{what} is the same in every trial of the session (set once, not re-set between "
        "trials), so one value of it holds for all trials",
        observables,
        (Relaxation("between", parameter, unit, f"{law}, z_i a standard normal draw per trial, "
                    "the same all trial long", visible, requires=requires, checked=True,
                    name=f"{what} changed between trials", varies=varies),),
        check="stability",
        alike=alike,
    )  # fmt: skip


TABLE: tuple[Assumption, ...] = (
    # The load path from the motor to the knee: motor encoder → cable → brace → cuffs → limb.
    Assumption(
        "cable",
        "law",
        "the Bowden cable between the motor's pulley and the brace's",
        "the cable delivers the torque its calibration b(τ) gives for its stretch (the motor "
        "angle − A × the brace angle, eqs. 5.6–5.7, one curve per direction of motion), with no "
        "friction, damping, slack or creep beyond the calibration",
        DELIVERED,
        (
            Relaxation(
                "coulomb",
                "friction_fraction",
                "1",
                "the delivered torque is the calibrated one × (1 + f) while the knee extends and "
                "× (1 − f) while it flexes (friction against the cable's motion, Heer §5.3)",
                (0.04, 0.15),
                signed=True,
                registry="transmission_friction",
                name="transmission friction",
            ),
            Relaxation(
                "viscous",
                "c_Nms_per_rad",
                "N·m·s/rad",
                "the cable adds −c·ω to the delivered torque while it pulls, ω the brace's "
                "angular rate (rad/s, flexion positive): a torque against the motion (a cable "
                "only pulls: the torque stays ≥ 0)",
                (0.005, 0.03),
            ),
            Relaxation(
                "drifting",
                "drift_per_s",
                "1/s",
                "the cable creeps: the delivered torque at a given stretch is the calibrated one "
                "× (1 + ρ·t), t the time since the trial's first sample",
                (0.002, 0.01),
                signed=True,
                name="cable creep over the trial",
            ),
            Relaxation(
                "play",
                "play_deg",
                "deg",
                "the cable is slack over p degrees of the brace's rotation: it pulls with the "
                "calibrated torque of a stretch that follows the recorded one through a play of "
                "A·p motor degrees (the stretch − A·p/2 while it grows, + A·p/2 while it "
                "shrinks, held in between for A·p after every reversal)",
                (0.5, 2.0),
                name="cable slack",
            ),
            Relaxation(
                "bias",
                "bias_Nm",
                "N·m",
                "the cable delivers the calibrated torque less a friction bias τ_f while it "
                "pulls, never below 0 (friction the calibration's curve does not hold, the same "
                "in either direction of motion)",
                (0.03, 0.15),
                name="cable friction bias",
            ),
        ),
        short="Bowden cable",
    ),
    Assumption(
        "cable_calibration",
        "value",
        "the cable's calibration b(τ), emulator.transmission",
        "the stretch that gives a torque τ is B·τ² + C·τ + D (motor degrees) with the "
        "calibration's B, C and D for each direction",
        DELIVERED,
        (
            Relaxation(
                "value",
                "scale",
                "1",
                "the real cable needs s × the calibration's stretch above its zero-torque offset "
                "D for the same torque (the real b(τ) = s·(B·τ² + C·τ) + D)",
                (0.03, 0.1),
                neutral=1.0,
                signed=True,
                name="cable calibration's slope off",
            ),
            Relaxation(
                "offset",
                "offset_deg",
                "deg",
                "the real cable's zero-torque stretch is D + o (motor degrees)",
                (0.3, 1.5),
                signed=True,
                name="cable calibration's zero off",
            ),
        ),
        short="cable calibration",
    ),
    Assumption(
        "pulley_ratio",
        "value",
        "the pulleys' ratio A = r_brace / r_motor",
        "A is the rig's (emulator.transmission brace_pulley_radius_m / motor_pulley_radius_m)",
        DELIVERED,
        (
            Relaxation(
                "value",
                "scale",
                "1",
                "the real ratio is s × the rig's",
                (0.01, 0.04),
                neutral=1.0,
                signed=True,
            ),
        ),
        short="pulley ratio",
    ),
    Assumption(
        "cuff",
        "law",
        "the cuffs and the soft tissue between the brace and the limb",
        "the cuffs are rigid: the brace turns with the knee, whatever the torque",
        ANGLES,
        (
            Relaxation(
                "elastic",
                "compliance_deg_per_Nm",
                "deg/(N·m)",
                "the brace lags the knee by c × the brace torque, settling with the soft "
                "tissue's time constant (first-order lag, 5–50 ms)",
                (0.3, 2.0),
                registry="cuff_compliance",
                name="cuff compliance",
            ),
            Relaxation(
                "stiffening",
                "stiffening_per_Nm",
                "1/(N·m)",
                "the cuff's deflection is c·τ / (1 + β·|τ|): the tissue stiffens under load",
                (0.3, 1.5),
                requires=("cuff.elastic",),
            ),
            Relaxation(
                "coulomb",
                "friction_Nm",
                "N·m",
                "a friction τ_s in parallel with the cuff's spring: the deflection stays while "
                "|τ − τ_elastic(δ)| ≤ τ_s, else the cuff carries τ_elastic(δ) + τ_s against "
                "its motion",
                (0.05, 0.2),
                requires=("cuff.elastic",),
                name="cuff friction (straps slipping)",
            ),
            Relaxation(
                "drifting",
                "drift_per_s",
                "1/s",
                "the straps loosen or tighten over the trial: the compliance is "
                "c·(1 + ρ·t), t the time since the trial's first sample",
                (0.005, 0.02),
                signed=True,
                requires=("cuff.elastic",),
            ),
            Relaxation(
                "play",
                "play_deg",
                "deg",
                "the brace turns freely by ±p/2 degrees in its cuffs: it stays where it is until "
                "the knee's motion takes it along at the edge of that dead band (brace − knee "
                "changes only at ±p/2)",
                (0.5, 2.0),
                name="cuff play (loose straps)",
            ),
        ),
        short="cuff",
    ),
    Assumption(
        "hinge",
        "direction",
        "the brace's hinge against the knee's own axis",
        "the brace's hinge turns about the knee's axis: with rigid cuffs the brace angle is the "
        "knee angle",
        ANGLES,
        (
            Relaxation(
                "offset",
                "offset_ratio",
                "1",
                "the hinge sits off the knee's axis by a fraction a of the cuffs' lever arm: the "
                "brace turns θ + a·sin θ (rad) when the knee turns θ",
                (0.02, 0.08),
                signed=True,
                name="hinge off the knee's axis",
            ),
        ),
        short="hinge",
    ),
    # The controller's spring (docs/rig.md §3).
    Assumption(
        "spring",
        "law",
        "the controller's emulated spring",
        "while the clutch is engaged the controller asks for τ = κ·max(0, θ_eq − θ), κ the "
        "manifest's rate and θ_eq = emulator.controller.equilibrium_deg, θ the encoder's angle, "
        "positive in flexion",
        DESIRED,
        (
            Relaxation(
                "value",
                "scale",
                "1",
                "the controller's real rate is s × the manifest's",
                (0.05, 0.2),
                neutral=1.0,
                signed=True,
                name="spring rate off the manifest's",
            ),
            Relaxation(
                "offset",
                "offset_deg",
                "deg",
                "the controller's equilibrium is θ_eq + o",
                (1.0, 4.0),
                signed=True,
                name="spring equilibrium off the config's",
            ),
            Relaxation(
                "stiffening",
                "stiffening_per_rad",
                "1/rad",
                "the controller's spring is τ = κ·x·(1 + a·x), x = max(0, θ_eq − θ) in rad",
                (0.2, 1.0),
                signed=True,
                name="spring law not linear",
            ),
        ),
        short="spring law",
    ),
    # Channels.
    Assumption(
        "encoder",
        "channel",
        "the brace's encoder, brace_angle_deg",
        "the encoder counts every increment of the brace angle at 5000 counts per turn "
        "(1250 lines, quadrature) and reports whole counts",
        ANGLES,
        (
            Relaxation(
                "step",
                "drop_deg",
                "deg",
                "the encoder loses Δ degrees of counts at one instant (a count drop): from then "
                "on it reads the brace angle − Δ",
                DROP_DETECTABLE_DEG,
                signed=True,
                registry="encoder_count_drop",
                name="encoder count drop",
            ),
            Relaxation(
                "gain",
                "gain",
                "1",
                "the encoder reads g × the brace angle (its counts per turn are not 5000)",
                (0.01, 0.04),
                neutral=1.0,
                signed=True,
            ),
            Relaxation(
                "drift",
                "drift_deg_per_s",
                "deg/s",
                "the encoder slips: it reads the brace angle − ḃ·t, t the time since the "
                "trial's first sample",
                (0.02, 0.1),
                signed=True,
            ),
        ),
        short="brace encoder",
    ),
    Assumption(
        "motor_encoder",
        "channel",
        "the motor's encoder, motor_angle_deg",
        "motor_angle_deg is the motor pulley's angle in degrees, without gain error",
        DELIVERED,
        (
            Relaxation(
                "gain",
                "gain",
                "1",
                "motor_angle_deg records g × the motor pulley's angle",
                (0.01, 0.04),
                neutral=1.0,
                signed=True,
            ),
        ),
        short="motor encoder",
    ),
    Assumption(
        "mocap",
        "channel",
        "motion capture's knee angle, knee_flexion_deg",
        "motion capture reads the knee's flexion without offset, gain error or artefact",
        ANGLES,
        (
            Relaxation(
                "offset",
                "zero_deg",
                "deg",
                "motion capture reads the knee angle + z",
                (1.0, 5.0),
                signed=True,
                registry="mocap_zero",
                name="motion-capture zero",
            ),
            Relaxation(
                "gain",
                "gain",
                "1",
                "motion capture reads g × the knee angle",
                (0.03, 0.1),
                neutral=1.0,
                signed=True,
                registry="mocap_gain",
                name="motion-capture gain",
            ),
            Relaxation(
                "harmonic",
                "amplitude_deg",
                "deg",
                "skin markers slide over the bones in step with the gait: motion capture reads "
                "the knee angle + a·sin(2π·k·φ + ψ), φ the gait phase (0 at heel strike, 1 at "
                "the next), k = 1, 2 or 3 and ψ any phase",
                (0.5, 2.0),
                signed=True,
                name="soft-tissue artefact locked to the gait",
            ),
        ),
        short="motion capture",
    ),
    Assumption(
        "torque_sensor",
        "channel",
        "the brace's torque sensor, brace_torque_Nm",
        "brace_torque_Nm is the brace torque as calibrated, without offset, gain error or drift, "
        "through the 20 Hz second-order Butterworth of the real-time model (Heer §5.2) and no "
        "other lag",
        DELIVERED,
        (
            Relaxation(
                "offset",
                "torque_offset_Nm",
                "N·m",
                "the sensor records the torque + o",
                (0.05, 0.3),
                signed=True,
                registry="torque_offset",
                name="torque-sensor offset",
            ),
            Relaxation(
                "gain",
                "gain",
                "1",
                "the sensor records g × the torque",
                (0.03, 0.1),
                neutral=1.0,
                signed=True,
            ),
            Relaxation(
                "drift",
                "drift_Nm_per_s",
                "N·m/s",
                "the sensor records the torque + ḃ·t, t the time since the trial's first sample",
                (0.002, 0.01),
                signed=True,
            ),
            Relaxation(
                "delay",
                "delay_s",
                "s",
                "the sample stamped t holds the (filtered) torque at t − d",
                (0.005, 0.02),
                name="torque-sensor lag",
            ),
        ),
        short="torque sensor",
    ),
    Assumption(
        "clocks",
        "timing",
        "the brace's and motion capture's clocks, time_s in both files",
        "the brace file and the motion-capture file share one clock, started by one trigger, and "
        "both run at their nominal rates (1000 Hz and 100 Hz)",
        ANGLES,
        (
            Relaxation(
                "delay",
                "clock_offset_s",
                "s",
                "the motion-capture frame stamped s shows the knee at s − d",
                (0.01, 0.04),
                signed=True,
                registry="mocap_clock",
                name="motion-capture clock offset",
            ),
            Relaxation(
                "drift",
                "rate_error",
                "1",
                "motion capture's clock runs (1 + ε) × the brace's: its frame stamped s (from "
                "the trial's first sample) shows the knee at s·(1 − ε)",
                (3e-4, 1.5e-3),
                signed=True,
                name="motion-capture clock rate off",
            ),
        ),
        short="clocks",
    ),
    # What the channels' datasheets state beyond their calibration.
    Assumption(
        "torque_linearity",
        "channel",
        "the torque sensor's datasheet",
        "the torque sensor is linear over its range and its noise is the datasheet's "
        "(emulator.sensors.load_cell_sd_Nm)",
        DELIVERED,
        (
            Relaxation(
                "nonlinearity",
                "quadratic_per_Nm",
                "1/(N·m)",
                "the sensor records τ·(1 + q·|τ|)",
                (0.02, 0.08),
                signed=True,
                name="torque sensor not linear",
            ),
        ),
        check="noise_levels",
        short="torque sensor's datasheet",
    ),
    Assumption(
        "encoder_resolution",
        "channel",
        "the encoder's and motion capture's datasheets",
        "the encoder reports whole counts of 0.072° and motion capture's knee angle has the "
        "datasheet's noise (emulator.sensors.mocap_sd_deg)",
        (),
        check="noise_levels",
        short="resolutions",
    ),
    # Timing of the controller (Heer Tables 5.1 and 6.1).
    Assumption(
        "loop",
        "timing",
        "the real-time control loop",
        "the controller runs at 1000 Hz: one brace sample per control step, its time stamps "
        "evenly spaced",
        (),
        check="loop_rate",
        short="control loop",
    ),
    Assumption(
        "clutch_engage",
        "timing",
        "the virtual clutch's engagement, Table 6.1",
        "the clutch engages at the peak flexion of a step once the knee has passed 40°",
        DESIRED,
        (
            Relaxation(
                "delay",
                "delay_s",
                "s",
                "the clutch engages d after the peak flexion that should engage it",
                (0.1, 0.2),
                name="clutch engaging late",
            ),
            Relaxation(
                "event",
                "loading_share",
                "1",
                "the clutch also engages at the peak flexions below 40° (the loading response's) "
                "once the knee has passed 40°, each run released as the clutch's rule releases "
                "Table 6.1's (the next peak extension, or the rule the files show): an arm that "
                "stays set once met (w = 1; the model predicts the mean step, so a lab whose "
                "peaks engage at random, w < 1, leaves each step's own residual)",
                (0.99, 1.0),
                name="clutch engaging at the loading response",
            ),
        ),
        check="table61",
        short="clutch engagement",
    ),
    Assumption(
        "clutch_release",
        "timing",
        "the virtual clutch's release, Table 6.1",
        "the clutch releases at the peak extension that follows",
        DESIRED,
        (
            Relaxation(
                "delay",
                "release_delay_s",
                "s",
                "the clutch releases d after the peak extension that should release it",
                (0.003, 0.1),
                registry="clutch_late_release",
                name="clutch releasing late",
            ),
            Relaxation(
                "event",
                "heel_strike_share",
                "1",
                "the clutch releases a share w of the way from the peak extension that should "
                "release it to the impact peak that follows (the first fall of the controller's "
                "velocity after it, Table 5.1's heel strike as its text reads; the chain's event "
                "detection takes the table's first rise, within milliseconds of the peak "
                "extension): at the impact peak for w = 1, before the peak extension for w < 0",
                (0.3, 1.0),
                signed=True,
                name="clutch releasing towards the impact peak",
            ),
            Relaxation(
                "threshold",
                "threshold_deg_per_s",
                "deg/s",
                "the clutch releases where the controller's velocity rises through −v on the way "
                "to the peak extension that should release it (ω_k−1 < −v ≤ ω_k): earlier, by "
                "the time its estimate takes to rise from −v to 0, never after the spring's end",
                (5.0, 40.0),
                name="clutch releasing at a velocity threshold",
            ),
        ),
        check="table61",
        short="clutch release",
    ),
    Assumption(
        "velocity_estimate",
        "timing",
        "the controller's velocity estimate, Heer §5.2",
        "the controller times its events on the chain's velocity: the encoder through a causal "
        "2nd-order Butterworth low-pass at emulator.controller.velocity_cutoff_Hz",
        DESIRED,
        (
            Relaxation(
                "delay",
                "lead_s",
                "s",
                "the controller's velocity runs l ahead of the chain's (as an unfiltered "
                "difference, a first-order filter or a higher cut-off runs): every event it "
                "times, the clutch's engagement and its release, falls l sooner (one that runs "
                "behind releases late: the registry's late release, the engagement unseen)",
                (0.01, 0.04),
                name="controller's velocity estimate ahead of the chain's",
            ),
        ),
        short="velocity estimate",
    ),
    Assumption(
        "gait_events",
        "timing",
        "the gait events the analysis finds, Table 5.1",
        "heel strikes found from the encoder's angle and velocity fall on the gait's own heel "
        "strikes",
        (),
        check="heel_strikes",
        short="gait events",
    ),
    Assumption(
        "motor",
        "value",
        "the motor, its gearhead and their thermal resistances, emulator.budget",
        "the motor's torque constant, resistance, efficiency and thermal resistances and the "
        "gearhead's ratio and limits are the datasheets' (Heer §4.3–4.4)",
        (),
        check="budget",
        short="motor constants",
    ),
    # What must stay the same between trials.
    _between(
        "straps",
        "the cuffs' compliance",
        "spread",
        "1",
        "the straps are re-fastened: trial i's cuff compliance is the session's × (1 + s·z_i)",
        (0.2, 0.5),
        "cuff.elastic",
        ("cuff.elastic",),
    ),
    _between(
        "mocap_zero",
        "motion capture's zero",
        "spread_deg",
        "deg",
        "motion capture is re-zeroed: trial i reads the knee angle + s·z_i",
        (1.0, 3.0),
        "mocap.offset",
        # a trial's zero is its mean offset from the encoder: an encoder that drifts over each
        # trial shifts it with the trial's length and where its drops fall
        alike=("encoder.drift",),
    ),
    _between(
        "torque_zero",
        "the torque sensor's zero",
        "spread_Nm",
        "N·m",
        "the torque sensor is re-zeroed: trial i records the torque + s·z_i",
        (0.05, 0.2),
        "torque_sensor.offset",
        observables=DELIVERED,
        # the inactive torque departs alike for a re-zeroed sensor and a re-tensioned cable, and
        # for a sensor whose lag reads each trial's speed, or whose drift each trial's length,
        # apart
        alike=("cable_tension_between", "torque_sensor.delay", "torque_sensor.drift"),
    ),
    _between(
        "cable_tension",
        "the cable's zero-torque stretch D",
        "spread_deg",
        "deg",
        "the cable is re-tensioned: trial i's zero-torque stretch is D + s·z_i (motor degrees)",
        (0.3, 1.0),
        "cable_calibration.offset",
        observables=DELIVERED,
        alike=("torque_zero_between",),
    ),
)


def relaxations() -> dict[str, tuple[Assumption, Relaxation]]:
    """Every relaxation of the emulator's table by its term key (``row.family``)."""
    return table.relaxations(TABLE)


def registry_terms() -> dict[str, str]:
    """The registry effect each relaxation is, by term key (registry relaxations only)."""
    return table.registry_terms(TABLE)


def markdown() -> str:
    """The table in words (docs/emulator_assumptions.md)."""
    return table.markdown(
        TABLE,
        "What the emulator analysis assumes, and how each assumption can fail",
        "exobench.emulator.model.assumptions",
        "docs/rig.md §3, Heer and the analysis",
    )
