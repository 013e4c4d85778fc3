"""Global K and M: symmetry, definiteness, rigid modes, mass, the affine fast path, quadrature."""

from __future__ import annotations

from math import factorial

import numpy as np
import pytest
import scipy.linalg as sla

from flexarm.fe import (
    TetMesh,
    assemble,
    element_mass,
    mass_properties,
    modes,
    rigid_body_mass_matrix,
    stiffness_blocks,
    tet_quadrature,
)

MESHES = ["irregular_tet4", "irregular_tet10", "curved_tet10"]


@pytest.fixture(scope="module")
def matrices(request, steel):
    """K, M of each fixture mesh, assembled once per module."""
    cache = {}

    def get(name):
        if name not in cache:
            mesh = request.getfixturevalue(name)
            cache[name] = (mesh, *assemble(mesh, steel))
        return cache[name]

    return get


@pytest.mark.parametrize("name", MESHES)
def test_k_and_m_symmetric(name, matrices):
    _, K, M = matrices(name)
    for A in (K, M):
        assert A.shape == (A.shape[0], A.shape[0])
        assert abs(A - A.T).max() <= 1e-12 * abs(A).max()


@pytest.mark.parametrize("order, curved", [(1, 0.0), (2, 0.0), (2, 0.1)])
def test_k_psd_with_exactly_six_zero_eigenvalues(order, curved, make_perturbed_box, steel):
    """Dense spectrum of K: nothing below -tiny, exactly 6 (rigid) eigenvalues near 0."""
    mesh = make_perturbed_box(order=order, divisions=(2, 2, 2), curved=curved, seed=1)
    K, M = assemble(mesh, steel)
    lam = sla.eigvalsh(K.toarray())
    tiny = 1e-10 * lam[-1]
    assert lam[0] >= -tiny
    assert int((np.abs(lam) <= tiny).sum()) == 6
    # ... and a clear gap: the 7th eigenvalue is an elastic one.
    assert lam[6] > 1e-6 * lam[-1]
    # M is positive definite (consistent mass).
    mu = sla.eigvalsh(M.toarray())
    assert mu[0] > 0


@pytest.mark.parametrize("order", [1, 2])
def test_free_part_has_exactly_six_rigid_modes(order, steel):
    """modes() of an unsupported part: 6 near-zero modes, then a clearly elastic one."""
    mesh = TetMesh.box((1.0, 0.2, 0.1), (8, 2, 1), order=order)
    K, M = assemble(mesh, steel)
    assert K.shape[0] > 400 or order == 1  # Tet10: the factorise + ARPACK path
    m = modes(K, M, n=8)
    assert m.n_rigid == 6
    assert np.all(m.is_rigid[:6]) and not np.any(m.is_rigid[6:])
    f = m.freq_hz
    assert np.all(f[:6] < 1e-3 * f[6])
    assert f[6] > 10.0  # lowest elastic mode of a 1 m steel strip: tens of Hz


@pytest.mark.parametrize("name", ["irregular_tet4", "irregular_tet10"])
def test_total_mass_is_rho_v(name, matrices, steel):
    mesh, _, M = matrices(name)
    volume = mesh.volumes().sum()
    assert volume == pytest.approx(1.0, rel=1e-12)  # the perturbed unit cube
    for c in range(3):
        e = np.zeros(mesh.n_dofs)
        e[c::3] = 1.0
        assert e @ (M @ e) == pytest.approx(steel.rho * volume, rel=1e-12)


def test_curved_tet10_mass_equals_integrated_volume(matrices, steel):
    """For curved elements M integrates det J exactly: total mass = rho * int det J."""
    mesh, _, M = matrices("curved_tet10")
    pts, w = tet_quadrature(6)
    from flexarm.fe import Tet10

    dN = Tet10.shape_grad(pts)
    J = np.einsum("eai,qaj->eqij", mesh.points[mesh.tets], dN)
    volume = float((np.linalg.det(J) * w).sum())
    assert volume == pytest.approx(1.0, rel=2e-2)  # boundary mid-nodes moved: close to 1
    assert abs(volume - 1.0) > 1e-6  # ... but really curved
    e = np.zeros(mesh.n_dofs)
    e[0::3] = 1.0
    assert e @ (M @ e) == pytest.approx(steel.rho * volume, rel=1e-12)


@pytest.mark.parametrize("name", ["irregular_tet4", "irregular_tet10"])
def test_rigid_kinetic_energy_matches_mass_properties(name, matrices, steel,
                                                      make_rigid_body_vectors):
    """R^T M R over the 6 rigid motions is the rigid-body mass matrix (mass, COM, inertia)."""
    mesh, _, M = matrices(name)
    ref = np.array([0.1, 0.2, -0.3])
    R = make_rigid_body_vectors(mesh.points, center=ref)
    expected = rigid_body_mass_matrix(mass_properties(mesh, steel.rho), ref)
    got = R.T @ (M @ R)
    assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()


def test_mass_properties_of_a_box(make_perturbed_box):
    """Analytic box a x b x c at an offset origin, meshed irregularly inside."""
    a, b, c, rho = 2.0, 1.0, 0.5, 2700.0
    origin = np.array([1.0, -2.0, 3.0])
    unit = make_perturbed_box(order=1, divisions=(4, 3, 2), seed=3)
    mesh = TetMesh(unit.points * [a, b, c] + origin, unit.tets)
    mp = mass_properties(mesh, rho)
    m = rho * a * b * c
    assert mp.mass == pytest.approx(m, rel=1e-13)
    np.testing.assert_allclose(mp.center_of_mass, origin + [a / 2, b / 2, c / 2], rtol=1e-13)
    expected = m / 12 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2])
    np.testing.assert_allclose(mp.inertia, expected, rtol=0, atol=1e-12 * expected.max())
    # parallel axes: about the min corner
    Ic = mp.inertia_about(origin)
    assert Ic[0, 0] == pytest.approx(m / 3 * (b**2 + c**2), rel=1e-12)
    assert Ic[0, 1] == pytest.approx(-m * a * b / 4, rel=1e-12)


@pytest.mark.parametrize("name", ["irregular_tet4", "irregular_tet10"])
def test_affine_fast_path_equals_quadrature_path(name, request, steel):
    mesh = request.getfixturevalue(name)
    fast = stiffness_blocks(mesh, steel, affine=True)
    general = stiffness_blocks(mesh, steel, affine=False)
    nn = mesh.tets.shape[1]
    assert fast.shape == general.shape == (mesh.n_tets, nn, nn, 3, 3)
    assert np.abs(fast - general).max() <= 1e-12 * np.abs(general).max()
    m_fast = element_mass(mesh, steel.rho, affine=True)
    m_general = element_mass(mesh, steel.rho, affine=False)
    assert np.abs(m_fast - m_general).max() <= 1e-12 * np.abs(m_general).max()


def test_element_stiffness_of_unit_tet_by_hand(steel):
    """Tet4 on the reference tet: K = V B^T D B with the textbook B and D matrices."""
    mesh = TetMesh.unit_tet()
    K = stiffness_blocks(mesh, steel)[0].transpose(0, 2, 1, 3).reshape(12, 12)
    grads = np.array([[-1.0, -1, -1], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    Bm = np.zeros((6, 12))
    for a, (gx, gy, gz) in enumerate(grads):
        Bm[:, 3 * a:3 * a + 3] = [[gx, 0, 0], [0, gy, 0], [0, 0, gz],
                                  [gy, gx, 0], [0, gz, gy], [gz, 0, gx]]
    lam, mu = steel.lame_lambda, steel.lame_mu
    D = np.zeros((6, 6))
    D[:3, :3] = lam
    D[np.arange(3), np.arange(3)] += 2 * mu
    D[np.arange(3, 6), np.arange(3, 6)] = mu
    expected = Bm.T @ D @ Bm / 6.0
    assert np.abs(K - expected).max() <= 1e-12 * np.abs(expected).max()


def _monomials(degree):
    return [(a, b, c) for a in range(degree + 1) for b in range(degree + 1 - a)
            for c in range(degree + 1 - a - b)]


@pytest.mark.parametrize("degree", range(1, 9))
def test_quadrature_exact_to_its_degree(degree):
    """int x^a y^b z^c over the reference tet = a! b! c! / (a + b + c + 3)!."""
    pts, w = tet_quadrature(degree)
    assert np.all(w > 0)
    assert np.all(pts >= 0) and np.all(pts.sum(axis=1) <= 1)
    for a, b, c in _monomials(degree):
        exact = factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3)
        got = w @ (pts[:, 0] ** a * pts[:, 1] ** b * pts[:, 2] ** c)
        assert got == pytest.approx(exact, rel=1e-13, abs=0), (a, b, c)


@pytest.mark.parametrize("degree", [1, 2, 3])
def test_quadrature_degree_is_not_overstated(degree):
    """A rule is not exact one degree higher (so the degree label means something)."""
    pts, w = tet_quadrature(degree)
    errors = []
    for a, b, c in _monomials(degree + 1):
        if a + b + c == degree + 1:
            exact = factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3)
            got = w @ (pts[:, 0] ** a * pts[:, 1] ** b * pts[:, 2] ** c)
            errors.append(abs(got - exact) / exact)
    assert max(errors) > 1e-6


def _faulty(fault: str, order: int) -> TetMesh:
    """A 2 x 2 x 2 box (48 elements) with one kind of fault at elements 5 and 17."""
    box = TetMesh.box(divisions=(2, 2, 2), order=order)
    pts, tets = box.points.copy(), box.tets.copy()
    if fault == "nan":
        pts[tets[5, 0], 1] = np.nan
    elif fault == "inverted":
        for e in (5, 17):
            tets[e, :4] = tets[e, [1, 0, 2, 3]]
            if order == 2:  # the mid-edge nodes follow their swapped corners
                tets[e, 4:] = tets[e, [4, 6, 5, 8, 7, 9]]
    elif fault == "flat":
        for e in (5, 17):
            pts[tets[e, 3]] = pts[tets[e, :3]].mean(axis=0)  # also flattens its neighbours
    return TetMesh(pts, tets)


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("call", ["assemble", "stiffness_matrix", "mass_matrix"])
@pytest.mark.parametrize(("fault", "message"), [
    ("nan", "mesh: node coordinates contain NaN or inf"),
    ("inverted", "mesh: 2 inverted tetrahedra (first: element 5)"),
    ("flat", "zero-volume tetrahedra (first: element"),
])
def test_api_assembly_refuses_a_broken_mesh(fault, message, call, order, steel):
    """Without the check these assemble: NaN entries, or K with negative diagonal terms."""
    import flexarm.fe.assembly as fa
    from flexarm.fe.errors import MeshError

    mesh = _faulty(fault, order)
    args = (mesh, steel.rho) if call == "mass_matrix" else (mesh, steel)
    with pytest.raises(MeshError) as err:
        getattr(fa, call)(*args)
    assert message in str(err.value) and "\n" not in str(err.value)
    if fault == "flat":  # every flattened element is counted, the first named
        vol = mesh.volumes()
        bad = np.flatnonzero(np.abs(vol) <= 1e-12 * np.abs(vol).mean())
        assert str(err.value) == (f"mesh: {bad.size} zero-volume tetrahedra "
                                  f"(first: element {bad[0]})")
    # the same box without the fault assembles, with K's diagonal positive
    K = fa.stiffness_matrix(_faulty("none", order), steel)
    assert K.diagonal().min() > 0
