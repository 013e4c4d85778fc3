"""Coordinate systems of universal files (2420, 18): the same test written with its nodes
in a turned and shifted local system reads as the file written in the global frame; a
cylindrical system puts a node at its analytic point and turns its directions into the
analytic radial, tangential and axial ones; the spherical convention is SDynPy's; a
node in an undefined system, or measured on a slant along one direction only, is
refused in one line."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from flexarm.fe.errors import ReadError
from flexarm.validation.data.formats.uff import read_uff
from flexarm.validation.data.formats.uff_systems import CoordinateSystem

pyuff = pytest.importorskip("pyuff")

NODES = np.array([11, 12, 13])
XYZ = np.array([[0.3, -0.2, 1.1], [0.9, 0.4, 0.7], [-0.5, 0.1, 0.2]])  # global [m]
FREQ = np.arange(1, 41) * 2.5  # evenly spaced lines [Hz]
#: Local system 2: turned about a slant axis and shifted (rows: its axes, globally).
AXES = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix().T
ORIGIN = np.array([0.25, -0.75, 0.5])
RNG = np.random.default_rng(7)
PHI = RNG.normal(size=(2, 3, 3))  # (mode, node, xyz) global
#: Receptance [m/N] (dof out, dof in, line): every node x, y, z over node 11 x, y, z.
H = (RNG.normal(size=(9, 3, 1)) + 1j * RNG.normal(size=(9, 3, 1))) / (1 + FREQ / 40.0)
POSE = ("rig", np.zeros(6))


def _file(path, local: bool, systems=None):
    """The test as pyuff writes it: nodes 11 and 12 in system 2 (``local``) or global,
    node 13 always global (system 0); 55 shapes and 58 receptances in each node's
    system."""
    in_cs = np.array([local, local, False])
    turn = np.where(in_cs[:, None, None], AXES[None], np.eye(3)[None])  # rows: local axes
    xyz = np.where(in_cs[:, None], (XYZ - ORIGIN) @ AXES.T, XYZ)
    cs = np.where(in_cs, 2, 0)
    sets = [pyuff.prepare_2420(Part_UID=1, Part_Name="rig", CS_sys_labels=[1, 2],
                               CS_types=[0, 0], CS_colors=[8, 8], CS_names=["global", "turned"],
                               CS_matrices=[np.vstack([np.eye(3), np.zeros(3)]),
                                            np.vstack([AXES, ORIGIN])])]
    sets = systems if systems is not None else sets
    sets.append(pyuff.prepare_2411(node_nums=NODES, def_cs=cs, disp_cs=cs,
                                   color=np.ones(3, int), x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2]))
    phi = np.einsum("kab,mkb->mka", turn, PHI)
    for r in range(2):
        sets.append(pyuff.prepare_55(model_type=1, analysis_type=2, data_ch=2, spec_data_type=8,
                                     node_nums=NODES, r1=phi[r, :, 0], r2=phi[r, :, 1],
                                     r3=phi[r, :, 2], load_case=1, mode_n=r + 1,
                                     freq=10.0 * (r + 1), modal_damp_vis=0.01))
    blocks = np.zeros((9, 9))  # dof turn: local = T global, node-major
    for k in range(3):
        blocks[3 * k:3 * k + 3, 3 * k:3 * k + 3] = turn[k]
    local_H = np.einsum("ao,oif,bi->abf", blocks, H, blocks[:3, :3])
    for o in range(9):
        for i in range(3):
            sets.append(pyuff.prepare_58(func_type=4, rsp_node=int(NODES[o // 3]),
                                         rsp_dir=o % 3 + 1, ref_node=int(NODES[0]),
                                         ref_dir=i + 1, data=local_H[o, i], x=FREQ,
                                         ordinate_spec_data_type=8, orddenom_spec_data_type=13,
                                         abscissa_spec_data_type=18))
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    return path


def _frf_by_label(frf) -> dict:
    outs, ins, A = frf.matrix()
    return {(o, i): A[:, a, b] for a, o in enumerate(outs) for b, i in enumerate(ins)}


def test_a_turned_and_shifted_system_reads_as_the_global_file(tmp_path):
    ref = read_uff(_file(tmp_path / "global.uff", local=False), *POSE)
    got = read_uff(_file(tmp_path / "local.uff", local=True), *POSE)
    assert got.nodes.tolist() == ref.nodes.tolist() == NODES.tolist()
    assert np.max(np.abs(got.coordinates - XYZ)) < 1e-14  # 2411: 17 digits
    assert got.shapes.dofs == ref.shapes.dofs == [f"{n}{d}" for n in NODES for d in "xyz"]
    # 55 holds 6 digits of each local component: the turn spreads their round-off
    scale = np.max(np.abs(PHI))
    assert np.max(np.abs(got.shapes.shapes - PHI.reshape(2, 9))) < 1e-5 * scale
    assert np.max(np.abs(got.shapes.shapes - ref.shapes.shapes)) < 1e-5 * scale
    a, b = _frf_by_label(got.frfs[0]), _frf_by_label(ref.frfs[0])
    assert sorted(a) == sorted(b) and len(a) == 27
    top = np.max(np.abs(H))
    for key, h in b.items():
        assert np.max(np.abs(a[key] - h)) < 1e-9 * top
        o, i = key
        truth = H[3 * list(NODES).index(int(o[:-1])) + "xyz".index(o[-1]), "xyz".index(i[-1])]
        assert np.max(np.abs(a[key] - truth)) < 1e-9 * top


def test_dataset_18_defines_the_same_system_as_2420(tmp_path):
    """Testlab's older form: origin, a point on +x, a point in +xz (6 digits, so an
    exactly written quarter turn) gives what the 2420 matrix gives."""
    global AXES, ORIGIN
    saved = AXES, ORIGIN
    AXES, ORIGIN = np.array([[0.0, 1, 0], [-1, 0, 0], [0, 0, 1]]), np.array([0.5, -0.25, 1.0])
    try:
        by_18 = [pyuff.prepare_18(cs_num=[2], cs_type=[0], ref_cs_num=[0], color=[8],
                                  method=[1], cs_name=["turned"], ref_o=[ORIGIN],
                                  x_point=[ORIGIN + AXES[0]], xz_point=[ORIGIN + AXES[2]])]
        a = read_uff(_file(tmp_path / "18.uff", local=True, systems=by_18), *POSE)
        b = read_uff(_file(tmp_path / "2420.uff", local=True), *POSE)
    finally:
        AXES, ORIGIN = saved
    assert np.array_equal(a.coordinates, b.coordinates)
    assert np.array_equal(a.shapes.shapes, b.shapes.shapes)
    assert np.array_equal(a.frfs[0].H, b.frfs[0].H)


def test_cylindrical_system_puts_a_node_at_its_analytic_point(tmp_path):
    """A cylindrical system (axis turned onto global -y, origin shifted) in a file in mm:
    node 1 at r = 400 mm, theta = 30 deg, z = 250 mm; its shape (radial, tangential,
    axial) becomes the analytic base-frame vector.  Node 2 at theta = 90 deg of an
    axis-parallel cylinder: a uniaxial radial sensor there reads along +y."""
    axes = np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]])  # local z = global -y
    origin_mm = np.array([100.0, 200.0, -50.0])
    t = np.deg2rad(30.0)
    sets = [pyuff.prepare_164(units_code=4, units_description="mm", temp_mode=1,
                              length=1000.0, force=1.0, temp=1.0, temp_offset=273.15),
            pyuff.prepare_2420(Part_UID=1, Part_Name="rig", CS_sys_labels=[3, 4],
                               CS_types=[1, 1], CS_colors=[8, 8], CS_names=["cyl", "upright"],
                               CS_matrices=[np.vstack([axes, origin_mm]),
                                            np.vstack([np.eye(3), np.zeros(3)])]),
            pyuff.prepare_2411(node_nums=np.array([1, 2]), def_cs=np.array([3, 4]),
                               disp_cs=np.array([3, 4]), color=np.ones(2, int),
                               x=np.array([400.0, 300.0]), y=np.array([30.0, 90.0]),
                               z=np.array([250.0, 0.0])),
            pyuff.prepare_55(model_type=1, analysis_type=2, data_ch=2, spec_data_type=8,
                             node_nums=np.array([1, 2]), r1=np.array([0.5, 2.0]),
                             r2=np.array([-0.25, 0.0]), r3=np.array([0.125, 0.0]),
                             load_case=1, mode_n=1, freq=12.0, modal_damp_vis=0.01)]
    path = tmp_path / "cyl.uff"
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    got = read_uff(path, *POSE)
    ex, ey, ez = axes
    point = origin_mm / 1000 + 0.4 * np.cos(t) * ex + 0.4 * np.sin(t) * ey + 0.25 * ez
    assert np.allclose(got.coordinates, [point, [0.0, 0.3, 0.0]], rtol=0, atol=1e-15)
    e_r, e_t = np.cos(t) * ex + np.sin(t) * ey, -np.sin(t) * ex + np.cos(t) * ey
    s = got.shapes
    assert s.dofs == ["1x", "1y", "1z", "2y"]
    # mm only scales positions: shapes are as written (exact in 6 digits)
    assert np.allclose(s.shapes[0, :3], 0.5 * e_r - 0.25 * e_t + 0.125 * ez, rtol=0,
                       atol=1e-15)
    assert s.shapes[0, 3] == 2.0


def test_spherical_convention_is_sdynpys():
    """Positions and displacement directions of a turned, shifted spherical system equal
    SDynPy's own (``global_coord``, ``global_deflection``)."""
    import os

    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")  # SDynPy imports Qt
    sdpy = pytest.importorskip("sdynpy")
    from sdynpy.core.sdynpy_geometry import coordinate_system_array, global_coord, global_deflection

    ours = CoordinateSystem(5, 2, AXES, ORIGIN)
    theirs = coordinate_system_array(5, "sph", 1, 2, np.vstack([AXES, ORIGIN]))
    local = np.array([[0.7, 35.0, 120.0], [1.3, 100.0, -40.0]])  # r, theta, phi [deg]
    points = ours.to_global(local)
    for k in range(2):
        assert np.allclose(points[k], global_coord(theirs, local[k]), rtol=0, atol=1e-14)
        rot = ours.directions(points[k:k + 1])[0]
        for d in range(3):
            want = global_deflection(theirs, np.eye(3)[d], points[k])
            assert np.allclose(rot[:, d], want, rtol=0, atol=1e-14)
    assert sdpy is not None


def test_a_node_in_an_undefined_system_is_refused(tmp_path):
    path = tmp_path / "undefined.unv"
    sets = [pyuff.prepare_2420(Part_UID=1, Part_Name="rig", CS_sys_labels=[1], CS_types=[0],
                               CS_colors=[8], CS_names=["global"],
                               CS_matrices=[np.vstack([np.eye(3), np.zeros(3)])]),
            pyuff.prepare_2411(node_nums=np.array([4, 5]), def_cs=np.array([1, 1]),
                               disp_cs=np.array([1, 7]), color=np.ones(2, int),
                               x=np.zeros(2), y=np.zeros(2), z=np.arange(2.0))]
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    with pytest.raises(ReadError) as err:
        read_uff(path)
    text = str(err.value)
    assert "\n" not in text and text.startswith(str(path))
    assert "node 5 refers to coordinate system 7" in text and "export" in text


def test_a_uniaxial_sensor_on_a_slant_is_refused(tmp_path):
    """Node 12 measured along local x only, in a system turned about a slant axis: its
    direction has no base axis, and the file is refused naming the node and system."""
    path = _file(tmp_path / "slant.uff", local=True)
    sets = [d for d in pyuff.UFF(str(path)).read_sets()
            if d["type"] != 58 or (d["rsp_node"] != 12 or d["rsp_dir"] == 1)]
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    with pytest.raises(ReadError, match=r"node 12 is measured along a direction of its "
                       r"coordinate system 2 .*measure x, y and z"):
        read_uff(path, *POSE)
