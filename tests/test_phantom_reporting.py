"""Statistics, summary, reproduction table, figures and report of the phantom group."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from conftest import SMALL_RUN, snakemake
from exobench import tables
from exobench.phantom import reference
from exobench.phantom.chain.metrics import METRIC_COLUMNS
from exobench.phantom.report import plots
from exobench.phantom.study import comparison, significance, statistics

# shares the small run (its tests touch its folder): one pytest-xdist worker runs the group
pytestmark = [pytest.mark.slow, SMALL_RUN]


def test_statistics_tables(small_run):
    stats = small_run / "results/phantom/stats"
    kruskal = pd.read_csv(stats / "kruskal.csv")
    assert list(kruskal.columns) == [
        "metric", "analysis", "H", "df", "p", "n", "epsilon2", "epsilon2_max", "eta2_H",
        "epsilon2_ci_low", "epsilon2_ci_high", "outliers_left_out",
    ]  # fmt: skip
    study = kruskal[kruskal["analysis"] == "as_study"]
    assert list(study["metric"]) == list(METRIC_COLUMNS)
    assert (kruskal["df"] == 5).all()
    assert ((study["epsilon2_ci_low"] < study["epsilon2_ci_high"])
            & (study["epsilon2_ci_low"] >= 0)
            & (study["epsilon2_ci_high"] <= study["epsilon2_max"])).all()  # fmt: skip
    for metric in METRIC_COLUMNS:
        dunn = pd.read_csv(stats / "dunn" / f"{metric}.csv")
        assert list(dunn.columns) == statistics.DUNN_COLUMNS
        pairs = dunn[dunn["analysis"] == "as_study"]
        assert len(pairs) == 15 and (pairs["p_adjust_method"] == "bonferroni").all()
        assert ((pairs["p_adjusted"] >= pairs["p_unadjusted"]) & (pairs["p_adjusted"] <= 1)).all()
        assert ((pairs["cliffs_delta_ci_low"] <= pairs["cliffs_delta"])
                & (pairs["cliffs_delta"] <= pairs["cliffs_delta_ci_high"])).all()  # fmt: skip
    marks = pd.read_csv(stats / "notation.csv", keep_default_na=False)
    assert marks["notation"].str.fullmatch(r"(\(\*\)|(\(\d\))*)").all()
    assert (stats / "kruskal.csv.provenance.json").is_file()


def test_outliers_are_named_in_the_metrics_counted_and_left_out_in_a_sensitivity_row(small_run):
    results = small_run / "results/phantom"
    found = pd.read_csv(results / "outliers.csv")
    metrics = tables.read_table(results / "metrics.parquet").data
    flagged = metrics[metrics["outlier_metrics"] != ""]
    assert (
        flagged.groupby(["trial", "stride"]).ngroups == found.groupby(["trial", "stride"]).ngroups
    )
    for row in found.itertuples():
        stride = metrics[(metrics["trial"] == row.trial) & (metrics["stride"] == row.stride)]
        assert row.metric in stride["outlier_metrics"].iloc[0].split(";")
        assert row.reason in stride["outlier_reason"].iloc[0]
    summary = pd.read_csv(results / "summary.csv")
    assert summary["outliers"].sum() == len(found)
    kruskal = pd.read_csv(results / "stats/kruskal.csv")
    plain = kruskal[kruskal["analysis"] == "without_outliers"]
    assert set(plain["metric"]) == set(found["metric"])
    text = (results / "summary.md").read_text()
    assert "**Outliers**" in text
    assert found.empty or f"{len(found)} values" in text


def test_the_studys_significance_statements_are_compared_and_counted(small_run):
    results = small_run / "results/phantom"
    table = pd.read_csv(results / "significance_comparison.csv")
    statements = reference.read_significance(small_run / "raw/reference/seed000_significance.csv")
    assert set(table["statement"].astype(str)) == set(statements["statement"])
    compared = table[table["agree"].notna()]
    assert set(compared["reproduced"]) <= {"different", "not different"}
    disagree = compared[~compared["agree"].astype(bool)]
    design = disagree["paired"] == disagree["study"]  # the study's decision is the design's
    assert disagree.loc[~design, "cause"].isin(significance.CAUSES).all()
    assert disagree.loc[design, "cause"].fillna("").eq("").all()
    assert disagree.loc[design, "detail"].str.contains("unpaired test misses it").all()
    assert set(compared["paired"]) <= {"different", "not different"}
    alike = compared[compared["study"] == "not different"]
    assert alike["tost_margin"].gt(0).all() and alike["tost_margin_source"].str.len().gt(0).all()
    counted = significance.counts(table)
    text = (results / "summary.md").read_text()
    assert (f"{counted['statements_agree']} of {counted['statements']} statements agree" in text
            and f"{counted['pairs_agree']} of {counted['pairs']} pairs" in text)  # fmt: skip


def test_a_difference_between_the_twins_prediction_and_the_chain_is_a_named_finding(small_run):
    """The method checking itself: every number the twin predicts whose measurement on the
    twin's own recordings differs beyond their uncertainty names the side that is wrong, in
    method_check.csv and in summary.md."""
    results = small_run / "results/phantom"
    table = pd.read_csv(results / "method_check.csv", keep_default_na=False)
    assert len(table) > 20
    combined = np.hypot(table["twin_se"].astype(float), table["chain_se"].astype(float))
    beyond = (table["chain"] - table["twin"]).abs() > table["limit"] * combined
    assert (beyond == table["beyond"]).all()
    text = (results / "summary.md").read_text()
    for row in table[beyond].itertuples():
        assert row.side in {"chain", "twin", "both"}, row.finding
        assert row.finding and row.finding in text
    assert f"in {int(beyond.sum())}" in text


def test_paper_findings_hold_on_the_twin(small_run):
    """Qualitative findings of seed 000 §3 on the default (calibrated) twin."""
    kruskal = pd.read_csv(small_run / "results/phantom/stats/kruskal.csv")
    kruskal = kruskal[kruskal["analysis"] == "as_study"].set_index("metric")
    assert kruskal.loc["phantom_stance_flexion_deg", "p"] > 0.05
    # 20 analysed strides per trial here: the strong effects are significant; interface work
    # (large stride-to-stride spread) is checked by its effect size below.
    for changed in ("exo_stance_flexion_deg", "exo_stiffness_Nm_per_rad"):
        assert kruskal.loc[changed, "p"] < 0.05, changed
    summary = pd.read_csv(small_run / "results/phantom/summary.csv")
    median = summary.pivot(index="metric", columns="spring_stiffness_N_per_m", values="median")
    spring_ratio = 21700 / 3400
    for metric in ("peak_moment_Nm", "phantom_stiffness_Nm_per_rad"):
        ratio = median.loc[metric, 21700.0] / median.loc[metric, 3400.0]
        assert 1.0 < ratio < spring_ratio / 3, (metric, ratio)
    exo = (
        median.loc["exo_stiffness_Nm_per_rad", 21700.0]
        / median.loc["exo_stiffness_Nm_per_rad", 3400.0]
    )
    assert exo > 3.0
    flexion = median.loc["exo_stance_flexion_deg"]
    assert flexion[3400.0] / flexion[21700.0] > 1.8
    interface = median.loc["work_interface_negative_J"]
    assert interface[21700.0] / interface[3400.0] > 1.5


def test_reproduction_table_has_every_reported_number(small_run):
    reported = pd.read_csv(small_run / "raw/reference/seed000_reported.csv")
    table = pd.read_csv(small_run / "results/phantom/paper_comparison.csv", keep_default_na=False,
                        na_values=[""])  # fmt: skip
    assert list(table.columns) == comparison.COLUMNS
    assert len(table) == len(reported)
    assert table["reproduced"].notna().all()
    pd.testing.assert_series_equal(table["metric"], reported["metric"])
    assert (table["abs_error"] == (table["reproduced"] - table["reported"]).abs()).all()
    # the twin's calibration targets are marked, not counted as reproduced
    residuals = pd.read_csv(small_run / "results/phantom/calibration/residuals.csv")
    targets = comparison.calibration_targets(residuals)
    springs = [None if pd.isna(s) else float(s) for s in table["spring_stiffness_N_per_m"]]
    keys = list(zip(table["metric"], springs, strict=True))
    marked = {
        k for k, role in zip(keys, table["role"], strict=True) if role == "calibration target"
    }
    derived = {k for k, role in zip(keys, table["role"], strict=True) if role == "derived"}
    # a target the role rule finds derived from other rows is counted as neither, and marks the
    # rows it is derived from as targets (fitted through it)
    through = marked - (targets - derived)
    assert targets - derived <= marked and derived
    basis = dict(zip(keys, table["role_basis"], strict=True))
    assert all("fit through" in basis[k] for k in through)
    assert (table["tolerance"] >= table["rounding"]).all()
    missed = table[~table["within_tolerance"].astype(bool)]
    assert missed["reason"].fillna("").str.len().gt(0).all()
    got, total = comparison.rate(table, ["prediction"])
    text = (small_run / "results/phantom/summary.md").read_text()
    assert f"{total or 'no'} number{'s' if total != 1 else ''} out of sample" in text
    assert not total or f"{got} reproduced within tolerance" in text


def test_figures_exist_as_png_and_pdf_and_report_builds(small_run):
    folder = small_run / "results/figures/phantom"
    for name in plots.FIGURES:
        png, pdf = folder / f"{name}.png", folder / f"{name}.pdf"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert pdf.read_bytes()[:5] == b"%PDF-"
    snakemake(small_run, "phantom", "--configfile", "small.yaml", "--report", "report.html")
    html = (small_run / "report.html").read_text()
    for name in plots.FIGURES:
        assert f"{name}.png" in html
    assert "paper_comparison.csv" in html


def test_figures_are_byte_identical_on_rerun(small_run):
    folder = small_run / "results/figures/phantom"
    before = {p.name: p.read_bytes() for p in folder.glob("fig*")}
    snakemake(small_run, "phantom_figures", "--configfile", "small.yaml", "--forcerun",
              "phantom_figures")  # fmt: skip
    after = {p.name: p.read_bytes() for p in folder.glob("fig*")}
    assert before == after
