"""The report of a static comparison at any size: per-series panels for a few series,
panels per pose and load direction with measured bands past many readings, a residual
density, poses found by their joint angles when labels do not name them, and a table
summarised per pose and direction that holds the series' numbers."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from flexarm.validation.data.measurements import StaticData
from flexarm.validation.static import compare, plots, report
from flexarm.validation.static.compare import compare_static
from flexarm.validation.static.report import binned, write_report


@pytest.fixture()
def small_limits(monkeypatch):
    """Thresholds a test's few hundred readings cross."""
    small = dataclasses.replace(compare.tol, plot_max_points=50, plot_max_panels=4,
                                table_max_rows=10)
    for module in (compare, plots, report):
        monkeypatch.setattr(module, "tol", small)
    return small


def _series(demo, labels, n_steps=6):
    """Series ``labels`` of ``n_steps`` loads along +y (odd ones at pose P2, else P1)."""
    robot = demo[0]
    rows = len(labels) * n_steps
    q = np.repeat([robot.pose("P2") if k % 2 else robot.pose("P1")
                   for k in range(len(labels))], n_steps, axis=0)
    force = np.zeros((rows, 3))
    force[:, 1] = np.tile(np.arange(n_steps) * 150.0, len(labels))
    disp = np.random.default_rng(2).normal(size=(rows, 3)) * 2e-5
    disp[::n_steps] = 0.0
    return StaticData(series=np.repeat(labels, n_steps), steps=np.tile(np.arange(n_steps),
                                                                        len(labels)),
                      q=q, force=force, disp=disp)


def test_binned_bands_are_the_percentiles_per_load_level():
    x = np.repeat([0.0, 100.0, 250.0], 201)
    y = np.column_stack([np.tile(np.arange(201.0), 3), -np.tile(np.arange(201.0), 3)])
    centres, lo, mid, hi = binned(x, y)
    assert centres.tolist() == [0.0, 100.0, 250.0]
    assert lo[:, 0].tolist() == [10.0] * 3 and mid[:, 0].tolist() == [100.0] * 3
    assert hi[:, 1].tolist() == [-10.0] * 3
    centres, *_ = binned(np.linspace(0, 1, 1000), np.ones((1000, 1)), n_bins=4)  # equal bins
    assert centres.tolist() == [0.125, 0.375, 0.625, 0.875]


def test_poses_by_joint_angles_when_labels_do_not_name_them(demo, small_limits):
    cmp = compare_static(demo[1], _series(demo, [f"run{k}" for k in range(12)]))
    names, of_series = cmp.pose_groups()
    assert of_series.tolist() == [0, 1] * 6 and all(n.startswith("q=") for n in names)
    summary = cmp.summary()
    assert [(r[1], r[2]) for r in summary] == [("+y", 6), ("+y", 6)]
    for k, row in enumerate(summary):
        mine = [r for r, g in zip(cmp.table, of_series, strict=True) if g == k]
        assert row[3] == pytest.approx(np.mean([r.mean_abs_mm for r in mine]), rel=1e-12)
        assert row[4] == max(r.max_abs_mm for r in mine)
    text = cmp.text()
    assert "12 series: one row per pose and load direction" in text
    assert len(text.splitlines()) == 2 + 2 + 2  # head, rule, two groups, note, chi2


def test_many_readings_draw_bands_and_a_density(demo, small_limits, figures, tmp_path):
    cmp = compare_static(demo[1], _series(demo, [f"P{k % 2 + 1}_y{k}" for k in range(20)]))
    files = write_report(tmp_path / "r", cmp)
    assert [f.parent for f in files] == [tmp_path / "r"] * 5
    panels = [ax for ax in figures["deflection_vs_force.png"].axes if ax.get_visible()]
    assert [ax.get_title() for ax in panels] == ["P1 +y (10 series)", "P2 +y (10 series)"]
    assert all(ax.collections for ax in panels)  # 60 readings a panel: 5-95 % bands
    density = figures["residual_vs_torque.png"].axes
    assert len(density) > 3 and density[0].collections  # rows x, y, z of 2-D histograms
    counts = density[0].collections[0].get_array()
    assert np.nansum(counts) == len(cmp.predicted)  # every reading in one cell


def test_a_few_series_keep_one_panel_each(demo, figures, tmp_path):
    cmp = compare_static(demo[1], _series(demo, ["P1_y", "P2_y", "P1_y2"]))
    write_report(tmp_path, cmp)
    titles = [ax.get_title() for ax in figures["deflection_vs_force.png"].axes
              if ax.get_visible()]
    assert titles == ["P1_y", "P2_y", "P1_y2"]
    assert cmp.text().splitlines()[2].split()[0] == "P1_y"  # every series printed
