"""The diagnosis pictures: history from the nominal model with a noise floor, residuals
against joint torque with a legend, and the CSV behind them."""

import numpy as np
import pytest

from flexarm.validation.static.plots import (
    NOISE_FLOOR_FACTOR,
    plot_history,
    plot_residual_vs_torque,
    write_residuals,
)

ROWS = [{"version": 0, "model": "baseline", "rms_fit_um": 22.2, "rms_heldout_um": 23.0,
         "band_lo": 0.8, "band_hi": 1.2},
        {"version": 1, "model": "baseline + joint 2 backlash", "rms_fit_um": 20.3,
         "rms_heldout_um": 21.0, "band_lo": 0.81, "band_hi": 1.21}]


def test_history_starts_at_the_nominal_model_with_a_noise_floor(tmp_path, figures):
    plot_history(tmp_path / "history.png", ROWS, nominal_rms=161e-6, sigma=15e-6)
    ax = figures["history.png"].axes[0]
    fit_bars = ax.containers[0]
    np.testing.assert_allclose([b.get_height() for b in fit_bars], [161.0, 22.2, 20.3])
    assert [t.get_text() for t in ax.get_xticklabels()] == ["nominal", "v0", "v1"]
    floor = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    assert floor and floor[0].get_ydata()[0] == pytest.approx(NOISE_FLOOR_FACTOR * 15.0)
    assert ax.get_yscale() == "log"  # 161 vs 20 µm: linear bars would hide the fits
    assert len(ax.get_legend().get_texts()) == 4 and "µm" in ax.get_ylabel()
    # the chi-square band of the last version, as RMS: floor * sqrt(band)
    [band] = [p for p in ax.patches if p.get_alpha() == pytest.approx(0.12)]
    corners = band.get_transform().transform(band.get_path().vertices)
    ys = ax.transData.inverted().transform(corners)[:, 1]
    assert (ys.min(), ys.max()) == pytest.approx(NOISE_FLOOR_FACTOR * 15.0
                                                 * np.sqrt([0.81, 1.21]), rel=1e-6)


def test_history_without_nominal_is_the_versions_only(tmp_path, figures):
    plot_history(tmp_path / "history.png", ROWS)
    ax = figures["history.png"].axes[0]
    assert len(ax.containers[0]) == 2 and ax.get_yscale() == "linear"


def test_residual_plot_skips_joints_without_torque(tmp_path, figures):
    rng = np.random.default_rng(0)
    tau = np.column_stack([rng.normal(0, 500, 40), rng.normal(0, 200, 40),
                           np.full(40, 1e-14)])
    res = rng.normal(0, 20e-6, (40, 3))
    plot_residual_vs_torque(tmp_path / "r.png", tau, res)
    fig = figures["r.png"]
    assert len(fig.axes) == 2 and "joint 3 carries no torque" in fig._suptitle.get_text()
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == [
        "residual x", "residual y", "residual z"]
    np.testing.assert_allclose(fig.axes[1].get_lines()[2].get_ydata(), res[:, 2] * 1e6)
    path = write_residuals(tmp_path / "residuals.csv", [f"s{i}" for i in range(40)], tau, res)
    rows = np.loadtxt(path, delimiter=",", skiprows=1, usecols=range(1, 7))
    np.testing.assert_allclose(rows[:, 3:], res * 1e6, rtol=1e-9)
    np.testing.assert_allclose(rows[:, :3], tau, rtol=1e-9)


def test_residuals_csv_holds_the_deflection_plot_data(tmp_path):
    rng = np.random.default_rng(1)
    tau, force = rng.normal(0, 100, (5, 2)), rng.normal(0, 300, (5, 3))
    meas, pred = rng.normal(0, 1e-3, (5, 3)), rng.normal(0, 1e-3, (5, 3))
    path = write_residuals(tmp_path / "r.csv", list("abcde"), tau, meas - pred, force, meas,
                           pred)
    head = path.read_text().splitlines()[0].split(",")
    assert head == ["series", "tau_j1_Nm", "tau_j2_Nm", "f_N", "dx_meas_mm", "dy_meas_mm",
                    "dz_meas_mm", "dx_model_mm", "dy_model_mm", "dz_model_mm", "res_x_um",
                    "res_y_um", "res_z_um"]
    rows = np.loadtxt(path, delimiter=",", skiprows=1, usecols=range(1, 13))
    np.testing.assert_allclose(rows[:, 2], np.linalg.norm(force, axis=1), rtol=1e-9)
    np.testing.assert_allclose(rows[:, 3:6] - rows[:, 6:9], rows[:, 9:] * 1e-3, rtol=1e-7,
                               atol=1e-12)
