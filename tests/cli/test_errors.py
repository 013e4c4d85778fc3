"""The CLI: one clear line per bad input, no traceback, no half-written output."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.cli import main
from flexarm.fe import TetMesh
from flexarm.meshes import bar_surface, write_surface, write_volume_mesh


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "cache"))


def _error_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert "Traceback" not in "\n".join(err)
    return err[-1]


@pytest.fixture()
def bar_vtu(tmp_path):
    path = tmp_path / "bar.vtu"
    write_volume_mesh(path, TetMesh.box((1.0, 0.05, 0.05), (20, 1, 1), order=2))
    return path


def test_modal_clamped_bar_prints_bending_pair(bar_vtu, capsys):
    assert main(["modal", str(bar_vtu), "--material", "steel", "--fix", "x=min", "-n", "4"]) == 0
    out = capsys.readouterr().out
    freqs = [float(line.split()[1]) for line in out.splitlines() if line.strip()[:1].isdigit()]
    # Euler-Bernoulli 41.78 Hz; a coarse Tet10 bar is a little stiff.
    assert 41.0 < freqs[0] < 43.5 and abs(freqs[0] - freqs[1]) < 0.5


def test_modal_free_reports_six_rigid_modes(bar_vtu, capsys, tmp_path):
    csv = tmp_path / "modes.csv"
    assert main(["modal", str(bar_vtu), "-n", "2", "--csv", str(csv)]) == 0
    assert "rigid-body modes: 6" in capsys.readouterr().out
    rows = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert rows.shape == (8, 3) and rows[:6, 2].sum() == 6 and rows[6:, 2].sum() == 0


def test_modal_missing_file(tmp_path, capsys):
    assert main(["modal", str(tmp_path / "nope.vtu")]) == 2
    line = _error_line(capsys)
    assert line.startswith("flexarm modal: error:") and "nope.vtu" in line


def test_modal_poisson_ratio(bar_vtu, capsys):
    assert main(["modal", str(bar_vtu), "--material", "210e9,0.5,7850"]) == 2
    assert _error_line(capsys) == (
        "flexarm modal: error: Poisson ratio must be in (-1, 0.5), got 0.5"
    )


def test_modal_unknown_material(bar_vtu, capsys):
    assert main(["modal", str(bar_vtu), "--material", "cheese"]) == 2
    assert "material must be one of steel|cast_iron|aluminium|nafems or 'E,nu,rho'" in _error_line(
        capsys
    )


def test_modal_fix_selects_nothing(bar_vtu, capsys):
    assert main(["modal", str(bar_vtu), "--fix", "x<-5"]) == 2
    assert _error_line(capsys) == (
        f"flexarm modal: error: {bar_vtu}: --fix selection 'x<-5' selects no nodes"
    )


def test_modal_inverted_tets(tmp_path, capsys):
    mesh = TetMesh.box((1.0, 0.1, 0.1), (4, 1, 1))
    tets = mesh.tets.copy()
    tets[3] = tets[3][[0, 2, 1, 3]]
    path = tmp_path / "inverted.vtu"
    write_volume_mesh(path, TetMesh(mesh.points, tets))
    assert main(["modal", str(path)]) == 2
    assert _error_line(capsys) == (
        f"flexarm modal: error: {path}: 1 inverted tetrahedra (first: element 3)"
    )


def test_mesh_writes_quality_and_volume_mesh(tmp_path, capsys):
    stl = tmp_path / "bar.stl"
    write_surface(stl, bar_surface(400.0, 50.0, 50.0))  # millimetres
    out = tmp_path / "bar.vtu"
    assert main(["mesh", str(stl), "--units", "mm", "--size", "0.025", "--order", "2",
                 "-o", str(out)]) == 0
    assert out.exists()
    from flexarm.meshes import read_volume_mesh

    mesh = read_volume_mesh(out)
    assert mesh.order == 2
    assert abs(mesh.volumes().sum() - 0.4 * 0.05 * 0.05) < 1e-3 * 0.4 * 0.05 * 0.05
    assert "dihedral" in capsys.readouterr().out.lower()


def test_mesh_absurd_units_leave_no_output(tmp_path, capsys):
    stl = tmp_path / "bar.stl"
    write_surface(stl, bar_surface(400.0, 50.0, 50.0))  # millimetres, read as metres
    out = tmp_path / "bar.vtu"
    assert main(["mesh", str(stl), "--units", "m", "--size", "0.01", "-o", str(out)]) == 2
    line = _error_line(capsys)
    assert line.startswith("flexarm mesh: error:") and "bar.stl" in line and "units" in line
    assert not out.exists()


def test_mesh_garbage_file(tmp_path, capsys):
    bad = tmp_path / "garbage.stl"
    bad.write_bytes(b"\x00\x01 this is not an stl" * 3)
    assert main(["mesh", str(bad), "--size", "0.01", "-o", str(tmp_path / "x.vtu")]) == 2
    line = _error_line(capsys)
    assert line.startswith("flexarm mesh: error:") and "garbage.stl" in line
    assert not (tmp_path / "x.vtu").exists()


def test_mesh_negative_size(tmp_path, capsys):
    stl = tmp_path / "bar.stl"
    write_surface(stl, bar_surface(0.4, 0.05, 0.05))
    assert main(["mesh", str(stl), "--size", "-1", "-o", str(tmp_path / "x.vtu")]) == 2
    assert _error_line(capsys) == (
        "flexarm mesh: error: --size -1: must be > 0 and <= 10 m"
    )
