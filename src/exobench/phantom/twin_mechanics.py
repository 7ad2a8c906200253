"""Time-domain mechanics of the phantom rig: hexapod drive, leg, interface, bars, chain, spring.

State variables integrated at the analog rate (implicit steps; the interface by the trapezoidal
rule), vectorised over strides (rows);
the loop runs over time samples only. While the clutch is engaged one knee moment M passes in
series (all quantities knee-equivalent, at the knee joint):

    programme θ_prog ─drive─ phantom θ_p ─interface─ bars θ_e ─frame─ output ─play─ spring side s

- drive (hexapod, vertical stiffness k_d): θ_p = θ_prog − M/(k_d·x_K²) (:func:`drive_compliance`);
- interface (soft tissue + straps, Kelvin–Voigt): M = k_i·(δ + β·δ³) + c_i·δ̇, δ = θ_p − θ_e;
- frame (bars, clutch, chain links): M = k_f·σ, σ = θ_e − θ_output;
- play (tension-only chain slack): the output turns play_rad before the spring side is loaded,
  no moment while slack, u = output − spring-side rotation ∈ (−∞, play_rad], M ≥ 0;
- spring side: M = M_s(s) + f, M_s the spring + tensioner moment (seed 000 eqs. 2.1–2.2 while
  the extension spring is taut, the tensioner alone once it is slack) and f the Coulomb
  friction of chain and clutch, |f| ≤ τ: the spring side sticks while |M − M_s(s)| ≤ τ.
Quasi-static bodies: the bars, chain and spring side are massless (RIG.md lumps the exoskeleton's
parts into the phantom's segments, which move with the programme and carry the inertia in
:mod:`dynamics`); the drive deflection neglects its own inertia.
A disabled compliance is rigid, a disabled play is a bilateral rigid chain.
The clutch level per sample comes from :func:`twin.clutch_level`: the clutch's torque capacity
is unbounded while the level is 1 and falls with the level (times the moment held) during
release; a load above the capacity slips the clutch. When disengaged the spring side rests at s = 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from exobench.phantom.rig import Rig

NEWTON_TOLERANCE_RAD = 1e-13
NEWTON_ITERATIONS = 30


@dataclass(frozen=True)
class Chain:
    """Per-stride parameters (arrays broadcast over strides) of the series chain."""

    joint_stiffness_Nm_per_rad: np.ndarray
    spring_stiffness_N_per_m: np.ndarray
    travel_m_per_rad: float
    pretension_N: float
    tensioner_knee_stiffness_Nm_per_rad: float
    k_interface_Nm_per_rad: float = np.inf
    stiffening_per_rad2: float = 0.0
    c_interface_Nms_per_rad: float = 0.0
    k_frame_Nm_per_rad: float = np.inf
    friction_Nm: float = 0.0
    play_rad: float = 0.0

    @property
    def slack_rotation_rad(self) -> np.ndarray:
        """Spring-side rotation where the spring's tension F0 + k_l·r·(T/t)·s reaches 0."""
        return -self.pretension_N / (self.spring_stiffness_N_per_m * self.travel_m_per_rad)

    def spring_moment(self, rotation_rad):
        """Spring-side knee moment M_s(s): k_θ·s taut (eq. 2.2), tensioner slope once slack."""
        kink = self.slack_rotation_rad
        slack = self.tensioner_knee_stiffness_Nm_per_rad * (rotation_rad - kink)
        return np.where(
            rotation_rad >= kink,
            self.joint_stiffness_Nm_per_rad * rotation_rad,
            self.joint_stiffness_Nm_per_rad * kink + slack,
        )

    def spring_rotation(self, moment_Nm):
        """Spring-side rotation s holding a moment: the inverse of :meth:`spring_moment`."""
        kink = self.slack_rotation_rad
        taut = moment_Nm / self.joint_stiffness_Nm_per_rad
        slack = kink + (moment_Nm - self.joint_stiffness_Nm_per_rad * kink) / (
            self.tensioner_knee_stiffness_Nm_per_rad
        )
        return np.where(taut >= kink, taut, slack)

    def spring_force(self, rotation_rad):
        """Spring tension F = F0 + k_l·r·(T/t)·s, 0 when slack."""
        travel = self.spring_stiffness_N_per_m * self.travel_m_per_rad * rotation_rad
        return np.maximum(self.pretension_N + travel, 0.0)

    def spring_extension(self, rotation_rad):
        """Spring elongation from its pre-tensioned length r·(T/t)·s, stopped at its free length."""
        return self.travel_m_per_rad * np.maximum(rotation_rad, self.slack_rotation_rad)


def knee_offset_m(flexion_rad, rig: Rig):
    """Horizontal distance x_K = l1·l2·sin θ / |hip − ankle| of the knee from the hip–ankle line."""
    l1, l2 = rig.thigh_length_m, rig.shank_length_m
    distance = np.sqrt(l1**2 + l2**2 + 2.0 * l1 * l2 * np.cos(flexion_rad))
    return l1 * l2 * np.sin(flexion_rad) / distance


def drive_compliance(programmed_rad, rig: Rig, k_drive_N_per_m: float):
    """Knee-equivalent drive compliance 1/(k_d·x_K²) (rad/N·m) at the programmed posture.

    Definition: the ankle sits (F_y − F_y,free)/k_d below its programmed height, F_y,free the
    vertical ankle force the same programme needs with the exoskeleton disengaged (a lab teaches
    its programme with the leg alone); quasi-statically F_y − F_y,free = M/x_K (virtual work,
    dy_ankle/dθ = x_K), so θ_phantom = θ_prog − M/(k_d·x_K²), x_K at the programmed posture.
    """
    if np.isinf(k_drive_N_per_m):
        return np.zeros_like(programmed_rad)
    return 1.0 / (k_drive_N_per_m * knee_offset_m(programmed_rad, rig) ** 2)


def _interface_tangent(chain: Chain, delta_k, delta_prev, rate_prev, dt_s: float):
    """Tangent (δ ≈ δ0 + c·M) at δ_k of the trapezoidal step of the interface,
    k_i·g(δ) + (2c_i/h)(δ − δ_prev) = M + c_i·δ̇_prev, g(δ) = δ + βδ³ (second-order accurate)."""
    if np.isinf(chain.k_interface_Nm_per_rad):
        return 0.0, np.zeros_like(delta_prev)
    k, beta, damping = (
        chain.k_interface_Nm_per_rad,
        chain.stiffening_per_rad2,
        chain.c_interface_Nms_per_rad,
    )
    viscous, carried = 2.0 * damping / dt_s, damping * rate_prev
    if beta == 0:  # linear: exact in one step
        return 1.0 / (k + viscous), (viscous * delta_prev + carried) / (k + viscous)
    tangent = k * (1.0 + 3.0 * beta * delta_k**2) + viscous
    moment_k = k * (delta_k + beta * delta_k**3) + viscous * (delta_k - delta_prev) - carried
    return 1.0 / tangent, delta_k - moment_k / tangent


class _SpringSide:
    """Spring side of a set of strides: branches M_s = K·s + M0 (taut, slack), Coulomb friction."""

    def __init__(self, chain: Chain, strides: int):
        self.k_taut = np.broadcast_to(chain.joint_stiffness_Nm_per_rad, (strides,)).astype(float)
        self.kink = np.broadcast_to(chain.slack_rotation_rad, (strides,)).astype(float)
        self.k_slack = float(chain.tensioner_knee_stiffness_Nm_per_rad)
        self.base = (self.k_taut - self.k_slack) * self.kink  # M0 of the slack branch
        self.tau = float(chain.friction_Nm)

    def moment(self, s):
        """M_s(s) on the branch s lies on."""
        return np.where(s >= self.kink, self.k_taut * s, self.k_slack * s + self.base)

    def respond(self, moment, s_prev):
        """Stick test under a given moment: s holds while |M − M_s(s)| ≤ τ, else slides."""
        excess = moment - self.moment(s_prev)
        driven = moment - np.sign(excess) * self.tau
        taut = driven / self.k_taut
        slid = np.where(taut >= self.kink, taut, (driven - self.base) / self.k_slack)
        return np.where(np.abs(excess) > self.tau, slid, s_prev)

    def solve(self, compliance, target, s_prev):
        """Moment and s with compliance·M + s = target, s by the stick test (trial stick step)."""
        held = self.moment(s_prev)
        gap = target - s_prev
        m_stick = np.divide(gap, compliance, out=np.zeros_like(gap), where=compliance > 0)
        sticks = (compliance > 0) & (np.abs(m_stick - held) <= self.tau)
        friction = np.sign(gap - compliance * held) * self.tau
        # Sliding on branch M_s = K·s + M0: compliance·M + (M − f − M0)/K = target.
        m_taut = (target + friction / self.k_taut) / (compliance + 1.0 / self.k_taut)
        s_taut = (m_taut - friction) / self.k_taut
        on_taut = s_taut >= self.kink
        m_slack = (target + (friction + self.base) / self.k_slack) / (
            compliance + 1.0 / self.k_slack
        )
        moment = np.where(sticks, m_stick, np.where(on_taut, m_taut, m_slack))
        s_slack = (m_slack - friction - self.base) / self.k_slack
        return moment, np.where(sticks, s_prev, np.where(on_taut, s_taut, s_slack))


def simulate(
    programmed_rad: np.ndarray,
    level: np.ndarray,
    drive: np.ndarray,
    dt_s: float,
    chain: Chain,
) -> dict[str, np.ndarray]:
    """States of every stride, shape (strides, samples), from the programmed knee angle.

    ``level`` is the clutch level per sample (1 engaged, 0 free, in between releasing), ``drive``
    the knee-equivalent drive compliance per sample (:func:`drive_compliance`).
    """
    strides, samples = programmed_rad.shape
    spring_side = _SpringSide(chain, strides)
    frame_c = 0.0 if np.isinf(chain.k_frame_Nm_per_rad) else 1.0 / chain.k_frame_Nm_per_rad
    play = float(chain.play_rad)
    # Samples along the first axis: each step reads and writes contiguous rows.
    prog = np.ascontiguousarray(programmed_rad.T)
    levels = np.ascontiguousarray(np.broadcast_to(level, programmed_rad.shape).T)
    outer = np.ascontiguousarray(np.broadcast_to(drive, programmed_rad.shape).T) + frame_c
    out = {name: np.zeros((samples, strides)) for name in ("moment", "interface", "slack", "s")}
    delta, s, slack = np.zeros(strides), np.zeros(strides), np.zeros(strides)
    rate = np.zeros(strides)  # interface deflection rate δ̇ (trapezoidal rule)
    reference, hold = np.zeros(strides), np.zeros(strides)
    was_on = np.zeros(strides, bool)
    for i in range(samples):
        lvl = levels[i]
        on = lvl > 0
        starting = on & ~was_on
        releasing = on & (lvl < 1)
        delta_k = delta
        for _ in range(NEWTON_ITERATIONS):
            c_int, offset = _interface_tangent(chain, delta_k, delta, rate, dt_s)
            if starting.any():  # the frame output locks where the bars are (M = 0 there)
                reference = np.where(starting, prog[i] - offset, reference)
            free = prog[i] - reference - offset  # = (drive + interface + frame)·M + u + s
            moment, spring = spring_side.solve(outer[i] + c_int, free - play, s)
            u = play
            if play > 0:  # tension-only chain: slack (no moment) where the taut solution pushes
                loose = moment <= 0
                spring = np.where(loose, spring_side.respond(0.0, s), spring)
                moment = np.where(loose, 0.0, moment)
                u = np.where(loose, free - spring, play)
            slips = releasing & (np.abs(moment) > lvl * hold)
            if slips.any():  # the clutch slips at its capacity, the chain keeps its slack
                moment = np.where(slips, np.sign(moment) * lvl * hold, moment)
                spring = np.where(slips, spring_side.respond(moment, s), spring)
                u = np.where(slips, slack, u)
            moment = np.where(on, moment, 0.0)
            new_delta = offset + c_int * moment
            if chain.stiffening_per_rad2 == 0:
                delta_k = new_delta
                break
            converged = np.abs(new_delta - delta_k).max() < NEWTON_TOLERANCE_RAD
            delta_k = new_delta
            if converged:
                break
        if slips.any():  # a slipping clutch moves the locked frame output with it
            moved = prog[i] - (outer[i] + c_int) * moment - offset - u - spring
            reference = np.where(slips, moved, reference)
        rate = 2.0 * (delta_k - delta) / dt_s - rate
        delta = delta_k
        s = np.where(on, spring, 0.0)
        slack = np.where(on, u, 0.0)
        hold = np.where(lvl >= 1, np.abs(moment), hold)
        was_on = on
        out["moment"][i] = moment
        out["interface"][i] = delta
        out["slack"][i] = slack
        out["s"][i] = s
    moment, interface, s = out["moment"].T, out["interface"].T, out["s"].T
    phantom = programmed_rad - drive * moment
    columns = Chain(
        joint_stiffness_Nm_per_rad=spring_side.k_taut[:, None],
        spring_stiffness_N_per_m=np.broadcast_to(chain.spring_stiffness_N_per_m, (strides,))[
            :, None
        ],
        travel_m_per_rad=chain.travel_m_per_rad,
        pretension_N=chain.pretension_N,
        tensioner_knee_stiffness_Nm_per_rad=chain.tensioner_knee_stiffness_Nm_per_rad,
    )
    return {
        "phantom_knee_angle_rad": phantom,
        "drive_deflection_rad": programmed_rad - phantom,
        "knee_moment_Nm": moment,
        "interface_deflection_rad": interface,
        "exo_knee_angle_rad": phantom - interface,
        "frame_deflection_rad": frame_c * moment,
        "chain_slack_rad": out["slack"].T,
        "spring_side_rotation_rad": s,
        "spring_force_N": columns.spring_force(s),
        "spring_extension_m": columns.spring_extension(s),
    }
