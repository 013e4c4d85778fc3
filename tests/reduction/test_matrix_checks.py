"""A superelement file is trusted for its content, not its checksum: damage written
through flexarm's own writers (a valid checksum) is refused on reading, in every format,
before anything is converted."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from reduction_helpers import STEEL

from flexarm.fe import ReadError
from flexarm.reduction import formats
from flexarm.reduction.matrix_checks import RIGID_BODY_MODES, check_matrices
from flexarm.reduction.reduce import reduce_part
from flexarm.reduction.superelement import reduced_rigid_modes
from flexarm.reduction.tolerances import tol


@pytest.fixture(scope="module", params=["rbe2", "rbe3", "nodes"])
def se(request, bar):
    mesh, regions, KM = bar
    return reduce_part(mesh, STEEL, regions, request.param, "cb", 4, matrices=KM)


def _rigid(se):
    return reduced_rigid_modes(se.node_positions, se.dofs_per_node, se.n_dofs)


def test_reduced_links_pass_with_margin(se):
    """Their rigid modes sit far below the zero threshold, their elastic ones far above."""
    import scipy.linalg

    check_matrices(se.K, se.M, _rigid(se), se.mass, "bar.h5")
    w2 = scipy.linalg.eigh(se.K, se.M, eigvals_only=True)
    zero, elastic = np.abs(w2[:RIGID_BODY_MODES]), w2[RIGID_BODY_MODES:]
    assert zero.max() < 1e-3 * tol.file_psd * w2[-1]
    assert elastic.min() > 1e3 * tol.file_psd * w2[-1]


def test_a_rigid_body_passes_and_its_mass_is_the_files():
    M = np.diag([2.0, 2.0, 2.0, 0.1, 0.2, 0.3])
    check_matrices(np.zeros((6, 6)), M, np.eye(6), 2.0, "rigid.h5")
    with pytest.raises(ReadError, match=r"^rigid\.h5: M holds 2 kg but the file states "
                                        r"2\.002 kg$"):
        check_matrices(np.zeros((6, 6)), M, np.eye(6), 2.002, "rigid.h5")


def _damaged(se, **changes):
    return {"K": se.K, "M": se.M, **changes}


@pytest.mark.parametrize("label, change, message", [
    ("nan", lambda se: _damaged(se, M=np.where(np.eye(se.n_dofs) > 0, np.nan, se.M)),
     r"M holds \d+ non-finite entries \(nan at row 1, column 1\)"),
    ("inf", lambda se: _damaged(se, K=se.K + np.diag([np.inf] + [0.0] * (se.n_dofs - 1))),
     r"K holds 1 non-finite entry \(inf at row 1, column 1\)"),
    ("M negated", lambda se: _damaged(se, M=-se.M), r"M is not positive definite"),
    ("M singular", lambda se: _damaged(se, M=se.M * (np.arange(se.n_dofs) > 0)[:, None]
                                       * (np.arange(se.n_dofs) > 0)),
     r"M is not positive definite \(eigenvalues 0 to"),
    ("K negated", lambda se: _damaged(se, K=-se.K), r"K is not positive semi-definite"),
    ("K asymmetric", lambda se: _damaged(se, K=se.K + np.triu(np.full_like(
        se.K, 1e-6 * np.abs(se.K).max()), 1)),
     r"K is not symmetric \(relative asymmetry"),
    ("mechanism", lambda se: _damaged(se, K=se.K * (np.arange(se.n_dofs) < se.n_dofs - 1)
                                      * (np.arange(se.n_dofs) < se.n_dofs - 1)[:, None]),
     r"K has 7 zero-energy modes, not the 6 rigid-body motions of a free link"),
    ("fixed", lambda se: _damaged(se, K=se.K + np.eye(se.n_dofs) * np.abs(se.K).max()),
     r"K has 0 zero-energy modes, not the 6"),
])
def test_each_damage_is_named_with_its_figure(se, label, change, message):
    d = change(se)
    with pytest.raises(ReadError, match=r"^part\.h5: " + message):
        check_matrices(d["K"], d["M"], _rigid(se), se.mass, "part.h5")


def test_rigid_motions_must_be_free_of_strain(se):
    """Node positions that do not belong to K (the part drawn twice as long): K R is no
    longer zero.  Not a shift or a uniform scaling: rigid motions of those span the same
    space."""
    R = reduced_rigid_modes(se.node_positions * [2.0, 1.0, 1.0], se.dofs_per_node, se.n_dofs)
    residual = np.linalg.norm(se.K @ R) / (np.linalg.norm(se.K) * np.linalg.norm(R))
    assert residual > 1e3 * tol.file_rigid
    with pytest.raises(ReadError, match=r"strain K \(relative residual \d\.\de-0\d"):
        check_matrices(se.K, se.M, R, se.mass, "part.h5")


@pytest.mark.parametrize("ext", ["h5", "npz", "mtx", "bdf"])
def test_damage_with_a_valid_checksum_is_refused_on_reading(se, tmp_path, ext):
    good = formats.read(formats.write(tmp_path / f"good.{ext}", se))
    assert np.array_equal(good.M, se.M)
    path = formats.write(tmp_path / f"bad.{ext}", dataclasses.replace(se, M=-se.M))
    with pytest.raises(ReadError, match=rf"bad\.{ext}: M is not positive definite"):
        formats.read(path)


def test_convert_refuses_before_writing(se, tmp_path):
    M = np.array(se.M)
    M[2, 3] = M[3, 2] = np.nan
    src = formats.write(tmp_path / "nan.h5", dataclasses.replace(se, M=M))
    with pytest.raises(ReadError, match=r"nan\.h5: M holds 2 non-finite entries"):
        formats.convert(src, tmp_path / "laundered.npz")
    assert not (tmp_path / "laundered.npz").exists()
