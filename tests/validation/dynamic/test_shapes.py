"""Model shapes at measurement points and the modal CSV with shapes."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly.analyses import modes
from flexarm.fe.errors import ReadError
from flexarm.validation.data.formats import read_measurements, write_modal
from flexarm.validation.data.shape_data import Points, ShapeData
from flexarm.validation.dynamic.shapes import default_points, model_shapes, point_map
from flexarm.validation.lab.modal_lab import virtual_shapes


@pytest.mark.parametrize("pose", ["P1", "P2", "P3"])
def test_point_at_the_tcp_moves_like_the_tcp(demo, pose):
    robot, arm = demo
    pts = default_points(robot)
    q = robot.pose(pose)
    _, _, phi = model_shapes(arm, q, pts, [601] * 3, list("xyz"))
    assert np.max(np.abs(phi - modes(arm, q).tcp_shapes[:3].T)) < 1e-12


def test_rigid_link_points_follow_rigid_transport(demo):
    """Two points on one rigid link: u_b - u_a = theta x (p_b - p_a) (base frame)."""
    robot, arm = demo
    q = robot.pose("P3")
    pts = Points(nodes=[1, 2], links=[4, 4], positions=[[0.1, 0.02, 0.0], [0.8, -0.05, 0.03]])
    D = point_map(arm, q, pts)
    from flexarm.robot.kinematics import link_frames

    R = link_frames(robot.chain, q)[4, :3, :3]
    x = np.random.default_rng(0).standard_normal(D.shape[-1])
    ua, ub = D[0] @ x, D[1] @ x
    # the link's rotation theta from two more points: theta x e_x and theta x e_y
    pts3 = Points(nodes=[1, 2, 3], links=[4, 4, 4],
                  positions=[[0, 0, 0], [1.0, 0, 0], [0, 1.0, 0]])
    D3 = point_map(arm, q, pts3) @ x

    def skew(v):
        return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])

    A = np.vstack([-skew(R[:, 0]), -skew(R[:, 1])])
    d = np.r_[D3[1] - D3[0], D3[2] - D3[0]]
    theta = np.linalg.lstsq(A, d, rcond=None)[0]
    assert np.allclose(A @ theta, d, atol=1e-12)  # rigid: exactly a rotation
    dp = R @ (pts.positions[1] - pts.positions[0])
    assert np.allclose(ub - ua, np.cross(theta, dp), atol=1e-10)


def test_modal_csv_with_shapes_round_trip(tmp_path, demo):
    robot, arm = demo
    data = virtual_shapes(arm, {p: robot.pose(p) for p in ("P1", "P2")}, default_points(robot),
                          n_modes=3, shape_noise=0.01, seed=4)
    path = write_modal(tmp_path / "shapes.csv", data)
    back = read_measurements(path)
    assert isinstance(back, ShapeData) and back == data


def test_modal_csv_shape_errors_name_line_and_column(tmp_path):
    head = "pose,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,mode,freq_Hz,node,dir,phi\n"
    row = "P1,0,0,0,0,0,0,{m},{f},{n},{d},0.5\n"
    path = tmp_path / "s.csv"
    path.write_text(head + row.format(m=1, f=7, n=1, d="x") + row.format(m=1, f=7, n=1, d="y")
                    + row.format(m=2, f=9, n=1, d="x"))
    with pytest.raises(ReadError, match=r"s.csv, line 4, column 'node': mode 2 .* lists 1 DOFs"):
        read_measurements(path)
    path.write_text(head + row.format(m=1, f=7, n=1, d="x") + row.format(m=1, f=8, n=1, d="y"))
    with pytest.raises(ReadError, match=r"line 3, column 'freq_Hz': the frequency of mode 1"):
        read_measurements(path)
    path.write_text(head.replace(",phi", "") .replace(",dir", "")
                    + "P1,0,0,0,0,0,0,1,7,1\n")
    with pytest.raises(ReadError, match="mode shapes need the columns node, dir and phi"):
        read_measurements(path)


def test_stiff_flexible_links_give_the_emodel_shapes(tmp_path):
    """Craig-Bampton links 1e6 times stiffer: the shapes at points through the
    superelements' recovery equal the E-model's (the box arm's surface and tet masses
    agree) -- checks the recovery, the floating-frame coordinates and the rigid offset
    from the nearest FE node (points inside the boxes and on their faces)."""
    from flexarm.assembly.build import BuildOptions, build_robot
    from flexarm.assembly.emodel import emodel
    from flexarm.assembly.flexible import flexible_arm
    from flexarm.assembly.linkflex import links_arm

    from ...box_arm import box_arm_robot, box_mesher

    robot = box_arm_robot(tmp_path)
    opts = BuildOptions("cb", 6).resolved(robot)
    builds = build_robot(robot, opts, cache=False, mesher=box_mesher)
    flex = flexible_arm(robot, opts, builds=builds, mesher=box_mesher)
    rigid = emodel(robot, method="surface")
    stiff = links_arm(rigid, flex, 1e-6)
    pts = Points(nodes=[1, 2, 3, 4], links=[1, 1, 2, 2],
                 positions=[[0.1, 0.0, 0.5], [0.0, 0.0, 0.3], [0.6, 0.06, 0.0], [1.0, 0, 0]])
    nodes, dirs = np.repeat(pts.nodes, 3), np.tile(list("xyz"), pts.n_points)
    for pose in ("P1", "P2"):
        q = robot.pose(pose)
        f_flex, _, a = model_shapes(stiff, q, pts, nodes, dirs, 4, builds)
        f_rigid, _, e = model_shapes(rigid, q, pts, nodes, dirs, 4)
        assert np.allclose(f_flex, f_rigid, rtol=1e-5)
        a = a * np.sign(np.sum(a * e, axis=1))[:, None]
        assert np.abs(a - e).max() < 1e-6 * np.abs(e).max()
