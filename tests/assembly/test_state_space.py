"""The arm as a state-space model: its FRF is ``frf``'s, its poles the arm's eigenvalues,
its DC gain the static compliance (by python-control and by scipy.signal), for the
E-model, the CB arm and the full-FE arm; truncation keeps the DC gain exact; files
round-trip bit for bit."""

import numpy as np
import pytest
import scipy.io
import scipy.signal

from flexarm.assembly.analyses import frf, modes, tcp_compliance
from flexarm.assembly.arm import build_arm
from flexarm.assembly.build import BuildOptions
from flexarm.assembly.formats import read_state_space, write_state_space
from flexarm.assembly.full_arm import full_arm
from flexarm.assembly.state_space import state_space
from flexarm.assembly.system import system_matrices

from ..box_arm import box_mesher

control = pytest.importorskip("control", reason="python-control (pip install control) is "
                                                "needed to check the export against it")


@pytest.fixture(scope="module")
def arms(demo_robot, flex_arm):
    return {"emodel": build_arm(demo_robot).model, "cb": flex_arm}


def _relmax(a, b) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


@pytest.mark.parametrize("which", ["emodel", "cb"])
def test_frf_of_the_matrices_is_frf(arms, demo_robot, which):
    arm, q = arms[which], demo_robot.pose("P1")
    ss = state_space(arm, q)
    f = np.concatenate([[0.0], np.geomspace(0.5, 400.0, 60)])
    H = frf(arm, q, f)
    assert _relmax(ss.frequency_response(f)[:, :6, :6], H) < 1e-10
    # and through python-control's own evaluation of the same matrices
    sys = control.ss(ss.A, ss.B, ss.C, ss.D)
    Hc = np.stack([sys(2j * np.pi * fk)[:6, :6] for fk in f[::6]])
    assert _relmax(Hc, H[::6]) < 1e-10


@pytest.mark.parametrize("which", ["emodel", "cb"])
def test_poles_are_the_arm_eigenvalues(arms, demo_robot, which):
    arm, q = arms[which], demo_robot.pose("P1")
    ss = state_space(arm, q)
    md = modes(arm, q)
    w, z = md.omega, md.damping
    wd = w * np.sqrt(1 - z**2)
    ours = np.concatenate([-z * w + 1j * wd, -z * w - 1j * wd])
    eig = np.linalg.eigvals(ss.A)
    # match every pole of A to the nearest eigenvalue of the arm, one to one
    order_a = np.lexsort((eig.imag, np.round(np.abs(eig), 6)))
    order_b = np.lexsort((ours.imag, np.round(np.abs(ours), 6)))
    assert np.max(np.abs(eig[order_a] - ours[order_b]) / np.abs(ours[order_b])) < 1e-9
    np.testing.assert_allclose(np.sort_complex(ss.poles()), np.sort_complex(ours), rtol=1e-12)


@pytest.mark.parametrize("which", ["emodel", "cb"])
def test_dc_gain_is_the_static_compliance(arms, demo_robot, which, tmp_path):
    arm, q = arms[which], demo_robot.pose("P1")
    path = write_state_space(tmp_path / "arm_P1.mat", state_space(arm, q))
    ss = read_state_space(path)
    sys = control.ss(ss.A, ss.B, ss.C, ss.D, inputs=list(ss.input_names),
                     outputs=list(ss.output_names))
    G = sys.dcgain()
    C = tcp_compliance(arm, q)
    assert _relmax(G[:6, :6], C) < 1e-10
    # the joint blocks: deflections per joint torque are K^-1 on the joint coordinates
    sm = system_matrices(arm, q)
    tors = [ss.output_names.index(f"{n}_torsion") - 6 for n in arm.joint_names]
    joint_rows = np.concatenate(arm.layout["joint"])
    Kinv = np.linalg.inv(sm.K)[np.ix_(joint_rows, joint_rows[tors])]
    assert _relmax(G[6:, 6:], Kinv) < 1e-10
    assert sys.input_labels[1] == "tcp_Fy" and sys.output_labels[1] == "tcp_uy"


def test_scipy_signal_step_settles_at_the_compliance(arms, demo_robot, tmp_path):
    arm, q = arms["emodel"], demo_robot.pose("P1")
    write_state_space(tmp_path / "arm.mat", state_space(arm, q))
    m = scipy.io.loadmat(tmp_path / "arm.mat")
    names = [str(s.squeeze()) for s in m["input_names"].ravel()]
    i, o = names.index("tcp_Fy"), 1
    sys = scipy.signal.StateSpace(m["A"], m["B"][:, [i]], m["C"][[o]], m["D"][[o]][:, [i]])
    t = np.linspace(0.0, 40.0, 4001)  # the slowest mode has decayed by e^-50
    _, y, _ = scipy.signal.lsim(sys, np.full(t.size, 800.0), t)
    assert abs(y[-1] / (800.0 * tcp_compliance(arm, q)[1, 1]) - 1) < 1e-9
    assert y.max() > 800.0 * tcp_compliance(arm, q)[1, 1]  # a damped step overshoots


def test_truncation_keeps_the_static_gain(arms, demo_robot):
    arm, q = arms["cb"], demo_robot.pose("P1")
    full, cut = state_space(arm, q), state_space(arm, q, n_modes=8)
    assert cut.A.shape == (16, 16) and np.any(cut.D) and not np.any(full.D)
    assert _relmax(cut.dc_gain(), full.dc_gain()) < 1e-10
    f = np.geomspace(1.0, 0.3 * cut.freq_hz[-1], 20)  # well below the first mode left out
    Hf, Hc = full.frequency_response(f)[:, :3, :3], cut.frequency_response(f)[:, :3, :3]
    assert _relmax(Hc, Hf) < 1e-2


def test_full_fe_arm_frf_and_dc_gain(box_robot):
    full = full_arm(box_robot, BuildOptions(), n_modes=6, mesher=box_mesher)
    q = box_robot.pose("P1")
    ss = state_space(full, q)
    f = np.concatenate([[0.0], np.geomspace(1.0, 2 * ss.freq_hz[-1], 25)])
    assert ss.n_modes == 6 and np.any(ss.D)
    assert _relmax(ss.frequency_response(f)[:, :6, :6], frf(full, q, f)) < 1e-10
    assert _relmax(ss.dc_gain()[:6, :6], tcp_compliance(full, q)) < 1e-10


@pytest.mark.parametrize("suffix", [".mat", ".npz"])
def test_files_round_trip_bit_for_bit(arms, demo_robot, tmp_path, suffix):
    ss = state_space(arms["cb"], demo_robot.pose("P1"), model="CB")
    back = read_state_space(write_state_space(tmp_path / f"arm{suffix}", ss))
    for k in ("A", "B", "C", "D", "omega", "damping", "input_participation",
              "output_participation", "q"):
        assert np.array_equal(getattr(back, k), getattr(ss, k)), k
    assert back.input_names == ss.input_names and back.output_units == ss.output_units
    assert back.state_names == ss.state_names and back.model == "CB"


def test_a_file_that_is_not_one_is_one_line_error(tmp_path):
    from flexarm.fe.errors import ReadError

    bad = tmp_path / "x.npz"
    np.savez(bad, A=np.zeros((2, 2)))
    with pytest.raises(ReadError, match=r"x\.npz: missing field"):
        read_state_space(bad)
