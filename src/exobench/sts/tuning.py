"""Spring–damper parameters that minimise the user's joint torque over the motion.

The module torque preload + k·φ + c·φ̇ is linear in its parameters, so minimising the mean
square of the user's torque (required − module) at each joint is a bounded linear
least-squares problem (scipy.optimize.lsq_linear), solved per joint.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd
from scipy.optimize import lsq_linear

from exobench.sts.loads import JOINTS, module_torques
from exobench.sts.motion import Motion

PARAMETERS = ("preload_Nm", "stiffness_Nm_per_rad", "damping_Nms_per_rad")


def rms(values: np.ndarray) -> float:
    """Root mean square over the samples."""
    return float(np.sqrt(np.mean(np.square(values))))


def tune(motion: Motion, required_Nm: np.ndarray, bounds: Mapping) -> dict:
    """Bounded least-squares module parameters per joint and the fit's residuals."""
    lower = [bounds["lower"][p] for p in PARAMETERS]
    upper = [bounds["upper"][p] for p in PARAMETERS]
    out = {}
    for i, joint in enumerate(JOINTS):
        design = np.column_stack(
            [np.ones_like(motion.t_s), motion.q_rad[:, i], motion.qd_rad_per_s[:, i]]
        )
        fit = lsq_linear(design, required_Nm[:, i], bounds=(lower, upper), method="bvls")
        user = required_Nm[:, i] - design @ fit.x
        out[joint] = {
            **dict(zip(PARAMETERS, fit.x.tolist(), strict=True)),
            "at_lower_bounds": [PARAMETERS[k] for k in np.flatnonzero(fit.active_mask < 0)],
            "at_upper_bounds": [PARAMETERS[k] for k in np.flatnonzero(fit.active_mask > 0)],
            "required_rms_Nm": rms(required_Nm[:, i]),
            "user_rms_Nm": rms(user),
            "required_peak_Nm": float(np.max(np.abs(required_Nm[:, i]))),
            "user_peak_Nm": float(np.max(np.abs(user))),
        }
    return out


def law_fit(motion: Motion, required_Nm: np.ndarray, bounds: Mapping, configured: Mapping) -> dict:
    """The tuned modules of one law (:func:`tune`), their parameters by joint, how many sit at
    their upper bound (what a module can give), and the user's RMS torque with the configured
    modules beside them."""
    fit = tune(motion, required_Nm, bounds)
    user = required_Nm - module_torques(motion, configured)
    return {
        "tuned": fit,
        "tuned_modules": {j: {p: fit[j][p] for p in PARAMETERS} for j in JOINTS},
        "user_rms_configured_Nm": {j: rms(user[:, i]) for i, j in enumerate(JOINTS)},
        "parameters_at_upper_bounds": sum(len(fit[j]["at_upper_bounds"]) for j in JOINTS),
    }


def module_table(
    law: str, motion: Motion, required_Nm: np.ndarray, configured: Mapping, tuned: Mapping
) -> pd.DataFrame:
    """Per-sample required, module and user torques with the configured and the tuned modules."""
    columns = {"law": law, "t_s": motion.t_s}
    settings = {
        "configured": module_torques(motion, configured),
        "tuned": module_torques(motion, tuned),
    }
    for i, joint in enumerate(JOINTS):
        columns[f"{joint}_required_Nm"] = required_Nm[:, i]
        for name, module in settings.items():
            columns[f"{joint}_module_{name}_Nm"] = module[:, i]
            columns[f"{joint}_user_{name}_Nm"] = required_Nm[:, i] - module[:, i]
    return pd.DataFrame(columns)
