"""The emulator twin's sample loop at 1000 Hz: the real-time controller and the plant, compiled.

The twin writes its own rules, apart from the analysis (:mod:`controller`, :mod:`effects`), so
the discrepancy engine's forward models cannot agree with the test data by sharing its code.
Per sample:
- cuffs: the brace angle lags the anatomical one in proportion to the brace torque, settling
  with the soft tissue's time constant (first order);
- encoder: the brace angle quantised to counts, minus the counts lost so far;
- brace velocity: backward difference of the encoder through the causal 2nd-order low-pass;
- gait events, knee column of Table 5.1: peak flexion (angle above 40°, velocity turns
  negative), peak extension (after a peak flexion, velocity turns positive), heel strike (after
  a peak extension, angle below 20°, velocity rising);
- virtual clutch, Table 6.1: engages at a peak flexion above 40°, disengages at the next peak
  extension; a departing controller holds it ``hold`` samples longer;
- spring law τ = κ·max(0, θ_eq − θ) on the encoder angle (docs/rig.md §3);
- motor set point of eqs. (5.6)–(5.8), A·θ + b(τ) with b(τ) = B·τ² + C·τ + D blended by the
  direction of motion, tracked by the PID of eq. (5.3) (forward-Euler integral, filtered
  derivative) driving a first-order motor velocity response;
- cable: the torque whose offset b(τ) equals motor − A·brace on the direction the brace really
  moves, changed by transmission friction (more in extension, less in flexion).
"""

from __future__ import annotations

import numba
import numpy as np

# Event codes of :func:`run`'s ``event`` output.
PEAK_FLEXION, PEAK_EXTENSION, HEEL_STRIKE = 1, 2, 3


@numba.njit(cache=True)
def _weight(rate_deg_per_s, blend_deg_per_s):
    """Share of the extension calibration in eq. (5.8): 1 below −blend, 0 above +blend."""
    return min(max(0.5 - rate_deg_per_s / (2.0 * blend_deg_per_s), 0.0), 1.0)


@numba.njit(cache=True)
def _offset_deg(torque_Nm, b, c, d):
    """b(τ) = B·τ² + C·τ + D (eqs. 5.6 / 5.7)."""
    return (b * torque_Nm + c) * torque_Nm + d


@numba.njit(cache=True)
def _torque_Nm(offset_deg, b, c, d):
    """τ ≥ 0 with b(τ) = offset, the inverse of eqs. (5.6) / (5.7) (0 while the cable is slack)."""
    excess = offset_deg - d
    root = np.sqrt(max(c * c + 4.0 * b * excess, 0.0))
    return max(2.0 * excess / (c + root), 0.0)


@numba.njit(cache=True)
def _event(flags, angle, omega, omega_prev, limits):
    """One sample of Table 5.1 (knee) and Table 6.1; returns the event code detected, 0 if none.

    ``flags`` holds (flexion, extension, engaged); ``limits`` the angles (deg) above which a
    peak flexion counts, below which a heel strike counts and above which the clutch engages.
    """
    code = 0
    if angle > limits[0] and omega_prev >= 0.0 and omega < 0.0:
        flags[0], flags[1], code = True, False, PEAK_FLEXION
    elif flags[0] and omega_prev <= 0.0 and omega > 0.0:
        flags[0], flags[1], code = False, True, PEAK_EXTENSION
    elif flags[1] and angle < limits[1] and omega > omega_prev:
        flags[1], code = False, HEEL_STRIKE
    if not flags[2] and angle > limits[2] and omega_prev > 0.0 >= omega:
        flags[2] = True
    elif flags[2] and omega_prev < 0.0 <= omega:
        flags[2] = False
    return code


@numba.njit(cache=True)
def run(anatomical, dropped, step_deg, dt, b, a, limits, cuff, cuff_lag, hold, stiffness,
        equilibrium, set_point_shift, ratio, blend, extension, flexion, pid, motor_tau,
        friction):  # fmt: skip
    """Controller and plant of one trial at every sample (the rules of the module docstring).

    Returns brace, encoder, torque, desired torque, motor angle, clutch (1 while the spring
    acts) and event code per sample. ``limits`` are :func:`_event`'s angles, passed in (not read
    as globals, which a compiled and cached function would keep); ``extension`` and ``flexion``
    hold (B, C, D); ``pid`` holds (k_p, k_i, k_d, N).
    """
    n = anatomical.shape[0]
    brace_out, encoder_out, torque_out = np.zeros(n), np.zeros(n), np.zeros(n)
    desired_out, motor_out, clutch_out = np.zeros(n), np.zeros(n), np.zeros(n)
    event_out = np.zeros(n, np.int8)
    flags = np.zeros(3, np.bool_)
    kp, ki, kd, n_filter = pid[0], pid[1], pid[2], pid[3]
    raw_1 = raw_2 = omega_1 = omega_2 = 0.0
    integral = derivative = error_prev = 0.0
    motor = ratio * anatomical[0] + _offset_deg(0.0, flexion[0], flexion[1], flexion[2])
    motor_rate = torque = cuff_offset = encoder_prev = 0.0
    brace_prev = anatomical[0]
    released = -hold - 1  # the sample at which Table 6.1 last released the clutch (none yet)
    for i in range(n):
        cuff_offset += cuff_lag * (cuff * torque - cuff_offset)
        brace = anatomical[i] + cuff_offset
        encoder = step_deg * np.floor(brace / step_deg) - dropped[i]
        raw = 0.0 if i == 0 else (encoder - encoder_prev) / dt
        omega = b[0] * raw + b[1] * raw_1 + b[2] * raw_2 - a[1] * omega_1 - a[2] * omega_2
        was_engaged = flags[2]
        event_out[i] = _event(flags, encoder, omega, omega_1, limits)
        raw_2, raw_1, omega_2, omega_1 = raw_1, raw, omega_1, omega
        if was_engaged and not flags[2]:
            released = i
        clutch = flags[2] or i < released + hold
        desired = stiffness * np.radians(max(0.0, equilibrium - encoder)) if clutch else 0.0
        w = _weight(omega, blend)
        target = ratio * (encoder + set_point_shift) + (
            w * _offset_deg(desired, extension[0], extension[1], extension[2])
            + (1.0 - w) * _offset_deg(desired, flexion[0], flexion[1], flexion[2])
        )
        error = target - motor
        if i == 0:
            error_prev = error
        derivative = (1.0 - n_filter * dt) * derivative + kd * n_filter * (error - error_prev)
        command = kp * error + integral + derivative
        integral += ki * dt * error
        error_prev = error
        motor_rate += dt / motor_tau * (command - motor_rate)
        motor += motor_rate * dt
        w = _weight((brace - brace_prev) / dt, blend)
        offset = motor - ratio * brace
        cable = w * _torque_Nm(offset, extension[0], extension[1], extension[2]) + (
            1.0 - w
        ) * _torque_Nm(offset, flexion[0], flexion[1], flexion[2])
        torque = cable * (1.0 + friction * (2.0 * w - 1.0))
        brace_out[i], encoder_out[i], torque_out[i] = brace, encoder, torque
        desired_out[i], motor_out[i], clutch_out[i] = desired, motor, clutch
        encoder_prev, brace_prev = encoder, brace
    return brace_out, encoder_out, torque_out, desired_out, motor_out, clutch_out, event_out
