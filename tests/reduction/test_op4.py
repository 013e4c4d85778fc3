"""OP4 export: matrices come back bit for bit through pyNastran's independent reader
(zero columns, three-digit exponents, subnormals included); a superelement's K, M and
DOF table match the DMIG numbering."""

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
