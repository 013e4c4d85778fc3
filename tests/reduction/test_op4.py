"""OP4 export: matrices come back bit for bit through pyNastran's independent reader
(zero columns, three-digit exponents, subnormals included); symmetric up to round-off is
written symmetric (form 6); a superelement's K, M and DOF table match the DMIG
numbering."""

import numpy as np
import pytest
from reduction_helpers import STEEL

from flexarm.reduction import formats
from flexarm.reduction.formats.dmig import dof_labels
from flexarm.reduction.formats.op4 import write_matrices
from flexarm.reduction.reduce import reduce_part

op4 = pytest.importorskip("pyNastran.op4.op4", reason="pyNastran reads OP4 independently")


def _read(path):
    return op4.read_op4(str(path), precision="default", debug=False)


def test_matrices_bit_for_bit(tmp_path):
    rng = np.random.default_rng(7)
    A = rng.standard_normal((11, 11)) * 10.0 ** rng.integers(-300, 300, (11, 11))
    A = A + A.T
    A[4], A[:, 4] = 0.0, 0.0  # a null column
    A[0, 0] = 5e-324  # subnormal
    R = rng.standard_normal((3, 7))
    R[:, 0] = 0.0
    write_matrices(tmp_path / "m.op4", {"KAAX": A, "G_1": R})
    back = _read(tmp_path / "m.op4")
    assert np.array_equal(back["KAAX"].data, A) and back["KAAX"].form == 6
    assert np.array_equal(back["G_1"].data, R) and back["G_1"].form == 2


def test_round_off_asymmetry_is_written_symmetric(tmp_path):
    """Form 6 when the asymmetry is round-off (scaled by the diagonal, so a rotational
    coordinate's small entries count as much as a translational one's); form 1 beyond."""
    rng = np.random.default_rng(3)
    B = rng.standard_normal((9, 9))
    s = np.array([1e8] * 3 + [1e2] * 3 + [1.0] * 3)  # N/m, N m/rad and modal scales
    A = (B @ B.T + 9 * np.eye(9)) * np.outer(s, s)
    noisy = A * (1 + 4e-16 * rng.standard_normal((9, 9)))
    skew = A.copy()
    skew[7, 4] *= 1 + 1e-9  # small in absolute terms (1e-7 of the largest entry's scale)
    write_matrices(tmp_path / "m.op4", {"MAAX": noisy, "SKEW": skew})
    back = _read(tmp_path / "m.op4")
    M = back["MAAX"].data
    assert back["MAAX"].form == 6 and np.array_equal(M, M.T)
    assert np.abs(M - noisy).max() <= np.abs(noisy - noisy.T).max()
    assert back["SKEW"].form == 1 and np.array_equal(back["SKEW"].data, skew)


def test_bad_name_is_refused(tmp_path):
    with pytest.raises(ValueError, match="OP4 matrix name"):
        write_matrices(tmp_path / "m.op4", {"k aax": np.eye(2)})
    assert not (tmp_path / "m.op4").exists()


def test_superelement_round_trip(bar, tmp_path):
    mesh, regions, KM = bar
    se = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 5, matrices=KM)
    path = formats.write(tmp_path / "link.op4", se)
    back = _read(path)
    assert np.array_equal(back["KAAX"].data, se.K) and np.array_equal(back["MAAX"].data, se.M)
    ids, comps = dof_labels(len(se.node_positions), 6, se.n_modes)
    tab = back["DOFTAB"].data
    assert np.array_equal(tab[:, 0], ids) and np.array_equal(tab[:, 1], comps)
    assert np.array_equal(tab[: 6 * 2, 2], np.repeat([1.0, 2.0], 6)) and not tab[12:, 2].any()
    assert np.array_equal(back["GRIDXYZ"].data, se.node_positions)
    with pytest.raises(ValueError, match="cannot read"):
        formats.read(path)


def test_recovery_matrix_gives_the_full_fe_mode_shape(bar, tmp_path):
    """OTM (read by pyNastran) times the reduced coordinates of a free mode is the full-FE
    displacement field flexarm recovers, row by row through OTMDOF."""
    from flexarm.reduction.recovery import mode_coordinates, mode_shape

    mesh, regions, KM = bar
    se = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 5, matrices=KM)
    back = _read(formats.write(tmp_path / "link.op4", se))
    otm, tab = back["OTM"].data, back["OTMDOF"].data
    assert otm.shape == (3 * len(mesh.points), se.K.shape[0])
    assert np.array_equal(otm, np.asarray(se.T, float))  # float32 recovery, held exactly
    node, comp = tab[:, 0].astype(int) - 1, tab[:, 1].astype(int) - 1
    _, u = mode_shape(se, 2, "free")  # (n_fe, 3), largest displacement 1
    _, q = mode_coordinates(se, 2, "free")
    got = np.zeros_like(u)
    got[node, comp] = otm @ q
    got /= np.abs(got).max()
    np.testing.assert_allclose(got * np.sign(got.ravel() @ u.ravel()), u, rtol=0, atol=1e-6)
