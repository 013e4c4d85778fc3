"""Plots keyed by their inputs: a warm redraw is the stored file, a changed input a
new drawing, and what cannot be keyed is always drawn."""

from pathlib import Path

import numpy as np
import pytest

from flexarm.fe.plotting import picture_from_inputs, pyplot, save_figure

CALLS: list[str] = []


@picture_from_inputs
def _line_plot(path, y, title="", colour=None):
    CALLS.append(title)
    fig, ax = pyplot().subplots(figsize=(3, 2))
    ax.plot(np.asarray(y), color=colour if not callable(colour) else colour())
    ax.set_title(title)
    return save_figure(fig, path, dpi=50)


@pytest.fixture(autouse=True)
def _fresh_calls():
    CALLS.clear()


def test_equal_inputs_are_served_and_a_change_draws_again(tmp_path: Path):
    token = str(tmp_path)  # no earlier run drew this title
    y = np.linspace(0.0, 1.0, 50)
    first = _line_plot(tmp_path / "a.png", y, title=token)
    again = _line_plot(tmp_path / "b.png", y.copy(), title=token)
    assert CALLS == [token]
    assert first == tmp_path / "a.png" and again == tmp_path / "b.png"
    assert again.read_bytes() == first.read_bytes()
    changed = _line_plot(tmp_path / "c.png", y ** 2, title=token)
    assert CALLS == [token, token]
    assert changed.read_bytes() != first.read_bytes()


def test_other_formats_and_unpicklable_inputs_are_always_drawn(tmp_path: Path):
    token = str(tmp_path)
    for _ in range(2):
        _line_plot(tmp_path / "a.svg", [0.0, 1.0], title=token)
        _line_plot(tmp_path / "a.png", [0.0, 1.0], title=token, colour=lambda: "red")
    assert CALLS == [token] * 4
    assert (tmp_path / "a.svg").read_text().lstrip().startswith("<?xml")
