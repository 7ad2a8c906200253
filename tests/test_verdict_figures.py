"""No verdict stops the workflow (issue 34): the discrepancy figure, the terms figure and the
verdict in words draw and write any report the engine may give — estimates of any sign, at a fit
bound or without an interval, no effect at all, structure left unexplained with tentative
estimates and discovered terms — through the rules' own scripts, and name each estimate."""

from __future__ import annotations

import json
import runpy
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from matplotlib import pyplot as plt

import figure_checklist as checklist
from exobench import figures, tables
from exobench.phantom.report import discovery_plots, discrepancy_captions
from exobench.phantom.study import outliers as outlier_rule
from exobench.plumbing import codedeps
from exobench.selection import checks as direct_checks

SCRIPTS = Path(__file__).resolve().parents[1] / "workflow" / "scripts"
SPRING = "spring_stiffness_N_per_m"
SPRINGS = (3400.0, 21700.0)
PROTOCOL = {"work_window_s": 0.9, "stride_time_s": 2.0}


def parameter(name, unit, bounds, meaning):
    return {"name": name, "unit": unit, "bounds": list(bounds), "meaning": meaning}


# The registry and term library the synthetic reports draw from (as the report lists them).
REGISTRY = {
    "interface_compliance": {
        "description": "interface compliance (soft tissue and straps in series between limb "
        "and bars)",
        "observables": ["moment", "exo"],
        "requires": [],
        "parameters": [
            parameter(
                "k_interface_Nm_per_rad",
                "N·m/rad",
                (2.0, 1e5),
                "knee-equivalent interface stiffness",
            )
        ],
    },
    "knee_marker_offset": {
        "description": "knee markers off the joint's axis (the knee centre is misplaced)",
        "observables": ["moment", "exo"],
        "requires": [],
        "parameters": [
            parameter("offset_mm", "mm", (-30.0, 30.0), "knee centre offset along the thigh")
        ],
    },
    "spring_rate": {
        "description": "the spring's real rate differs from the manifest's (a wrong label)",
        "observables": ["moment", "spring", "force"],
        "requires": [],
        "parameters": [parameter("rate_ratio", "1", (0.33, 3.0), "real over stated spring rate")],
    },
    "interface_damping": {
        "description": "interface damping (viscous loss in the soft tissue and straps)",
        "observables": ["moment", "exo"],
        "requires": [],
        "parameters": [
            parameter("c_interface_Nms_per_rad", "N·m·s/rad", (0.0, 50.0), "damping"),
            parameter("c_growth_per_s", "1/s", (-1.0, 1.0), "change of the damping over the trial"),
        ],
    },
}
LIBRARY = {
    "ankle_force_offset": {
        "description": "the ankle load cells read with an offset (on their sum)",
        "observables": ["moment", "swing"],
        "requires": [],
        "parameters": [
            parameter("ankle_offset_N", "N", (-50.0, 50.0), "offset of the vertical ankle force")
        ],
    },
    "ankle_force_drift": {
        "description": "the ankle load cells drift over the trial (on their sum)",
        "observables": ["moment", "swing"],
        "requires": [],
        "parameters": [
            parameter(
                "ankle_drift_N_per_s", "N/s", (-5.0, 5.0), "drift of the vertical ankle force"
            )
        ],
    },
}


def entry(key, values, intervals, term=False):
    """A report entry (an effect, or a discovered term) with its estimates and intervals."""
    spec = (LIBRARY if term else REGISTRY)[key]
    units = {p["name"]: p["unit"] for p in spec["parameters"]}
    out = {
        "term" if term else "effect": key,
        "description": spec["description"],
        "observables": spec["observables"],
        "parameters": dict(values),
        "units": {name: units[name] for name in values},
        "ci95": dict(intervals),
    }
    if term:
        out["gain"] = {"gain_pct": 72.0}
        meaning = {p["name"]: p["meaning"] for p in spec["parameters"]}
        sizes = "; ".join(
            f"{meaning[k]} {v:.3g} [{intervals[k][0]:.3g}, {intervals[k][1]:.3g}] {units[k]}"
            for k, v in values.items()
        )
        out["statement"] = (
            f"Hypothesis for the lab to check: {spec['description']} ({sizes}; "
            "it removes 72 % of the remaining held-out error)."
        )
    return out


FLAGGED = {
    "flag": True,
    "observable": "moment",
    "correlates_with": "trial time",
    "statistic": 9.1,
    "threshold": 3.9,
}


def report(found=(), tentative=(), named=(), proposed=(), unexplained=None) -> dict:
    """A discrepancy report with the keys of ``discrepancy.json``."""
    verdict = unexplained or {
        "flag": False,
        "observable": None,
        "correlates_with": None,
        "statistic": 0.4,
        "threshold": 3.9,
    }
    units = {"moment": "Nm", "exo": "rad", "spring": "m", "force": "N", "swing": "Nm"}
    keys = [f"{o}_{u}" for o, u in units.items()]
    chosen = [e["effect"] for e in (*found, *tentative)]
    test = {
        "observable": "moment",
        "correlates_with": "trial time",
        "decision": "flagged",
        "flag": verdict["flag"],
        "size": 4.0,
        "size_floor": 3.0,
        "statistic": verdict["statistic"],
        "threshold": verdict["threshold"],
    }
    return {
        "baseline": {"loss": 100.0, "model": "rigid theory (seed 000 eqs. 2.1–2.2)"},
        "candidates": [{"effects": chosen, "loss": 1.0, "loss_se": 0.1, "score": 1.0}],
        "cause": "The rigid theory misses the data.",
        "discovery": {
            "library": LIBRARY,
            "named": list(named),
            "proposed": list(proposed),
            "searched": bool(named or proposed),
        },
        "dropped": [],
        "effects_found": list(found),
        "forward_path": [[], chosen],
        "gain": {
            "baseline_loss": 100.0,
            "extended_loss": 1.0,
            "held_out": True,
            "reduction_pct": 99.0,
            "baseline_rmse": dict.fromkeys(keys, 2.5),
            "extended_rmse": dict.fromkeys(keys, 0.125),
        },
        "group": "phantom",
        "intervals": "block bootstrap",
        "noise_scales": dict.fromkeys(keys, 0.02),
        "observable_names": {
            "moment": "knee moment",
            "exo": "exoskeleton-angle change",
            "spring": "spring-length change",
            "force": "spring force",
            "swing": "knee moment in the disengaged swing",
        },
        "observable_order": list(units),
        "observables": units,
        "registry": REGISTRY,
        "selected": chosen,
        "selection": "forward selection",
        "source": "recordings (manifest.csv)",
        "tentative": list(tentative),
        "unexplained": {**verdict, "tests": [test]},
    }


VERDICTS = {
    # the crash of issue 34: a tentative negative offset, structure left unexplained
    "negative estimate": report(
        tentative=[
            entry("knee_marker_offset", {"offset_mm": -13.0}, {"offset_mm": [-15.2, -10.9]})
        ],
        unexplained=FLAGGED,
    ),
    "at a fit bound": report(
        found=[entry("spring_rate", {"rate_ratio": 3.0}, {"rate_ratio": [3.0, 3.0]})]
    ),
    "without an interval": report(
        found=[
            entry(
                "interface_compliance",
                {"k_interface_Nm_per_rad": 60.05},
                {"k_interface_Nm_per_rad": None},
            ),
            entry(
                "interface_damping",
                {"c_interface_Nms_per_rad": 0.6, "c_growth_per_s": 0.0},
                {"c_interface_Nms_per_rad": [0.5, 0.7], "c_growth_per_s": None},
            ),
        ]
    ),
    "no effect": report(),
    "unexplained, tentative, with terms": report(
        tentative=[
            entry(
                "interface_compliance",
                {"k_interface_Nm_per_rad": 60.1},
                {"k_interface_Nm_per_rad": [55.0, 66.0]},
            )
        ],
        named=[
            entry(
                "ankle_force_offset",
                {"ankle_offset_N": -8.6},
                {"ankle_offset_N": [-9.5, -7.7]},
                term=True,
            )
        ],
        proposed=[
            entry(
                "ankle_force_drift",
                {"ankle_drift_N_per_s": 0.02},
                {"ankle_drift_N_per_s": [-0.01, 0.05]},
                term=True,
            )
        ],
        unexplained=FLAGGED,
    ),
}
# The medians' report of a run that compares with seed 000 (a positive estimate of a parameter
# the recordings' report gives negative).
REPORTED = {
    **report(found=[entry("knee_marker_offset", {"offset_mm": 4.0}, {"offset_mm": [2.0, 6.0]})]),
    "predictions": [{SPRING: s, "peak_moment_Nm": 5.0 + s / 5000} for s in SPRINGS],
    "numbers": [
        {
            "name": "peak knee moment",
            SPRING: s,
            "reported": 5.0 + s / 5000,
            "rounding": 0.05,
            "unit": "N·m",
            "baseline": 9.0 + s / 5000,
            "extended": 5.1 + s / 5000,
            "extended_error": 0.1,
        }
        for s in SPRINGS
    ],
}


def predictions() -> pd.DataFrame:
    """Measured, baseline and extended knee moment over a window of 3 strides per spring."""
    t = np.round(np.arange(0.0, 0.45, 0.01), 2)
    rows = pd.MultiIndex.from_product([SPRINGS, (10, 20, 30), t], names=[SPRING, "stride", "t_s"])
    frame = rows.to_frame(index=False)
    phase = np.sin(np.pi * frame["t_s"] / 0.45)
    angle = np.deg2rad(30.0 + 8.0 * phase)
    measured = (4.0 + frame[SPRING] / 5000) * phase + 0.01 * np.cos(frame["stride"] + frame["t_s"])
    return frame.assign(
        trial=[f"k{s:05.0f}" for s in frame[SPRING]],
        phantom_knee_angle_rad=angle,
        measured_moment_Nm=measured,
        baseline_moment_Nm=(2.0 + frame[SPRING] / 4000) * measured,
        extended_moment_Nm=measured + 0.02 * np.sin(40 * frame["t_s"]),
    )[
        [
            "trial",
            SPRING,
            "stride",
            "t_s",
            "phantom_knee_angle_rad",
            "measured_moment_Nm",
            "baseline_moment_Nm",
            "extended_moment_Nm",
        ]
    ]


def summary_table() -> pd.DataFrame:
    """``summary.csv``'s rows of the peak stance moment."""
    median = np.array([5.5, 8.0])
    return pd.DataFrame(
        {
            "metric": "peak_moment_Nm",
            SPRING: SPRINGS,
            "median": median,
            "q1": median - 1.5,
            "q3": median + 2.0,
            "iqr": 3.5,
            "mean": median + 0.3,
            "sd": 2.5,
            "n": [131, 133],
        }
    )


def term_table(verdict: dict) -> pd.DataFrame:
    """``discrepancy_terms.parquet`` for the report's terms: correction and residuals."""
    columns = ["term", "observable", "trial", "stride"] + [
        f"{kind}_{unit}"
        for unit in ("N", "Nm", "m", "rad")
        for kind in ("correction", "residual_before", "residual_after")
    ]
    parts = [pd.DataFrame(columns=columns)]
    rng = np.random.default_rng(3)
    for item in [*verdict["discovery"]["named"], *verdict["discovery"]["proposed"]]:
        correction = rng.normal(0.0, 0.5, 200)
        parts.append(
            pd.DataFrame(
                {
                    "term": item["term"],
                    "observable": "moment",
                    "trial": "k03400",
                    "stride": np.repeat(np.arange(10), 20),
                    "correction_Nm": correction,
                    "residual_before_Nm": correction + rng.normal(0.0, 0.05, 200),
                    "residual_after_Nm": rng.normal(0.0, 0.05, 200),
                }
            )
        )
    table = pd.concat(parts, ignore_index=True)
    return table.astype({c: float for c in columns[4:]} | {"stride": int})


class Named(list):
    """A rule's ``input``, ``output`` or ``params`` as a script sees them: a list of the values
    (lists flattened) whose names are attributes and keys."""

    def __init__(self, mapping):
        flat = [
            v for value in mapping.values() for v in (value if isinstance(value, list) else [value])
        ]
        super().__init__(flat)
        self._names = dict(mapping)

    def __getattr__(self, name):
        try:
            return self.__dict__["_names"][name]
        except KeyError:
            raise AttributeError(name) from None

    def __getitem__(self, key):
        return self._names[key] if isinstance(key, str) else super().__getitem__(key)

    def keys(self):
        return self._names.keys()

    def items(self):
        return self._names.items()


def run_rule(script: str, inputs: dict, outputs: dict, params: dict, folder: Path) -> None:
    """Run a rule's script on ``inputs`` as Snakemake would (a job that fails exits)."""
    log = folder / f"{script}.log"
    smk = type("Job", (), {})()
    code = codedeps.code_param(SCRIPTS / f"{script}.py")
    smk.input, smk.output, smk.log = Named(inputs), Named(outputs), [str(log)]
    smk.params = Named({**params, "code": code})
    smk.rule, smk.config = script, {"results_dir": str(folder)}
    try:
        runpy.run_path(str(SCRIPTS / f"{script}.py"), init_globals={"snakemake": smk})
    except SystemExit as stop:
        raise AssertionError(f"{script} stopped ({stop.code}):\n{log.read_text()}") from None


def written(folder: Path, verdict: dict, reported: dict | None) -> dict:
    """The discrepancy figure, the terms figure and summary.md the three rules write from the
    report (and the medians' report, when the run compares with seed 000)."""
    paths = {
        "recordings": folder / "discrepancy.json",
        "predictions": folder / "discrepancy_predictions.parquet",
        "terms": folder / "discrepancy_terms.parquet",
        "summary": folder / "summary.csv",
    }
    paths["recordings"].write_text(json.dumps(verdict))
    tables.write_table(paths["predictions"], predictions(), {"rule": "test"})
    tables.write_table(paths["terms"], term_table(verdict), {"rule": "test"})
    summary_table().to_csv(paths["summary"], index=False)
    compared = {}
    if reported is not None:
        compared = {
            "reported": folder / "discrepancy_reported.json",
            "paper": folder / "seed000_reported.csv",
        }
        compared["reported"].write_text(json.dumps(reported))
        pd.DataFrame(
            {
                "metric": "peak_moment_Nm",
                SPRING: SPRINGS,
                "value": [5.5, 8.0],
                "unit": "N·m",
                "source": "§3.2",
            }
        ).to_csv(compared["paper"], index=False)
    out = {
        name: {kind: folder / f"{name}.{kind}" for kind in ("png", "pdf", "caption.md")}
        for name in ("discrepancy", "discrepancy_terms")
    }
    run_rule(
        "phantom_discrepancy_figure",
        {**compared, **{k: paths[k] for k in ("predictions", "recordings", "summary")}},
        {f"discrepancy_{k.replace('.md', '')}": v for k, v in out["discrepancy"].items()},
        {"protocol": PROTOCOL, "figures": ["discrepancy"]},
        folder,
    )
    run_rule(
        "phantom_terms_figure",
        {k: paths[k] for k in ("terms", "predictions", "recordings")},
        {
            f"discrepancy_terms_{k.replace('.md', '')}": v
            for k, v in out["discrepancy_terms"].items()
        },
        {"figures": ["discrepancy_terms"]},
        folder,
    )
    checks = folder / "assumption_checks.csv"
    pd.DataFrame(columns=direct_checks.COLUMNS).to_csv(checks, index=False)
    kruskal, outliers = folder / "kruskal.csv", folder / "outliers.csv"
    pd.DataFrame({"metric": ["peak_moment_Nm"], "analysis": ["as_study"], "p": [0.01],
                  "epsilon2": [0.2], "epsilon2_max": [0.97], "epsilon2_ci_low": [0.1],
                  "epsilon2_ci_high": [0.3]}).to_csv(kruskal, index=False)  # fmt: skip
    pd.DataFrame(columns=outlier_rule.COLUMNS).to_csv(outliers, index=False)
    paired, wilcoxon, table = (folder / f for f in ("paired.csv", "wilcoxon.csv", "table.csv"))
    pd.DataFrame({"metric": ["peak_moment_Nm"], "friedman_p": [0.01], "mixed_p": [0.01],
                  "n_trajectories": [100], "trajectory_share": [0.9],
                  "trajectory_share_at_bound": [False], "mixed_p_at_floor": [False],
                  "trials_per_spring": [1],
                  "trial_variance": [float("nan")], "trial_p": [float("nan")]}).to_csv(
        paired, index=False)  # fmt: skip
    pd.DataFrame({"metric": ["peak_moment_Nm"], "p_adjusted": [0.01]}).to_csv(wilcoxon, index=False)
    pd.DataFrame({"metric": ["exo_stiffness_Nm_per_rad"], "spring_stiffness_N_per_m": [3400.0],
                  "invalid": [0]}).to_csv(table, index=False)  # fmt: skip
    verdict_inputs = {"recordings": paths["recordings"], "predictions": paths["predictions"],
                      "checks": checks, "kruskal": kruskal, "outliers": outliers,
                      "paired": paired, "wilcoxon": wilcoxon, "table": table}  # fmt: skip
    if reported is not None:
        fit = folder / "fit.json"
        fit.write_text(json.dumps({"parameters": {"offset_mm": 3.0}}))
        residuals = folder / "residuals.csv"
        pd.DataFrame({"metric": [], "twin": [], "reported": []}).to_csv(residuals, index=False)
        verdict_inputs = {"reported": compared["reported"], "fit": fit, "residuals": residuals,
                          **verdict_inputs}  # fmt: skip
    effects = {"knee_marker_offset": {"enabled": True, "offset_mm": "calibrated"}}
    source = {"acquisition": "files", "group": "phantom", "twin_blocks": ["phantom.twin"],
              "manifest": "<raw_dir>/phantom/manifest.csv", "calibration": None,
              "engine": "discrepancy.json"}  # fmt: skip
    run_rule(
        "phantom_verdict",
        verdict_inputs,
        {"summary": folder / "summary.md", "tests": folder / "residual_tests.md"},
        {
            "effects": effects if reported is not None else {},
            "source": source,
            "robust_z": 10.0,
            "alpha": 0.05,
            "slope_validity": {
                "marker_noise_sd_mm": 0.15,
                "marker_spacing_mm": 140.0,
                "noise_bandwidth_share": 0.12,
                "max_relative_error": 0.1,
            },
        },
        folder,
    )
    return {**out, "summary.md": folder / "summary.md"}


# Every verdict as a lab run; the crash of issue 34 beside seed 000's medians too (the squares,
# the calibration's parameter in the summary).
RUNS = [*((name, False) for name in VERDICTS), ("negative estimate", True)]


@pytest.mark.parametrize(("name", "compared"), RUNS)
def test_any_verdict_is_drawn_and_written_naming_each_estimate(tmp_path, name, compared):
    verdict, reported = VERDICTS[name], REPORTED if compared else None
    out = written(tmp_path, verdict, reported)
    for files in (out["discrepancy"], out["discrepancy_terms"]):
        assert all(path.stat().st_size > 0 for path in files.values())
    caption = out["discrepancy"]["caption.md"].read_text()
    text = out["summary.md"].read_text()
    for row in discovery_plots.estimates(verdict).itertuples():
        value = discovery_plots.plain(row.estimate)
        assert f"{row.effect}" in caption and value in caption, (row.effect, value)
        assert f"{row.estimate:.3g}" in text, (row.estimate, text)
        if row.bound:
            assert f"{row.bound} fit bound" in caption
        if np.isnan(row.low):
            assert "Without an interval" in caption and row.effect in caption
    if [*verdict["discovery"]["named"], *verdict["discovery"]["proposed"]]:
        terms = out["discrepancy_terms"]["caption.md"].read_text()
        assert "Panel (b)" in terms or "Panels (b)" in terms


@pytest.mark.parametrize("name", VERDICTS)
def test_any_verdict_meets_the_publication_checklist(name):
    """Drawn directly by the figure functions: readable whatever the verdict, the estimates
    panel's marks and whiskers where the report puts them, one key entry per kind drawn."""
    verdict = VERDICTS[name]
    inputs = (
        predictions(),
        verdict,
        summary_table(),
        PROTOCOL,
        REPORTED,
        pd.DataFrame({SPRING: SPRINGS, "value": [5.5, 8.0]}),
    )
    fig = discovery_plots.discrepancy(*inputs)
    caption = figures.caption_text(*discrepancy_captions.discrepancy(*inputs))
    problems = checklist.check(fig, caption)
    if not (
        discovery_plots.estimates(verdict)["high"] > discovery_plots.estimates(verdict)["low"]
    ).any():
        # point estimates only (no interval, or one collapsed on a bound): points at 0
        problems = [p for p in problems if not p.startswith("data fill") or "(c)" not in p]
    assert problems == []
    panel = fig.axes[2]  # (c) the estimates
    table = discovery_plots.estimates(verdict)
    labels = [t.get_text() for t in panel.get_yticklabels()]
    assert len(labels) == len(table)
    for row, (item, label) in enumerate(zip(table.itertuples(), labels, strict=True)):
        assert item.effect.split()[0] in label and "_" not in label
        lines = [line for line in panel.lines if list(line.get_ydata()) == [row, row]]
        if np.isnan(item.low):
            assert not lines  # no whisker without an interval
        else:
            ends = discovery_plots.relative([item.low, item.high], item.estimate)
            assert any(np.allclose(line.get_xdata(), ends) for line in lines)
    key = panel.get_legend()
    entries = [] if key is None else [t.get_text() for t in key.get_texts()]
    assert ("fit bound" in " ".join(entries)) == bool((table["bound"] != "").any())
    terms = discovery_plots.terms_figure(term_table(verdict), predictions(), verdict)
    terms_caption = figures.caption_text(*discrepancy_captions.terms(predictions(), verdict))
    assert checklist.check(terms, terms_caption) == []
    plt.close(fig)
    plt.close(terms)
