"""Independent recording generator for the knee exoskeleton emulator (docs/rig.md §3).

It imports nothing from exobench beyond itself (a test keeps it so): the engine's validation needs
recordings whose rig, controller and channels share no code with the twin or the analysis. Its
modules by what they write: :mod:`.rig` (the nominal rig and the violations), :mod:`.reading` (a
lab's reading of the thesis), :mod:`.gait` (the walker's knee), :mod:`.controller` (the 1 kHz
controller in closed loop with the rig: desired torque and motor angle), :mod:`.cable` (the Bowden
cable's torque), :mod:`.cuffs` (the brace against the knee), :mod:`.sensors` (encoder, torque
sensor, motion capture), :mod:`.files` (the CSVs, manifest and truth), :mod:`.study` (trials).

Written from the rig contract, docs/emulator_assumptions.md's one-line laws, Heer's thesis
(Tables 5.1 and 6.1, eqs. 5.3–5.8, §5.2's filters) and the physics:

- Gait: the knee walks through per-stride landmarks (heel strike near full extension, a loading
  peak, the stance minimum, toe-off, a swing peak of 55–65°, peak extension before the next heel
  strike), a C² spline through them; each stride's time and amplitude vary (2 %, 3 %) and each
  landmark by 0.7°. The knee is the walker's: the brace's torque does not change it.
- Brace: its hinge turns θ + a·sin θ; the cuffs deflect it δ towards c(t)·τ'/(1 + β|τ'|) with
  the tissue's time constant T (first order), c(t) = c·(1 + ρt), τ' = τ ∓ τ_s while the straps
  slip (|τ − τ_el(δ)| > τ_s, else δ sticks); their play p: a dead band of ±p/2 about
  θ + a·sin θ + δ, the brace staying where it was until the knee's motion takes it along at an
  edge, whatever the torque. τ is the delivered torque of the step before (flexion +: the brace
  turns further into flexion).
- Controller (every 1 ms, from the encoder's reading θ_e): ω, the 6 Hz second-order Butterworth
  of (θ_e,i − θ_e,i−1)·1 kHz; Table 5.1's knee events (peak flexion beyond 40°: ω_i−1 ≥ 0 > ω_i;
  then peak extension below 20°: ω_i−1 ≤ 0 < ω_i; then heel strike at the first ω_i < ω_i−1),
  reported, acting on nothing; Table 6.1: engage when θ_e > 40°, ω_i−1 > 0 and ω_i ≤ 0, release
  when ω_i−1 < −v and ω_i ≥ −v (v = 0, or clutch_release.threshold's), either taking effect d
  later (a release before a late engagement cancels it); with velocity_estimate.delay's lead l,
  the events and the clutch's rule read ω_i+m, m = round(l·1 kHz), as the loop's last run left
  it, run again until its runs repeat (l < 0: ω_i−|m|, a lag); with a loading share w, each peak
  flexion at or below 40° once θ_e has passed 40° engages too with probability w (one uniform a
  peak, from the trial's drawn seed);
  τ_des = κ·x·(1 + a·x), x = max(0, θ_eq − θ_e) in rad, while engaged, else 0; the motor set
  point A·θ_e + b(τ_des) through the nominal calibration blended by ω (eq. 5.8); the motor's
  reading follows its set point as a first-order lag of 2 ms; the pulley turns the
  reading / g.
- Cable: stretch θ_m − A'·θ_b (motor degrees, A' the real ratio); its slack a backlash of width
  A'·p: it pulls at y, the stretch − A'·p/2 while the stretch grows, + A'·p/2 while it shrinks,
  held between (starting taken up); τ = b'⁻¹(y) on the real calibration
  b'(τ) = s·(B·τ² + C·τ) + D + o + the trial's re-tensioning, per direction of the brace's true
  motion blended as eq. 5.8; 0 while slack; × (1 + f) while the brace extends, × (1 − f) while
  it flexes, × (1 + ρt), − c·ω_b (the brace's rate in rad/s, flexion +) while it pulls; never
  below 0 (a cable only pulls).
- Channels: the encoder's whole counts (0.072°) of g·θ_b − ḃt − Δ after the drop's instant;
  brace_torque_Nm = the causal 20 Hz second-order Butterworth of g·τ(1 + q|τ|), read d late,
  + o + ḃt + the trial's zero, + white noise (load_cell_sd_Nm, on the recorded samples);
  motor_angle_deg the motor's reading; desired_torque_Nm the controller's τ_des; motion capture
  at 100 Hz: z + g·θ(s') + a·sin(2πkφ(s') + ψ) (a of either sign) + the trial's zero + white
  noise (mocap_sd_deg), s' = s·(1 − ε) − d, s the frame's stamp from the trial's first sample,
  φ the gait phase.
- Time: t since the trial's first sample; the loop runs WARMUP_S before it (drifts and drops
  start at t = 0). Between trials: z_i ~ N(0, 1) truncated at ±3 per trial and key (a compliance
  below zero is held at zero: rigid cuffs).

Readings (:class:`.Reading`, reading=; None or NOMINAL is the above, byte for byte): a lab's own
reading of the thesis, axis by axis. Release at ω_i−1 < −v_th ≤ ω_i (v_th = 0: Table 6.1; added
to clutch_release.threshold's v) or at Table 5.1's heel strike, d_r later (added to
clutch_release.delay's d); engage as Table 6.1 or latched (θ_e > 40° once met stays met:
ω_i−1 > 0 ≥ ω_i engages at any angle, so at each stride's swing peak and its loading peak). ω: a
Butterworth of order 1 or 2 at the lab's cut-off, or the unfiltered centred difference
(θ_e,i − θ_e,i−2k)/(2k·h), k = 5, about sample i − k. The motor's lag T_m; τ = max(0, τ' − τ_f)
while the cable pulls, τ' the cable's torque above (a friction bias).

The lab's calibration (B, C, D) per direction is its controller's and its real cable's, for the
session or redone per trial (each trial's within B ± 5 %, C ± 2 %, D ± 0.25° of the session's);
its encoder counts 360°/N; its torque filter at its own cut-off, or none; its noise levels (unless
torque_noise_Nm or mocap_noise_deg is given); its motion capture re-zeroed per trial: + z_i,
z_i ~ U(−2.5°, 2.5°). Reading.lab_config() is what the lab states (calibration, filters and noise
under the emulator config block's keys, its rules in words under "lab"); draw_reading(rng) keeps
each axis at NOMINAL's value with probability 1/3, else draws a variant.

Truth (per trial, written as truth/<trial>.json): the trial, speed, stiffness, side, duration,
seed, noise levels, the violations, what was drawn for them ("drawn": the count drop's instant,
T, k and ψ, each between-trial z_i with the constant it set), the gait's heel strikes, and the
controller's own Table 5.1 events and Table 6.1 engagements ("controller"); with a reading given,
the reading ("reading") and the trial's draws of it ("reading_drawn": its calibration, its
motion-capture zero).

Random streams from the seed, apart: the gait, the noise, the draws (the count drop's instant, T,
the artefact's k and ψ, the z_i), and the reading's draws per trial, so a violation or a reading
leaves the others' samples alone.
"""

from .reading import NOMINAL, Reading, draw_reading
from .rig import (
    BETWEEN,
    BRACE_FORMATS,
    MANIFEST_COLUMNS,
    MOCAP_FORMATS,
    REQUIRES,
    VIOLATIONS,
    checked_violations,
)
from .study import RigState, Trial, simulate_study, write_study

__all__ = [
    "BETWEEN",
    "BRACE_FORMATS",
    "MANIFEST_COLUMNS",
    "MOCAP_FORMATS",
    "NOMINAL",
    "REQUIRES",
    "VIOLATIONS",
    "Reading",
    "RigState",
    "Trial",
    "checked_violations",
    "draw_reading",
    "simulate_study",
    "write_study",
]
