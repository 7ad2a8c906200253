"""The figure writer shared by every group's figure rules."""

from __future__ import annotations

import matplotlib
import matplotlib.pyplot
import pytest
from matplotlib.figure import Figure

from exobench import figures


def _two_panels():
    """A small constrained-layout figure of two titled panels."""
    fig, axes = figures.new_figure(ncols=2)
    for ax in axes.ravel():
        ax.plot([0.0, 1.0, 0.5])
        ax.set_title("knee moment (N·m)")
    return fig


@pytest.mark.parametrize("user_layout", [False, True])  # a matplotlibrc's constrained layout
def test_a_figure_is_laid_out_once_and_each_format_drawn_once_into_matplotlibs_own_bytes(
    tmp_path, monkeypatch, user_layout
):
    monkeypatch.setitem(matplotlib.rcParams, "figure.constrained_layout.use", user_layout)
    fig = _two_panels()
    draws = []
    original = Figure.draw
    monkeypatch.setattr(Figure, "draw", lambda self, r: (draws.append(1), original(self, r))[1])
    figures.save(fig, tmp_path / "a.png", tmp_path / "a.pdf", tmp_path / "b.png")
    assert len(draws) == 3  # one per file: the layout runs without a draw of its own
    assert fig.get_layout_engine() is None
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()  # same layout
    # matplotlib's own save, which lays the figure out in a draw first, writes the same bytes
    reference = figures.finish(_two_panels())
    with matplotlib.pyplot.rc_context(figures.STYLE):
        reference.savefig(tmp_path / "c.png", metadata={"Software": None})
    assert (tmp_path / "c.png").read_bytes() == (tmp_path / "a.png").read_bytes()


def test_a_saved_pdf_is_matplotlibs_own_save(tmp_path):
    """A PDF saved through figures.save holds the bytes matplotlib's own save writes (its font
    subsets as matplotlib makes them: no library is patched)."""
    fig, axes = figures.new_figure()
    axes[0, 0].plot([-1.0, 1.0], [0.0, 2.0])
    axes[0, 0].set_title("stiffness – flexion, difference (N·m)")  # ligatures, an en dash
    figures.save(fig, tmp_path / "a.png", tmp_path / "ours.pdf")
    with matplotlib.rc_context(figures.STYLE):
        fig.savefig(tmp_path / "own.pdf", metadata={"CreationDate": None, "Producer": None})
    ours, own = ((tmp_path / f"{name}.pdf").read_bytes() for name in ("ours", "own"))
    assert ours == own
    assert b"/FontFile2" in ours


def test_finish_writes_plain_ticks_and_letters_each_panel_once():
    fig, axes = figures.new_figure(ncols=2)
    axes[0, 0].plot([3.0, 22.0], [5.0, 50.0])
    axes[0, 0].set_yscale("log")
    axes[0, 1].plot([0.0, 1.0], [10000.0, 10001.0])  # an offset (+1e4) by default
    axes[0, 1].set_title("work loop")
    figures.finish(figures.finish(fig))
    fig.canvas.draw()
    labels = [
        t.get_text()
        for ax in fig.axes
        for t in (*ax.get_yticklabels(), *ax.get_yticklabels(minor=True))
    ]
    assert "40" in labels and not [t for t in labels if "10^" in t or "times" in t]
    assert axes[0, 1].yaxis.get_offset_text().get_text() == ""
    assert [figures.panel_letter(ax) for ax in fig.axes] == ["(a)", "(b)"]
    assert axes[0, 1].get_title() == "(b) work loop"  # a centred title stays centred


def test_labels_are_placed_apart_from_each_other():
    fig, axes = figures.new_figure()
    axes[0, 0].plot([0.0, 10.0], [0.0, 10.0])
    notes = figures.place_labels(axes[0, 0], [("1.5 s", (5.0, 5.0)), ("2 s", (5.2, 5.1))])
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    first, second = (note.get_window_extent(renderer) for note in notes)
    assert not first.overlaps(second)


def test_a_caption_is_wrapped_paragraphs(tmp_path):
    figures.write_caption(tmp_path / "a.caption.md", "word " * 40, "", "Panel (a): mean.")
    text = (tmp_path / "a.caption.md").read_text()
    assert text.endswith("Panel (a): mean.\n") and "\n\n" in text
    assert max(len(line) for line in text.splitlines()) <= 100
