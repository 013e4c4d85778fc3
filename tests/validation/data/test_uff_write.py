"""What ``lab`` writes as a universal file, read back by pyuff and by flexarm: the test
geometry at each pose (2420, 2411, 82) equal to the robot's forward kinematics, every
pose numbered apart, modal mass 1 for the lab's mass-normalised shapes (the FRFs
synthesised from the 55 sets equal the 58 sets), and the points table the geometry
gives equal to the one ``lab`` writes."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.kinematics import link_frames
from flexarm.validation.data.formats.csv_points import read_points
from flexarm.validation.data.formats.uff import read_uff
from flexarm.validation.data.formats.uff_write import write_uff
from flexarm.validation.dynamic.point_geometry import file_points
from flexarm.validation.lab.virtual_lab import lab_shapes, run_lab
from flexarm.validation.models import DEFAULT_OPTIONS, validation_models
from flexarm.validation.workflow import compare

pyuff = pytest.importorskip("pyuff")

POSES = ("P1", "P2")


@pytest.fixture(scope="module")
def lab_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("lab_write")
    lab = run_lab(poses=",".join(POSES), loads="0:800:800", dirs="y", modal=True, n_modes=6,
                  seed=4)
    return lab, lab.write(folder / "static.csv", folder / "lab.uff")


def forward_kinematics(robot, pose: str, points) -> np.ndarray:
    """(k, 3) base-frame positions [m] of the points table's rows at a named pose."""
    F = link_frames(robot.chain, robot.pose(pose))
    return np.array([F[i, :3, :3] @ p + F[i, :3, 3]
                     for i, p in zip(points.links, points.positions, strict=True)])


def test_geometry_at_each_pose_is_the_forward_kinematics(lab_file):
    lab, files = lab_file
    robot = load_demo_robot()
    points = read_points(files.points)
    sets = pyuff.UFF(str(files.modal)).read_sets()
    cs, = [d for d in sets if d["type"] == 2420]
    assert cs["CS_sys_labels"] == [1] and np.array_equal(cs["CS_matrices"][0],
                                                         np.vstack([np.eye(3), np.zeros(3)]))
    blocks = [d for d in sets if d["type"] == 2411]
    traces = [d for d in sets if d["type"] == 82]
    assert len(blocks) == len(traces) == len(POSES) and not any(d["type"] == 15 for d in sets)
    for j, (pose, block, trace) in enumerate(zip(POSES, blocks, traces, strict=True)):
        assert np.array_equal(block["node_nums"], points.nodes + 1000 * j)
        assert np.all(block["def_cs"] == 1) and np.all(block["disp_cs"] == 1)
        xyz = np.column_stack([block["x"], block["y"], block["z"]])
        assert np.max(np.abs(xyz - forward_kinematics(robot, pose, points))) < 1e-9
        # the stick figure runs base to TCP through every point of the pose
        assert trace["nodes"].tolist() == (np.sort(points.nodes) + 1000 * j).tolist()
    # each pose's shapes and FRFs use that pose's nodes; the mark says the offset
    for d in sets:
        if d["type"] in (55, 58):
            j = POSES.index(d["id4"].split()[1].removeprefix("pose="))
            ids = d["node_nums"] if d["type"] == 55 else [d["rsp_node"], d["ref_node"]]
            assert np.all(np.asarray(ids) // 1000 == j)
            assert d["id5"] == ("flexarm nodes+=1000" if j else "NONE")


def test_flexarm_reads_back_each_pose_in_point_ids(lab_file):
    lab, files = lab_file
    content = read_uff(files.modal)
    robot = load_demo_robot()
    points = read_points(files.points)
    assert [g.pose for g in content.geometry] == list(POSES)
    for g in content.geometry:
        assert np.array_equal(g.nodes, points.nodes)
        assert np.max(np.abs(g.coordinates - forward_kinematics(robot, g.pose, points))) < 1e-9
    assert np.array_equal(content.modal_mass, np.ones(len(lab.shapes.freq_hz)))
    assert content.shapes.poses.tolist() == lab.shapes.poses.tolist()
    for got, made in zip(content.frfs, lab.frfs, strict=True):
        assert np.array_equal(got.out_nodes, made.out_nodes)
        assert np.array_equal(got.in_nodes, made.in_nodes)


def test_one_pose_keeps_the_point_ids(tmp_path):
    lab = run_lab(poses="P3", loads="0:800:800", dirs="y", modal=True, n_modes=3)
    files = lab.write(tmp_path / "s.csv", tmp_path / "one.uff")
    assert "nodes+=" not in files.modal.read_text()
    block, = [d for d in pyuff.UFF(str(files.modal)).read_sets() if d["type"] == 2411]
    assert np.array_equal(block["node_nums"], lab.points.nodes)


def test_modal_mass_one_synthesises_the_lab_frfs():
    """Noise-free lab data at P1 with every mode of the E-model: the receptance
    sum_r phi_o phi_i / (m_r (w_r^2 - w^2 + 2 i zeta_r w_r w)) from the 55 sets as pyuff
    reads them (6 digits) equals the 58 sets; a modal mass of 1 is what makes it so."""
    robot = load_demo_robot()
    arm = validation_models(robot, DEFAULT_OPTIONS).arm
    poses = {"P1": robot.pose("P1")}
    lab = lab_shapes(arm, robot, poses, [], 100, 0.0, 0, frf_noise=0.0, band=(5.0, 120.0))
    assert len(lab["shapes"].freq_hz) == 12  # every mode of the E-model at the pose
    import tempfile
    from pathlib import Path

    path = write_uff(Path(tempfile.mkdtemp()) / "m.uff", lab["shapes"], lab["frfs"],
                     lab["geometry"], modal_mass=1.0)
    sets = pyuff.UFF(str(path)).read_sets()
    modes = [d for d in sets if d["type"] == 55]
    assert [d["modal_m"] for d in modes] == [1.0] * 12
    phi = {}
    for r, d in enumerate(modes):
        for k, n in enumerate(d["node_nums"]):
            for a, c in enumerate("xyz"):
                phi[(int(n), c, r)] = d[f"r{a + 1}"][k]
    wr = np.array([2 * np.pi * d["freq"] for d in modes])
    zeta = np.array([d["modal_damp_vis"] for d in modes])
    mass = np.array([d["modal_m"] for d in modes])
    frfs = [d for d in sets if d["type"] == 58]
    assert len(frfs) == 108
    for d in frfs:
        w = 2 * np.pi * d["x"]
        po = np.array([phi[(d["rsp_node"], "xyz"[d["rsp_dir"] - 1], r)] for r in range(12)])
        pi = np.array([phi[(d["ref_node"], "xyz"[d["ref_dir"] - 1], r)] for r in range(12)])
        den = mass * (wr**2 - w[:, None] ** 2 + 2j * zeta * wr * w[:, None])
        H = (po * pi / den).sum(axis=1)
        assert np.linalg.norm(H - d["data"]) <= 5e-5 * np.linalg.norm(d["data"])


def test_points_table_from_the_geometry_equals_the_labs(lab_file, tmp_path):
    """Without ``<file>.points.csv``, the 2411 block of the first pose gives the points
    table (each node on the nearest link), and ``compare`` pairs as with the table."""
    lab, files = lab_file
    robot = load_demo_robot()
    table = read_points(files.points)
    for pose in POSES:
        got = file_points(files.modal, robot, pose, robot.pose(pose))
        assert np.array_equal(got.nodes, table.nodes) and np.array_equal(got.links, table.links)
        assert np.max(np.abs(got.positions - table.positions)) < 1e-12
    alone = tmp_path / "alone.uff"
    alone.write_bytes(files.modal.read_bytes())
    a, b = compare(files.modal).poses, compare(alone).poses
    for x, y in zip(a, b, strict=True):
        assert x.model.tolist() == y.model.tolist()
        assert np.allclose(x.mac, y.mac, rtol=0, atol=1e-12)


def test_sdynpy_reads_geometry_shapes_and_frfs(lab_file):
    """SDynPy's own reader on the lab's file: a node set and a traceline per pose where
    the forward kinematics puts them, the 55 shapes, frequencies and damping ratios (7
    digits in the format's 13 columns) with modal mass 1, and the 58 receptances, all
    equal to what the lab made to 1e-6."""
    import os

    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")  # SDynPy imports Qt
    sdpy = pytest.importorskip("sdynpy")
    lab, files = lab_file
    robot = load_demo_robot()
    points = read_points(files.points)
    data = sdpy.uff.readuff(str(files.modal))
    geometry = sdpy.geometry.Geometry.from_uff(data)
    assert geometry.coordinate_system.id.tolist() == [1]
    ids = geometry.node.id
    for j, pose in enumerate(POSES):
        mine = (ids >= 1000 * j) & (ids < 1000 * (j + 1))
        assert np.array_equal(ids[mine], points.nodes + 1000 * j)
        xyz = geometry.node.coordinate[mine]
        assert np.max(np.abs(xyz - forward_kinematics(robot, pose, points))) < 1e-9
        assert np.array_equal(geometry.traceline.connectivity[j], points.nodes + 1000 * j)

    shapes = sdpy.shape.ShapeArray.from_uff(data)
    made = lab.shapes
    assert shapes.size == len(made.freq_hz)
    assert np.allclose(shapes.frequency, made.freq_hz, rtol=1e-6, atol=0)
    assert np.allclose(shapes.damping, made.damping_ratio, rtol=1e-6, atol=0)
    assert np.all(shapes.modal_mass == 1.0)
    col = {f"{n}{d}": k for k, (n, d) in enumerate(zip(made.nodes, made.dirs, strict=True))}
    for r in range(shapes.size):
        j = POSES.index(str(made.poses[r]))
        c = shapes[r].coordinate
        keys = [f"{int(n) - 1000 * j}{'xyz'[int(d) - 1]}"
                for n, d in zip(c.node, c.direction, strict=True)]
        truth = made.shapes[r, [col[k] for k in keys]]
        assert np.all(np.abs(shapes[r].shape_matrix - truth) <= 1e-6 * np.abs(truth) + 1e-300)

    frfs = sdpy.data.NDDataArray.from_uff(data)
    assert frfs.size == sum(len(f.H) for f in lab.frfs)
    k = 0
    for j, f in enumerate(lab.frfs):
        for row in range(len(f.H)):
            got = frfs[k]
            assert got.coordinate[0].node == f.out_nodes[row] + 1000 * j
            assert got.coordinate[1].node == f.in_nodes[row] + 1000 * j
            assert np.allclose(got.abscissa, f.freq_hz, rtol=1e-9, atol=0)
            assert np.all(np.abs(got.ordinate - f.H[row]) <= 1e-6 * np.abs(f.H[row]))
            k += 1


@pytest.mark.parametrize("complex_modes", [False, True])
def test_55_values_keep_seven_digits_and_blank_separated_fields(tmp_path, complex_modes):
    """Shapes over twelve decades, both signs: pyuff's reader gets every value to 5e-7
    (7 digits) where its exponent has one digit, to 5e-6 below 1e-9; every data line
    splits on white space into its 3 or 6 numbers, as readers that split need."""
    from flexarm.validation.data.shape_data import ShapeData

    rng = np.random.default_rng(3)
    values = rng.choice([-1, 1], 24) * 10.0 ** rng.uniform(-11, 1, 24) * rng.uniform(1, 9.99, 24)
    shapes = values.reshape(2, 12) * (1 + 0.5j if complex_modes else 1)
    s = ShapeData(poses=["P1", "P1"], q=np.zeros((2, 6)), modes=[1, 2],
                  freq_hz=[7.123456789, 12.987654321], damping_ratio=[0.0123456789, 0.02],
                  nodes=np.repeat([1, 2, 3, 4], 3), dirs=list("xyz") * 4, shapes=shapes)
    path = write_uff(tmp_path / "digits.uff", s, modal_mass=[1.0, 2.0])
    sets = [d for d in pyuff.UFF(str(path)).read_sets() if d["type"] == 55]
    got = np.array([np.column_stack([d["r1"], d["r2"], d["r3"]]).ravel() for d in sets])
    parts = [got.real, got.imag] if complex_modes else [got]
    truth = [shapes.real, shapes.imag] if complex_modes else [shapes]
    for g, t in zip(parts, truth, strict=True):
        rel = np.abs(g - t) / np.abs(t)
        assert np.all(rel[np.abs(t) >= 1e-9] <= 5e-7) and np.all(rel <= 5e-6)
    if complex_modes:
        w = 2 * np.pi * np.array([7.123456789, 12.987654321])
        assert np.allclose([abs(d["eig"]) for d in sets], w, rtol=5e-7, atol=0)
    else:
        assert np.allclose([d["freq"] for d in sets], [7.123456789, 12.987654321],
                           rtol=5e-7, atol=0)
        assert np.allclose([d["modal_damp_vis"] for d in sets], [0.0123456789, 0.02],
                           rtol=5e-7, atol=0)
        assert [d["modal_m"] for d in sets] == [1.0, 2.0]
    lines = path.read_text().splitlines()
    for k, line in enumerate(lines):
        if line.strip() == "55":
            data = lines[k + 10:k + 18:2]  # past 5 ID lines, 3 records, each node's id
            assert all(len(x.split()) == (6 if complex_modes else 3) for x in data)
