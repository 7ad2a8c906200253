"""What every figure of the default target should draw, derived here from the tables its caption
points to (``summary.csv``, ``curves.parquet``, ``discrepancy_predictions.parquet``, ``qc/``,
the emulator's samples and steps, Heer's values, the sit-to-stand trajectories …), independently
of the figure code (only its layout constants, where points stand side by side): one
:class:`figure_numbers.Panel` per panel, in the figure's panel order."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import numpy as np
import pandas as pd

from exobench import tables
from exobench.emulator.report import plots as emulator_plots
from exobench.phantom.rig import MARKERS, REQUIRED_ANALOGS
from figure_numbers import Panel

SPRING = "spring_stiffness_N_per_m"
COMPONENTS = ("knee", "exoskeleton", "interface", "spring", "frame")


class Phantom:
    """The phantom group's tables."""

    def __init__(self, results: Path, config: dict):
        folder = results / "phantom"
        self.folder, self.config = folder, config
        self.curves = tables.read_table(folder / "curves.parquet").data
        self.summary = pd.read_csv(folder / "summary.csv")
        self.outliers = pd.read_csv(folder / "outliers.csv")
        self.springs = sorted(self.curves[SPRING].unique())
        protocol = config["phantom"]["protocol"]
        self.clutch = (protocol["clutch_on_pct"], protocol["clutch_off_pct"])
        self.work_pct = 100.0 * protocol["work_window_s"] / protocol["stride_time_s"]

    def metric(self, name: str) -> pd.DataFrame:
        rows = self.summary[self.summary["metric"] == name]
        return rows.set_index(SPRING).loc[self.springs]

    def curve(self, spring, upto=None) -> pd.DataFrame:
        rows = self.curves[self.curves[SPRING] == spring]
        return rows if upto is None else rows[rows["gait_cycle_pct"] <= upto]

    def mean_curves(self, signal: str, upto=None) -> Panel:
        """Mean line and ± SD band of one signal per spring (``curves.parquet``)."""
        panel = Panel()
        for spring in self.springs:
            rows = self.curve(spring, upto)
            x, mean, sd = rows["gait_cycle_pct"], rows[f"mean_{signal}"], rows[f"sd_{signal}"]
            panel.line(x, mean).band(x, mean - sd, mean + sd)
        return panel

    def flagged(self, metric: str, panel: Panel) -> Panel:
        """The strides flagged as outliers in ``metric`` (``outliers.csv``), at their spring's bar
        and their value: one marker series, none without outliers."""
        rows = self.outliers[self.outliers["metric"] == metric]
        if len(rows):
            panel.line([self.springs.index(s) for s in rows[SPRING]], rows["value"])
        return panel

    def bars(self, metric: str, panel: Panel | None = None) -> Panel:
        """Mean ± SD bars per spring (``summary.csv``) and the metric's outlying strides."""
        panel = panel or Panel()
        rows, x = self.metric(metric), np.arange(len(self.springs))
        mean, sd = rows["mean"].to_numpy(), rows["sd"].to_numpy()
        panel.bars(x, mean).errorbar(x, mean, mean - sd, mean + sd, line=False)
        return self.flagged(metric, panel)

    def figure(self, name: str) -> list[Panel]:
        return getattr(self, name)()

    def fig05_kinematics(self):
        return [
            self.mean_curves("phantom_knee_angle_deg"),
            self.bars("phantom_stance_flexion_deg"),
            self.mean_curves("exo_knee_angle_deg"),
            self.bars("exo_stance_flexion_deg"),
        ]

    def fig06_kinetics(self):
        return [self.mean_curves("knee_moment_Nm"), self.bars("peak_moment_Nm")]

    def fig07_assistance(self):
        out = []
        for who in ("phantom", "exo"):
            loops = Panel()
            for spring in self.springs:
                rows = self.curve(spring)
                rows = rows[rows["gait_cycle_pct"].between(*self.clutch)]
                loops.line(rows[f"mean_{who}_knee_angle_deg"], rows["mean_knee_moment_Nm"])
            out += [loops, self.bars(f"{who}_stiffness_Nm_per_rad")]
        return out

    def fig08_power_by_spring(self):
        out = []
        for spring in self.springs:
            rows, panel = self.curve(spring, self.work_pct), Panel()
            for component in COMPONENTS:
                mean = rows[f"mean_power_{component}_W"]
                sd = rows[f"sd_power_{component}_W"]
                panel.line(rows["gait_cycle_pct"], mean).band(
                    rows["gait_cycle_pct"], mean - sd, mean + sd
                )
            out.append(panel)
        return out

    def fig09_power_by_component(self):
        return [self.mean_curves(f"power_{c}_W", self.work_pct) for c in COMPONENTS]

    def fig10_work(self):
        out = []
        for component in COMPONENTS:
            panel = self.flagged(f"work_{component}_net_J", Panel())
            for kind in ("positive", "negative"):
                self.bars(f"work_{component}_{kind}_J", panel)
            net = self.metric(f"work_{component}_net_J")["mean"].to_numpy()
            for x, value in enumerate(net):
                panel.line([x - 0.4, x + 0.4], [value, value]).line([x - 0.4, x + 0.4], [value] * 2)
            out.append(panel)
        return out

    def fig11_relative_work(self):
        out = {}
        summary = self.summary.set_index(["metric", SPRING])["mean"]
        for column, spring in enumerate(self.springs):
            for row, kind in enumerate(("positive", "negative")):
                values = np.array(
                    [abs(summary[(f"work_{p}_{kind}_J", spring)]) for p in
                     ("interface", "spring", "frame")]
                )  # fmt: skip
                shares = values / values.sum()
                panel = Panel()
                panel.wedges += list(shares)
                # the percentages written inside the wedges (pie: from 90°, counterclockwise)
                middle = np.deg2rad(90.0 + 360.0 * (np.cumsum(shares) - shares / 2))
                panel.numbers += [(0.7 * np.cos(a), 0.7 * np.sin(a), f"{100 * v:.0f}%")
                                  for a, v in zip(middle, shares, strict=True)]  # fmt: skip
                out[(row, column)] = panel
        return [out[key] for key in sorted(out)]

    def reference_mean_cycle(self):
        cycle = tables.read_table(self.folder / "reference" / "mean_cycle.parquet").data
        return [Panel().line(cycle["gait_cycle_pct"], cycle["knee_flexion_deg"])]

    def qc(self):
        manifest = pd.read_csv(self.folder.parents[1] / "raw" / "phantom" / "manifest.csv")
        springs = manifest.set_index("trial")[SPRING]
        trials = sorted(springs.index, key=lambda t: (springs[t], t))  # by spring rate
        channels = [*MARKERS, *REQUIRED_ANALOGS]
        filled, left, glitches = (np.zeros((len(trials), len(channels))) for _ in range(3))
        reasons = []
        for row, trial in enumerate(trials):
            events = tables.read_table(self.folder / "qc" / f"{trial}.parquet").data
            for event in events.itertuples():
                column = channels.index(event.channel)
                (filled if event.repair == "filled" else left)[row, column] += 1
                glitches[row, column] += event.kind != "dropout"
            strides = tables.read_table(self.folder / "strides" / f"{trial}.parquet").data
            reasons.append(strides["exclusion_reason"].replace("", "included").value_counts())
        events = Panel()
        events.images.append(np.where(glitches > 0, glitches, np.nan))
        for (row, column), count in np.ndenumerate(filled + left):
            if count:
                text = f"{filled[row, column]:.0f}" + (
                    f"/{left[row, column]:.0f}" if left[row, column] else ""
                )
                events.numbers.append((column, row, text))
        counts = pd.DataFrame(reasons, index=trials).fillna(0.0)
        order = ["included", *sorted(c for c in counts.columns if c != "included")]
        bars, start = Panel(), np.zeros(len(trials))
        for reason in order:
            width = counts[reason].to_numpy()
            if width.any():
                bars.rects += [
                    (s, y - 0.3, w, 0.6) for y, (s, w) in enumerate(zip(start, width, strict=True))
                ]
                start = start + width
        return [events, bars]

    def discrepancy(self):
        predictions = tables.read_table(self.folder / "discrepancy_predictions.parquet").data
        report = json.loads((self.folder / "discrepancy.json").read_text())
        reported = json.loads((self.folder / "discrepancy_reported.json").read_text())
        paper = pd.read_csv(self.folder.parents[1] / "raw" / "reference" / "seed000_reported.csv")
        # (a) summary.csv's peak stance moment, seed 000's medians, the model fitted to them
        peak = self.metric("peak_moment_Nm")
        kn = np.asarray(self.springs) / 1000
        a = Panel().errorbar(kn, peak["median"], peak["q1"], peak["q3"])
        paper = paper[paper["metric"] == "peak_moment_Nm"]
        a.line(paper[SPRING] / 1000, paper["value"])
        fitted = pd.DataFrame(reported["predictions"])
        a.line(fitted[SPRING] / 1000, fitted["peak_moment_Nm"])
        # (b) each model's RMS error per spring over the engine's window and its strides
        b = Panel()
        sample = predictions[predictions["fitted"]]
        for model in ("baseline", "extended"):
            error = sample[f"{model}_moment_Nm"] - sample["measured_moment_Nm"]
            rms = np.sqrt((error**2).groupby(sample[SPRING]).mean())
            b.line(rms.index / 1000, rms)
        # (c) every estimate, relative to itself, with its interval
        c = Panel()
        entries = [*report["effects_found"], *report["tentative"], *report["discovery"]["named"],
                   *report["discovery"]["proposed"]]  # fmt: skip
        medians = {k: v for e in reported["effects_found"] + reported["tentative"]
                   for k, v in e["parameters"].items()}  # fmt: skip
        row = 0
        for entry in entries:
            for name, value in entry["parameters"].items():
                low, high = entry["ci95"][name]
                ends = [(low - value) / abs(value) * 100, (high - value) / abs(value) * 100]
                c.line(ends, [row, row]).line(ends, [row, row]).line([0.0], [row])
                if name in medians:
                    c.line([(medians[name] - value) / abs(value) * 100], [row])
                row += 1
        # (d, e) every stride's measured loop of the softest and stiffest spring (every included
        # stride, not the engine's sample) and the mean loops
        loops = []
        for spring in (min(self.springs), max(self.springs)):
            rows = predictions[predictions[SPRING] == spring]
            mean = rows.groupby("t_s").mean(numeric_only=True)
            panel = Panel()
            for _, stride in rows.groupby(["trial", "stride"]):
                panel.line(np.rad2deg(stride["phantom_knee_angle_rad"]),
                           stride["measured_moment_Nm"])  # fmt: skip
            for model in ("measured", "baseline", "extended"):
                panel.line(np.rad2deg(mean["phantom_knee_angle_rad"]), mean[f"{model}_moment_Nm"])
            loops.append(panel)
        return [a, b, c, *loops]

    def discrepancy_terms(self):
        predictions = tables.read_table(self.folder / "discrepancy_predictions.parquet").data
        report = json.loads((self.folder / "discrepancy.json").read_text())
        sample = predictions[predictions["fitted"]]  # the engine's strides
        residual = sample["measured_moment_Nm"] - sample["extended_moment_Nm"]
        mean = residual.groupby([sample[SPRING], sample["t_s"]]).mean()
        panel = Panel()
        times = np.sort(predictions["t_s"].unique())
        noise = report["noise_scales"]["moment_Nm"]
        panel.band(times, np.full(len(times), -noise), np.full(len(times), noise))
        for spring in self.springs:
            panel.line(times, mean.loc[spring].loc[times])
        assert not report["discovery"]["named"] and not report["discovery"]["proposed"]
        return [panel]  # the small run discovers no term (the synthetic verdicts draw them)


def cycle_mean(samples: pd.DataFrame, column: str) -> tuple[np.ndarray, np.ndarray, int]:
    """Mean and SD of ``column`` over every complete step (heel strike to heel strike) on
    101 points of the gait cycle, and the number of steps."""
    strikes = np.flatnonzero(samples["heel_strike"].to_numpy())
    values = samples[column].to_numpy()
    grid = np.linspace(0.0, 100.0, 101)
    steps = np.array([np.interp(grid, np.linspace(0.0, 100.0, b - a), values[a:b])
                      for a, b in itertools.pairwise(strikes)])  # fmt: skip
    return steps.mean(axis=0), steps.std(axis=0), len(steps)


def emulator(root: Path, name: str) -> list[Panel]:
    """The emulator figures from ``summary.csv``, ``energy_per_step.parquet``, ``qc.json``, the
    per-trial samples and Heer's values (``seed002_reported.csv``)."""
    folder = root / "results" / "emulator"
    summary = pd.read_csv(folder / "summary.csv")
    manifest = pd.read_csv(root / "raw" / "emulator" / "manifest.csv")
    conditions = manifest.sort_values(["speed_m_per_s", "stiffness_Nm_per_rad"])
    samples = {t: tables.read_table(folder / "samples" / f"{t}.parquet").data
               for t in manifest["trial"]}  # fmt: skip
    grid = np.linspace(0.0, 100.0, 101)
    if name == "energy_per_step":
        return emulator_energy(folder, root, summary, conditions)
    if name == "angle_torque":
        speeds = sorted(conditions["speed_m_per_s"].unique())
        angle, torque = [Panel() for _ in speeds], [Panel() for _ in speeds]
        for column, speed in enumerate(speeds):
            for trial in conditions.loc[conditions["speed_m_per_s"] == speed, "trial"]:
                angle[column].line(grid, cycle_mean(samples[trial], "brace_angle_deg")[0])
                for signal in ("brace_torque_Nm", "desired_torque_Nm"):
                    torque[column].line(grid, cycle_mean(samples[trial], signal)[0])
        return [*angle, *torque]
    if name == "encoder_vs_mocap":
        out = []
        for mocap in ("mocap_angle_deg", "anatomical_angle_deg"):  # as recorded, then aligned
            for trial in conditions["trial"]:
                mean, sd, _ = cycle_mean(samples[trial], mocap)
                panel = Panel().band(grid, mean - sd, mean + sd).line(grid, mean)
                out.append(panel.line(grid, cycle_mean(samples[trial], "brace_angle_deg")[0]))
        return out
    if name == "activity_vs_table61":
        # per speed, every condition (κ = 0 too): the share of steps with the clutch engaged by
        # Table 6.1 (clutch_window) and the share with torque desired (active)
        out = []
        for speed in sorted(conditions["speed_m_per_s"].unique()):
            panel = Panel()
            for trial in conditions.loc[conditions["speed_m_per_s"] == speed, "trial"]:
                for activity in ("clutch_window", "active"):
                    panel.line(grid, cycle_mean(samples[trial], activity)[0])
            out.append(panel)
        return out
    raise KeyError(name)


def emulator_energy(folder: Path, root: Path, summary, conditions) -> list[Panel]:
    """Energy per step over Heer's (clutch) window: (a) every step per speed (dodged), the means
    per speed beside the torque window's, Heer's Table 6.3 cells, the named conditions circled;
    (b) every step less its condition's mean (mJ), ± SD."""
    steps = tables.read_table(folder / "energy_per_step.parquet").data
    qc = json.loads((folder / "qc.json").read_text())["trials"]
    paper = pd.read_csv(root / "raw" / "reference" / "seed002_reported.csv")
    energy = summary.set_index("trial")
    speeds = sorted(conditions["speed_m_per_s"].unique())
    stiffness = conditions.set_index("trial")["stiffness_Nm_per_rad"]
    a, b = Panel(), Panel()
    for index, speed in enumerate(speeds):
        trials = conditions.loc[conditions["speed_m_per_s"] == speed, "trial"]
        mine = steps[steps["trial"].isin(trials)]
        shift = emulator_plots.DODGE * (index - (len(speeds) - 1) / 2)
        a.line(stiffness[mine["trial"]].to_numpy() + shift, mine["energy_active_J"])
        a.line(stiffness[trials], energy.loc[trials, "mean_energy_active_J"])
        a.line(stiffness[trials], energy.loc[trials, "mean_energy_J"])  # the torque window
    cells = paper[paper["metric"] == "mean_energy_per_step_J"]
    for cell in cells.itertuples():
        a.line([cell.stiffness_Nm_per_rad], [cell.value])
    for trial in conditions["trial"]:
        departs = (qc[trial]["table61_crosscheck"].get("share_of_steps_disagreeing") or 0) > 0
        if qc[trial]["encoder_fault"] or departs:
            a.line([stiffness[trial]], [energy.loc[trial, "mean_energy_active_J"]])
    for number, trial in enumerate(conditions["trial"], start=1):
        values = steps.loc[steps["trial"] == trial, "energy_active_J"].to_numpy()
        x = number + (np.linspace(-emulator_plots.SPREAD, emulator_plots.SPREAD, values.size)
                      if values.size > 1 else np.zeros(values.size))  # fmt: skip
        b.line(x, 1000.0 * (values - energy.loc[trial, "mean_energy_active_J"]))
    sd = 1000.0 * energy.loc[conditions["trial"], "sd_energy_active_J"].to_numpy()
    numbers = np.arange(1, len(conditions) + 1)
    b.errorbar(numbers, np.zeros(numbers.size), -sd, sd, line=False)
    return [a, b]


def sts(results: Path, name: str) -> list[Panel]:
    """The sit-to-stand figures from the trajectories, loads, modules and finite-element tables."""
    folder = results / "sts"
    piecewise = tables.read_table(folder / "trajectories.parquet").data
    smooth = tables.read_table(folder / "trajectories_smooth.parquet").data
    loads = tables.read_table(folder / "loads.parquet").data
    joints = ("hip", "knee", "ankle")
    if name == "paths":
        paths = Panel()
        for point in ("C", "B", "A"):
            paths.line(piecewise[f"x{point}_mm"], piecewise[f"y{point}_mm"])
        for t in (0.0, 0.5, 1.0, 1.5, 2.0):
            row = piecewise.iloc[int(np.argmin(np.abs(piecewise["t_s"] - t)))]
            paths.line([0.0, *(row[f"x{p}_mm"] for p in "CBA")],
                       [0.0, *(row[f"y{p}_mm"] for p in "CBA")])  # fmt: skip
        angles = Panel()
        for frame in (piecewise, smooth):
            angles.line(frame["t_s"], np.degrees(frame["phi2_rad"] + frame["phi3_rad"]
                                                 - frame["phi1_rad"]))  # fmt: skip
            for i in (1, 2, 3):
                angles.line(frame["t_s"], np.degrees(frame[f"phi{i}_rad"]))
        return [paths, angles]
    if name == "torques":
        out = []
        for joint in joints:
            panel = Panel()
            for law in ("piecewise", "smooth"):
                rows = loads[loads["law"] == law]
                panel.line(rows["t_s"], rows[f"{joint}_dynamic_Nm"])
            rows = loads[loads["law"] == "smooth"]
            out.append(panel.line(rows["t_s"], rows[f"{joint}_quasistatic_Nm"]))
        return out
    if name == "modules":
        table = tables.read_table(folder / "spring_damper.parquet").data
        fit = json.loads((folder / "spring_damper.json").read_text())
        out = []
        for law in (fit["study_law"], "corrected_study_seat"):  # a row per law, the same task
            rows = table[table["law"] == law]
            for joint in joints:
                panel = Panel().line(rows["t_s"], rows[f"{joint}_required_Nm"])
                for setting in ("configured", "tuned"):
                    for part in ("module", "user"):
                        panel.line(rows["t_s"], rows[f"{joint}_{part}_{setting}_Nm"])
                out.append(panel)
        return out
    if name == "thigh":
        moment, force = Panel(), Panel()
        for law in ("piecewise", "corrected"):
            rows = loads[loads["law"] == law]
            moment.line(rows["t_s"], rows["thigh_bending_moment_Nm"])
            force.line(rows["t_s"], rows["thigh_axial_force_N"])
        return [moment, force]
    if name == "fe":
        field = tables.read_table(folder / "fe_field.parquet").data
        finest = json.loads((folder / "fe.json").read_text())["finest"]
        out = []
        for column, case in (("bending_von_mises_MPa", "bending"),
                             ("compression_von_mises_MPa", "compression")):  # fmt: skip
            panel = Panel()
            panel.images.append(field[column].to_numpy())
            peak = finest[case]["peak"]
            out.append(panel.line([peak["x_mm"]], [peak["y_mm"]]))
        out.append(Panel())
        out[-1].images.append(field["bending_displacement_mm"].to_numpy())
        return out
    raise KeyError(name)


def expected(name: str, root: Path, config: dict) -> list[Panel]:
    """What figure ``name`` ('phantom/fig05_kinematics', …) should draw, from its tables."""
    group, figure = name.split("/")
    if group == "phantom":
        return Phantom(root / "results", config).figure(figure)
    if group == "emulator":
        return emulator(root, figure)
    return sts(root / "results", figure)
