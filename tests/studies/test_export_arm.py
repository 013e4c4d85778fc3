"""export_arm: the OP4 arm is the assembled arm bit for bit (read by pyNastran), its
damping matrix is the modal damping, every link superelement comes along; a
state-space export checks itself against frf."""

import numpy as np
import pytest

from flexarm.assembly.analyses import modes
from flexarm.assembly.arm import Arm, ArmSpec, build_arm
from flexarm.assembly.full_arm import FullFEArm
from flexarm.assembly.system import system_matrices
from flexarm.studies.export_arm import export_arm, export_format

op4 = pytest.importorskip("pyNastran.op4.op4", reason="pyNastran reads OP4 independently")


@pytest.fixture(scope="module")
def cb_arm(demo_robot):
    return build_arm(demo_robot, ArmSpec("cb", mesh_size=0.06, n_modes=10))


def test_op4_arm_is_the_assembled_arm(cb_arm, demo_robot, tmp_path):
    q = demo_robot.pose("P1")
    ex = export_arm(cb_arm, q, tmp_path / "arm_P1.op4")
    back = op4.read_op4(str(ex.paths[0]), precision="default", debug=False)
    sm = system_matrices(cb_arm.model, q)
    assert np.array_equal(back["KAAX"].data, sm.K)
    # M's triangles differ by round-off (1e-16): written symmetric, as their mean
    M = back["MAAX"].data
    assert back["MAAX"].form == back["KAAX"].form == back["BAAX"].form == 6
    assert np.array_equal(M, M.T) and np.abs(M - sm.M).max() < 1e-15 * np.abs(sm.M).max()
    assert np.array_equal(back["GTCP"].data, sm.G_tcp)
    md = modes(cb_arm.model, q)
    modal = md.shapes.T @ back["BAAX"].data @ md.shapes
    np.testing.assert_allclose(np.diag(modal), 2 * md.damping * md.omega, rtol=1e-8)
    off = modal - np.diag(np.diag(modal))
    assert np.abs(off).max() < 1e-8 * np.abs(np.diag(modal)).max()
    rows = (tmp_path / "arm_P1_dofs.csv").read_text().splitlines()
    assert rows[0] == "spoint,name,unit" and rows[1] == "1,joint_1.torsion,rad"
    assert len(rows) == 1 + sm.K.shape[0]
    links = [p for p in ex.paths if p.name.startswith("arm_P1_") and p.suffix == ".op4"]
    assert len(links) == sum(b.superelement is not None for b in cb_arm.builds)
    lower = op4.read_op4(str(tmp_path / "arm_P1_lower_arm.op4"), precision="default",
                         debug=False)
    se = cb_arm.builds[2].superelement
    assert np.array_equal(lower["KAAX"].data, se.K)


def test_state_space_export_checks_itself(cb_arm, demo_robot, tmp_path):
    ex = export_arm(cb_arm, demo_robot.pose("P1"), tmp_path / "arm.npz")
    assert ex.frf_error < 1e-10 and ex.paths[0].is_file()
    assert "state-space FRF vs frf" in ex.text()


def test_bad_requests_fail_before_work(demo_robot, tmp_path):
    with pytest.raises(ValueError, match="known: .mat, .npz"):
        export_format(tmp_path / "arm.op2")
    with pytest.raises(ValueError, match="arm matrices"):
        export_format(tmp_path / "arm.mat", "op4")
    arm = build_arm(demo_robot)
    fake_full = Arm(demo_robot, FullFEArm(arm.model, ()), arm.spec)  # refused unbuilt
    with pytest.raises(ValueError, match="full-FE arm"):
        export_arm(fake_full, demo_robot.pose("P1"), tmp_path / "x.op4")
    assert not (tmp_path / "x.op4").exists()
