"""Tying 3-DOF master nodes rigidly to the seat centre."""

import numpy as np
import pytest

from flexarm.fe.material import MATERIALS
from flexarm.reduction import reduce_part
from flexarm.reduction.tie import tied_superelement
from flexarm.studies.part_study import bar_link


def test_tied_all_nodes_equals_rbe2():
    """All seat nodes tied rigidly to the centre is RBE2 (Guyan: exactly)."""
    mesh, regions = bar_link(divisions=(6, 2, 2))
    steel = MATERIALS["steel"]
    rbe2 = reduce_part(mesh, steel, regions, "rbe2", "guyan", 0)
    tied = tied_superelement(reduce_part(mesh, steel, regions, "nodes", "guyan", 0))
    assert tied.dofs_per_node == 6 and tied.n_dofs == rbe2.n_dofs
    np.testing.assert_allclose(tied.K, rbe2.K, rtol=1e-7, atol=1e-7 * np.abs(rbe2.K).max())
    np.testing.assert_allclose(tied.M, rbe2.M, rtol=1e-7, atol=1e-7 * np.abs(rbe2.M).max())
    q = np.linspace(-1e-4, 1e-4, rbe2.n_dofs)
    np.testing.assert_allclose(tied.expand(q), rbe2.expand(q), atol=1e-9)


def test_tie_needs_three_dof_masters():
    mesh, regions = bar_link(divisions=(4, 1, 1))
    se = reduce_part(mesh, MATERIALS["steel"], regions, "rbe2", "guyan", 0)
    with pytest.raises(ValueError, match="3-DOF master nodes"):
        tied_superelement(se)
