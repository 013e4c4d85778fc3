"""Bad input to the base layer: each case raises one clear, exact message."""

from __future__ import annotations

import re

import numpy as np
import pytest
import scipy.sparse as sp

from flexarm.fe import (
    FlexarmError,
    Material,
    MeshError,
    SingularMatrixError,
    TetMesh,
    assemble,
    available_backends,
    dof_split,
    factorize,
    material_from_string,
    nodal_load,
    select_nodes,
    static_solve,
)

UNIT = TetMesh.unit_tet().points


def exact(message: str) -> str:
    """``pytest.raises(match=...)`` pattern for the whole message, verbatim."""
    return "^" + re.escape(message) + "$"


# ---------------------------------------------------------------------- material
@pytest.mark.parametrize("nu", [0.5, 0.6])
def test_poisson_ratio_at_or_above_half(nu):
    with pytest.raises(ValueError, match=exact(f"Poisson ratio must be in (-1, 0.5), got {nu}")):
        Material(210e9, nu, 7850.0)


def test_poisson_ratio_from_cli_string():
    with pytest.raises(ValueError, match=exact("Poisson ratio must be in (-1, 0.5), got 0.5")):
        material_from_string("210e9,0.5,7850")


def test_poisson_ratio_just_below_half_is_accepted():
    m = Material(1e9, 0.499, 1000.0)
    assert m.lame_lambda / m.lame_mu == pytest.approx(2 * 0.499 / (1 - 2 * 0.499))


def test_nonpositive_modulus_and_negative_density():
    with pytest.raises(ValueError, match=exact("Young's modulus E must be > 0 Pa, got 0")):
        Material(0, 0.3, 7850.0)
    with pytest.raises(ValueError, match=exact("density must be >= 0 kg/m^3, got -1")):
        Material(210e9, 0.3, -1)


def test_material_string_malformed():
    msg = "material 'E,nu,rho' must be three numbers, got 'a,b,c'"
    with pytest.raises(ValueError, match=exact(msg)):
        material_from_string("a,b,c")


# -------------------------------------------------------------------------- mesh
def test_inverted_tet():
    mesh = TetMesh(UNIT, [[0, 2, 1, 3]])
    msg = "part.vtu: 1 inverted tetrahedra (first: element 0)"
    with pytest.raises(MeshError, match=exact(msg)):
        mesh.check("part.vtu")


def test_inverted_tet_among_good_ones():
    box = TetMesh.box(divisions=(2, 1, 1))
    tets = box.tets.copy()
    tets[3] = tets[3][[1, 0, 2, 3]]
    tets[7] = tets[7][[1, 0, 2, 3]]
    with pytest.raises(MeshError, match=exact("mesh: 2 inverted tetrahedra (first: element 3)")):
        TetMesh(box.points, tets).check()


def test_zero_volume_tet():
    flat = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], dtype=float)
    with pytest.raises(MeshError, match=exact("mesh: 1 zero-volume tetrahedra (first: element 0)")):
        TetMesh(flat, [[0, 1, 2, 3]]).check()


def test_zero_volume_tet_with_repeated_node_among_good_ones():
    box = TetMesh.box(divisions=(2, 1, 1))
    tets = np.vstack([box.tets, [[0, 0, 1, 2]]])
    msg = "mesh: 1 zero-volume tetrahedra (first: element 12)"
    with pytest.raises(MeshError, match=exact(msg)):
        TetMesh(box.points, tets).check()


def test_empty_mesh():
    empty = TetMesh(np.zeros((0, 3)), np.zeros((0, 4), dtype=int))
    with pytest.raises(MeshError, match=exact("mesh: the mesh has no tetrahedra")):
        empty.check()


def test_nan_coordinates():
    pts = UNIT.copy()
    pts[1, 2] = np.nan
    with pytest.raises(MeshError, match=exact("mesh: node coordinates contain NaN or inf")):
        TetMesh(pts, [[0, 1, 2, 3]]).check()


def test_connectivity_beyond_the_nodes():
    with pytest.raises(MeshError, match=exact("tets reference node 7 but the mesh has 4 nodes")):
        TetMesh(UNIT, [[0, 1, 2, 7]])


def test_negative_node_index_is_named():
    """The message must name the bad index (-1), not the largest valid one."""
    with pytest.raises(MeshError, match=exact("tets reference node -1 but the mesh has 4 nodes")):
        TetMesh(UNIT, [[0, 1, 2, -1]])


def test_node_set_beyond_the_nodes():
    msg = "node set 'fixed' references nodes outside the mesh"
    with pytest.raises(MeshError, match=exact(msg)):
        TetMesh(UNIT, [[0, 1, 2, 3]], {"fixed": [9]})


def test_wrong_element_width():
    with pytest.raises(ValueError, match=exact("tets must be (m, 4) or (m, 10), got (1, 3)")):
        TetMesh(UNIT, [[0, 1, 2]])


def test_mesh_errors_are_flexarm_errors():
    """The CLI turns every FlexarmError into one line: mesh errors must be among them."""
    assert issubclass(MeshError, FlexarmError)
    assert issubclass(SingularMatrixError, FlexarmError)


# --------------------------------------------------------------------- selection
@pytest.mark.parametrize("expr", ["x>5", "x=min & x=max", "z<-0.001"])
def test_selection_that_selects_nothing(expr, two_element_cantilever):
    with pytest.raises(ValueError, match=exact(f"selection '{expr}' selects no nodes")):
        select_nodes(two_element_cantilever, expr)


def test_selection_term_malformed(two_element_cantilever):
    msg = ("selection term 'foo' is neither a node set (known: fixed, tip) "
           "nor a comparison like 'x=min', 'z<0.01' [m]")
    with pytest.raises(ValueError, match=exact(msg)):
        select_nodes(two_element_cantilever, "foo")


def test_selection_by_node_set(two_element_cantilever):
    np.testing.assert_array_equal(select_nodes(two_element_cantilever, "fixed"),
                                  select_nodes(two_element_cantilever, "x=min"))
    assert select_nodes(two_element_cantilever, "tip & z=max").size == 2


# ------------------------------------------------------------------ DOFs, loads
@pytest.mark.parametrize("fixed, shown", [([0, 6], "0..6"), ([-1, 2], "-1..2")])
def test_fixed_dofs_out_of_range(fixed, shown):
    with pytest.raises(ValueError, match=exact(f"fixed DOFs must lie in [0, 6), got {shown}")):
        dof_split(6, fixed)


def test_nodal_load_on_empty_selection():
    with pytest.raises(ValueError, match=exact("nodal_load got an empty node selection")):
        nodal_load(4, [], [0.0, 0.0, 1.0])


# ----------------------------------------------------------------------- solvers
@pytest.fixture(scope="module")
def free_stiffness(steel):
    """K of an unsupported 1 m Tet4 bar: six rigid modes, singular."""
    K, _ = assemble(TetMesh.box((1.0, 0.1, 0.1), (4, 1, 1)), steel)
    return K


@pytest.mark.skipif("pardiso" not in available_backends(), reason="pypardiso not installed")
def test_singular_stiffness_pardiso(free_stiffness):
    msg = ("matrix is singular or not positive definite (PARDISO zero pivot): "
           "is the part fully supported?")
    f = np.ones(free_stiffness.shape[0])
    with pytest.raises(SingularMatrixError, match=exact(msg)):
        static_solve(free_stiffness, f, backend="pardiso")
    # partly supported (one node fixed: rotations about it remain) is singular too
    split = dof_split(free_stiffness.shape[0], [0, 1, 2])
    with pytest.raises(SingularMatrixError, match=exact(msg)):
        static_solve(free_stiffness, f, split, backend="pardiso")


def test_singular_stiffness_splu(free_stiffness):
    """The pure-scipy fallback must not return a garbage solution for a free part.

    SuperLU only stops on an *exactly* zero pivot; the six rigid modes give pivots
    ~1e-15 of the largest, so today it returns displacements of ~1e6 m instead.
    """
    f = np.ones(free_stiffness.shape[0])
    with pytest.raises(SingularMatrixError):
        static_solve(free_stiffness, f, backend="splu")


@pytest.mark.parametrize("backend", available_backends())
def test_empty_row_is_singular(backend):
    with pytest.raises(SingularMatrixError):
        factorize(sp.diags([1.0, 0.0, 2.0]).tocsr(), backend=backend)


def test_unknown_backend_and_bad_shapes():
    with pytest.raises(ValueError, match=exact(
            "solver backend must be one of pardiso, cholmod, splu, got 'mumps'")):
        factorize(sp.eye(3).tocsr(), backend="mumps")
    with pytest.raises(ValueError, match=exact("matrix must be square, got shape (2, 3)")):
        factorize(sp.csr_matrix(np.ones((2, 3))), backend="splu")
    with pytest.raises(ValueError, match=exact("right-hand side must have 3 rows, got shape (4,)")):
        factorize(sp.eye(3).tocsr(), backend="splu").solve(np.ones(4))
