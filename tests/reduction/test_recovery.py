import numpy as np
import pytest
from reduction_helpers import STEEL, rel

from flexarm.fe import InterfaceError, dof_split, static_solve
from flexarm.reduction.recovery import reduced_modes, static_deflection
from flexarm.reduction.reduce import coupled_model, reduce_part


def test_static_deflection_matches_full_field(bar):
    mesh, regions, KM = bar
    model = coupled_model(mesh, STEEL, regions, "rbe3", matrices=KM)
    se = reduce_part(mesh, STEEL, regions, "rbe3", "cb", 4, matrices=KM,
                     recovery_dtype=np.float64)
    wrench = np.array([0.0, 100.0, -50.0, 1.0, 0.0, 2.0])
    u = static_deflection(se, {"b": wrench}, clamped=["a"])
    n_i = model.coupling.n_interior
    f = np.zeros(model.K.shape[0])
    f[n_i + 6 : n_i + 12] = wrench
    x = static_solve(model.K, f, dof_split(f.size, n_i + np.arange(6)))
    u_full = (model.coupling.T @ x).reshape(-1, 3)
    assert rel(u, u_full) < 1e-8
    with pytest.raises(InterfaceError, match="clamp at least one interface"):
        static_deflection(se, {"b": wrench}, clamped=[])
    with pytest.raises(InterfaceError, match="no interface 'c'"):
        static_deflection(se, {"c": wrench}, clamped=["a"])


def test_reduced_modes_free_has_six_rigid(bar):
    mesh, regions, KM = bar
    se = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 4, matrices=KM)
    w, Q = reduced_modes(se, n=8)
    assert np.sum(np.abs(w) < 1e-6 * w[-1]) == 6
    assert np.allclose(Q.T @ se.M @ Q, np.eye(8), atol=1e-10)
