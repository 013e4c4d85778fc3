"""Arm pictures: recovery to the full field and PyVista output."""

import numpy as np
import pytest

from flexarm.assembly.analyses import modes
from flexarm.assembly.build import (
    BuildOptions,
    LinkBuild,
    cylinder_regions,
    link_material,
    link_regions,
)
from flexarm.assembly.flexible import flexible_arm
from flexarm.assembly.system import system_matrices
from flexarm.reduction import interfaces, reduce_part
from flexarm.reduction.couplings import rigid_transport
from flexarm.studies.render_arm import (
    compliance_ellipsoid,
    link_fields,
    mode_fields,
    render_arm_mode,
    superelement_dofs,
)

from ..box_arm import box_mesher

SIZE = (320, 240)


@pytest.fixture(scope="module")
def exact_arm(box_robot):
    """Box arm CB(6)/RBE2 with float64 recovery matrices (for 1e-10 checks)."""
    opts = BuildOptions("cb", 6).resolved(box_robot)
    builds, meshes = [], []
    for i, lk in enumerate(box_robot.links):
        names = link_regions(box_robot, i)
        mesh = box_mesher(lk, opts.mesh_size, 1)
        se = reduce_part(mesh, link_material(lk), cylinder_regions(lk, names), "rbe2", "cb", 6,
                         recovery_dtype=np.float64)
        builds.append(LinkBuild(lk.name, se, names))
        meshes.append(mesh)
    return flexible_arm(box_robot, opts, tuple(builds)), tuple(builds), meshes


@pytest.fixture(scope="module")
def cached_arm(box_robot):
    from flexarm.assembly.arm import Arm, ArmSpec
    from flexarm.assembly.build import build_robot

    opts = BuildOptions("cb", 6).resolved(box_robot)
    builds = build_robot(box_robot, opts, mesher=box_mesher)
    return Arm(box_robot, flexible_arm(box_robot, opts, builds), ArmSpec("cb", n_modes=6),
               builds)


@pytest.fixture(scope="module")
def gl():
    from flexarm.fe.errors import FlexarmError, MissingDependencyError
    from flexarm.reduction.render import render_backend

    try:
        return render_backend()
    except (FlexarmError, MissingDependencyError) as exc:
        pytest.skip(f"no off-screen rendering here: {exc}")


def test_recovery_matches_interface_dofs(box_robot, exact_arm):
    """Seat nodes of the recovered field move rigidly with their interface DOFs, and the
    TCP seat carries the assembled TCP motion (1e-10)."""
    arm, builds, meshes = exact_arm
    q = box_robot.pose("P1")
    sm = system_matrices(arm, q)
    md = modes(arm, q)
    for mode in (0, 3):
        x = md.shapes[:, mode]
        for i, (lb, mesh) in enumerate(zip(builds, meshes, strict=True)):
            se = lb.superelement
            s = superelement_dofs(arm, sm, i, x, se)
            u = se.expand(s)
            scale = np.abs(u).max()
            regions = cylinder_regions(box_robot.links[i], lb.regions)
            for k, itf in enumerate(interfaces(mesh, regions)):
                want = rigid_transport(mesh.points[itf.nodes] - se.node_positions[k]) \
                    @ s[6 * k : 6 * k + 6]
                np.testing.assert_allclose(u[itf.nodes], want, atol=1e-10 * scale)
        c = box_robot.chain.tcp_body
        se = builds[c].superelement
        k = builds[c].regions.index("tcp")
        s = superelement_dofs(arm, sm, c, x, se)[6 * k : 6 * k + 6]
        R = sm.frames[c, :3, :3]
        p = box_robot.chain.tool[:3, 3] - se.node_positions[k]
        tcp = np.r_[R @ (rigid_transport(p) @ s), R @ s[3:]]
        np.testing.assert_allclose(tcp, sm.G_tcp @ x, atol=1e-10 * np.abs(tcp).max())


def test_link_fields_in_base_frame(box_robot, cached_arm):
    arm, builds = cached_arm.model, cached_arm.builds
    q = box_robot.pose("P2")
    freq, fields = mode_fields(box_robot, arm, q, 1, builds)
    assert freq == pytest.approx(modes(arm, q).freq_hz[0])
    assert [f.name for f in fields] == [lk.name for lk in box_robot.links]
    F = system_matrices(arm, q).frames
    for f, lb, Fi in zip(fields, builds, F, strict=True):
        se = lb.superelement
        np.testing.assert_allclose(f.points, se.surface_points @ Fi[:3, :3].T + Fi[:3, 3])
        assert f.u.shape == f.points.shape and np.isfinite(f.u).all()
    x0 = np.zeros(arm.layout["n"])
    assert all(np.abs(f.u).max() == 0 for f in link_fields(box_robot, arm, q, x0, builds))


def test_compliance_ellipsoid_axes():
    A = np.diag([1.0, 4.0, 2.0])
    R = np.linalg.qr(np.arange(1.0, 10.0).reshape(3, 3) + np.eye(3))[0]
    C = np.zeros((6, 6))
    C[:3, :3] = R @ A @ R.T
    radii, V = compliance_ellipsoid(C)
    np.testing.assert_allclose(radii, [4.0, 2.0, 1.0])
    np.testing.assert_allclose(C[:3, :3] @ V, V * radii, atol=1e-12)


def _image(path):
    import imageio.v3 as iio

    return np.asarray(iio.imread(path))


def test_mode_pictures(box_robot, cached_arm, tmp_path, gl):
    q = box_robot.pose("P1")
    imgs = []
    for m in (1, 2):
        out = render_arm_mode(cached_arm, q, m, tmp_path / f"m{m}.png", window_size=SIZE)
        assert out.stat().st_size > 0
        imgs.append(_image(out))
    assert imgs[0].shape[:2] == (SIZE[1], SIZE[0])
    diff = np.abs(imgs[0].astype(float) - imgs[1].astype(float)).max(axis=-1)
    assert (diff > 30).mean() > 0.002  # the two modes look different
    ell = render_arm_mode(cached_arm, q, 1, tmp_path / "e.png", ellipsoid=True,
                          window_size=SIZE)
    assert np.abs(_image(ell).astype(float) - imgs[0]).max() > 30


def test_mode_gif_and_emodel(box_robot, tmp_path, gl):
    from flexarm.assembly.arm import build_arm

    arm = build_arm(box_robot)
    q = box_robot.pose("P1")
    gif = render_arm_mode(arm, q, 1, tmp_path / "e.gif", window_size=SIZE, n_frames=4)
    import imageio.v3 as iio

    frames = iio.imread(gif, index=None)
    assert frames.shape[0] == 4 and frames.shape[1:3] == (SIZE[1], SIZE[0])
    assert np.abs(frames[0].astype(float) - frames[1].astype(float)).max() > 0
    with pytest.raises(ValueError, match="png or .gif"):
        render_arm_mode(arm, q, 1, tmp_path / "e.jpg", window_size=SIZE)


def test_cli_show_arm(box_robot, cached_arm, tmp_path, monkeypatch, gl):
    """``flexarm show-arm`` writes the picture (the arm model is the cached box arm)."""
    import flexarm.assembly.arm as arm_module
    from flexarm.cli import main

    seen = {}

    def fake(robot, spec, progress=None):
        seen["model"] = spec.model
        return cached_arm

    monkeypatch.setattr(arm_module, "build_arm", fake)
    out = tmp_path / "arm_mode2.png"
    assert main(["show-arm", "--robot", str(box_robot.source), "--pose", "P2", "--mode", "2",
                 "--ellipsoid", "-o", str(out)]) == 0
    assert seen == {"model": "cb"} and out.stat().st_size > 0
    assert main(["show-arm", "--robot", str(box_robot.source), "--mode", "99",
                 "-o", str(out)]) == 2  # clear error, no traceback
