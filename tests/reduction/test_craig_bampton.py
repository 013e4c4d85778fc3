import numpy as np
import pytest
import scipy.linalg as sla
from reduction_helpers import STEEL

from flexarm.reduction.recovery import interface_dofs, reduced_modes
from flexarm.reduction.reduce import coupled_model, reduce_part


def clamped_full_omega2(model, clamp_names, n):
    c = model.coupling
    names = [i.name for i in model.interfaces]
    owner = np.repeat(c.node_interface, c.dofs_per_node)
    fixed = c.n_interior + np.flatnonzero(np.isin(owner, [names.index(s) for s in clamp_names]))
    free = np.setdiff1d(np.arange(model.K.shape[0]), fixed)
    K = model.K[free][:, free].toarray()
    M = model.M[free][:, free].toarray()
    return sla.eigh(K, M, eigvals_only=True, subset_by_index=(0, n - 1))


@pytest.mark.parametrize("coupling", ["rbe2", "rbe3"])
def test_cantilever_converges_from_above_monotonically(bar, coupling):
    mesh, regions, KM = bar
    model = coupled_model(mesh, STEEL, regions, coupling, matrices=KM)
    ref = clamped_full_omega2(model, ["a"], 10)
    prev = None
    for n in (0, 5, 10, 20, 40):
        se = reduce_part(mesh, STEEL, regions, coupling, "cb", n, matrices=KM)
        w = reduced_modes(se, clamped=["a"], n=10)[0]  # Guyan: only 6 DOFs are left
        k = len(w)
        assert np.all(w >= ref[:k] * (1 - 1e-10)), n
        if prev is not None:
            assert np.all(w[: len(prev)] <= prev * (1 + 1e-10)), n
        prev = w
    assert np.all(np.abs(prev[:6] / ref[:6] - 1) < 1e-3)


@pytest.mark.parametrize("coupling", ["rbe2", "rbe3"])
def test_all_interior_modes_is_exact(tiny_bar, coupling):
    mesh, regions, KM = tiny_bar
    model = coupled_model(mesh, STEEL, regions, coupling, matrices=KM)
    n_all = model.coupling.n_interior
    se = reduce_part(mesh, STEEL, regions, coupling, "cb", n_all, matrices=KM)
    ref = clamped_full_omega2(model, ["a"], 10)
    w = reduced_modes(se, clamped=["a"], n=10)[0]
    assert np.max(np.abs(w / ref - 1)) < 1e-8


def test_fixed_interface_frequencies_equal_full_model_all_clamped(bar):
    mesh, regions, KM = bar
    model = coupled_model(mesh, STEEL, regions, "rbe3", matrices=KM)
    se = reduce_part(mesh, STEEL, regions, "rbe3", "cb", 8, matrices=KM)
    ref = np.sqrt(clamped_full_omega2(model, ["a", "b"], 8)) / (2 * np.pi)
    assert np.max(np.abs(se.freq_hz / ref - 1)) < 1e-8


def test_diagonal_form(bar):
    mesh, regions, KM = bar
    se = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 6, diagonal=True, matrices=KM)
    b = se.n_boundary
    assert np.array_equal(se.M[b:, b:], np.eye(6))
    assert np.allclose(se.K[b:, b:], np.diag((2 * np.pi * se.freq_hz) ** 2), rtol=1e-13, atol=0)
    assert not np.any(se.K[:b, b:]) and not np.any(se.K[b:, :b])
    plain = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 6, matrices=KM)
    assert np.allclose(plain.K, se.K, rtol=0, atol=1e-8 * np.abs(se.K).max())
    assert np.allclose(plain.M, se.M, rtol=0, atol=1e-10 * np.abs(se.M).max())


def test_too_many_modes_and_bad_method(bar):
    mesh, regions, KM = bar
    with pytest.raises(ValueError, match="only"):
        reduce_part(mesh, STEEL, regions, "rbe2", "cb", 10**6, matrices=KM)
    with pytest.raises(ValueError, match="method must be one of"):
        reduce_part(mesh, STEEL, regions, "rbe2", "mcs", 4, matrices=KM)
    assert interface_dofs(reduce_part(mesh, STEEL, regions, "rbe2", "guyan", matrices=KM),
                          ["b"]).tolist() == list(range(6, 12))


@pytest.fixture(scope="module")
def link10():
    """Tet10 bar 0.6 x 0.06 x 0.06 m (16 x 2 x 2 cells, 2.5k DOF) with regions at both ends."""
    from reduction_helpers import end_regions

    from flexarm.fe import TetMesh, assemble

    mesh = TetMesh.box((0.6, 0.06, 0.06), (16, 2, 2), order=2)
    return mesh, end_regions(0.6, 0.06), assemble(mesh, STEEL)


@pytest.mark.parametrize("backend", ["splu", "pardiso"])
@pytest.mark.parametrize("method", ["cb", "guyan"])
def test_single_precision_factor_equals_the_double_path(link10, backend, method):
    from reduction_helpers import rel

    from flexarm.fe import available_backends
    from flexarm.reduction.reduce import reduce_with_stats

    if backend not in available_backends():
        pytest.skip(f"{backend} not installed")
    mesh, regions, KM = link10
    runs = {p: reduce_with_stats(mesh, STEEL, regions, "rbe2", method, 12, backend=backend,
                                 matrices=KM, precision=p) for p in ("double", "single")}
    (d, sd), (s, ss) = runs["double"], runs["single"]
    assert (sd.precision, ss.precision) == ("double", "single")
    # constraint modes and shift-invert solves refined to double accuracy: the reduced
    # matrices and frequencies are the double path's to rounding
    assert rel(s.K, d.K) < 1e-8 and rel(s.M, d.M) < 1e-8
    assert rel(s.T, d.T) < 1e-6  # the recovery matrix is stored in float32
    if method == "cb":
        assert np.max(np.abs(s.freq_hz / d.freq_hz - 1)) < 1e-9
