"""Superelement mode shapes for ParaView: mass-normalised with the FE mass matrix (or
scaled to a stated amplitude), the mode number, frequency and scale in the field data,
read back by meshio (``.vtu``) and by VTK itself (legacy ``.vtk``)."""

import numpy as np
import pytest
from reduction_helpers import STEEL

from flexarm.reduction import render
from flexarm.reduction.reduce import reduce_part

meshio = pytest.importorskip("meshio")


@pytest.fixture(scope="module")
def bar_se(bar):
    mesh, regions, KM = bar
    return reduce_part(mesh, STEEL, regions, "rbe2", "cb", 4, matrices=KM), KM[1]


def test_vtu_shape_is_mass_normalised_with_the_fe_mass(bar_se, tmp_path):
    se, M_fe = bar_se
    m = meshio.read(render.write_mode(se, 2, tmp_path / "m2.vtu"))
    assert m.field_data["mode"].tolist() == [2] and m.field_data["modal_mass"].tolist() == [1.0]
    assert m.field_data["freq_hz"][0] == se.freq_hz[1]
    q = np.zeros(se.n_dofs)
    q[se.n_boundary + 1] = 1.0
    u = se.expand(q)
    u /= np.sqrt(u.ravel() @ M_fe @ u.ravel())  # unit modal mass on the full FE model
    # the recovery matrix is stored in float32
    np.testing.assert_allclose(m.point_data["mode_shape"], u[se.surface_nodes], rtol=1e-5,
                               atol=1e-5 * np.abs(u).max())
    assert m.field_data["max_displacement"][0] == pytest.approx(
        np.linalg.norm(m.point_data["mode_shape"], axis=1).max(), rel=1e-12)


def test_amplitude_is_stated_in_the_legacy_file(bar_se, tmp_path):
    se, _ = bar_se
    unit = meshio.read(render.write_mode(se, 1, tmp_path / "m1.vtu", "free"))
    path = render.write_mode(se, 1, tmp_path / "m1.vtk", "free", amplitude=2e-3)
    m = meshio.read(path)
    assert np.linalg.norm(m.point_data["mode_shape"], axis=1).max() == pytest.approx(2e-3)
    s = 2e-3 / unit.field_data["max_displacement"][0]
    np.testing.assert_allclose(m.point_data["mode_shape"], s * unit.point_data["mode_shape"],
                               rtol=1e-12, atol=1e-18)
    pv = pytest.importorskip("pyvista")
    fd = pv.read(path).field_data  # binary legacy VTK: big-endian values
    assert int(fd["mode"][0]) == 1 and fd["freq_hz"][0] == unit.field_data["freq_hz"][0]
    assert fd["modal_mass"][0] == pytest.approx(s * s, rel=1e-12)
    assert fd["max_displacement"][0] == pytest.approx(2e-3, rel=1e-12)
    with pytest.raises(ValueError, match="amplitude must be > 0"):
        render.write_mode(se, 1, tmp_path / "bad.vtu", amplitude=0.0)
    assert not (tmp_path / "bad.vtu").exists()
