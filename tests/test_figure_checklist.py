"""Every figure of the default target against the publication checklist (tests/figure_checklist.py),
drawn by the package's own figure functions from the small run's tables, the caption file the run
wrote beside it, and the numbers it draws against the tables' (tests/figure_numbers.py)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from matplotlib import pyplot as plt

import figure_checklist as checklist
import figure_numbers
import figure_tables
from conftest import SMALL, SMALL_RUN
from exobench import figures, tables
from exobench.emulator.recordings import acquire
from exobench.emulator.report import plots as emulator_plots
from exobench.phantom import reference
from exobench.phantom.report import discovery_plots, discrepancy_captions
from exobench.phantom.report import plots as phantom_plots
from exobench.sts import plots as sts_plots

# the module's figures stay open while its tests look at them
pytestmark = [
    pytest.mark.slow,
    SMALL_RUN,
    pytest.mark.filterwarnings("ignore:More than 20 figures have been opened"),
]

ALPHA = 0.05  # phantom_statistics' level (the caption files the run wrote must agree)
# The figures whose panels state their window and their strides or steps (the sit-to-stand
# figures show one simulated motion: their panels state the window only).
COUNTED = (
    *(f"phantom/{name}" for name in phantom_plots.FIGURES),
    "emulator/energy_per_step",
    "emulator/angle_torque",
    "emulator/encoder_vs_mocap",
    "emulator/activity_vs_table61",
)
WINDOW_ONLY = ("sts/paths", "sts/torques", "sts/modules", "sts/thigh")
STATIC = ("sts/fe",)  # the thigh link by finite elements: a static model, no time window


def merged(base: dict, override: dict) -> dict:
    """``base`` with ``override``'s values, nested."""
    out = dict(base)
    for key, value in override.items():
        out[key] = merged(base[key], value) if isinstance(value, dict) else value
    return out


def phantom(results: Path, config: dict) -> dict:
    """The phantom group's figures (as phantom_figures, phantom_reference_cycle and the
    discrepancy figure rules draw them) and their captions."""
    folder = results / "phantom"
    drawing = phantom_plots.Figures(
        tables.read_table(folder / "curves.parquet").data,
        pd.read_csv(folder / "summary.csv"),
        pd.read_csv(folder / "stats" / "notation.csv", keep_default_na=False),
        config["phantom"]["protocol"],
        ALPHA,
        pd.read_csv(folder / "outliers.csv"),
    )
    drawn = {f"phantom/{name}": draw(drawing) for name, draw in phantom_plots.FIGURES.items()}
    cycle = tables.read_table(folder / "reference" / "mean_cycle.parquet").data
    drawn["phantom/reference_mean_cycle"] = reference.mean_cycle_figure(cycle)
    drawn.update(discrepancy_figures(results, config))
    manifest = pd.read_csv(results.parent / "raw" / "phantom" / "manifest.csv")
    springs = manifest.set_index("trial")["spring_stiffness_N_per_m"].to_dict()
    checks, strides = (
        {t: tables.read_table(folder / kind / f"{t}.parquet").data for t in manifest["trial"]}
        for kind in ("qc", "strides")
    )
    labels = config["phantom"]["rig"]["labels"]
    drawn["phantom/qc"] = (
        phantom_plots.quality_control(checks, strides, springs, labels),
        phantom_plots.quality_control_caption(
            checks, strides, config["phantom"]["chain"]["max_gap_frames"], springs, labels
        ),
    )
    return drawn


def discrepancy_inputs(results: Path, config: dict) -> tuple:
    """The discrepancy figure's tables, as phantom_discrepancy_figure reads them (the small run
    compares with seed 000)."""
    folder = results / "phantom"
    paper = pd.read_csv(results.parent / "raw" / "reference" / "seed000_reported.csv")
    protocol = config["phantom"]["protocol"]
    return (
        tables.read_table(folder / "discrepancy_predictions.parquet").data,
        json.loads((folder / "discrepancy.json").read_text()),
        pd.read_csv(folder / "summary.csv"),
        {key: protocol[key] for key in ("work_window_s", "stride_time_s")},
        json.loads((folder / "discrepancy_reported.json").read_text()),
        paper[paper["metric"] == discovery_plots.PEAK],
    )


def discrepancy_figures(results: Path, config: dict) -> dict:
    """The discrepancy and terms figures and their captions, as their rules draw them."""
    inputs = discrepancy_inputs(results, config)
    terms = tables.read_table(results / "phantom" / "discrepancy_terms.parquet").data
    return {
        "phantom/discrepancy": (
            discovery_plots.discrepancy(*inputs),
            discrepancy_captions.discrepancy(*inputs),
        ),
        "phantom/discrepancy_terms": (
            discovery_plots.terms_figure(terms, inputs[0], inputs[1]),
            discrepancy_captions.terms(inputs[0], inputs[1]),
        ),
    }


def sts(results: Path) -> dict:
    """The sit-to-stand figures and captions (as sts_figures draws them)."""
    folder = results / "sts"
    names = {"piecewise": "", "smooth": "_smooth", "corrected": "_corrected"}
    drawn = sts_plots.all_figures(
        {law: tables.read_table(folder / f"trajectories{suffix}.parquet").data
         for law, suffix in names.items()},
        tables.read_table(folder / "loads.parquet").data,
        json.loads((folder / "motion_comparison.json").read_text()),
        tables.read_table(folder / "spring_damper.parquet").data,
        json.loads((folder / "beam_check.json").read_text()),
        (json.loads((folder / "fe.json").read_text()),
         tables.read_table(folder / "fe_field.parquet").data,
         tables.read_table(folder / "fe_mesh.parquet").data),
    )  # fmt: skip
    return {f"sts/{name}": value for name, value in drawn.items()}


def emulator(root: Path) -> dict:
    """The emulator figures and captions (as emulator_figures draws them)."""
    folder = root / "results" / "emulator"
    manifest = acquire.read_manifest(root / "raw" / "emulator" / "manifest.csv")
    samples = {
        trial: tables.read_table(folder / "samples" / f"{trial}.parquet").data
        for trial in manifest["trial"]
    }
    qc = json.loads((folder / "qc.json").read_text())["trials"]
    drawn = emulator_plots.all_figures(
        pd.read_csv(folder / "summary.csv"),
        tables.read_table(folder / "energy_per_step.parquet").data,
        samples,
        manifest,
        qc,
        pd.read_csv(root / "raw" / "reference" / "seed002_reported.csv"),
    )
    return {f"emulator/{name}": value for name, value in drawn.items()}


@pytest.fixture(scope="module")
def config(small_run) -> dict:
    """The small run's config (the shipped one with the small protocol)."""
    return merged(yaml.safe_load((small_run / "config" / "config.yaml").read_text()), SMALL)


@pytest.fixture(scope="module")
def drawn(small_run, config) -> dict:
    """Every figure of the small run drawn again from its tables: name -> (figure, caption)."""
    results = small_run / "results"
    out = {**phantom(results, config), **sts(results), **emulator(small_run)}
    yield {name: (fig, figures.caption_text(*caption)) for name, (fig, caption) in out.items()}
    plt.close("all")


FIGURES = (
    *COUNTED,
    *WINDOW_ONLY,
    *STATIC,
    "phantom/reference_mean_cycle",
    "phantom/discrepancy",
    "phantom/discrepancy_terms",
    "phantom/qc",
)


def test_every_figure_of_the_run_is_checked(small_run, drawn):
    folder = small_run / "results" / "figures"
    made = {path.relative_to(folder).with_suffix("").as_posix() for path in folder.rglob("*.png")}
    assert made == set(FIGURES) == set(drawn)


@pytest.mark.parametrize("name", FIGURES)
def test_the_caption_file_beside_the_figure_is_what_its_function_says(small_run, drawn, name):
    path = small_run / "results" / "figures" / f"{name}.caption.md"
    assert path.read_text(encoding="utf-8") == drawn[name][1]


@pytest.mark.parametrize("name", FIGURES)
def test_figure_meets_the_publication_checklist(drawn, name):
    fig, caption = drawn[name]
    assert checklist.check(fig, caption) == []


@pytest.mark.parametrize("name", FIGURES)
def test_the_numbers_drawn_are_the_numbers_of_the_tables(small_run, config, drawn, name):
    """Every line, marker, bar, whisker, band, wedge, cell and number each panel draws is what
    the tables its caption points to give, for the same window and strides, and every number
    they give is drawn (tests/figure_tables.py derives them from the tables)."""
    wanted = figure_tables.expected(name, small_run, config)
    assert figure_numbers.check_figure(drawn[name][0], wanted) == []


@pytest.mark.parametrize("name", (*COUNTED, "phantom/discrepancy"))
def test_every_panel_states_its_window_and_its_strides(drawn, name):
    assert checklist.window_and_strides_missing(drawn[name][0]) == []


@pytest.mark.parametrize("name", WINDOW_ONLY)
def test_every_model_panel_states_its_time_window(drawn, name):
    assert checklist.window_and_strides_missing(drawn[name][0], counted=False) == []


BAR_FIGURES = [f"phantom/{name}" for name in ("fig05_kinematics", "fig06_kinetics",
                                               "fig07_assistance", "fig10_work")]  # fmt: skip


@pytest.mark.parametrize("name", BAR_FIGURES)
def test_no_bar_panel_clips_a_whisker_or_an_outlier(drawn, name):
    """Every whisker's end and every stride flagged as an outlier lies inside its axis, clear
    of its edges, and the caption says so (issue 43: figure 10 clipped whiskers)."""
    fig, caption = drawn[name]
    for ax in figures.panels(fig):
        panel = figure_numbers.read(ax)
        if not panel.rects:
            continue
        ends = [y for a, b in panel.whiskers for y in (a[1], b[1])]
        ends += [y for _, ys in panel.lines for y in ys]
        low, high = ax.get_ylim()
        margin = 0.01 * (high - low)
        assert low + margin < min(ends) and max(ends) < high - margin, ax.get_title()
    assert "nothing is clipped" in caption.replace("\n", " ")


def test_the_checklist_catches_what_issue_30_found():
    """Each fault the issue names, drawn on purpose, is caught."""
    fig, axes = figures.new_figure(2, 1)
    axes[0, 0].plot([3, 22], [5, 50])
    axes[0, 0].set_yscale("log")
    axes[0, 0].set_ylim(1, 1000)  # the data span a third of the axis
    axes[0, 1].bar([0, 1], [1.0, 2.0], yerr=[0.1, 0.2])
    axes[0, 1].annotate("(1)(4)", (0, 1.5))
    axes[0, 1].annotate("overlapping label", (0, 1.5))
    problems = checklist.check(fig, "Bars: mean.\n")
    assert any(p.startswith("data fill") for p in problems)
    assert any(p.startswith("overlap") for p in problems)
    assert "significance marks drawn, not explained" in problems
    assert "error bars drawn, their meaning not stated" in problems
    assert "caption names no panel" in problems
    raw, axes = plt.subplots(1, 2)
    axes[0].plot([3, 22], [5, 50])
    axes[0].set_yscale("log")
    found = checklist.not_plain(raw, checklist.drawn_texts(raw))
    assert any("10^" in p or "times" in p for p in found)
    assert checklist.letters_missing(raw)
    plt.close(fig)
    plt.close(raw)


def test_figure_7_spends_its_axis_on_the_engaged_loops(drawn):
    """The work loops fill their axis: no stretch of zero moment (issue 30)."""
    fig, _ = drawn["phantom/fig07_assistance"]
    for ax in figures.panels(fig)[::2]:
        engaged = np.concatenate(
            [
                line.get_xdata()[abs(line.get_ydata()) > 0.05 * abs(line.get_ydata()).max()]
                for line in ax.lines
            ]
        )
        low, high = ax.get_xlim()
        assert engaged.max() - engaged.min() > 0.8 * (high - low)


@pytest.mark.parametrize("name", (*WINDOW_ONLY, *STATIC))
def test_the_sit_to_stand_texts_stay_inside_the_saved_figure(drawn, name):
    """At the resolution the PNG is saved at (issue 42: panel (c)'s title of torques.png ran
    past the right edge at 150 dpi while it fitted at the screen's 100)."""
    fig, _ = drawn[name]
    fig.set_dpi(figures.STYLE["savefig.dpi"])
    try:
        assert checklist.outside_figure(fig, checklist.drawn_texts(fig)) == []
    finally:
        fig.set_dpi(figures.STYLE["figure.dpi"])


def test_the_fe_figure_marks_each_peak_where_the_report_puts_it(small_run, drawn):
    finest = json.loads((small_run / "results" / "sts" / "fe.json").read_text())["finest"]
    fig, caption = drawn["sts/fe"]
    bending, compression, deflection = figures.panels(fig)
    for ax, case in ((bending, "bending"), (compression, "compression")):
        assert finest[case]["peak"]["where"] in ax.get_title(loc="left")
    assert "bearing" in caption and "fig. 9" in caption
    assert f"{finest['bending']['max_displacement_mm']:.2f} mm" in deflection.get_title(loc="left")


def test_the_paths_figure_says_which_way_the_motion_runs(drawn):
    """Upright at 0 s to seated at 2 s (seed 001's laws): in the caption, in panel (a)'s title
    and panel (b)'s time axis, and an arrow on every joint's path."""
    fig, caption = drawn["sts/paths"]
    paths, angles = figures.panels(fig)
    assert "Time runs from upright at 0 s to seated at 2 s" in caption.replace("\n", " ")
    assert "upright at 0 s → seated at 2 s" in paths.get_title(loc="left")
    assert angles.get_xlabel() == "time (s): upright at 0 s → seated at 2 s"
    arrows = [t for t in paths.texts if getattr(t, "arrow_patch", None) and not t.get_text()]
    assert len(arrows) == 3


def test_the_paths_legend_names_both_laws_and_the_time_labels_stand_apart(drawn):
    fig, _ = drawn["sts/paths"]
    legend = figures.panels(fig)[1].get_legend()
    names = [text.get_text() for text in legend.get_texts()]
    assert any("minimum-jerk" in name for name in names)
    assert any("piecewise" in name for name in names)
    assert not [p for p in checklist.check(fig, "Panel (a).\n") if p.startswith("overlap")]


def test_the_energy_figure_names_the_fault_the_analysis_found(small_run, drawn):
    qc = json.loads((small_run / "results" / "emulator" / "qc.json").read_text())["trials"]
    faulty = [trial for trial, record in qc.items() if record["encoder_fault"]]
    assert faulty  # the default twin drops counts before condition 12
    fig, caption = drawn["emulator/energy_per_step"]
    notes = [t.get_text().replace("\n", " ") for t in figures.panels(fig)[0].get_legend().texts]
    assert any("condition 12" in note and "count drop" in note for note in notes)
    assert "condition 12" in caption


def test_the_energy_figure_draws_heers_values_and_the_spread_of_the_steps(small_run, drawn):
    """Heer's two surviving Table 6.3 cells are markers on (a), named in its legend; on (b) the
    steps of each condition spread about its mean over Heer's (clutch) window as the steps table
    has them."""
    fig, _ = drawn["emulator/energy_per_step"]
    energy, spread = figures.panels(fig)
    heer = [(line.get_xdata()[0], line.get_ydata()[0]) for line in energy.lines
            if line.get_marker() == "D"]  # fmt: skip
    assert sorted(heer) == [(3.5, 0.634), (3.5, 0.836)]
    names = [t.get_text() for t in energy.get_legend().texts]
    assert sum("Heer, condition" in name for name in names) == 2
    steps = tables.read_table(small_run / "results" / "emulator" / "energy_per_step.parquet").data
    spread_mJ = 1000.0 * steps.groupby("trial")["energy_active_J"].std(ddof=0)
    drawn_mJ = [np.std(line.get_ydata()) for line in spread.lines if line.get_marker() == "."]
    assert len(drawn_mJ) == len(spread_mJ)
    assert max(drawn_mJ) == pytest.approx(spread_mJ.max()) and max(drawn_mJ) > 0.5


def test_the_encoder_figure_shows_condition_12s_raw_gap(small_run, drawn):
    """Condition 12's panel as recorded (l) shows its gap: the means drawn, motion capture less
    encoder, exceed condition 11's by the count drop the twin planted before it; aligned (x),
    the drop is gone; a legend names what is drawn."""
    fig, _ = drawn["emulator/encoder_vs_mocap"]
    panels = figures.panels(fig)
    truth = json.loads((small_run / "raw" / "emulator" / "truth" / "v12_k35.json").read_text())

    def gap(ax) -> float:
        mocap, encoder = (np.mean(line.get_ydata()) for line in ax.lines)
        return float(mocap - encoder)

    raw_11, raw_12, aligned_12 = (gap(panels[i]) for i in (10, 11, 23))
    assert panels[11].get_title(loc="left").startswith("(l) raw: 1.2 m/s, κ 3.5")
    assert panels[23].get_title(loc="left").startswith("(x) aligned: 1.2 m/s, κ 3.5")
    assert raw_12 - raw_11 == pytest.approx(truth["encoder_count_drop_deg"], abs=0.5)
    assert raw_12 > 4.0 and abs(aligned_12) < 0.5
    legend = [t.get_text() for t in fig.legends[0].texts]
    assert any("as recorded" in text for text in legend) and any("aligned" in t for t in legend)
