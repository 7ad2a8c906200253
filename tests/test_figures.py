"""The figure writer shared by every group's figure rules."""

from __future__ import annotations

import matplotlib
import pytest
from matplotlib.figure import Figure

from exobench import figures


@pytest.mark.parametrize("user_layout", [False, True])  # a matplotlibrc's constrained layout
def test_each_format_after_the_first_is_drawn_once_with_the_first_layout(
    tmp_path, monkeypatch, user_layout
):
    monkeypatch.setitem(matplotlib.rcParams, "figure.constrained_layout.use", user_layout)
    fig, axes = figures.new_figure(ncols=2)
    for ax in axes.ravel():
        ax.plot([0.0, 1.0, 0.5])
        ax.set_title("knee moment (N·m)")
    draws = []
    original = Figure.draw
    monkeypatch.setattr(Figure, "draw", lambda self, r: (draws.append(1), original(self, r))[1])
    figures.save(fig, tmp_path / "a.png", tmp_path / "a.pdf", tmp_path / "b.png")
    # the first save lays the figure out (one draw) and draws it; each later save draws once
    assert len(draws) == 2 + 2
    assert fig.get_layout_engine() is None
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()  # same layout
