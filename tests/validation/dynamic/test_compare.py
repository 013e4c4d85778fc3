"""compare on modal and FRF data: tables, chi^2_red, plots."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexarm.robot.effects import parse_effect
from flexarm.validation.dynamic.compare import (
    compare_frf,
    compare_modal,
    write_frf_report,
    write_modal_report,
)
from flexarm.validation.lab.modal_lab import virtual_modal

from ..helpers import frf_data


def _poses(robot):
    return {p: robot.pose(p) for p in ("P1", "P2")}


def test_compare_modal_exact_and_wrong_stiffness(tmp_path, demo):
    robot, arm = demo
    exact = virtual_modal(arm, _poses(robot), n_modes=3, freq_noise=0.0)
    cmp = compare_modal(arm, exact)
    assert len(cmp.table) == 6 and cmp.chi2_red < 1e-12 and cmp.rms_pct < 1e-9
    soft = virtual_modal(arm, _poses(robot), [parse_effect("stiffness:j2=0.5")], 3, 0.0)
    cmp = compare_modal(arm, soft)
    errs = np.array([r.error_pct for r in cmp.table])
    assert np.all(errs >= -1e-9) and errs.max() > 2  # the model is stiffer: too high
    assert cmp.chi2_red > cmp.band[1]
    paths = write_modal_report(tmp_path, cmp)
    assert all(p.stat().st_size > 0 for p in paths)
    lines = paths[0].read_text().splitlines()
    assert lines[0] == "pose,mode,model_mode,matched,measured_hz,model_hz,error_hz,error_pct"
    r = cmp.table[0]
    assert lines[1] == (f"{r.pose},{r.mode},{r.model_mode},{r.matched},{r.measured_hz!r},"
                        f"{r.model_hz!r},{r.error_hz!r},{r.error_pct!r}")


def test_compare_modal_matches_by_frequency_and_drops_spurious_lines(demo):
    import dataclasses

    robot, arm = demo
    exact = virtual_modal(arm, _poses(robot), n_modes=3, freq_noise=0.0)
    # modes 2 and 3 of P1 listed the other way round, and a spurious 1 Hz line at P2
    order = [0, 2, 1, 3, 4, 5]
    f = list(np.asarray(exact.freq_hz)[order]) + [1.0]
    swapped = dataclasses.replace(
        exact, poses=list(np.asarray(exact.poses)[order]) + ["P2"],
        q=list(np.asarray(exact.q)[order]) + [exact.q[3]],
        modes=list(np.asarray(exact.modes)[order]) + [4], freq_hz=f)
    cmp = compare_modal(arm, swapped)
    assert [r.model_mode for r in cmp.table[:3]] == [1, 3, 2]
    assert [r.matched for r in cmp.table] == [True] * 6 + [False]
    # the spurious line is shown but not scored: the matched rows are exact
    assert cmp.chi2_red < 1e-12 and cmp.rms_pct < 1e-9


def test_compare_frf_exact_and_shifted(tmp_path, demo):
    robot, arm = demo
    cmp = compare_frf(arm, frf_data(arm, robot))
    assert len(cmp.table) == 2
    assert all(r.rms_log10_mag < 1e-9 and abs(r.peak_error_pct) < 1e-9 for r in cmp.table)
    cmp = compare_frf(arm, frf_data(arm, robot, [parse_effect("stiffness:j2=0.5")]))
    assert max(r.rms_log10_mag for r in cmp.table) > 0.05
    paths = write_frf_report(tmp_path, cmp)
    assert all(p.stat().st_size > 0 for p in paths)


def test_frf_overlay_csv_is_the_plotted_lines(tmp_path, demo, monkeypatch):
    import matplotlib.figure

    saved = {}
    real = matplotlib.figure.Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        saved[Path(fname).name] = self  # drawn in the report's temporary folder
        return real(self, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", savefig)
    robot, arm = demo
    data = frf_data(arm, robot, [parse_effect("stiffness:j2=0.5")])
    cmp = compare_frf(arm, data)
    _, png, csv_path = write_frf_report(tmp_path, cmp)
    table = np.genfromtxt(csv_path, delimiter=",", names=True, dtype=None, encoding=None)
    axes = saved[png.name].axes
    n = len(cmp.table)
    assert len(axes) == 2 * n and axes[0].get_ylabel() == "|H| [mm/kN]"
    for c, r in enumerate(cmp.table):
        rows = table[(table["pose"] == r.pose) & (table["input"] == r.input)
                     & (table["output"] == r.output)]
        meas, model = axes[c].get_lines()  # the top row: magnitudes
        np.testing.assert_allclose(meas.get_xdata(), rows["freq_Hz"], rtol=1e-9)
        np.testing.assert_allclose(
            meas.get_ydata(), np.hypot(rows["re_H_meas_m_per_N"], rows["im_H_meas_m_per_N"]) * 1e6,
            rtol=1e-8)
        np.testing.assert_allclose(
            model.get_ydata(),
            np.hypot(rows["re_H_model_m_per_N"], rows["im_H_model_m_per_N"]) * 1e6, rtol=1e-8)
    # SI in the file: the measured column is the data's own receptance
    np.testing.assert_allclose(np.sort(table["re_H_meas_m_per_N"]),
                               np.sort(np.real(data.receptance)), rtol=1e-9)
