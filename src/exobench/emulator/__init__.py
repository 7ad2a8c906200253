"""Knee exoskeleton emulator: energy stored per step in an emulated clutched spring (seed 002)."""

from collections.abc import Iterable, Mapping


def trial_name(speed_m_per_s: float, stiffness_Nm_per_rad: float) -> str:
    """Trial identifier from speed and stiffness, e.g. v08_k35 for 0.8 m/s and 3.5 N·m/rad."""
    return f"v{round(10 * speed_m_per_s):02d}_k{round(10 * stiffness_Nm_per_rad):02d}"


def twin_trial_names(config: Mapping) -> list[str]:
    """Trials the emulator twin writes: every speed × stiffness of the protocol."""
    protocol = config["emulator"]["protocol"]
    return [
        trial_name(v, k)
        for v in protocol["speeds_m_per_s"]
        for k in protocol["stiffnesses_Nm_per_rad"]
    ]


def twin_files(trial_names: Iterable[str]) -> list[str]:
    """The files the twin writes for these trials (all it may overwrite)."""
    kinds = ("brace", "mocap")
    return ["manifest.csv", *(f"{n}_{kind}.csv" for n in trial_names for kind in kinds)]


def analysis_settings(config: Mapping) -> dict:
    """What the analysis needs from the config: the controller's filter, equilibrium, limits."""
    cfg = config["emulator"]
    return {
        **cfg["analysis"],
        "velocity_cutoff_Hz": cfg["controller"]["velocity_cutoff_Hz"],
        "equilibrium_deg": cfg["controller"]["equilibrium_deg"],
        "direction_blend_deg_per_s": cfg["controller"]["direction_blend_deg_per_s"],
        "transmission": cfg["transmission"],
        "seed": int(config["seed"]),
    }
