"""Time-domain mechanics of the phantom rig: hexapod drive, leg, interface, bars, chain, spring.

State variables integrated at the analog rate (implicit steps; the interface by the trapezoidal
rule) in a compiled loop over strides and samples. While the clutch is engaged one knee moment M
passes in series (all quantities knee-equivalent, at the knee joint):

    programme θ_prog ─drive─ phantom θ_p ─interface─ bars θ_e ─frame─ output ─play─ spring side s

- drive (hexapod, vertical stiffness k_d): θ_p = θ_prog − M/(k_d·x_K²) (:func:`drive_compliance`);
- interface (soft tissue + straps, Kelvin–Voigt): M = k_i·(δ + β·δ³) + c_i·δ̇, δ = θ_p − θ_e;
- frame (bars, clutch, chain links): M = k_f·σ, σ = θ_e − θ_output;
- play (tension-only chain slack): the output turns play_rad before the spring side is loaded,
  no moment while slack, u = output − spring-side rotation ∈ (−∞, play_rad], M ≥ 0;
- spring side: M = M_s(s) + f, M_s the spring + tensioner moment (seed 000 eqs. 2.1–2.2 while
  the extension spring is taut, the tensioner alone once it is slack) and f the Coulomb
  friction of chain and clutch, |f| ≤ τ: the spring side sticks while |M − M_s(s)| ≤ τ.
Quasi-static bodies: the bars, chain and spring side are massless (docs/rig.md lumps the
exoskeleton's parts into the phantom's segments, which move with the programme and carry the
inertia in :mod:`dynamics`); the drive deflection neglects its own inertia.
A disabled compliance is rigid, a disabled play is a bilateral rigid chain.
The clutch level per sample comes from :func:`twin.clutch_level`: the clutch's torque capacity
is unbounded while the level is 1 and falls with the level (times the moment held) during
release; a load above the capacity slips the clutch. When disengaged the spring side rests at s = 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
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


def drive_compliance(knee_offset: np.ndarray, k_drive_N_per_m: float):
    """Knee-equivalent drive compliance 1/(k_d·x_K²) (rad/N·m) at the programmed posture.

    ``knee_offset`` holds x_K of that posture (:func:`knee_offset_m`). Definition: the ankle
    sits (F_y − F_y,free)/k_d below its programmed height, F_y,free the vertical ankle force the
    same programme needs with the exoskeleton disengaged (a lab teaches its programme with the
    leg alone); quasi-statically F_y − F_y,free = M/x_K (virtual work, dy_ankle/dθ = x_K), so
    θ_phantom = θ_prog − M/(k_d·x_K²), x_K at the programmed posture.
    """
    if np.isinf(k_drive_N_per_m):
        return np.zeros_like(knee_offset)
    return 1.0 / (k_drive_N_per_m * knee_offset**2)


@numba.njit(cache=True)
def _interface_tangent(k, beta, damping, delta_k, delta_prev, rate_prev, dt_s):
    """Tangent (δ ≈ δ0 + c·M) at δ_k of the trapezoidal step of the interface,
    k_i·g(δ) + (2c_i/h)(δ − δ_prev) = M + c_i·δ̇_prev, g(δ) = δ + βδ³ (second-order accurate)."""
    if np.isinf(k):
        return 0.0, 0.0
    viscous, carried = 2.0 * damping / dt_s, damping * rate_prev
    if beta == 0.0:  # linear: exact in one step
        return 1.0 / (k + viscous), (viscous * delta_prev + carried) / (k + viscous)
    tangent = k * (1.0 + 3.0 * beta * delta_k**2) + viscous
    moment_k = k * (delta_k + beta * delta_k**3) + viscous * (delta_k - delta_prev) - carried
    return 1.0 / tangent, delta_k - moment_k / tangent


@numba.njit(cache=True)
def _held(s, k_taut, kink, k_slack, base):
    """Spring-side moment M_s(s) on the branch s lies on (taut: k_θ·s; slack: tensioner)."""
    return k_taut * s if s >= kink else k_slack * s + base


@numba.njit(cache=True)
def _respond(moment, s_prev, k_taut, kink, k_slack, base, tau):
    """Stick test under a given moment: s holds while |M − M_s(s)| ≤ τ, else slides."""
    excess = moment - _held(s_prev, k_taut, kink, k_slack, base)
    if abs(excess) <= tau:
        return s_prev
    driven = moment - np.sign(excess) * tau
    taut = driven / k_taut
    return taut if taut >= kink else (driven - base) / k_slack


@numba.njit(cache=True)
def _spring_solve(compliance, target, s_prev, k_taut, kink, k_slack, base, tau):
    """Moment and s with compliance·M + s = target, s by the stick test (trial stick step);
    sliding on branch M_s = K·s + M0: compliance·M + (M − f − M0)/K = target."""
    held = _held(s_prev, k_taut, kink, k_slack, base)
    gap = target - s_prev
    if compliance > 0.0 and abs(gap / compliance - held) <= tau:
        return gap / compliance, s_prev
    friction = np.sign(gap - compliance * held) * tau
    m_taut = (target + friction / k_taut) / (compliance + 1.0 / k_taut)
    s_taut = (m_taut - friction) / k_taut
    if s_taut >= kink:
        return m_taut, s_taut
    m_slack = (target + (friction + base) / k_slack) / (compliance + 1.0 / k_slack)
    return m_slack, (m_slack - friction - base) / k_slack


@numba.njit(cache=True)
def _steps(prog, levels, outer, k_taut, kink, k_slack, tau, k_i, beta, damping, play, dt_s,
           engage_at):  # fmt: skip
    """The time loop of :func:`simulate`, compiled: every stride (row), every sample."""
    strides, samples = prog.shape
    moment_out, delta_out = np.zeros((strides, samples)), np.zeros((strides, samples))
    slack_out, s_out = np.zeros((strides, samples)), np.zeros((strides, samples))
    for j in range(strides):
        kt, kk = k_taut[j], kink[j]
        base = (kt - k_slack) * kk  # M0 of the slack branch
        delta = s = slack = rate = reference = hold = 0.0
        was_on = False
        for i in range(samples):
            lvl = levels[j, i]
            on = lvl > 0.0
            starting = on and not was_on
            releasing = on and lvl < 1.0
            delta_k = delta
            c_int = offset = moment = spring = u = 0.0
            slips = False
            for _ in range(NEWTON_ITERATIONS):
                c_int, offset = _interface_tangent(k_i, beta, damping, delta_k, delta, rate, dt_s)
                if starting:  # the frame output locks where the bars are (M = 0 there), at
                    late = i - engage_at  # the engagement instant, between samples
                    late = late if 0.0 < late < 1.0 and i > 0 else 0.0
                    reference = prog[j, i] - late * (prog[j, i] - prog[j, i - 1]) - offset
                free = prog[j, i] - reference - offset  # = (drive + interface + frame)·M + u + s
                moment, spring = _spring_solve(
                    outer[j, i] + c_int, free - play, s, kt, kk, k_slack, base, tau
                )
                u = play
                if play > 0.0 and moment <= 0.0:  # tension-only chain: slack, no moment
                    spring = _respond(0.0, s, kt, kk, k_slack, base, tau)
                    moment = 0.0
                    u = free - spring
                slips = releasing and abs(moment) > lvl * hold
                if slips:  # the clutch slips at its capacity, the chain keeps its slack
                    moment = np.sign(moment) * lvl * hold
                    spring = _respond(moment, s, kt, kk, k_slack, base, tau)
                    u = slack
                if not on:
                    moment = 0.0
                new_delta = offset + c_int * moment
                converged = beta == 0.0 or abs(new_delta - delta_k) < NEWTON_TOLERANCE_RAD
                delta_k = new_delta
                if converged:
                    break
            if slips:  # a slipping clutch moves the locked frame output with it
                reference = prog[j, i] - (outer[j, i] + c_int) * moment - offset - u - spring
            rate = 2.0 * (delta_k - delta) / dt_s - rate
            delta = delta_k
            s = spring if on else 0.0
            slack = u if on else 0.0
            if lvl >= 1.0:
                hold = abs(moment)
            was_on = on
            moment_out[j, i], delta_out[j, i] = moment, delta
            slack_out[j, i], s_out[j, i] = slack, s
    return moment_out, delta_out, slack_out, s_out


def simulate(
    programmed_rad: np.ndarray,
    level: np.ndarray,
    drive: np.ndarray,
    dt_s: float,
    chain: Chain,
    engage_at: float = 0.0,
) -> dict[str, np.ndarray]:
    """States of every stride, shape (strides, samples), from the programmed knee angle.

    ``level`` is the clutch level per sample (1 engaged, 0 free, in between releasing), ``drive``
    the knee-equivalent drive compliance per sample (:func:`drive_compliance`), ``engage_at``
    the (fractional) sample at which the clutch locks (it holds from the next whole sample on).
    """
    strides = programmed_rad.shape[0]
    frame_c = 0.0 if np.isinf(chain.k_frame_Nm_per_rad) else 1.0 / chain.k_frame_Nm_per_rad
    k_taut = np.broadcast_to(chain.joint_stiffness_Nm_per_rad, (strides,)).astype(float)
    kink = np.broadcast_to(chain.slack_rotation_rad, (strides,)).astype(float)
    moment, interface, slack, s = _steps(
        np.ascontiguousarray(programmed_rad, dtype=float),
        np.ascontiguousarray(np.broadcast_to(level, programmed_rad.shape), dtype=float),
        np.broadcast_to(drive, programmed_rad.shape) + frame_c,
        k_taut,
        kink,
        float(chain.tensioner_knee_stiffness_Nm_per_rad),
        float(chain.friction_Nm),
        float(chain.k_interface_Nm_per_rad),
        float(chain.stiffening_per_rad2),
        float(chain.c_interface_Nms_per_rad),
        float(chain.play_rad),
        float(dt_s),
        float(engage_at),
    )
    phantom = programmed_rad - drive * moment
    columns = Chain(
        joint_stiffness_Nm_per_rad=k_taut[:, None],
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
        "chain_slack_rad": slack,
        "spring_side_rotation_rad": s,
        "spring_force_N": columns.spring_force(s),
        "spring_extension_m": columns.spring_extension(s),
    }
