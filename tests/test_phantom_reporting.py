"""Statistics, summary, reproduction table, figures and report of the phantom group."""

from __future__ import annotations

import pandas as pd
import pytest

from conftest import SMALL_RUN, snakemake
from exobench.phantom.chain.metrics import METRIC_COLUMNS
from exobench.phantom.report import plots

# shares the small run (its tests touch its folder): one pytest-xdist worker runs the group
pytestmark = [pytest.mark.slow, SMALL_RUN]


def test_statistics_tables(small_run):
    stats = small_run / "results/phantom/stats"
    kruskal = pd.read_csv(stats / "kruskal.csv")
    assert list(kruskal.columns) == ["metric", "H", "df", "p", "n"]
    assert set(kruskal["metric"]) == set(METRIC_COLUMNS)
    assert (kruskal["df"] == 5).all()
    for metric in METRIC_COLUMNS:
        matrix = pd.read_csv(stats / "dunn" / f"{metric}.csv", index_col=0)
        assert matrix.shape == (6, 6)
        assert ((matrix.to_numpy() >= 0) & (matrix.to_numpy() <= 1)).all()
    marks = pd.read_csv(stats / "notation.csv", keep_default_na=False)
    assert marks["notation"].str.fullmatch(r"(\(\*\)|(\(\d\))*)").all()
    assert (stats / "kruskal.csv.provenance.json").is_file()


def test_paper_findings_hold_on_the_twin(small_run):
    """Qualitative findings of seed 000 §3 on the default (calibrated) twin."""
    kruskal = pd.read_csv(small_run / "results/phantom/stats/kruskal.csv").set_index("metric")
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
    table = pd.read_csv(small_run / "results/phantom/paper_comparison.csv")
    assert list(table.columns) == [
        "metric", "spring_stiffness_N_per_m", "reported", "reproduced", "unit",
        "abs_error", "rel_error", "source",
    ]  # fmt: skip
    assert len(table) == len(reported)
    assert table["reproduced"].notna().all()
    pd.testing.assert_series_equal(table["metric"], reported["metric"])
    assert (table["abs_error"] == (table["reproduced"] - table["reported"]).abs()).all()


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
