import dataclasses

import numpy as np
import pytest
import scipy.linalg as sla
from reduction_helpers import STEEL, rel

from flexarm.fe import mass_properties
from flexarm.reduction.couplings import rigid_transport
from flexarm.reduction.reduce import reduce_part
from flexarm.reduction.superelement import matrix_mass_properties

CASES = [("rbe2", None), ("rbe3", None), ("nodes", 4), ("nodes", None)]


def full_mass_properties(mesh, M):
    Phi = rigid_transport(mesh.points).transpose(0, 1, 2).reshape(-1, 6)
    return matrix_mass_properties(M, Phi)


@pytest.mark.parametrize("coupling,k", CASES)
def test_free_superelement_rigid_modes_and_mass_properties(bar10, coupling, k):
    mesh, regions, (K, M) = bar10
    se = reduce_part(mesh, STEEL, regions, coupling, "cb", 6, n_masters=k, matrices=(K, M))
    w = sla.eigh(se.K, se.M, eigvals_only=True)
    assert int(np.sum(np.abs(w) < 1e-8 * w.max())) == 6
    assert w[6] > 1e4 * np.abs(w[:6]).max()
    full = full_mass_properties(mesh, M)
    assert abs(se.mass / full.mass - 1) < 1e-10
    assert rel(se.center_of_mass, full.center_of_mass) < 1e-10
    assert rel(se.inertia, full.inertia) < 1e-10
    geo = mass_properties(mesh, STEEL.rho)  # and the consistent mass is exact
    assert abs(se.mass / geo.mass - 1) < 1e-10 and rel(se.inertia, geo.inertia) < 1e-9


@pytest.mark.parametrize("coupling,k", CASES)
def test_symmetric_psd(bar, coupling, k):
    mesh, regions, KM = bar
    se = reduce_part(mesh, STEEL, regions, coupling, "cb", 5, n_masters=k, matrices=KM)
    assert np.array_equal(se.K, se.K.T) and np.array_equal(se.M, se.M.T)
    ev = np.linalg.eigvalsh(se.K)
    assert ev[0] > -1e-10 * ev[-1]
    assert np.linalg.eigvalsh(se.M)[0] > 0


def test_expand_and_fields(bar):
    mesh, regions, KM = bar
    se = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 3, matrices=KM)
    assert se.n_dofs == 15 and se.n_boundary == 12 and se.units == "SI"
    assert se.T.dtype == np.float32 and se.T.shape == (mesh.n_dofs, 15)
    q = np.zeros(15)
    q[:3] = [1e-3, 0, 0]  # interface a translates along x: its face moves with it
    u = se.expand(q)
    assert u.shape == (mesh.n_nodes, 3)
    assert np.allclose(u[mesh.points[:, 0] == 0, 0], 1e-3, rtol=1e-6)
    assert se.surface_faces.max() < len(se.surface_points)
    assert np.allclose(se.surface_points, mesh.points[se.surface_nodes])
    with pytest.raises(ValueError, match="q must have shape"):
        se.expand(np.zeros(3))
    with pytest.raises(ValueError, match="K and M must be square"):
        type(se)(**{**se.__dict__, "K": np.zeros((3, 4))})


def test_same_inputs_same_hash(bar):
    mesh, regions, KM = bar
    a = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 3, matrices=KM)
    b = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 3, matrices=KM)
    c = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 4, matrices=KM)
    assert a.input_hash == b.input_hash != c.input_hash


def test_repr_is_short_and_states_the_figures(bar):
    mesh, regions, KM = bar
    se = reduce_part(mesh, STEEL, regions, "rbe3", "cb", 5, matrices=KM)
    text = repr(se)
    assert len(text) < 300 and "\n" not in text
    assert text.startswith(f"Superelement(cb, rbe3, {se.n_dofs} DOF: interfaces a 6, b 6; "
                           f"{se.n_modes} modal")
    listed = text.split("fixed-interface ")[1].split(" Hz")[0].split(", ")
    assert [float(f) for f in listed[:3]] == pytest.approx(se.freq_hz[:3], rel=5e-4)
    assert listed[3] == "…" and f"mass {se.mass:.4g} kg" in text


@pytest.mark.parametrize("ext", ["h5", "npz", "mtx"])
def test_load_reads_every_format_like_the_registry(bar, tmp_path, ext):
    from flexarm.reduction import formats
    from flexarm.reduction.superelement import Superelement

    mesh, regions, KM = bar
    se = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 4, matrices=KM)
    path = formats.write(tmp_path / f"link.{ext}", se)
    loaded = Superelement.load(path)
    # Matrix Market bundles hold matrices and interfaces, not T or the surface mesh
    kept = [f for f in dataclasses.fields(se)
            if ext != "mtx" or f.name not in ("T", "surface_points", "surface_faces",
                                              "surface_nodes")]
    for f in kept:
        a, b = getattr(se, f.name), getattr(loaded, f.name)
        if isinstance(a, np.ndarray):
            assert a.dtype == b.dtype and np.array_equal(a, b), f.name
        else:
            assert a == b, f.name
    assert repr(loaded) == repr(se)


def test_load_names_the_file_it_cannot_read(tmp_path):
    from flexarm.fe.errors import ReadError
    from flexarm.reduction.superelement import Superelement

    bad = tmp_path / "junk.npz"
    bad.write_bytes(b"not a zip")
    with pytest.raises(ReadError, match="junk.npz"):
        Superelement.load(bad)
    with pytest.raises(ValueError, match="unknown superelement extension"):
        Superelement.load(tmp_path / "link.xyz")
