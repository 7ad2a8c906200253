"""``<results_dir>/index.md``: one line for every summary, table and figure a run leaves, from one
registry of glob patterns (relative to the results folder) grouped by group.

Adding an output to a rule means adding its line here: the rule ``results_index`` (the last
of the default target) lists what the results folder holds and fails, naming the files, when
one matches no entry. A pattern's ``*`` also matches across folders; a figure's entry covers
its PNG, PDF and caption. Entries that match no file of the run are left out of the index.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from fnmatch import fnmatchcase
from pathlib import Path

from exobench.errors import InputError

INDEX = "index.md"
REPORT = "report.html"
RUN = "the run"  # what every run leaves; its families are not counted (logs grow while it runs)

# group -> (pattern, what it is), in reading order. A pattern names a file, a family of files
# (per trial or per metric) or the three files of a figure (png, pdf, caption.md).
ENTRIES: dict[str, tuple[tuple[str, str], ...]] = {
    "phantom": (
        (
            "phantom/summary.md",
            "the verdict in words: source, what the rigid theory gets "
            "wrong, set against recovered, what is left, the study's statistics and numbers "
            "reproduced, the direct checks",
        ),
        ("phantom/residual_tests.md", "every residual test of the engine in plain words"),
        (
            "phantom/summary.csv",
            "median, quartiles, IQR, mean, SD, n and outliers per spring "
            "and metric (included strides)",
        ),
        (
            "phantom/paper_comparison.csv",
            "every number W.S.B. et al. report against the "
            "reproduced one: role by exobench.roles (calibration target, setting, derived, "
            "prediction) with its basis, tolerance, reason for a miss",
        ),
        (
            "phantom/significance_comparison.csv",
            "W.S.B. et al.'s significance statements "
            "against the reproduced unpaired (Dunn) and paired (Wilcoxon, Friedman, mixed model) "
            "tests, pair by pair, TOST of the 'not different' pairs, and the cause of a "
            "disagreement",
        ),
        (
            "phantom/method_check.csv",
            "the twin's prediction of each number against the "
            "chain's measurement of its recordings, and which side is wrong (with the twin)",
        ),
        (
            "phantom/stats/kruskal.csv",
            "Kruskal–Wallis per metric: H, df, p, n, ε² (with its maximum), η²_H "
            "with their 95 % bootstrap interval; as the study, and without outliers",
        ),
        (
            "phantom/stats/dunn/*.csv",
            "Dunn's tests per metric, one row per spring pair: z, p "
            "unadjusted and Bonferroni-adjusted, Cliff's δ with its interval at the "
            "Bonferroni level 1 − α/m",
        ),
        ("phantom/stats/notation.csv", "the study's significance marks per spring and metric"),
        (
            "phantom/stats/paired.csv",
            "the design run, per metric: Friedman (Kendall's W), mixed model y ~ spring + "
            "(1 | trajectory), trial as a random effect (or the one-trial confound)",
        ),
        (
            "phantom/stats/wilcoxon.csv",
            "paired Wilcoxon tests per metric and spring pair (Bonferroni), the share of "
            "trajectories higher with its interval at the adjusted level",
        ),
        (
            "phantom/outliers.csv",
            "every stride value beyond the robust-z threshold, with its reason",
        ),
        ("phantom/metrics.parquet", "per-stride metrics of every trial, inclusion and outliers"),
        ("phantom/curves.parquet", "mean and SD curves over the gait cycle per spring"),
        ("phantom/assumption_checks.csv", "direct checks of the rig's assumptions"),
        ("phantom/discrepancy.json", "the model-discrepancy engine's report on the recordings"),
        (
            "phantom/discrepancy_predictions.parquet",
            "measured, rigid-theory and extended-model "
            "knee moment over every included stride's window (`fitted`: the engine's sample)",
        ),
        ("phantom/discrepancy_terms.parquet", "the corrections of the discovered terms"),
        (
            "phantom/discrepancy_reported.json",
            "the engine on the medians W.S.B. et al. report, "
            "each held out, with its stated uncertainty",
        ),
        ("phantom/calibration/fit.json", "the twin's calibration to W.S.B. et al.'s medians"),
        (
            "phantom/calibration/residuals.csv",
            "the calibration targets and the twin's own prediction of each",
        ),
        (
            "phantom/calibration/strides.parquet",
            "the calibrated twin's simulated strides (the spread behind its medians)",
        ),
        (
            "phantom/method/truth_metrics.parquet",
            "the twin's true per-stride metrics (the method check's reference)",
        ),
        ("phantom/reference/mean_cycle.parquet", "the reference mean knee-flexion cycle"),
        ("phantom/acquired/*.parquet", "per trial: markers, analog and events as acquired"),
        (
            "phantom/filtered/*.parquet",
            "per trial: gap-filled, filtered markers (100 Hz) and analog",
        ),
        ("phantom/angles/*.parquet", "per trial: knee angles and spring length"),
        ("phantom/strides/*.parquet", "per trial: strides, inclusion and exclusion reason"),
        ("phantom/qc/*.parquet", "per trial: every glitch, dropout and saturated run"),
        ("phantom/moments/*.parquet", "per trial: knee moment and its sensitivities"),
        ("phantom/kinetics/*.parquet", "per trial: power partition of the analysed strides"),
        ("figures/phantom/fig05_kinematics.*", "figure 5: knee kinematics per spring"),
        ("figures/phantom/fig06_kinetics.*", "figure 6: knee moment and peak stance moment"),
        ("figures/phantom/fig07_assistance.*", "figure 7: work loops and stiffness"),
        ("figures/phantom/fig08_power_by_spring.*", "figure 8: power per component, by spring"),
        ("figures/phantom/fig09_power_by_component.*", "figure 9: power per spring, by component"),
        ("figures/phantom/fig10_work.*", "figure 10: positive, negative and net work"),
        ("figures/phantom/fig11_relative_work.*", "figure 11: shares of the work"),
        ("figures/phantom/qc.*", "quality control: events per channel, strides kept"),
        ("figures/phantom/reference_mean_cycle.*", "the reference mean knee cycle"),
        ("figures/phantom/discrepancy.*", "measured against rigid theory and extended model"),
        ("figures/phantom/discrepancy_terms.*", "what the extended model leaves; terms found"),
    ),
    "sts": (
        (
            "sts/summary.md",
            "the verdict in words: source (the model only), the study's motion laws against its "
            "own words and balance, the corrected laws and their gains, the thigh link by finite "
            "elements against the beam formulas and the study's numbers",
        ),
        ("sts/checks.csv", "every check of every motion law: value, expected, decision, basis"),
        ("sts/corrected_laws.json", "the corrected laws' postures and what sets them"),
        ("sts/readings.json", "every reading of the study's law: what rejects it, the verdict"),
        ("sts/study_comparison.csv", "the study's numbers beside the project's, with roles"),
        ("sts/sections.csv", "the section search's candidates, confirmed by finite elements"),
        (
            "sts/trajectories_corrected_study_seat.parquet",
            "sit-to-stand joint trajectories (corrected law, the study's seat)",
        ),
        ("sts/trajectories.parquet", "sit-to-stand joint trajectories (piecewise law)"),
        ("sts/trajectories_smooth.parquet", "sit-to-stand joint trajectories (smooth law)"),
        ("sts/trajectories_corrected.parquet", "sit-to-stand joint trajectories (corrected laws)"),
        ("sts/verification.json", "kinematics checked against the closed vector loop"),
        ("sts/loads.parquet", "joint loads over the motion"),
        ("sts/motion_comparison.json", "the two motion laws compared"),
        ("sts/spring_damper.json", "the tuned spring–damper modules"),
        ("sts/spring_damper.parquet", "module torques over the motion"),
        ("sts/beam_check.json", "the thigh link's strength against the study's FEA"),
        (
            "sts/fe.json",
            "the thigh link by finite elements: peaks, deflection, mesh convergence, the closed-"
            "form checks, the beam formulas against it and the loadings tested against the study",
        ),
        ("sts/fe_field.parquet", "the finite-element von Mises field (bending and compression)"),
        ("sts/fe_mesh.parquet", "the finite-element mesh the field is on"),
        ("figures/sts/paths.*", "figure: joint paths"),
        ("figures/sts/torques.*", "figure: joint torques"),
        ("figures/sts/modules.*", "figure: spring–damper modules"),
        ("figures/sts/thigh.*", "figure: the thigh link's strength"),
        ("figures/sts/fe.*", "figure: the thigh link's von Mises field (the study's fig. 9)"),
    ),
    "emulator": (
        ("emulator/summary.md", "the verdict in words"),
        ("emulator/residual_tests.md", "every residual test of the engine in plain words"),
        ("emulator/summary.csv", "energy per step per condition"),
        ("emulator/energy_per_step.parquet", "energy stored per step"),
        ("emulator/qc.json", "quality control of every trial"),
        ("emulator/assumption_checks.csv", "direct checks of the rig's assumptions"),
        ("emulator/qc/*.json", "per trial: quality control"),
        ("emulator/discrepancy.json", "the model-discrepancy engine's report"),
        ("emulator/budget.json", "motor and gearhead budget"),
        (
            "emulator/heer_comparison.csv",
            "every number of Heer's thesis the group computes beside the project's: role (twin "
            "setting, calibration target, prediction), tolerance, reason for a miss",
        ),
        ("emulator/samples/*.parquet", "per trial: the analysed samples"),
        ("emulator/steps/*.parquet", "per trial: the steps and their energy"),
        ("figures/emulator/energy_per_step.*", "figure: energy stored per step"),
        ("figures/emulator/angle_torque.*", "figure: torque against angle"),
        ("figures/emulator/encoder_vs_mocap.*", "figure: encoder against motion capture"),
        (
            "figures/emulator/activity_vs_table61.*",
            "figure: recorded spring activity against Table 6.1 per gait phase",
        ),
    ),
    "validation (rules validate_*, not in the default target)": (
        ("validation/cases/*.csv", "phantom engine validation: cases per batch"),
        ("validation/openworld/*", "open-world validation: cases and summary"),
        ("validation/discrepancy.csv", "phantom engine validation: every case"),
        ("validation/summary.csv", "phantom engine validation: summary"),
        ("validation/emulator/*", "emulator engine validation: cases and summary"),
        ("figures/validation/*", "validation figures"),
    ),
    RUN: (
        (INDEX, "this index"),
        (REPORT, "the HTML report of every figure and table, once built (below)"),
        (
            "*.provenance.json",
            "beside every CSV, JSON and Markdown output: its provenance "
            "(rule, inputs' sha256, config and code hashes); Parquet files carry it inside",
        ),
        ("logs/*", "each rule's log, one folder per rule and one file per job"),
        ("benchmarks/*", "each rule's Snakemake benchmark (seconds, memory)"),
    ),
}
# Present only while a run is going (one writer per results folder), never listed.
TRANSIENT = {".exobench.lock"}


def entry(relative: str) -> tuple[str, str, str] | None:
    """The first entry (group, pattern, line) whose pattern matches a results-relative path."""
    for group, rows in ENTRIES.items():
        for pattern, line in rows:
            if fnmatchcase(relative, pattern):
                return group, pattern, line
    return None


def results_files(results: Path) -> list[str]:
    """Every file under the results folder but the transient ones, as sorted POSIX paths
    relative to it."""
    found = (p.relative_to(results).as_posix() for p in results.rglob("*") if p.is_file())
    return sorted(f for f in found if f not in TRANSIENT)


def unlisted(files: Iterable[str]) -> list[str]:
    """The files no entry describes."""
    return [f for f in files if entry(f) is None]


def grouped(files: Sequence[str]) -> dict[str, dict[tuple[str, str], list[str]]]:
    """group -> (pattern, line) -> the files it matches, in the registry's order."""
    out: dict[str, dict[tuple[str, str], list[str]]] = {}
    for path in files:
        found = entry(path)
        if found is not None:
            group, pattern, line = found
            out.setdefault(group, {}).setdefault((pattern, line), []).append(path)
    return {g: {k: out[g][k] for k in ENTRIES[g] if k in out[g]} for g in ENTRIES if g in out}


def render(files: Sequence[str]) -> str:
    """index.md: how to build the HTML report, then per group one line per entry with files."""
    lines = [
        "# What this results folder holds",
        "",
        "One line per summary, table and figure of the run (a family of per-trial or per-metric "
        "files, or a figure's PNG, PDF and caption, is one line). Start with each group's "
        "verdict: `phantom/summary.md`, `sts/summary.md` and `emulator/summary.md`.",
        "",
        "The HTML report of every figure and table with its caption: from the project's folder, "
        "`.venv/bin/snakemake --report results/report.html` (with `--config results_dir=…` when "
        "the results live elsewhere).",
        "",
    ]
    for group, entries in grouped(files).items():
        lines += [f"## {group}", ""]
        for (pattern, line), matched in entries.items():
            if len(matched) == 1 and matched[0] == pattern:
                name = f"[`{pattern}`]({pattern})"
            elif group == RUN:
                name = f"`{pattern}`"
            else:
                name = f"`{pattern}` ({len(matched)} files)"
            lines.append(f"- {name}: {line}")
        lines.append("")
    return "\n".join(lines).rstrip() + "\n"


def build(results: Path) -> str:
    """The index of a results folder; bad input (:class:`InputError`) naming every file no entry
    of :data:`ENTRIES` describes."""
    files = [f for f in results_files(results) if f != INDEX] + [INDEX]
    missing = unlisted(files)
    if missing:
        raise InputError(
            results,
            "results index",
            "every file described by an entry of exobench.plumbing.results_index.ENTRIES (add "
            "the new output's line there)",
            ", ".join(missing),
        )
    return render(sorted(files))
