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
    ELLIPSOID_FLOOR,
    compliance_ellipsoid,
    ellipsoid_axes,
    ellipsoid_surface,
    link_fields,
    mode_fields,
    render_arm_mode,
    superelement_dofs,
    write_arm_mode,
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


def test_mode_pictures(box_robot, cached_arm, tmp_path, gl, monkeypatch):
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "cache"))  # really drawn here
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
                 "--model", "cb", "--ellipsoid", "-o", str(out)]) == 0
    assert seen == {"model": "cb"} and out.stat().st_size > 0
    assert main(["show-arm", "--robot", str(box_robot.source), "--pose", "P2",
                 "-o", str(tmp_path / "default.png")]) == 0
    assert seen == {"model": "emodel"}  # the default of every arm command
    assert main(["show-arm", "--robot", str(box_robot.source), "--mode", "99",
                 "-o", str(out)]) == 2  # clear error, no traceback


def test_ellipsoid_axes_are_the_principal_compliances_to_a_stated_length():
    R = np.linalg.qr(np.arange(1.0, 10.0).reshape(3, 3) + np.eye(3))[0]
    C = np.zeros((6, 6))
    C[:3, :3] = R @ np.diag([8.0, 4.0, 0.08]) @ R.T
    radii, V, axes = ellipsoid_axes(C, 0.3)
    np.testing.assert_allclose(radii, [8.0, 4.0, 0.08])
    np.testing.assert_allclose(C[:3, :3] @ V, V * radii, atol=1e-12)
    assert np.linalg.det(V) == pytest.approx(1.0)  # a rotation: no mirrored ellipsoid
    # proportional to the compliances, longest = 0.3 m, the 1 % axis raised to the floor
    np.testing.assert_allclose(axes, [0.3, 0.15, ELLIPSOID_FLOOR * 0.3])
    with pytest.raises(ValueError, match="no positive"):
        ellipsoid_axes(np.zeros((6, 6)), 0.3)


def test_ellipsoid_surface_is_a_closed_ellipsoid_at_its_centre():
    R = np.linalg.qr(np.arange(1.0, 10.0).reshape(3, 3) + np.eye(3))[0]
    R = R * np.sign(np.linalg.det(R))
    c, a = np.array([2.0, -0.1, 0.6]), np.array([0.3, 0.12, 0.05])
    pts, tri = ellipsoid_surface(c, R, a, n=64)
    # every vertex on the quadric (p - c)^T R diag(a^-2) R^T (p - c) = 1
    y = (pts - c) @ R / a
    np.testing.assert_allclose(np.einsum("ij,ij->i", y, y), 1.0, rtol=1e-12)
    # closed and consistently oriented: each directed edge once, its reverse once
    e = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    assert len({tuple(x) for x in e}) == len(e)
    assert {tuple(x) for x in e} == {tuple(x) for x in e[:, ::-1]}
    # divergence theorem: outward volume -> 4/3 pi abc (inscribed polyhedron, 1 % low)
    v = np.einsum("ij,ij->i", pts[tri[:, 0]], np.cross(pts[tri[:, 1]], pts[tri[:, 2]])).sum() / 6
    assert 0.99 < v / (4 / 3 * np.pi * a.prod()) < 1.0
    np.testing.assert_allclose(pts.mean(axis=0), c, atol=1e-12)


class _Recorder:
    """Stands in for a PyVista plotter: keeps the meshes and texts added to it."""

    def __init__(self):
        self.meshes, self.texts = [], []

    def add_mesh(self, mesh, **kwargs):
        self.meshes.append((mesh, kwargs))

    def add_text(self, text, **kwargs):
        self.texts.append(text)


def test_ellipsoid_is_drawn_at_the_moving_tcp_with_the_tool(box_robot):
    """The ellipsoid's centre is the TCP of the kinematics (moved with the mode), the tool
    runs from the flange to it, and the caption states the principal values and scale."""
    from flexarm.assembly.arm import build_arm
    from flexarm.robot.kinematics import tcp_frame
    from flexarm.studies.tcp_ellipsoid import add_ellipsoid, tcp_ellipsoid

    arm = build_arm(box_robot)
    q = box_robot.pose("P1")
    x = modes(arm.model, q).shapes[:, 0]
    e = tcp_ellipsoid(arm, q, x)
    np.testing.assert_allclose(e.tcp, tcp_frame(arm.model.chain, q)[:3, 3], atol=1e-12)
    np.testing.assert_allclose(e.u, system_matrices(arm.model, q).G_tcp @ x)
    scale = 0.01 / np.linalg.norm(e.u[:3])  # 10 mm at the TCP, as the pictures draw it
    p = _Recorder()
    moving = add_ellipsoid(p, e, 0.2, scale)
    (ell, _), (axes, _), (tool, _) = p.meshes
    np.testing.assert_allclose(np.asarray(ell.points).mean(axis=0), e.tcp + scale * e.u[:3],
                               atol=1e-9)
    ext = np.sort(np.linalg.norm(np.asarray(axes.points)[3:] - np.asarray(axes.points)[:3],
                                 axis=1))[::-1]
    radii, _, drawn = ellipsoid_axes(e.C, 0.2)
    np.testing.assert_allclose(ext, 2 * drawn)
    assert ext[-1] >= 2 * ELLIPSOID_FLOOR * 0.2 - 1e-12  # a solid, never a flat disc
    # the tool moves rigidly with the TCP (small rotation), so it keeps its length
    tp = np.asarray(tool.points)
    theta = scale * e.u[3:]
    np.testing.assert_allclose(tp[0], e.flange + scale * e.u[:3]
                               + np.cross(theta, e.flange - e.tcp), atol=1e-12)
    np.testing.assert_allclose(tp[1], e.tcp + scale * e.u[:3], atol=1e-12)
    L0 = np.linalg.norm(e.tcp - e.flange)
    assert L0 > 0 and np.linalg.norm(tp[1] - tp[0]) == pytest.approx(L0, rel=1e-3)
    assert f"{1e6 * radii[0]:.3g}" in p.texts[0] and "200 mm" in p.texts[0]
    # each moving mesh carries one displacement per point
    assert all(np.shape(u) == np.shape(pts) for _, pts, u in moving)


def test_arm_mode_vtu_is_the_recovered_field(box_robot, cached_arm, tmp_path):
    import meshio

    q = box_robot.pose("P2")
    path = write_arm_mode(cached_arm, q, 2, tmp_path / "arm.vtu", "P2")
    m = meshio.read(path)
    # the mass-normalised mode, normalised here with the assembled mass matrix
    sm = system_matrices(cached_arm.model, q)
    md = modes(cached_arm.model, q)
    x = md.shapes[:, 1] / np.sqrt(md.shapes[:, 1] @ sm.M @ md.shapes[:, 1])
    fields = link_fields(box_robot, cached_arm.model, q, x, cached_arm.builds)
    pts = np.vstack([f.points for f in fields])
    u = np.vstack([f.u for f in fields])
    np.testing.assert_allclose(m.points, pts, rtol=1e-12)
    scale = np.abs(u).max()
    np.testing.assert_allclose(m.point_data["mode_shape"], u, rtol=1e-9, atol=1e-12 * scale)
    assert m.field_data["mode"].tolist() == [2] and m.field_data["modal_mass"].tolist() == [1.0]
    assert m.field_data["freq_hz"][0] == pytest.approx(md.freq_hz[1], rel=1e-12)
    assert m.field_data["max_displacement"][0] == pytest.approx(
        np.linalg.norm(u, axis=1).max(), rel=1e-9)
    tri = m.cells_dict["triangle"]
    assert len(tri) == sum(len(f.faces) for f in fields) and tri.max() == len(pts) - 1
    link = m.cell_data["link"][0]
    assert np.bincount(link).tolist() == [len(f.faces) for f in fields]
    with pytest.raises(ValueError, match="vtu or .vtk"):
        write_arm_mode(cached_arm, q, 2, tmp_path / "arm.stl")


def test_cli_show_arm_vtu(box_robot, cached_arm, tmp_path, monkeypatch):
    """``show-arm -o x.vtk`` writes the mesh without any renderer; pyvista reads it."""
    import meshio

    import flexarm.assembly.arm as arm_module
    from flexarm.cli import main

    monkeypatch.setattr(arm_module, "build_arm", lambda robot, spec, progress=None: cached_arm)
    out = tmp_path / "arm.vtk"
    assert main(["show-arm", "--robot", str(box_robot.source), "--pose", "P1", "--mode", "1",
                 "-o", str(out)]) == 0
    m = meshio.read(out)
    assert main(["show-arm", "--robot", str(box_robot.source), "--pose", "P1", "--mode", "1",
                 "--max-displacement", "0.002", "-o", str(tmp_path / "a.vtu")]) == 0
    a = meshio.read(tmp_path / "a.vtu")
    assert np.linalg.norm(a.point_data["mode_shape"], axis=1).max() == pytest.approx(2e-3)
    # the scale is stated: mass-normalised shape x s, generalised mass s^2
    s = 2e-3 / np.linalg.norm(m.point_data["mode_shape"], axis=1).max()
    np.testing.assert_allclose(a.point_data["mode_shape"], s * m.point_data["mode_shape"],
                               rtol=1e-12, atol=1e-15)
    assert a.field_data["modal_mass"][0] == pytest.approx(s * s, rel=1e-12)
    assert a.field_data["max_displacement"][0] == pytest.approx(2e-3, rel=1e-12)
    assert main(["show-arm", "--robot", str(box_robot.source), "--ellipsoid",
                 "-o", str(tmp_path / "e.vtu")]) == 2
    assert not (tmp_path / "e.vtu").exists()
    pv = pytest.importorskip("pyvista")
    legacy = pv.read(out)  # the legacy file's field data, read by VTK itself
    assert legacy.n_points == len(m.points)
    assert int(legacy.field_data["mode"][0]) == 1 and legacy.field_data["modal_mass"][0] == 1.0
    assert legacy.field_data["freq_hz"][0] == pytest.approx(a.field_data["freq_hz"][0],
                                                            rel=1e-15)


def test_arm_pictures_come_from_the_cache_until_what_they_show_changes(
        box_robot, cached_arm, tmp_path, monkeypatch, gl):
    import flexarm.studies.render_arm as module

    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "cache"))
    draws = []
    real = module.save_picture
    monkeypatch.setattr(module, "save_picture", lambda *a: (draws.append(a[1]), real(*a))[1])
    q = box_robot.pose("P1")
    a = render_arm_mode(cached_arm, q, 1, tmp_path / "a.png", window_size=SIZE)
    b = render_arm_mode(cached_arm, q, 1, tmp_path / "b.png", window_size=SIZE)
    assert len(draws) == 1 and a.read_bytes() == b.read_bytes()
    render_arm_mode(cached_arm, q, 1, tmp_path / "c.png", window_size=SIZE, ellipsoid=True)
    assert len(draws) == 2
    q2 = np.array(q, dtype=float)
    q2[1] += 1e-9  # a pose change far below a pixel is still another picture
    render_arm_mode(cached_arm, q2, 1, tmp_path / "d.png", window_size=SIZE)
    assert len(draws) == 3
