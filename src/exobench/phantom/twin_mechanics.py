"""Time-domain mechanics of the phantom rig: hexapod drive, leg, interface, bars, chain, spring.

State variables integrated at the analog rate (implicit Euler), vectorised over strides (rows);
the loop runs over time samples only. While the clutch is engaged one knee moment M passes in
series (all quantities knee-equivalent, at the knee joint):

    programme θ_prog ─drive─ phantom θ_p ─interface─ bars θ_e ─frame─ output ─play─ spring side s

- drive (hexapod, vertical stiffness k_d): θ_p = θ_prog − M/(k_d·x_K²), see :func:`drive_compliance`;
- interface (soft tissue + straps, Kelvin–Voigt): M = k_i·(δ + β·δ³) + c_i·δ̇, δ = θ_p − θ_e;
- frame (bars, clutch, chain links): M = k_f·σ, σ = θ_e − θ_output;
- play (tension-only chain slack): the output turns play_rad before the spring side is loaded,
  no moment while slack, u = output − spring-side rotation ∈ (−∞, play_rad], M ≥ 0;
- spring side: M = M_s(s) + f, M_s the spring + tensioner moment (seed 000 eqs. 2.1–2.2 while
  the extension spring is taut, the tensioner alone once it is slack) and f the Coulomb
  friction of chain and clutch, |f| ≤ τ: the spring side sticks while |M − M_s(s)| ≤ τ.
Quasi-static bodies: the exoskeleton bars, chain and spring side are massless (their inertia is
< 1 % of the phantom's segments, carried with them in RIG.md's masses); the drive deflection
ignores its own inertia (the leg's inertial loads along the programme are taught with it).
A disabled compliance is rigid, a disabled play is a bilateral rigid chain.
The clutch level per sample comes from the twin (:func:`twin.clutch_level`): its torque capacity is unbounded while the
level is 1 and falls with the level (times the moment held) during release; a load above the
capacity slips the clutch. When disengaged the spring side rests at s = 0.
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
        """Spring-side rotation where the extension spring's tension F0 + k_l·r·(T/t)·s reaches 0."""
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


def _interface_tangent(chain: Chain, delta_k, delta_prev, dt_s: float):
    """Tangent compliance and offset (δ ≈ δ0 + M·c) of k_i(δ + βδ³) + c_i(δ − δ_prev)/h about δ_k."""
    if np.isinf(chain.k_interface_Nm_per_rad):
        return 0.0, np.zeros_like(delta_prev)
    k, beta, viscous = (
        chain.k_interface_Nm_per_rad,
        chain.stiffening_per_rad2,
        chain.c_interface_Nms_per_rad / dt_s,
    )
    tangent = k * (1.0 + 3.0 * beta * delta_k**2) + viscous
    moment_k = k * (delta_k + beta * delta_k**3) + viscous * (delta_k - delta_prev)
    return 1.0 / tangent, delta_k - moment_k / tangent


def _spring_side(chain: Chain, moment, s_prev):
    """Stick test of the spring side under a moment: holds while |M − M_s(s)| ≤ τ, else slides."""
    excess = moment - chain.spring_moment(s_prev)
    slides = np.abs(excess) > chain.friction_Nm
    return np.where(
        slides, chain.spring_rotation(moment - np.sign(excess) * chain.friction_Nm), s_prev
    )


def _taut_moment(chain: Chain, compliance, offset, target, s_prev):
    """Moment with the chain taut: compliance·M + offset + s(M) = target, s by the stick test."""
    tau = chain.friction_Nm
    held = chain.spring_moment(s_prev)
    gap = target - offset - s_prev
    with np.errstate(divide="ignore", invalid="ignore"):
        m_stick = np.where(compliance > 0, gap / compliance, 0.0)
    sticks = (compliance > 0) & (np.abs(m_stick - held) <= tau)
    friction = np.sign(gap - compliance * held) * tau
    k_theta = chain.joint_stiffness_Nm_per_rad
    kink = chain.slack_rotation_rad
    k_slack = chain.tensioner_knee_stiffness_Nm_per_rad
    # Each branch M_s = K·s + M0 of the spring side: compliance·M + offset + (M − f − M0)/K = target.
    taut = (target - offset + friction / k_theta) / (compliance + 1.0 / k_theta)
    base = (k_theta - k_slack) * kink
    slack = (target - offset + (friction + base) / k_slack) / (compliance + 1.0 / k_slack)
    m_slide = np.where((taut - friction) / k_theta >= kink, taut, slack)
    return np.where(sticks, m_stick, m_slide)


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
    shape = (strides,)
    frame_c = 0.0 if np.isinf(chain.k_frame_Nm_per_rad) else 1.0 / chain.k_frame_Nm_per_rad
    play = float(chain.play_rad)
    names = ("moment", "interface", "slack", "spring")
    out = {name: np.zeros((strides, samples)) for name in names}
    delta, s, slack = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    reference, hold = np.zeros(shape), np.zeros(shape)
    was_on = np.zeros(shape, bool)
    for i in range(samples):
        on = level[:, i] > 0
        capacity = np.where(level[:, i] >= 1, np.inf, level[:, i] * hold)
        s_prev = np.where(on & was_on, s, 0.0)
        slack_prev = np.where(on & was_on, slack, 0.0)
        delta_k = delta
        for _ in range(NEWTON_ITERATIONS):
            c_int, offset = _interface_tangent(chain, delta_k, delta, dt_s)
            compliance = drive[:, i] + c_int + frame_c
            # The frame output locks where the bars are at the engagement sample (M = 0 there).
            ref = np.where(on & ~was_on, programmed_rad[:, i] - offset, reference)
            target = programmed_rad[:, i] - ref  # = compliance·M + offset + u + s
            moment = _taut_moment(chain, compliance, offset, target - play, s_prev)
            spring = _spring_side(chain, moment, s_prev)
            u = np.full(shape, play)
            if play > 0:  # tension-only chain: slack (no moment) where the taut solution pushes
                loose = moment <= 0
                spring = np.where(loose, _spring_side(chain, 0.0, s_prev), spring)
                moment = np.where(loose, 0.0, moment)
                u = np.where(loose, target - offset - spring, u)
            slips = np.abs(moment) > capacity
            if slips.any():
                moment = np.where(slips, np.sign(moment) * capacity, moment)
                spring = np.where(slips, _spring_side(chain, moment, s_prev), spring)
                u = np.where(slips, slack_prev, u)
            moment = np.where(on, moment, 0.0)
            new_delta = offset + c_int * moment
            converged = np.max(np.abs(new_delta - delta_k), initial=0.0) < NEWTON_TOLERANCE_RAD
            delta_k = new_delta
            if chain.stiffening_per_rad2 == 0 or converged:
                break
        s = np.where(on, spring, 0.0)
        slack = np.where(on, u, 0.0)
        delta = delta_k
        # A slipping clutch moves the locked frame output with it (identity when it holds).
        reference = programmed_rad[:, i] - drive[:, i] * moment - delta - frame_c * moment
        reference -= slack + s
        hold = np.where(level[:, i] >= 1, np.abs(moment), hold)
        was_on = on
        out["moment"][:, i] = moment
        out["interface"][:, i] = delta
        out["slack"][:, i] = slack
        out["spring"][:, i] = s
    moment = out["moment"]
    phantom = programmed_rad - drive * moment
    columns = Chain(
        joint_stiffness_Nm_per_rad=np.broadcast_to(chain.joint_stiffness_Nm_per_rad, shape)[
            :, None
        ],
        spring_stiffness_N_per_m=np.broadcast_to(chain.spring_stiffness_N_per_m, shape)[:, None],
        travel_m_per_rad=chain.travel_m_per_rad,
        pretension_N=chain.pretension_N,
        tensioner_knee_stiffness_Nm_per_rad=chain.tensioner_knee_stiffness_Nm_per_rad,
    )
    return {
        "phantom_knee_angle_rad": phantom,
        "drive_deflection_rad": programmed_rad - phantom,
        "knee_moment_Nm": moment,
        "interface_deflection_rad": out["interface"],
        "exo_knee_angle_rad": phantom - out["interface"],
        "frame_deflection_rad": frame_c * moment,
        "chain_slack_rad": out["slack"],
        "spring_side_rotation_rad": out["spring"],
        "spring_force_N": columns.spring_force(out["spring"]),
        "spring_extension_m": columns.spring_extension(out["spring"]),
    }
