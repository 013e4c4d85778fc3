"""TCP paths: quaternions, circle/sphere geometry, and the thesis ball-bar circles."""

from __future__ import annotations

import math
from importlib.resources import files

import numpy as np
import pytest

from flexarm.robot.formats.rapid import Motion, Procedure, RobTarget, read_rapid
from flexarm.robot.paths import (
    circle_through,
    fit_circle,
    fit_sphere,
    quat_angle,
    quat_conjugate,
    quat_from_intrinsic_xyz,
    quat_from_matrix,
    quat_multiply,
    quat_normalize,
    quat_to_matrix,
    sample_procedure,
    slerp,
)

THESIS = files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod"
#: The four distinct targets of each horizontal circle (the fifth repeats the first).
CIRCLES = {
    "Path_30": ["Target_70", "Target_80", "Target_90", "Target_100"],
    "Path_40": ["Target_120", "Target_130", "Target_140", "Target_150"],
    "Path_50": ["Target_170", "Target_180", "Target_190", "Target_200"],
}

# Expected values derived by hand from the printed coordinates (appendix B):
# * Path_30: Target_70/90 have x = 1488.34 / 1178.34 at y = 47.78 and Target_80/100 have
#   y = 202.78 / -107.22 at x = 1333.34, so the axis is x = 1333.34, y = 47.78 and
#   r30 = 1488.34 - 1333.34 = 155.000 at z = 588.13.
# * Path_40 / Path_50: Target_120 and Target_170 lie on y = 47.78, so
#   r40 = 1451.767 - 1333.34 = 118.427 (z = 688.13), r50 = 1476.256 - 1333.34 = 142.916
#   (z = 648.13); the other targets agree (e.g. Target_130: 1.707^2 + 118.415^2 = 118.427^2).
# * Sphere r^2 + (z - z0)^2 = R^2 through circles 30 and 40:
#   z0 = (r30^2 - r40^2 + z30^2 - z40^2) / (2 (z30 - z40)) = 588.1298, R = 155.0000;
#   circle 50 checks: 142.916^2 + 60^2 = 154.99998^2.  r40 = sqrt(155^2 - 100^2) and
#   r50 = sqrt(155^2 - 60^2) to the printed 3 decimals: the pivot is the centre of the
#   Path_30 circle and the bar is 155 mm long.
AXIS_XY = (1333.34, 47.78)
EXPECTED = {"Path_30": (588.13, 155.0), "Path_40": (688.13, 118.427),
            "Path_50": (648.13, 142.916)}
PIVOT = (1333.34, 47.78, 588.13)
BAR_LENGTH = 155.0


@pytest.fixture(scope="module")
def thesis():
    return read_rapid(THESIS)


def _points(mod, names):
    return np.array([mod.targets[n].pos_mm for n in names])


def _random_quats(rng, n):
    return quat_normalize(rng.normal(size=(n, 4)))


# ----------------------------------------------------------------------------- quaternions

def test_quat_matrix_round_trip_and_product():
    rng = np.random.default_rng(0)
    q = _random_quats(rng, 200)
    R = quat_to_matrix(q)
    assert np.allclose(R @ np.swapaxes(R, -1, -2), np.eye(3), atol=1e-13)
    assert np.allclose(np.linalg.det(R), 1.0, atol=1e-13)
    back = quat_from_matrix(R)
    canon = np.where(q[:, :1] < 0, -q, q)
    assert np.allclose(back, canon, atol=1e-12)
    # every pivot branch of Shepperd's method: 180 deg turns about x, y, z and identity
    for qq in ([0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [1, 0, 0, 0]):
        assert np.allclose(quat_from_matrix(quat_to_matrix(qq)), qq, atol=1e-15)
    p = _random_quats(rng, 200)
    assert np.allclose(quat_to_matrix(quat_multiply(q, p)), R @ quat_to_matrix(p), atol=1e-13)
    assert np.allclose(quat_multiply(q, quat_conjugate(q)), [1, 0, 0, 0], atol=1e-15)
    with pytest.raises(ValueError, match="zero quaternion"):
        quat_normalize([0, 0, 0, 0])
    with pytest.raises(ValueError, match=r"\(\.\.\., 4\)"):
        quat_normalize([1, 0, 0])


def test_intrinsic_xyz_order():
    # about x first, then about the *new* y axis: R = Rx @ Ry (not Ry @ Rx)
    R = quat_to_matrix(quat_from_intrinsic_xyz([90, 90, 0]))
    Rx = quat_to_matrix([math.cos(math.pi / 4), math.sin(math.pi / 4), 0, 0])
    Ry = quat_to_matrix([math.cos(math.pi / 4), 0, math.sin(math.pi / 4), 0])
    assert np.allclose(R, Rx @ Ry, atol=1e-15)


def test_slerp_unit_shortest_constant_rate():
    rng = np.random.default_rng(1)
    q0, q1 = _random_quats(rng, 50), _random_quats(rng, 50)
    t = rng.uniform(size=50)
    q = slerp(q0, q1, t)
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-15)
    total = quat_angle(q0, q1)
    assert np.all(total <= np.pi + 1e-12)  # the shorter way
    assert np.allclose(quat_angle(q0, q), t * total, atol=1e-9)
    assert np.allclose(quat_angle(q, q1), (1 - t) * total, atol=1e-9)
    # end points, and -q1 (same rotation) gives the same path
    assert np.allclose(slerp(q0, q1, 0.0), q0, atol=1e-15)
    assert np.allclose(quat_angle(slerp(q0, q1, 1.0), q1), 0.0, atol=1e-7)
    assert np.allclose(slerp(q0, -q1, t), q, atol=1e-14)
    # one pair, many t; and the small-angle branch
    ts = np.linspace(0, 1, 11)
    assert slerp(q0[0], q1[0], ts).shape == (11, 4)
    tiny = quat_normalize([1, 1e-12, 0, 0])
    assert np.allclose(slerp([1, 0, 0, 0], tiny, ts), [1, 0, 0, 0], atol=1e-11)


# ----------------------------------------------------------------------------- geometry

def test_circle_through_and_fit_random_circles():
    rng = np.random.default_rng(2)
    for _ in range(20):
        c = rng.uniform(-2000, 2000, 3)
        n = quat_to_matrix(_random_quats(rng, 1))[0][:, 2]
        u = np.cross(n, rng.normal(size=3))
        u /= np.linalg.norm(u)
        v = np.cross(n, u)
        r = rng.uniform(10, 500)
        phi = np.sort(rng.uniform(0, 1.9 * np.pi, 6))
        pts = c + r * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)
        c3, n3, r3 = circle_through(pts[0], pts[2], pts[5])
        assert np.allclose(c3, c, atol=1e-8) and abs(r3 - r) < 1e-8
        assert np.allclose(n3, n, atol=1e-10)  # counter-clockwise about n
        cf, nf, rf = fit_circle(pts)
        assert np.allclose(cf, c, atol=1e-8) and abs(rf - r) < 1e-8
        assert np.allclose(nf, n, atol=1e-10)
        cf, nf, _ = fit_circle(pts[::-1])
        assert np.allclose(nf, -n, atol=1e-10)  # reversed order flips the normal
    # vectorised over a batch
    P = rng.normal(size=(3, 5, 3))
    cb, nb, rb = circle_through(P[0], P[1], P[2])
    assert cb.shape == (5, 3) and nb.shape == (5, 3) and rb.shape == (5,)
    assert np.allclose(np.linalg.norm(P - cb, axis=-1), rb, atol=1e-9)
    with pytest.raises(ValueError, match="collinear"):
        circle_through([0, 0, 0], [1, 1, 1], [2, 2, 2])
    with pytest.raises(ValueError, match="collinear"):
        fit_circle([[0, 0, 0], [1, 0, 0], [3, 0, 0]])
    with pytest.raises(ValueError, match=r"\(n, 3\) with n >= 3"):
        fit_circle([[0, 0, 0], [1, 0, 0]])


def test_fit_sphere_random():
    rng = np.random.default_rng(3)
    c, r = np.array([800.0, -120.0, 600.0]), 155.0
    d = rng.normal(size=(30, 3))
    pts = c + r * d / np.linalg.norm(d, axis=1, keepdims=True)
    cf, rf = fit_sphere(pts)
    assert np.allclose(cf, c, atol=1e-9) and abs(rf - r) < 1e-9
    with pytest.raises(ValueError, match="coplanar"):
        fit_sphere(pts * [1, 1, 0])


# ----------------------------------------------------------------------------- thesis circles

@pytest.mark.parametrize("proc", sorted(CIRCLES))
def test_thesis_circles_are_horizontal(thesis, proc):
    P = _points(thesis, CIRCLES[proc])
    z, r = EXPECTED[proc]
    fitted = fit_circle(P)
    for k in range(4):  # every exact 3-point circle agrees with the least-squares one
        c3, n3, r3 = circle_through(*np.delete(P, k, axis=0))
        assert np.allclose(c3, fitted[0], atol=2e-3), k  # printed to 0.001 mm
        assert abs(r3 - fitted[2]) < 2e-3
        assert np.allclose(np.abs(n3), [0, 0, 1], atol=1e-9)
    c, n, rf = fitted
    assert np.allclose(n, [0, 0, 1], atol=1e-9)  # counter-clockwise seen from above
    assert np.allclose(c, [*AXIS_XY, z], atol=0.01)
    assert abs(rf - r) < 0.01
    assert np.abs(np.linalg.norm(P - c, axis=1) - rf).max() < 1e-3
    # the procedure's MoveC pair really runs around this circle
    motions = thesis.procedures[proc].motions
    assert [t.name for m in motions for t in m.targets][:5] == CIRCLES[proc] + [
        motions[-1].to_point.name]
    assert motions[-1].to_point.pos_mm.tolist() == P[0].tolist()


def test_thesis_ball_bar_sphere(thesis):
    P = np.vstack([_points(thesis, names) for names in CIRCLES.values()])
    centre, radius = fit_sphere(P)
    assert np.allclose(centre, PIVOT, atol=0.01)
    assert abs(radius - BAR_LENGTH) < 0.01
    residual = np.linalg.norm(P - centre, axis=1) - radius
    assert np.abs(residual).max() < 1e-3  # printed to 0.001 mm
    # the hand derivation, redone numerically from the circle fits
    (c30, _, r30), (c40, _, r40) = fit_circle(P[:4]), fit_circle(P[4:8])
    z0 = (r30**2 - r40**2 + c30[2] ** 2 - c40[2] ** 2) / (2 * (c30[2] - c40[2]))
    assert abs(z0 - 588.1298) < 1e-3
    assert abs(math.hypot(r30, c30[2] - z0) - BAR_LENGTH) < 1e-3


def test_thesis_path_10_second_ball_bar_setup(thesis):
    """Path_10 (a horizontal then a vertical half circle) lies on another 155 mm sphere."""
    P = _points(thesis, ["Target_50", "Target_20", "Target_60", "Target_40"])
    centre, radius = fit_sphere(P)
    assert np.allclose(centre, [882.84, -132.32, 583.49], atol=0.01)
    assert abs(radius - 155.0) < 0.01
    _, n_first, _ = circle_through(P[0], P[1], P[2])
    _, n_second, _ = circle_through(P[2], P[3], P[0])
    assert abs(n_first[2]) > 0.999 and abs(n_second[0]) > 0.999  # horizontal, then vertical


# ----------------------------------------------------------------------------- sampling

@pytest.mark.parametrize("proc", sorted(CIRCLES))
def test_sampled_arcs_stay_on_the_circle(thesis, proc):
    step = 2.0
    path = sample_procedure(thesis.procedures[proc], step_mm=step)
    motions = thesis.procedures[proc].motions
    assert path.kinds == ("MoveJ", "MoveC", "MoveC")
    assert path.points_mm.shape == (path.n_points, 3) and path.quats.shape == (path.n_points, 4)
    start = motions[0].to_point.pos_mm
    for k in (1, 2):
        seg = path.points_mm[path.segments == k]
        p0 = start if k == 1 else motions[1].to_point.pos_mm
        c, n, r = circle_through(p0, motions[k].cir_point.pos_mm, motions[k].to_point.pos_mm)
        assert np.abs(np.linalg.norm(seg - c, axis=1) - r).max() < 1e-9
        assert np.abs((seg - c) @ n).max() < 1e-9
        assert seg[-1].tolist() == motions[k].to_point.pos_mm.tolist()  # exact targets kept
        assert any(np.array_equal(p, motions[k].cir_point.pos_mm) for p in seg)
    gaps = np.linalg.norm(np.diff(path.points_mm, axis=0), axis=1)
    assert gaps.max() <= step + 1e-9
    # arc length: one full turn
    r = EXPECTED[proc][1]
    assert abs(path.arc_length_mm[-1] - 2 * math.pi * r) < 2e-3
    assert np.all(np.diff(path.arc_length_mm) > 0)
    assert np.allclose(path.quats, thesis.targets[CIRCLES[proc][0]].quat, atol=1e-9)
    assert any("not sampled" in note for note in path.notes)
    assert path.points_m[0, 0] == pytest.approx(path.points_mm[0, 0] * 1e-3)


def test_path_30_arc_length_exact(thesis):
    path = sample_procedure(thesis.procedures["Path_30"], step_mm=5.0)
    assert path.arc_length_mm[-1] == pytest.approx(2 * math.pi * 155.0, abs=1e-9)


def test_path_60_tool_turns_with_the_circle(thesis):
    """Path_60: Path_40's circle clockwise, tool pointing down and turning once with it."""
    path = sample_procedure(thesis.procedures["Path_60"], step_mm=2.0, step_deg=0.5)
    assert np.allclose(np.linalg.norm(path.quats, axis=1), 1.0, atol=1e-15)
    assert np.all(np.sum(path.quats[1:] * path.quats[:-1], axis=1) > 0)  # sign-continuous
    R = quat_to_matrix(path.quats)
    assert np.abs(R[:, :, 2] - [0, 0, -1]).max() < 1e-12
    yaw = np.unwrap(np.arctan2(R[:, 1, 0], R[:, 0, 0]))
    assert np.degrees(yaw[-1] - yaw[0]) == pytest.approx(-360.0, abs=1e-6)
    steps = quat_angle(path.quats[1:], path.quats[:-1])
    assert np.degrees(steps.max()) <= 0.5 + 1e-9
    c, n, _ = circle_through(*_points(thesis, ["Target_220", "Target_230", "Target_240"]))
    assert np.allclose(n, [0, 0, -1], atol=1e-9)  # clockwise seen from above
    assert np.allclose(c[:2], AXIS_XY, atol=0.01)
    assert sum("corner zone 'z100'" in note for note in path.notes) == 3


def test_moveJ_flagged_and_start_pose(thesis):
    proc = thesis.procedures["Path_30"]
    home = RobTarget("home", [1333.34, 47.78, 800.0], [0.5, 0.5, 0.5, -0.5], [0, 1, -1, 1],
                     [9e9] * 6)
    path = sample_procedure(proc, start=home, step_mm=10.0)
    assert path.points_mm[0].tolist() == home.pos_mm.tolist()
    joint = path.is_joint_interpolated
    assert joint[path.segments == 0].all() and not joint[path.segments > 0].any()
    assert (path.segments == 0).sum() == 1 + math.ceil(math.hypot(155.0, 800 - 588.13) / 10)
    assert any("MoveJ line 70 drawn as a straight line" in note for note in path.notes)


def test_sampling_errors(thesis):
    p = thesis.targets
    line = Motion("MoveL", (p["Target_70"],), "v10", "fine", "tool0", None, (), 3)
    bad = Motion("MoveC", (p["Target_80"], p["Target_70"]), "v10", "fine", "tool0", None, (), 4)
    with pytest.raises(ValueError, match="MoveC on line 4: start, CirPoint 'Target_80' and "
                                         "ToPoint 'Target_70' are collinear"):
        sample_procedure(Procedure("p", (line, bad), 1))
    with pytest.raises(ValueError, match="MoveC on line 4 starts the procedure"):
        sample_procedure(Procedure("p", (bad,), 1))
    with pytest.raises(ValueError, match="no motions"):
        sample_procedure(Procedure("p", (), 1))
    with pytest.raises(ValueError, match="step_mm"):
        sample_procedure(Procedure("p", (line,), 1), step_mm=0)
    jt = thesis.joint_targets["calib_post"]
    absj = Motion("MoveAbsJ", (jt,), "v10", "fine", "tool0", None, (), 5)
    with pytest.raises(ValueError, match="MoveAbsJ on line 5: a joint target needs fk="):
        sample_procedure(Procedure("p", (line, absj), 1))
    path = sample_procedure(Procedure("p", (line, absj), 1),
                            fk=lambda q: ([1333.34, 47.78, 700.0], [0.5, 0.5, 0.5, -0.5]))
    assert path.points_mm[-1].tolist() == [1333.34, 47.78, 700.0]
    assert path.is_joint_interpolated[-1]


def test_paths_reexports_segment_geometry():
    """The geometry moved to ``path_geometry``; ``paths`` keeps exporting the same objects."""
    from flexarm.robot import path_geometry, paths, quaternions

    for name in ("circle_through", "fit_circle", "fit_sphere"):
        assert getattr(paths, name) is getattr(path_geometry, name)
    for name in ("quat_normalize", "quat_to_matrix", "slerp", "quat_angle"):
        assert getattr(paths, name) is getattr(quaternions, name)
    assert all(hasattr(paths, name) for name in paths.__all__)


def test_sample_arc_keeps_targets_and_steps():
    from flexarm.robot.path_geometry import sample_arc, sample_line

    q = np.array([1.0, 0, 0, 0])
    p0, pc, p1 = np.array([10.0, 0, 0]), np.array([0, 10.0, 0]), np.array([-10.0, 0, 0])
    P, Q, s = sample_arc(circle_through(p0, pc, p1), p0, q, pc, q, p1, q, 1.0, 1.0)
    assert P[-1].tolist() == p1.tolist() and any(np.array_equal(p, pc) for p in P)
    assert s[-1] == pytest.approx(10 * math.pi, abs=1e-12)
    assert np.linalg.norm(np.diff(np.vstack([p0, P]), axis=0), axis=1).max() <= 1.0
    P, Q, s = sample_line(p0, q, p1, quat_from_intrinsic_xyz([0, 0, 90]), 100.0, math.pi / 18)
    assert len(P) == 9 and s[-1] == 20.0  # 90 deg in 10 deg steps beats 20 mm in 100 mm
