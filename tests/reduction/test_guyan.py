import numpy as np
import pytest
from reduction_helpers import STEEL, rel

from flexarm.fe import dof_split, static_solve
from flexarm.reduction.guyan import guyan
from flexarm.reduction.recovery import interface_dofs
from flexarm.reduction.reduce import coupled_model, reduce_part


def full_compliance(model, clamp: str, load: str):
    """(n_b, n_b) compliance at interface ``load`` of the coupled FE model, ``clamp`` held."""
    c = model.coupling
    n_i = c.n_interior
    names = [i.name for i in model.interfaces]
    owner = np.repeat(c.node_interface, c.dofs_per_node)

    def dofs(name):
        return n_i + np.flatnonzero(owner == names.index(name))

    split = dof_split(model.K.shape[0], dofs(clamp))
    F = np.zeros((model.K.shape[0], dofs(load).size))
    F[dofs(load), np.arange(dofs(load).size)] = 1.0
    return static_solve(model.K, F, split)[dofs(load)]


@pytest.mark.parametrize("coupling,k", [("rbe2", None), ("rbe3", None), ("nodes", 4)])
def test_guyan_reproduces_static_interface_compliance(bar, coupling, k):
    mesh, regions, KM = bar
    model = coupled_model(mesh, STEEL, regions, coupling, k, matrices=KM)
    se = reduce_part(mesh, STEEL, regions, coupling, "guyan", n_masters=k, matrices=KM)
    free = interface_dofs(se, ["b"])
    C_red = np.linalg.inv(se.K[np.ix_(free, free)])
    C_full = full_compliance(model, "a", "b")
    assert rel(C_red, C_full) < 1e-8


def test_guyan_equals_cb_with_zero_modes(bar):
    mesh, regions, KM = bar
    g = reduce_part(mesh, STEEL, regions, "rbe2", "guyan", matrices=KM)
    c = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 0, matrices=KM)
    assert np.array_equal(g.K, c.K) and np.array_equal(g.M, c.M)


def test_guyan_two_springs():
    import scipy.sparse as sp

    K = sp.csr_matrix([[2.0, -1.0], [-1.0, 1.0]])
    r = guyan(K, sp.identity(2, format="csr"), 1, backend="splu")
    assert np.allclose(r.K, 0.5) and np.allclose(r.T, [[0.5], [1.0]])
