"""Robot TOML: write-then-read round trip of a robot with every optional table (spring base,
tool, poses, model options, wrist, custom materials, lumped masses, regions, emodel, Rayleigh,
rigid directions, [nonlinear]); degrees in the file; mesh paths relative to it; error messages."""

from __future__ import annotations

import copy
import math
import re

import numpy as np
import pytest
import tomllib

from flexarm.fe.errors import ReadError
from flexarm.fe.material import MATERIALS, Material
from flexarm.robot.demo_arm import demo_robot_path
from flexarm.robot.effects import Effect
from flexarm.robot.formats import toml as robot_toml
from flexarm.robot.formats.toml import FORMAT_VERSION, from_dict, to_dict

FOLDER = demo_robot_path().parent
BASE_K = (np.diag([2e9, 2e9, 3e9, 4e7, 4e7, 5e7]) + 1e6 * (np.ones((6, 6)) - np.eye(6))).tolist()
WRIST_K = [[3e5, 1e4, 0.0], [1e4, 2e5, 2e4], [0.0, 2e4, 1e5]]

FULL = {
    "format_version": 1,
    "name": "every table",
    "model": {"element_order": 2, "mesh_size": 0.05, "cb_modes": 6, "mesher": "gmsh"},
    "base": {"support": "spring", "damping_ratio": 0.05, "stiffness": BASE_K},
    "tool": {"xyz": [0.1, 0.02, -0.03], "rpy_deg": [10.0, 20.0, 30.0], "link": "l2"},
    "poses": {"home": [0.0, 0.0, 0.0], "bent": [10.5, -20.0, 33.3]},
    "wrist": {"coupling": [[1.0, 0.0, 0.0], [0.1, 1.0, 0.0], [0.05, 0.2, 1.0]],
              "stiffness": WRIST_K},
    "links": [
        {"name": "l0", "mesh": "meshes/base.stl", "material": "cast_iron"},
        {"name": "l1", "mesh": "meshes/frame.stl",
         "material": {"E": 1.1e11, "nu": 0.29, "rho": 4430.0, "name": "titanium"},
         "lumped": [{"name": "motor", "mass": 12.5, "position": [0.1, 0.2, 0.3],
                     "inertia": [[0.2, 0.01, 0.0], [0.01, 0.3, 0.0], [0.0, 0.0, 0.4]]},
                    {"name": "gear", "mass": 3.0, "position": [0.0, 0.0, 0.1],
                     "inertia": [0.01, 0.02, 0.03]}],
         "regions": {"j1": {"center": [0.0, 0.0, 0.0], "axis": [0.0, 0.0, 1.0], "r_min": 0.05,
                            "r_max": 0.1, "half_width": 0.02, "coupling": "rbe3"},
                     "j2": {"center": [0.2, 0.0, 0.0], "axis": [0.0, 1.0, 0.0], "r_min": 0.0,
                            "r_max": 0.08, "half_width": 0.03}}},
        {"name": "l2", "units": "mm", "material": "2.1e11,0.3,7800",
         "lumped": [{"name": "flange", "mass": 2.0, "position": [50.0, 0.0, 0.0]}]},
        {"name": "l3", "mesh": "meshes/turning_disc.stl", "material": "steel"},
    ],
    "joints": [
        {"name": "j1", "parent": "l0", "child": "l1", "origin": [0.0, 0.0, 0.5],
         "axis": [0.0, 0.0, 1.0], "limits_deg": [-170.0, 170.0], "gear_ratio": 100.0,
         "rpy_deg": [0.0, 0.0, 15.0],
         "model": {"torsion": 5e5, "tilt": 2e7, "radial": 1e9, "axial": "rigid",
                   "damping_ratio": 0.03, "rayleigh": [1.0, 1e-4]},
         "emodel": {"torsion": 5e5, "tilt": 4e6, "tilt2": 5e6}},
        {"name": "j2", "parent": "l1", "child": "l2", "origin": [0.2, 0.0, 0.0],
         "axis": [0.0, 1.0, 0.0], "model": {"torsion": 3e6}},
        {"name": "j3", "parent": "l1", "child": "l3", "origin": [0.2, 0.3, 0.0],
         "axis": [0.6, 0.0, 0.8], "limits_deg": [-400.0, 400.0], "gear_ratio": -50.0,
         "model": {"torsion": 2e5, "tilt": "rigid", "radial": 2e9}},
    ],
    "nonlinear": {
        "j2": {"backlash_rad": 1e-4, "hardening_extra_rad_per_Nm": 2e-7,
               "hardening_threshold_Nm": 300.0},
        "j3": {"hysteresis_lost_rad": 5e-5, "hysteresis_radius_Nm": 150.0},
    },
}


def exact(message: str) -> str:
    return "^" + re.escape(message) + "$"


@pytest.fixture(scope="module")
def full():
    return from_dict(copy.deepcopy(FULL), FOLDER, source=None)


@pytest.fixture(scope="module")
def round_trip(full, tmp_path_factory):
    path = tmp_path_factory.mktemp("toml") / "deep" / "er" / "robot.toml"
    robot_toml.write(path, full)
    return path, robot_toml.read(path)


def test_read_values(full):
    """What the reader makes of the tables: radians, rigid = inf, diagonal shorthands."""
    j1, j2, j3 = full.joints
    assert j1.lower == pytest.approx(math.radians(-170)) and j2.upper == pytest.approx(math.pi)
    assert j1.rpy == pytest.approx((0.0, 0.0, math.radians(15)))
    assert j1.model.axial == math.inf and j1.model.rayleigh == (1.0, 1e-4)
    assert j1.emodel.tilt_2 == 5e6 and j1.emodel.radial == math.inf
    assert j2.model.free_dofs.tolist() == [3] and j2.emodel is None
    assert j3.model.free_dofs.tolist() == [1, 2, 3] and j3.gear_ratio == -50.0
    l1, l2 = full.links[1], full.links[2]
    assert l1.material == Material(1.1e11, 0.29, 4430.0, "titanium")
    assert l1.lumped[1].inertia == ((0.01, 0.0, 0.0), (0.0, 0.02, 0.0), (0.0, 0.0, 0.03))
    assert l1.regions["j2"].coupling == "rbe2"  # default
    assert l2.mesh is None and l2.units == "mm" and l2.material.name == "custom"
    assert l2.lumped[0].inertia == ((0.0,) * 3,) * 3
    assert full.links[0].material is MATERIALS["cast_iron"]
    assert full.links[0].mesh == (FOLDER / "meshes" / "base.stl").resolve()
    assert full.base.kind == "spring" and np.allclose(full.base.stiffness, BASE_K)
    assert full.poses["bent"] == pytest.approx(np.radians([10.5, -20.0, 33.3]).tolist())
    assert full.options.mesher == "gmsh" and full.options.element_order == 2
    assert full.effects == (
        Effect("backlash", 1, (("width", 1e-4),)),
        Effect("hardening", 1, (("extra", 2e-7), ("threshold", 300.0))),
        Effect("hysteresis", 2, (("lost", 5e-5), ("radius", 150.0))),
    )


def test_round_trip_keeps_every_field(full, round_trip):
    path, back = round_trip
    assert back.source == path.resolve() and back.name == full.name
    assert back.options == full.options and back.base.kind == full.base.kind
    assert back.base.damping_ratio == full.base.damping_ratio
    np.testing.assert_array_equal(back.base.stiffness, full.base.stiffness)
    assert back.tool.xyz == full.tool.xyz and back.tool.link == full.tool.link
    np.testing.assert_allclose(back.tool.rpy, full.tool.rpy, rtol=1e-15)
    assert back.wrist_coupling == full.wrist_coupling
    assert back.wrist_stiffness == full.wrist_stiffness
    assert back.poses.keys() == full.poses.keys()
    for k in full.poses:
        np.testing.assert_allclose(back.poses[k], full.poses[k], rtol=1e-12, atol=1e-15)
    for a, b in zip(back.links, full.links, strict=True):
        assert (a.name, a.mesh, a.material, a.units, a.lumped) == (b.name, b.mesh, b.material,
                                                                    b.units, b.lumped)
        assert a.regions == b.regions
    for a, b in zip(back.joints, full.joints, strict=True):
        assert (a.name, a.parent, a.child, a.origin, a.axis, a.gear_ratio) == (
            b.name, b.parent, b.child, b.origin, b.axis, b.gear_ratio)
        assert a.model == b.model and a.emodel == b.emodel
        np.testing.assert_allclose([a.lower, a.upper, *a.rpy], [b.lower, b.upper, *b.rpy],
                                   rtol=1e-15, atol=1e-18)
    assert back.effects == full.effects
    # a second write gives the same file
    again = path.with_name("again.toml")
    robot_toml.write(again, back)
    assert again.read_text() == path.read_text()


def test_file_holds_degrees_rigid_and_relative_paths(full, round_trip):
    path, _ = round_trip
    data = tomllib.loads(path.read_text())
    assert data["format_version"] == FORMAT_VERSION == 1
    j1 = data["joints"][0]
    assert j1["limits_deg"] == pytest.approx([-170.0, 170.0], rel=1e-14)
    assert j1["rpy_deg"] == pytest.approx([0.0, 0.0, 15.0], rel=1e-14)
    assert j1["model"]["axial"] == "rigid" and j1["model"]["rayleigh"] == [1.0, 1e-4]
    assert j1["emodel"]["radial"] == "rigid" and j1["emodel"]["tilt2"] == 5e6
    assert data["tool"]["rpy_deg"] == pytest.approx([10.0, 20.0, 30.0], rel=1e-14)
    assert data["poses"]["bent"] == [10.5, -20.0, 33.3]
    assert data["model"]["mesher"] == "gmsh"
    assert data["links"][1]["material"] == {"E": 1.1e11, "nu": 0.29, "rho": 4430.0,
                                            "name": "titanium"}
    assert data["links"][0]["material"] == "cast_iron"
    mesh = data["links"][0]["mesh"]
    assert mesh.startswith("../") and (path.parent / mesh).resolve() == full.links[0].mesh
    assert data["nonlinear"] == FULL["nonlinear"]
    assert "mesh" not in data["links"][2]


def test_optional_tables_are_left_out():
    minimal = {"links": [{"name": "a"}, {"name": "b", "lumped": [{"mass": 1.0}]}],
               "joints": [{"name": "j", "parent": "a", "child": "b", "origin": [0, 0, 0],
                           "axis": [0, 0, 1], "model": {"torsion": 1e5}}]}
    r = from_dict(minimal, FOLDER)
    d = to_dict(r, FOLDER)
    assert {"wrist", "nonlinear"}.isdisjoint(d) and "mesher" not in d["model"]
    assert "stiffness" not in d["base"] and "link" not in d["tool"]
    assert r.base.kind == "clamped" and r.options.mesher == "tetwild" and r.effects == ()
    assert r.links[0].material is MATERIALS["steel"]


@pytest.mark.parametrize("edit, message", [
    (lambda d: d.update(format_version=2),
     "format_version: cannot read version 2 (this flexarm reads 1)"),
    (lambda d: d["nonlinear"].update(j9={"backlash_rad": 1e-4}),
     "nonlinear.j9: no such joint (have ['j1', 'j2', 'j3'])"),
    (lambda d: d["nonlinear"]["j3"].pop("hysteresis_radius_Nm"),
     "nonlinear.j3.hysteresis_radius_Nm is required with hysteresis_lost_rad"),
    (lambda d: d["nonlinear"]["j2"].update(backlash_deg=0.1),
     "nonlinear.j2: unknown key 'backlash_deg' (did you mean 'backlash_rad'?)"),
    (lambda d: d["links"][1]["material"].pop("rho"),
     "links.l1.material needs E, nu and rho, missing 'rho'"),
    (lambda d: d["links"][1]["lumped"][0].update(inertia=[1.0, 2.0]),
     "links.l1.lumped.motor.inertia must be 3 principal values or a 3x3 matrix, got [1.0, 2.0]"),
    (lambda d: d["links"][1]["regions"]["j1"].pop("r_max"),
     "links.l1.regions.j1: missing key 'r_max'"),
    (lambda d: d["links"][2].update(colour="red"),
     "links.l2: unknown key 'colour' (allowed: ['lumped', 'material', 'mesh', 'name', "
     "'regions', 'units', 'volume_meshes'])"),
    (lambda d: d["joints"][1]["model"].update(tilt="stiff"),
     "joints.j2.model.tilt must be a number or \"rigid\", got 'stiff'"),
    (lambda d: d["joints"][0]["emodel"].pop("torsion"),
     "joints.j1.emodel.torsion is required [N m/rad]"),
    (lambda d: d["joints"][1].update(limits_deg=[0.0]),
     "joints.j2.limits_deg must be [lower, upper], got [0.0]"),
    (lambda d: d["joints"][2].pop("origin"), "joints.j3.origin is required"),
    (lambda d: d["base"].update(stiffness=[1e9] * 5 + [-1.0]),
     "base.stiffness: negative stiffness -1"),
    # a table or key that would be dropped silently changes the model: all are errors
    (lambda d: d.update(tol=d.pop("tool")), "top level: unknown key 'tol' (did you mean 'tool'?)"),
    (lambda d: d.update(robot_name="x"),
     "top level: unknown key 'robot_name' (allowed: ['base', 'effects', 'format_version', "
     "'joints', 'links', 'modal_damping', 'model', 'name', 'nonlinear', 'poses', 'tool', "
     "'wrist'])"),
    (lambda d: d["wrist"].update(couplng=d["wrist"].pop("coupling")),
     "wrist: unknown key 'couplng' (did you mean 'coupling'?)"),
    (lambda d: d["model"].update(mesh_siz=0.01), "model: unknown key 'mesh_siz' (did you mean "
     "'mesh_size'?)"),
    (lambda d: d["base"].update(suport="spring"),
     "base: unknown key 'suport' (did you mean 'support'?)"),
    (lambda d: d["tool"].update(rpy=[0, 0, 0]), "tool: unknown key 'rpy' (did you mean "
     "'rpy_deg'?)"),
    (lambda d: d["links"][1]["lumped"][0].update(mas=1.0),
     "links.l1.lumped.motor: unknown key 'mas' (did you mean 'mass'?)"),
    (lambda d: d["links"][1]["regions"]["j1"].update(halfwidth=0.1),
     "links.l1.regions.j1: unknown key 'halfwidth' (did you mean 'half_width'?)"),
    (lambda d: d["links"][1]["material"].update(rh0=1.0),
     "links.l1.material: unknown key 'rh0' (did you mean 'rho'?)"),
    (lambda d: d["joints"][1].update(name="j1"), "joints: duplicate name 'j1' (names must be "
     "unique)"),
    (lambda d: d.update(tool=3), "tool must be a table, got 3"),
    (lambda d: d.update(joints={"name": "j1"}),
     "joints must be an array of tables ([[joints]]), got {'name': 'j1'}"),
    (lambda d: d["poses"].update(home="zero"),
     "poses.home must be a list of joint angles in degrees, got 'zero'"),
    (lambda d: d["poses"].update(home=[0.0, 900.0, 0.0]),
     "poses.home: j2 = 900 deg outside limits [-180, 180] deg"),
    (lambda d: d["model"].update(mesh_size=-0.01),
     "model.mesh_size must be a positive edge length [m], got -0.01"),
    (lambda d: d["model"].update(element_order=3),
     "model.element_order must be 1 (Tet4) or 2 (Tet10), got 3"),
    (lambda d: d["model"].update(cb_modes=-1), "model.cb_modes must be >= 0, got -1"),
    (lambda d: d["nonlinear"]["j2"].update(backlash_rad=-1e-4),
     "nonlinear.j2: backlash width must be >= 0, got -0.0001"),
    (lambda d: d["nonlinear"]["j3"].update(hysteresis_radius_Nm=0.0),
     "nonlinear.j3: hysteresis radius must be > 0, got 0"),
    (lambda d: d["joints"][1].update(limits_deg=[-float("inf"), 10.0]),
     "joints.j2.limits must be finite, got [-inf, 10] deg"),
])
def test_error_messages(edit, message):
    data = copy.deepcopy(FULL)
    edit(data)
    with pytest.raises(ValueError, match=exact(message)):
        from_dict(data, FOLDER)


def test_read_errors_name_the_file(tmp_path):
    bad = tmp_path / "syntax.toml"
    bad.write_text("name = \n")
    with pytest.raises(ReadError, match=r"^.*syntax\.toml: "):
        robot_toml.read(bad)
    wrong = tmp_path / "version.toml"
    wrong.write_text("format_version = 3\n")
    with pytest.raises(ReadError, match=r"version\.toml: format_version: cannot read version 3"):
        robot_toml.read(wrong)
    with pytest.raises(FileNotFoundError):
        robot_toml.read(tmp_path / "missing.toml")


def test_a_region_to_review_keeps_its_mark(tmp_path):
    """``review = true`` reads as a ReviewRegion that selects like any region, is written
    back, and is left out of regions nobody marked."""
    from flexarm.robot.seat_review import ReviewRegion, is_review

    data = copy.deepcopy(FULL)
    data["links"][1]["regions"]["j2"]["review"] = True
    robot = from_dict(data, FOLDER)
    j1, j2 = robot.links[1].regions["j1"], robot.links[1].regions["j2"]
    assert isinstance(j2, ReviewRegion) and is_review(j2) and not is_review(j1)
    assert j2.contains(np.array([[0.25, 0.0, 0.0], [0.2, 0.5, 0.0]])).tolist() == [True, False]
    path = tmp_path / "review.toml"
    robot_toml.write(path, robot)
    text = path.read_text()
    assert text.count("review = true") == 1
    back = robot_toml.read(path)
    assert is_review(back.links[1].regions["j2"]) and not is_review(back.links[1].regions["j1"])
    assert back.links[1].regions["j2"] == j2
    data["links"][1]["regions"]["j2"]["review"] = "yes"
    with pytest.raises(ValueError, match=exact("links.l1.regions.j2.review must be true or "
                                               "false, got 'yes'")):
        from_dict(data, FOLDER)
