"""Full-FE reference: unreduced links joined like the reduced ones."""

import numpy as np
import pytest

from flexarm.assembly.analyses import natural_frequencies, tcp_compliance
from flexarm.assembly.build import BuildOptions
from flexarm.assembly.flexible import flexible_arm
from flexarm.assembly.full_fe import full_fe_analysis, full_fe_bodies, sparse_bodies

from ..box_arm import box_mesher


@pytest.fixture(scope="module")
def reference(box_robot):
    arm = flexible_arm(box_robot, BuildOptions("cb", 20), mesher=box_mesher)
    bodies = full_fe_bodies(box_robot, BuildOptions(), mesher=box_mesher)
    return arm, full_fe_analysis(arm, bodies, box_robot.pose("P1"), 8)


def test_sparse_assembly_equals_system_matrices(box_robot):
    """The sparse joiner on the reduced bodies reproduces ``system_matrices``."""
    arm = flexible_arm(box_robot, BuildOptions("cb", 4), mesher=box_mesher)
    q = box_robot.pose("P2")
    res = full_fe_analysis(arm, sparse_bodies(arm), q, 6, backend="splu")
    np.testing.assert_allclose(res.freq_hz, natural_frequencies(arm, q)[:6], rtol=1e-9)
    np.testing.assert_allclose(res.C, tcp_compliance(arm, q), rtol=1e-9, atol=1e-20)


def test_cb_converges_to_full_fe(box_robot, reference):
    arm, ref = reference
    q = box_robot.pose("P1")
    f_cb = natural_frequencies(arm, q)[:8]
    assert np.all(f_cb >= ref.freq_hz * (1 - 1e-9))  # Rayleigh-Ritz: from above
    assert np.abs(f_cb / ref.freq_hz - 1).max() < 1e-4
    # interface loads: static condensation is exact
    np.testing.assert_allclose(np.diag(tcp_compliance(arm, q)), np.diag(ref.C), rtol=1e-8)


def test_guyan_degrades_with_frequency(box_robot, reference):
    _, ref = reference
    q = box_robot.pose("P1")
    gy = flexible_arm(box_robot, BuildOptions("guyan"), mesher=box_mesher)
    err = natural_frequencies(gy, q)[:8] / ref.freq_hz - 1
    assert np.all(err >= -1e-9)
    assert err[:4].max() < 0.005 and err[4:].max() > 0.05  # fine low, poor above ~300 Hz


@pytest.mark.slow
def test_demo_p1_cb_within_half_percent(demo_robot):
    """CB vs full FE at P1, default settings (CB(10), RBE2, 30 mm Tet4)."""
    opts = BuildOptions()
    arm = flexible_arm(demo_robot, opts)
    q = demo_robot.pose("P1")
    ref = full_fe_analysis(arm, full_fe_bodies(demo_robot, opts), q, 10)
    f = natural_frequencies(arm, q)[:10]
    assert np.abs(f / ref.freq_hz - 1).max() < 0.005
    C = np.diag(tcp_compliance(arm, q))
    assert np.abs(C / np.diag(ref.C) - 1).max() < 0.005
    assert arm.layout["n"] * 100 <= ref.n_dofs
    gy = flexible_arm(demo_robot, BuildOptions("guyan"))
    err = np.abs(natural_frequencies(gy, q)[:10] / ref.freq_hz - 1)
    assert err[ref.freq_hz < 100].max() < 0.002 and err[ref.freq_hz > 100].max() > 0.003
