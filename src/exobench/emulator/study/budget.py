"""Motor thermal check (seed 002 eqs. 4.1–4.2) and the torque budget of the transmission (§4.4)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np


def winding_rise_K(current_A, resistance_ohm, alpha_per_K, thermal_K_per_W):
    """Eq. (4.1): steady winding temperature rise ΔT = R_th·R25·I² / (1 − α·R_th·R25·I²)."""
    heat = thermal_K_per_W * resistance_ohm * np.square(current_A)
    return heat / (1.0 - alpha_per_K * heat)


def max_current_A(max_rise_K, resistance_ohm, alpha_per_K, thermal_K_per_W):
    """Eq. (4.2): continuous current at the largest winding rise, √(ΔT/(R25(αΔT + 1)R_th))."""
    return np.sqrt(
        max_rise_K / (resistance_ohm * (alpha_per_K * max_rise_K + 1.0) * thermal_K_per_W)
    )


def compare_reported(result: Mapping, reported) -> dict:
    """Each §4.4 number of seed002_reported.csv beside the computed one."""
    rows = reported[reported["condition"].isna()]
    computed = {
        "max_continuous_current_heat_sink_A": result["max_continuous_current_A"]["heat_sink"],
        "motor_torque_at_max_current_Nm": result["motor_torque_at_max_current_Nm"],
        "gearhead_torque_at_max_current_Nm": result["gearhead_torque_at_max_current_Nm"],
        "cable_tension_at_max_current_N": result["cable_tension_at_max_current_N"],
    }
    return {
        row.metric: {"reported": float(row.value), "computed": computed[row.metric]}
        for row in rows.itertuples()
        if row.metric in computed
    }


def check(cfg: Mapping, transmission: Mapping, torque_Nm: np.ndarray) -> dict:
    """Thermal limits, torque chain and the demand of the recorded brace torques."""
    motor, gear = cfg["motor"], cfg["gearhead"]
    loss = cfg["transmission_loss"]
    r_m, r_b = transmission["motor_pulley_radius_m"], transmission["brace_pulley_radius_m"]
    thermal = {
        setting: motor["winding_housing_K_per_W"] + motor[key]
        for setting, key in (
            ("manufacturer", "housing_ambient_K_per_W"),
            ("heat_sink", "housing_ambient_heatsink_K_per_W"),
        )
    }
    currents = {
        s: float(
            max_current_A(
                motor["max_winding_rise_K"],
                motor["terminal_resistance_ohm"],
                motor["copper_coefficient_per_K"],
                r,
            )
        )
        for s, r in thermal.items()
    }
    motor_torque = currents["heat_sink"] * motor["torque_constant_Nm_per_A"] * motor["efficiency"]
    gear_torque = motor_torque * gear["ratio"] * gear["efficiency"]

    def brace_torque(gear_Nm: float) -> float:
        return gear_Nm / r_m * r_b * (1.0 - loss)

    def current_for(brace_Nm):
        gear_Nm = np.abs(brace_Nm) * r_m / (r_b * (1.0 - loss))
        return (
            gear_Nm
            / (gear["ratio"] * gear["efficiency"])
            / (motor["torque_constant_Nm_per_A"] * motor["efficiency"])
        )

    peak = float(np.max(np.abs(torque_Nm)))
    rms = float(np.sqrt(np.mean(np.square(torque_Nm))))
    rms_current = float(current_for(rms))
    rise = float(
        winding_rise_K(
            rms_current,
            motor["terminal_resistance_ohm"],
            motor["copper_coefficient_per_K"],
            thermal["heat_sink"],
        )
    )
    return {
        "max_continuous_current_A": currents,
        "motor_torque_at_max_current_Nm": motor_torque,
        "gearhead_torque_at_max_current_Nm": gear_torque,
        "cable_tension_at_max_current_N": gear_torque / r_m,
        "brace_torque_limit_continuous_Nm": brace_torque(gear["continuous_Nm"]),
        "brace_torque_limit_intermittent_Nm": brace_torque(gear["intermittent_Nm"]),
        "demand": {
            "peak_brace_torque_Nm": peak,
            "rms_brace_torque_Nm": rms,
            "peak_motor_current_A": float(current_for(peak)),
            "rms_motor_current_A": rms_current,
            "winding_rise_at_rms_current_K": rise,
        },
        "margins": {
            "peak_torque_vs_intermittent": brace_torque(gear["intermittent_Nm"]) / peak
            if peak > 0
            else None,
            "rms_current_vs_continuous": currents["heat_sink"] / rms_current
            if rms_current > 0
            else None,
            "winding_rise_vs_max": motor["max_winding_rise_K"] / rise if rise > 0 else None,
        },
    }
