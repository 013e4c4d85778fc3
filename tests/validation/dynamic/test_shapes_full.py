"""Mode shapes at measurement points of the full-FE arm: the E-model's rigid bodies as
sparse bodies give the E-model's shapes, and Craig-Bampton's shapes (through the
superelements' recovery) match the full FE model's on a small arm."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly.full_arm import FullFEArm
from flexarm.assembly.full_fe import sparse_bodies
from flexarm.validation.data.measurements import DIRECTIONS
from flexarm.validation.dynamic.mac import mac
from flexarm.validation.dynamic.shapes import default_points, model_shapes

from .test_mac import box_points


def _dofs(points):
    return np.repeat(points.nodes, 3), np.tile(list(DIRECTIONS), points.n_points)


def test_rigid_bodies_as_sparse_bodies_give_the_emodel_shapes():
    from flexarm.assembly.emodel import emodel
    from flexarm.robot.demo_arm import load_demo_robot

    robot = load_demo_robot()
    arm = emodel(robot, equivalent=False)
    full = FullFEArm(arm, sparse_bodies(arm), n_modes=8)
    pts = default_points(robot)
    nodes, dirs = _dofs(pts)
    q = robot.pose("P2")
    f_e, _, A = model_shapes(arm, q, pts, nodes, dirs, 8)
    f_f, _, B = model_shapes(full, q, pts, nodes, dirs, 8)
    np.testing.assert_allclose(f_f, f_e, rtol=1e-9)
    sign = np.sign(np.einsum("ij,ij->i", A, B))[:, None]
    np.testing.assert_allclose(sign * B, A, rtol=0, atol=1e-9 * np.abs(A).max())


@pytest.fixture(scope="module")
def box_models(box_robot):
    from flexarm.assembly.build import BuildOptions, build_robot
    from flexarm.assembly.flexible import flexible_arm
    from flexarm.assembly.full_arm import full_arm

    from ...box_arm import box_mesher

    opts = BuildOptions("cb", 20).resolved(box_robot)
    builds = build_robot(box_robot, opts, cache=False, mesher=box_mesher)
    cb = flexible_arm(box_robot, opts, builds=builds, mesher=box_mesher)
    full = full_arm(box_robot, BuildOptions(), n_modes=8, mesher=box_mesher)
    return cb, builds, full


@pytest.mark.parametrize("pose", ["P1", "P2"])
def test_cb_shapes_match_the_full_fe_shapes(box_robot, box_models, pose):
    """First 6 modes at 8 points on the column and the arm (two on coupled seats): MAC(CB,
    full FE) > 0.999 on the diagonal, frequencies within 0.01 % (CB from above)."""
    cb, builds, full = box_models
    pts = box_points()
    nodes, dirs = _dofs(pts)
    q = box_robot.pose(pose)
    f_cb, _, A = model_shapes(cb, q, pts, nodes, dirs, 6, builds)
    f_full, _, B = model_shapes(full, q, pts, nodes, dirs, 6)
    assert np.all(f_cb >= f_full * (1 - 1e-9)) and np.abs(f_cb / f_full - 1).max() < 1e-4
    d = np.diag(mac(A, B))
    print(f"\n{pose}: 1 - MAC(CB, full FE) at most {1 - d.min():.1e}")  # noqa: T201
    assert d.min() > 0.999, d
