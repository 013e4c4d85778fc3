"""MAC, pairing and CoMAC against the generating model, a constructed mode swap, and a
stiffness change on one link."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from flexarm.robot.effects import parse_effect
from flexarm.validation.data.shape_data import Points
from flexarm.validation.dynamic.compare_shapes import compare_shapes
from flexarm.validation.dynamic.mac import comac, mac, pair_modes
from flexarm.validation.dynamic.shapes import default_points
from flexarm.validation.lab.modal_lab import virtual_shapes


def test_mac_is_scale_and_phase_blind_and_matches_definition():
    rng = np.random.default_rng(0)
    A = rng.standard_normal((4, 9)) + 1j * rng.standard_normal((4, 9))
    B = A * np.exp(1j * rng.uniform(0, 6, (4, 1))) * rng.uniform(0.1, 9, (4, 1))
    assert np.allclose(np.diag(mac(A, B)), 1.0, atol=1e-12)
    a, b = A[0], A[1]
    direct = abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)
    assert mac(A, A)[0, 1] == pytest.approx(direct, rel=1e-12)


@pytest.mark.parametrize("seed", range(5))
def test_mac_diagonal_against_generating_model(demo, seed):
    """Shapes at the default points (2 % shape noise) against the model that made them."""
    robot, arm = demo
    pts = default_points(robot)
    poses = {p: robot.pose(p) for p in ("P1", "P2", "P3")}
    data = virtual_shapes(arm, poses, pts, n_modes=6, shape_noise=0.02, seed=seed)
    cmp = compare_shapes(arm, data, pts)
    for pc in cmp.poses:
        assert pc.model.tolist() == list(range(6))
        assert np.all(pc.pair_mac > 0.99), pc.pair_mac
        assert not pc.swapped.any()


def test_mac_pairing_fixes_a_frequency_swap(demo):
    """Joint 4 at a quarter of its modelled stiffness: at P2 its torsion mode (model
    mode 6, 128 Hz) drops to 68 Hz, below model mode 5 (85 Hz), whose shape is measured
    at 86 Hz.  Frequency-only assignment pairs the measured 68 Hz mode with model mode 5
    and the 86 Hz mode with mode 6; MAC pairs each with the model mode of its shape."""
    robot, arm = demo
    pts = default_points(robot)
    data = virtual_shapes(arm, {"P2": robot.pose("P2")}, pts,
                          [parse_effect("stiffness:j4=0.25")], n_modes=6, freq_noise=0.0)
    pc = compare_shapes(arm, data, pts).poses[0]
    assert pc.f_meas[4] < pc.f_model[4] < pc.f_meas[5] < pc.f_model[5]
    assert pc.by_frequency[4:].tolist() == [4, 5]  # frequency only: the j4 mode -> mode 5
    assert pc.model[4:].tolist() == [5, 4]  # MAC: each to the model mode of its shape
    assert np.all(pc.pair_mac[4:] > 0.9) and pc.swapped[4:].all()
    assert pc.model[:4].tolist() == [0, 1, 2, 3] and np.all(pc.pair_mac[:4] > 0.97)


def test_unpaired_mode_is_reported_not_forced():
    M = np.array([[0.95, 0.1], [0.2, 0.3], [0.05, 0.9]])
    p = pair_modes(M, [10.0, 12.0, 30.0], [10.2, 29.0])
    assert p.model.tolist() == [0, -1, 1]
    assert p.mac[1] == pytest.approx(0.2)  # its best within a factor 2 (29 Hz is not)


def test_comac_drops_only_where_the_shapes_differ():
    rng = np.random.default_rng(2)
    A = rng.standard_normal((5, 12))
    B = 3.0 * A
    B[:, 7] = rng.standard_normal(5)  # one DOF of the model is unrelated
    c = comac(A, B)
    assert np.argmin(c) == 7 and np.delete(c, 7).min() > 0.9


@pytest.fixture(scope="module")
def box_flexible(tmp_path_factory):
    """The three-link box arm (column and arm Craig-Bampton, structured tet meshes)."""
    from flexarm.assembly.build import BuildOptions, build_robot
    from flexarm.assembly.flexible import flexible_arm

    from ...box_arm import box_arm_robot, box_mesher

    robot = box_arm_robot(tmp_path_factory.mktemp("box"))
    opts = BuildOptions("cb", 6).resolved(robot)
    builds = build_robot(robot, opts, cache=False, mesher=box_mesher)
    return robot, flexible_arm(robot, opts, builds=builds, mesher=box_mesher), builds


def box_points() -> Points:
    """Four points up the column's +x face (link 1), four along the arm's top (link 2)."""
    column = [[0.1, 0.0, z] for z in (0.2, 0.4, 0.6, 0.8)]
    arm = [[x, 0.0, 0.06] for x in (0.25, 0.5, 0.75, 1.0)]
    return Points(nodes=[100, 101, 102, 103, 200, 201, 202, 203], links=[1] * 4 + [2] * 4,
                  positions=column + arm)


@pytest.mark.parametrize("pose", ["P1", "P2"])
def test_comac_localises_a_softer_link(box_flexible, pose):
    """The column (link 1) twice as compliant as modelled: its two points of lowest
    CoMAC are the lowest of all (shapes through the superelements' recovery).

    CoMAC does not localise everything: the arm (link 2) twice as compliant gives its
    lowest CoMAC on the column too (the modes are column-dominated and the column's
    small motions change most), which this test does not hide."""
    robot, arm, builds = box_flexible
    pts = box_points()
    truth = replace(arm, bodies=tuple(replace(b, K=b.K / 2) if k == 1 else b
                                      for k, b in enumerate(arm.bodies)))
    data = virtual_shapes(truth, {pose: robot.pose(pose)}, pts, n_modes=6, freq_noise=0.0,
                          builds=builds)
    pc = compare_shapes(arm, data, pts, builds=builds).poses[0]
    assert pc.model.tolist() == list(range(6))  # a stiffness change, not a new mode
    lowest = pc.nodes[np.argsort(pc.comac)[:2]]
    assert set(lowest // 100) == {1}, (pose, pc.comac.round(3))
    assert pc.comac[pc.nodes // 100 == 2].min() > pc.comac.min() + 0.02
