"""EMA (LSCF + LSFD) on noisy model FRFs: frequencies, damping, shapes."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.cli import main
from flexarm.validation.data.formats import read_measurements
from flexarm.validation.dynamic.ema import run_ema
from flexarm.validation.dynamic.mac import mac
from flexarm.validation.dynamic.shapes import default_points, model_shapes
from flexarm.validation.lab.modal_lab import virtual_frfs

#: 0.25 Hz lines up to 1.2 x the 6th mode at P1 (139 Hz).
FREQ = 0.25 * np.arange(1, 669)


@pytest.mark.parametrize("seed", [1, pytest.param(2, marks=pytest.mark.slow),
                                  pytest.param(3, marks=pytest.mark.slow)])
def test_ema_recovers_the_first_six_modes_from_2pct_noisy_frfs(demo, seed):
    """References at the TCP (x, y, z), responses x, y, z at the 12 default points."""
    robot, arm = demo
    pts = default_points(robot)
    poses = {p: robot.pose(p) for p in ("P1", "P2")}
    frfs = virtual_frfs(arm, poses, pts, [(601, d) for d in "xyz"], FREQ, noise=0.02,
                        seed=seed)
    res = run_ema(frfs)
    for pm in res.poses:
        f, zeta, phi = model_shapes(arm, pm.frf.q, pts, pm.nodes, pm.dirs, 6)
        assert len(pm.freq_hz) >= 6
        assert np.all(np.abs(pm.freq_hz[:6] / f - 1) < 0.005), pm.freq_hz[:6] / f - 1
        assert np.all(np.abs(pm.damping[:6] / zeta - 1) < 0.10), pm.damping[:6] / zeta - 1
        assert np.all(np.diag(mac(pm.shapes[:6], phi)) > 0.98)
        ok = np.isfinite(pm.synthesised)
        err = np.linalg.norm((pm.synthesised - pm.frf.H)[ok]) / np.linalg.norm(pm.frf.H[ok])
        assert err < 0.03  # the fit leaves the 2 % noise, not more


def test_ema_command_from_the_lab_file(tmp_path):
    """lab -> UFF (58 FRFs, 2 % noise) -> ema -> modal CSV with shapes and the pictures."""
    assert main(["lab", "--poses", "P1,P2", "--loads", "0:800:800", "--dirs", "y",
                 "--modal", str(tmp_path / "lab.uff"), "--n-modes", "6",
                 "-o", str(tmp_path / "static.csv")]) == 0
    out = tmp_path / "ema" / "modal.csv"
    assert main(["ema", str(tmp_path / "lab.uff"), "-o", str(out)]) == 0
    data = read_measurements(out)
    assert data.n_dofs == 34 and set(data.pose_labels()) == {"P1", "P2"}
    for name in ("stabilisation_P1", "frf_P1", "stabilisation_P2", "frf_P2"):
        assert (tmp_path / "ema" / f"modal.{name}.png").stat().st_size > 10_000
    assert (tmp_path / "ema" / "modal.points.csv").exists()
    assert main(["ema", str(tmp_path / "lab.uff"), "-o", str(out), "--band", "300:400"]) == 2


def test_ema_modal_mass_and_geometry_in_its_universal_file(demo, tmp_path):
    """Noise-free FRFs at P1 in a universal file with its geometry: the modal mass of each
    unit shape from the driving points equals 1 / |phi|^2 of the model's mass-normalised
    shape at the same DOFs (first four modes, away from the band's top), and the
    universal file ema writes carries it and the geometry."""
    from flexarm.validation.data.formats.uff import read_uff
    from flexarm.validation.data.formats.uff_geometry import PoseGeometry, stick_figure
    from flexarm.validation.data.formats.uff_write import write_uff
    from flexarm.validation.dynamic.point_geometry import point_coordinates

    robot, arm = demo
    pts = default_points(robot)
    q = robot.pose("P1")
    frfs = virtual_frfs(arm, {"P1": q}, pts, [(601, d) for d in "xyz"], FREQ, noise=0.0)
    geometry = [PoseGeometry("P1", pts.nodes, point_coordinates(robot, q, pts),
                             stick_figure(pts))]
    res = run_ema(write_uff(tmp_path / "frf.uff", frfs=frfs, geometry=geometry))
    pm, = res.poses
    _, _, phi = model_shapes(arm, pm.frf.q, pts, pm.nodes, pm.dirs, 4)
    assert np.allclose(pm.modal_mass[:4], 1 / np.sum(phi**2, axis=1), rtol=5e-3)
    back = read_uff(res.write(tmp_path / "modes.uff"))
    assert np.allclose(back.modal_mass, pm.modal_mass, rtol=1e-5)
    g, = back.geometry
    assert g.pose == "P1" and np.array_equal(g.nodes, pts.nodes)
    assert np.max(np.abs(g.coordinates - geometry[0].coordinates)) < 1e-15
