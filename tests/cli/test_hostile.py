"""Hostile input through ``flexarm.cli.main``: every case ends with one clear error line.

Each case builds its inputs in ``tmp_path`` (a robot TOML edited from the demo arm's, a
measurement CSV edited from the shipped example, a URDF, a CAD surface, a folder where a
file belongs, ...), runs one command and asserts: the exit code; exactly one error line,
the last on stderr, naming the file, line, option or key and the figure at fault; no
traceback; no output file and no temporary ``.part`` file left behind; and for the cases
that used to run away (meshing at an absurd edge length), a time and memory cap.
"""

from __future__ import annotations

import re
import resource
import time
from pathlib import Path

import pytest

from flexarm.cli import main
from flexarm.robot.demo_arm import demo_robot_path
from flexarm.validation import example_path

DEMO = demo_robot_path()
STATIC = example_path("static")
#: Peak memory [MB] a refused request may add (pytetwild alone would take gigabytes).
MEMORY_CAP_MB = 300
#: Seconds a refused request may take: a runaway (meshing at an absurd edge) runs for many
#: minutes, so the cap is generous for a busy machine.
TIME_CAP_S = 60


@pytest.fixture(autouse=True)
def _caches(monkeypatch, tmp_path):
    """The shared test cache for the demo arm's meshes; a private one where a case says."""
    import os

    shared = os.environ.get("FLEXARM_TEST_CACHE")
    monkeypatch.setenv("FLEXARM_CACHE", shared or os.environ["FLEXARM_CACHE"])


# --- inputs ----------------------------------------------------------------------------
def robot(tmp: Path, *edits: tuple[str, str], name: str = "robot.toml") -> Path:
    """The demo robot TOML with ``(old, new)`` text edits, its meshes referenced in place."""
    text = (DEMO.read_text().replace('mesh = "meshes/', f'mesh = "{DEMO.parent}/meshes/')
            .replace('= "tets/', f'= "{DEMO.parent}/tets/'))
    for old, new, *count in edits:  # (old, new) replaces the first, (old, new, -1) every one
        assert old in text, old
        text = text.replace(old, new, *(count or [1]))
    path = tmp / name
    path.write_text(text)
    return path


def static_csv(tmp: Path, edit=None, name: str = "static.csv") -> Path:
    """The static example with ``edit(data_rows) -> data_rows`` (rows as field lists)."""
    lines = STATIC.read_text().splitlines()
    head = [ln for ln in lines if ln.startswith("#") or ln.startswith("series")]
    rows = [[f.strip() for f in ln.split(",")] for ln in lines if ln not in head and ln]
    if edit is not None:
        rows = edit(rows)
    path = tmp / name
    path.write_text("\n".join(head + [", ".join(r) for r in rows]) + "\n")
    return path


def cell(row: int, column: int, value: str):
    def edit(rows):
        rows[row][column] = value
        return rows
    return edit


URDF_HEAD = ('<robot name="r"><link name="a"><inertial><mass value="5"/></inertial></link>'
             '<link name="b"><inertial><origin xyz="0.5 0 0"/><mass value="2"/></inertial>'
             '</link><link name="c"><inertial><mass value="1"/></inertial></link>')


def joint(name, parent, child, kind="revolute"):
    return (f'<joint name="{name}" type="{kind}"><origin xyz="0.5 0 0"/><parent link="{parent}"/>'
            f'<child link="{child}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1"/></joint>')


def urdf(tmp: Path, body: str, name: str = "r.urdf") -> Path:
    path = tmp / name
    path.write_text(body)
    return path


GOOD_URDF = URDF_HEAD + joint("j1", "a", "b") + joint("j2", "b", "c") + "</robot>"


def box_stl(tmp: Path, dims=(0.1, 0.1, 0.1), name: str = "box.stl") -> Path:
    from flexarm.meshes import bar_surface, write_surface

    path = tmp / name
    write_surface(path, bar_surface(*dims))
    return path


def box_vtu(tmp: Path, name: str = "bar.vtu") -> Path:
    from flexarm.fe import TetMesh
    from flexarm.meshes import write_volume_mesh

    path = tmp / name
    write_volume_mesh(path, TetMesh.box((1.0, 0.05, 0.05), (8, 1, 1), order=1))
    return path


# --- the table -------------------------------------------------------------------------
# Each case: (id, build(tmp) -> argv, exit code, regexes the error line must match, files
# that must not exist afterwards (relative to tmp)).
CASES = []


def case(id_, build, *needles, code=2, absent=(), capped=False):
    CASES.append(pytest.param(build, code, needles, absent, capped, id=id_))


# Robot TOML: misspelt or unknown tables and keys are errors with a suggestion.
def _robot_case(id_, edits, *needles):
    case(id_, lambda t: ["compliance", "--robot", str(robot(t, *edits))], r"robot\.toml: ",
         *needles)


_robot_case("toml-tol-table", [("[tool]", "[tol]")],
            re.escape("top level: unknown key 'tol' (did you mean 'tool'?)"))
_robot_case("toml-wrist-typo", [("coupling = [\n    [1.0", "couplin = [\n    [1.0")],
            re.escape("wrist: unknown key 'couplin' (did you mean 'coupling'?)"))
_robot_case("toml-model-typo", [("mesh_size = 0.03", "mesh_siz = 0.03")],
            re.escape("model: unknown key 'mesh_siz' (did you mean 'mesh_size'?)"))
_robot_case("toml-model-cb-typo", [("cb_modes = 10", "cbmodes = 10")], "did you mean 'cb_modes'")
_robot_case("toml-base-typo", [('support = "clamped"', 'suport = "clamped"')],
            "base: unknown key 'suport'")
_robot_case("toml-tool-typo", [("rpy_deg = [0.0, 90.0, 0.0]", "rpy = [0.0, 90.0, 0.0]")],
            "tool: unknown key 'rpy' .did you mean 'rpy_deg'")
_robot_case("toml-unknown-top-key", [('name = "flexarm', 'nmae = "flexarm')],
            "unknown key 'nmae' .did you mean 'name'")
_robot_case("toml-link-key-typo", [('units = "m"', 'unit = "m"')],
            "links.base: unknown key 'unit' .did you mean 'units'")
_robot_case("toml-region-typo", [("half_width = 0.002", "halfwidth = 0.002")],
            "links.base.regions.base: unknown key 'halfwidth'")
_robot_case("toml-lumped-typo", [("mass = 19.0", "mas = 19.0")],
            "links.frame.lumped.motor_gear_1: unknown key 'mas'")
_robot_case("toml-joint-model-typo", [("torsion = ", "torsoin = ")], "unknown key 'torsoin'")
_robot_case("toml-duplicate-joint", [('name = "joint_2"', 'name = "joint_1"')],
            re.escape("joints: duplicate name 'joint_1'"))
_robot_case("toml-duplicate-link", [('name = "frame"', 'name = "base"')], "duplicate")
_robot_case("toml-units-in", [('units = "m"\nmaterial = "cast_iron"\n\n[[links.lumped]]',
                               'units = "in"\nmaterial = "cast_iron"\n\n[[links.lumped]]')],
            r"links\.frame\.units: the CAD is 0\.0146 m across with units='in' but carries "
            r"joint_2 at 0\.175 m")
_robot_case("toml-units-mm", [('units = "m"', 'units = "mm"')],
            r"links\.base\.units: the CAD is 0\.00056 m across with units='mm'")
_robot_case("toml-units-unknown", [('units = "m"', 'units = "furlong"')],
            "links.base.units: unknown unit 'furlong'")
_robot_case("toml-syntax", [("[tool]", "[tool")], "line")
_robot_case("toml-pose-out-of-limits", [("P1 = [0.0, 52.0", "P1 = [0.0, 252.0")],
            r"poses\.P1: joint_2 = 252 deg outside limits")
_robot_case("toml-pose-wrong-count", [("P1 = [0.0, 52.0, ", "P1 = [52.0, ")],
            "poses.P1 must have 6 angles, got 5")
_robot_case("toml-pose-text", [("P1 = [0.0, 52.0, -19.0, 12.0, -15.0, -11.0]", 'P1 = "up"')],
            "poses.P1 must be a list of joint angles in degrees")
_robot_case("toml-table-is-number", [('name = "flexarm', 'nonlinear = 3\nname = "flexarm')],
            "nonlinear must be a table, got 3")
_robot_case("toml-links-typo", [("[[links]]", "[[linkz]]", -1), ("[links.", "[linkz.", -1)],
            "unknown key 'linkz' .did you mean 'links'")
_robot_case("toml-joint-no-origin", [("origin = [0.0, 0.0, 0.495]\n", "")],
            r"joints\.joint_1\.origin is required")
_robot_case("toml-gear-ratio-zero", [("gear_ratio = ", "gear_ratio = 0.0 # ")],
            "gear_ratio must be nonzero")
_robot_case("toml-base-support", [('support = "clamped"', 'support = "floating"')],
            "base.support must be clamped|spring, got 'floating'")
_robot_case("toml-tool-link", [('link = "turning_disc"', 'link = "flange"')],
            "tool.link: unknown link 'flange'")
_robot_case("toml-region-coupling", [('coupling = "rbe2"', 'coupling = "glue"')],
            "coupling must be rbe2|rbe3, got 'glue'")
_robot_case("toml-region-radii", [("r_min = 0.18", "r_min = 0.38")],
            "need 0 <= r_min <= r_max")
_robot_case("toml-wrist-singular", [("[0.025, 1.0, 0.0]", "[1.0, 0.0, 0.0]")],
            "wrist.coupling must be an invertible 3x3 matrix")
_robot_case("toml-material-incomplete", [('material = "cast_iron"',
                                          'material = { E = 2.1e11, nu = 0.3 }')],
            "needs E, nu and rho, missing 'rho'")
_robot_case("toml-mesh-size-negative", [("mesh_size = 0.03", "mesh_size = -0.03")],
            re.escape("model.mesh_size must be a positive edge length [m], got -0.03"))
_robot_case("toml-mesh-size-nan", [("mesh_size = 0.03", "mesh_size = nan")],
            "model.mesh_size must be a positive edge length")
_robot_case("toml-element-order", [("element_order = 1", "element_order = 3")],
            "model.element_order must be 1")
_robot_case("toml-cb-modes-negative", [("cb_modes = 10", "cb_modes = -2")],
            "model.cb_modes must be >= 0")
_robot_case("toml-mesher", [("cb_modes = 10", 'cb_modes = 10\nmesher = "tetgen"')],
            "model.mesher must be one of")
_robot_case("toml-material", [('material = "cast_iron"', 'material = "cheese"')],
            "unknown material 'cheese'")
_robot_case("toml-negative-lumped-mass", [("mass = 19.0", "mass = -19.0")],
            r"lumped\.motor_gear_1\.mass must be >= 0 kg")
_robot_case("toml-missing-mesh", [("meshes/base.stl", "meshes/nope.stl")], "file not found")
_robot_case("toml-format-version", [("format_version = 1", "format_version = 9")],
            "format_version: cannot read version 9")
_robot_case("toml-limits-reversed", [("limits_deg = [-180.0, 180.0]",
                                      "limits_deg = [180.0, -180.0]")], "limits reversed")
_robot_case("toml-joint-unknown-parent", [('parent = "frame"', 'parent = "fram"')],
            "unknown link 'fram'")
_robot_case("toml-axis-not-unit", [("axis = [0.0, 0.0, 1.0]\nlimits_deg",
                                    "axis = [0.0, 0.0, 2.0]\nlimits_deg")], "unit vector")
_robot_case("toml-nonlinear-negative-backlash", [
    ("[[links]]", "[nonlinear.joint_2]\nbacklash_rad = -1e-4\n\n[[links]]")],
    "nonlinear.joint_2: backlash width must be >= 0, got -0.0001")
_robot_case("toml-nonlinear-unknown-joint", [
    ("[[links]]", "[nonlinear.joint_9]\nbacklash_rad = 1e-4\n\n[[links]]")],
    "nonlinear.joint_9: no such joint")
case("toml-binary", lambda t: ["compliance", "--robot", str(_write(t / "robot.toml",
                                                                   b"\xff\xfe\x00garbage"))],
     r"robot\.toml: not a UTF-8 text file")
case("toml-empty", lambda t: ["compliance", "--robot", str(_write(t / "robot.toml", b""))],
     r"robot\.toml: ")
case("toml-missing", lambda t: ["compliance", "--robot", str(t / "nope.toml")], r"nope\.toml")
case("toml-is-folder", lambda t: ["compliance", "--robot", str(_mkdir(t / "robot.toml"))],
     r"robot\.toml: .*Is a directory")
case("robot-unknown-extension", lambda t: ["compliance", "--robot",
                                           str(_write(t / "robot.yaml", b"a: 1"))], "yaml")


def _write(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


def _mkdir(path: Path) -> Path:
    path.mkdir(parents=True, exist_ok=True)
    return path


# --pose: names, counts, numbers and joint limits.
def _pose_case(id_, pose, *needles):
    case(id_, lambda t: ["modes", "--pose", pose], r"--pose: ", *needles)


_pose_case("pose-over-limit", "0,260,-19,12,-15,-11",
           re.escape("joint_2 = 260 deg is outside its limits [-90, 150] deg"))
_pose_case("pose-under-limit", "0,0,0,0,-200,0", "joint_5 = -200 deg is outside its limits")
_pose_case("pose-nan", "nan,0,0,0,0,0", "joint_1 = nan deg")
_pose_case("pose-inf", "0,inf,0,0,0,0", "joint_2 = inf deg")
_pose_case("pose-count", "0,10,20", "pose needs 6 angles in degrees, got '0,10,20'")
_pose_case("pose-unknown-name", "P9", "pose must be one of")
_pose_case("pose-text", "up,down", "pose must be one of")
_pose_case("pose-too-many", "0,0,0,0,0,0,0", "pose needs 6 angles")
_pose_case("pose-empty-fields", ",,,", "pose needs 6 angles")
_pose_case("pose-hex", "0x1,0,0,0,0,0", "pose must be one of")


# Measurement CSVs (compare and diagnose read the same way).
def _csv_case(id_, edit, *needles, command="compare"):
    case(id_, lambda t: [command, str(static_csv(t, edit))], r"static\.csv", *needles)


_csv_case("csv-q2-952", cell(0, 3, "952"),
          re.escape("column 'q2_deg': 952 is not a plausible angle (more than 720 deg)"))
_csv_case("csv-q2-952-diagnose", cell(0, 3, "952"), "column 'q2_deg'", command="diagnose")
_csv_case("csv-dx-1e300", cell(1, 11, "1e300"),
          r"line \d+, column 'dx_mm': 1e300 is not a plausible length")
_csv_case("csv-fy-4e12", cell(1, 9, "4e12"),
          r"line \d+, column 'fy_N': 4e12 is not a plausible force \(more than 1e\+07 N\)")
_csv_case("csv-q5-two-turns", cell(3, 6, "-800"), "column 'q5_deg': -800 is not a plausible")
_csv_case("csv-sigma-zero", cell(2, 14, "0"), "column 'sigma_mm': sigma must be positive")
_csv_case("csv-unclosed-quote", cell(2, 0, '"c1_y'), "malformed CSV")
_csv_case("csv-label-comma", cell(2, 0, "c1,y"), "decimal commas")
_csv_case("csv-nan", cell(1, 11, "nan"), "column 'dx_mm': 'nan' is not a finite number")
_csv_case("csv-inf", cell(1, 9, "-inf"), "column 'fy_N': '-inf' is not a finite number")
_csv_case("csv-text", cell(2, 12, "abc"), "column 'dy_mm': 'abc' is not a number")
_csv_case("csv-empty-cell", cell(2, 12, ""), "column 'dy_mm': empty value")
_csv_case("csv-step-not-int", cell(2, 1, "1.5"), "column 'step': '1.5' is not an integer")
_csv_case("csv-step-order", cell(2, 1, "0"), "column 'step': step 0 does not follow step 1")
_csv_case("csv-reference-nonzero", cell(0, 11, "0.5"), "reference reading")
_csv_case("csv-negative-sigma", cell(2, 14, "-0.015"), "column 'sigma_mm': sigma must be positive")
_csv_case("csv-decimal-comma", cell(2, 12, "0,081"), "decimal commas")
_csv_case("csv-short-row", lambda rows: [rows[0][:-2]] + rows[1:], "13 fields, expected 15")
case("csv-semicolons", lambda t: ["compare", str(_write(
    t / "semi.csv", STATIC.read_bytes().replace(b", ", b";")))],
    r"semi\.csv, line \d+: the fields are separated by ';'")
case("csv-tabs", lambda t: ["compare", str(_write(
    t / "tabs.csv", STATIC.read_bytes().replace(b", ", b"\t")))], r"separated by '\\t'")
case("csv-empty", lambda t: ["compare", str(_write(t / "empty.csv", b""))],
     r"empty\.csv: no header row")
case("csv-comments-only", lambda t: ["compare", str(_write(t / "c.csv", b"# nothing\n"))],
     r"c\.csv: no header row")
case("csv-header-only", lambda t: ["compare", str(_write(
    t / "h.csv", STATIC.read_bytes().split(b"c1_y")[0]))], r"h\.csv, line \d+: no data rows")
case("csv-binary", lambda t: ["compare", str(_write(t / "b.csv", b"\x89PNG\r\n\x1a\n\xff\xfe"))],
     r"b\.csv: not a UTF-8 text file")
case("csv-missing", lambda t: ["compare", str(t / "gone.csv")], r"gone\.csv")
case("csv-folder", lambda t: ["compare", str(_mkdir(t / "dir.csv"))], r"dir\.csv")
case("csv-unknown-columns", lambda t: ["compare", str(_write(t / "u.csv", b"a,b\n1,2\n"))],
     r"u\.csv, line 1")
case("csv-duplicate-column", lambda t: ["compare", str(_write(
    t / "d.csv", STATIC.read_bytes().replace(b"q3_deg", b"q2_deg", 1)))],
    r"d\.csv, line \d+, column 'q2_deg': duplicate column")
case("csv-unit-unknown", lambda t: ["compare", str(_write(
    t / "uu.csv", STATIC.read_bytes().replace(b"dx_mm", b"dx_furlong", 1)))],
    r"uu\.csv, line \d+, column 'dx_furlong': unknown unit 'furlong'")


# URDF import: graph checks, bad XML, outputs.
def _urdf_case(id_, body, *needles, out="out.toml"):
    case(id_, lambda t: ["import-urdf", str(urdf(t, body)), "-o", str(t / out), "--no-regions"],
         r"r\.urdf", *needles, absent=(out,))


_urdf_case("urdf-loop", URDF_HEAD + joint("j1", "a", "b") + joint("j2", "b", "c")
           + joint("j3", "c", "b") + "</robot>", "closed loop")
_urdf_case("urdf-missing-parent", URDF_HEAD + joint("j1", "a", "b") + joint("j2", "ghost", "c")
           + "</robot>", "parent link 'ghost' does not exist")
_urdf_case("urdf-missing-child", URDF_HEAD + joint("j1", "a", "b") + joint("j2", "b", "ghost")
           + "</robot>", "child link 'ghost' does not exist")
_urdf_case("urdf-prismatic", URDF_HEAD + joint("j1", "a", "b") + joint("j2", "b", "c", "prismatic")
           + "</robot>", "type 'prismatic' is not supported")
_urdf_case("urdf-duplicate-joint", URDF_HEAD + joint("j1", "a", "b") + joint("j1", "b", "c")
           + "</robot>", "duplicate joint name 'j1'")
_urdf_case("urdf-bad-xml", URDF_HEAD + joint("j1", "a", "b"), "")
_urdf_case("urdf-empty", "", "")
_urdf_case("urdf-not-robot", "<html><body>hello</body></html>", "")
case("urdf-output-is-folder", lambda t: ["import-urdf", str(urdf(t, GOOD_URDF)), "-o",
                                         str(_mkdir(t / "out.toml")), "--no-regions"],
     r"out\.toml: is a folder, not a file name")


IRB_URDF = Path("/work/shared/data/irb4600/urdf/irb4600_60_205.urdf")


def _irb_with(t: Path, extra: str) -> Path:
    """The IRB 4600 URDF with ``extra`` joints, its meshes referenced in place."""
    if not IRB_URDF.is_file():
        pytest.skip("the IRB 4600 URDF is not here")
    text = IRB_URDF.read_text().replace('filename="../meshes/',
                                        f'filename="{IRB_URDF.parent.parent}/meshes/')
    return urdf(t, text.replace("</robot>", extra + "</robot>"), "irb.urdf")


def _irb_case(id_, extra, *needles):
    case(id_, lambda t: ["import-urdf", str(_irb_with(t, extra)), "-o", str(t / "irb.toml"),
                         "--no-regions"], r"irb\.urdf: ", *needles, absent=("irb.toml",),
         capped=True)


_irb_case("irb-loop-link5-to-link2",
          '<joint name="loop" type="revolute"><parent link="link_5"/><child link="link_2"/>'
          '<axis xyz="0 0 1"/><limit lower="-1" upper="1"/></joint>',
          "closed loop: link 'link_2' is the child of joints")
_irb_case("irb-missing-parent",
          '<link name="extra"><inertial><mass value="1"/></inertial></link>'
          '<joint name="j_extra" type="revolute"><parent link="link_9"/><child link="extra"/>'
          '<axis xyz="0 0 1"/><limit lower="-1" upper="1"/></joint>',
          "joint 'j_extra': parent link 'link_9' does not exist")


# Meshing: hopeless edge lengths and unit mistakes are refused before pytetwild runs.
def _mesh_case(id_, dims, args, *needles, **kw):
    case(id_, lambda t: ["mesh", str(box_stl(t, dims)), *args, "-o", str(t / "out.vtu")],
         r"box\.stl", *needles, absent=("out.vtu",), **kw)


_mesh_case("mesh-edge-1e-5", (0.1, 0.1, 0.1), ["--size", "1e-5"],
           r"edge 1e-05 m on a part of 0\.001 m\^3 gives about 8\.5e\+12 tetrahedra \(limit "
           r"2e\+06, about 1\.7e\+07 GB to mesh\): use an edge of at least 0\.0016 m",
           capped=True)
_mesh_case("mesh-edge-1e-4", (0.1, 0.1, 0.1), ["--size", "1e-4"], "tetrahedra", capped=True)
_mesh_case("mesh-edge-larger-than-part", (0.1, 0.1, 0.1), ["--size", "0.5"],
           r"edge 0\.5 m is larger than the part \(0\.1 m across\)", capped=True)
_mesh_case("mesh-units-mm-on-metres", (1.2, 0.3, 0.3), ["--units", "mm", "--size", "0.03"],
           r"edge 0\.03 m is larger than the part \(0\.0012 m across\)", capped=True)
_mesh_case("mesh-units-m-on-millimetres", (400.0, 50.0, 50.0), ["--size", "0.01"],
           "are the units right", capped=True)
_mesh_case("mesh-units-unknown", (0.1, 0.1, 0.1), ["--units", "furlong", "--size", "0.01"],
           "furlong")
case("mesh-size-negative", lambda t: ["mesh", str(box_stl(t)), "--size", "-1", "-o",
                                      str(t / "out.vtu")], "--size -1: must be > 0",
     absent=("out.vtu",))
case("mesh-garbage-stl", lambda t: ["mesh", str(_write(t / "g.stl", b"\x00\x01 not an stl" * 9)),
                                    "--size", "0.01", "-o", str(t / "out.vtu")], r"g\.stl",
     absent=("out.vtu",))
case("mesh-missing-file", lambda t: ["mesh", str(t / "no.stl"), "--size", "0.01", "-o",
                                     str(t / "out.vtu")], r"no\.stl", absent=("out.vtu",))
case("mesh-unsupported-extension", lambda t: ["mesh", str(_write(t / "p.step", b"ISO-10303")),
                                              "--size", "0.01", "-o", str(t / "out.vtu")],
     r"p\.step", absent=("out.vtu",))


# Outputs onto folders, unreadable meshes.
case("modal-csv-is-folder", lambda t: ["modal", str(box_vtu(t)), "-n", "2", "--csv",
                                       str(_mkdir(t / "modes.csv"))],
     r"modes\.csv: is a folder, not a file name")
case("reduce-output-is-folder", lambda t: [
    "reduce", str(box_vtu(t)), "--interface", "root:0,0.025,0.025,1,0,0,0.05,0.001",
    "--method", "guyan", "-o", str(_mkdir(t / "se.h5"))], r"se\.h5: is a folder, not a file name")
case("mesh-output-is-folder", lambda t: ["mesh", str(box_stl(t)), "--size", "0.05", "-o",
                                         str(_mkdir(t / "out.vtu"))],
     r"out\.vtu: is a folder, not a file name")
case("reduce-mtx-onto-file", lambda t: [
    "reduce", str(box_vtu(t)), "--interface", "root:0,0.025,0.025,1,0,0,0.05,0.001",
    "--method", "guyan", "-o", str(_write(t / "se.mtx", b"my notes"))],
    r"se\.mtx: Not a directory")
case("reduce-mtx-onto-other-folder", lambda t: [
    "reduce", str(box_vtu(t)), "--interface", "root:0,0.025,0.025,1,0,0,0.05,0.001",
    "--method", "guyan", "-o", str(_write(_mkdir(t / "se.mtx") / "keep.txt", b"x").parent)],
    r"se\.mtx: Directory not empty")
case("modal-mesh-garbage", lambda t: ["modal", str(_write(t / "m.vtu", b"<VTKFile garbage"))],
     r"m\.vtu")
case("modal-mesh-missing", lambda t: ["modal", str(t / "none.vtu")], r"none\.vtu")

# Numbers typed on the command line: one module of cases, registered with case() above.
from . import hostile_numbers  # noqa: E402, F401


def _last_error(err: str, command: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert "Traceback" not in err and 'File "' not in err, err
    errors = [ln for ln in lines if ": error: " in ln]
    assert len(errors) == 1 and lines[-1] == errors[0], err
    assert errors[0].startswith(f"flexarm {command}: error: "), errors[0]
    return errors[0]


@pytest.mark.parametrize("build, code, needles, absent, capped", CASES)
def test_hostile_input_gives_one_clear_line(tmp_path, capsys, build, code, needles, absent,
                                            capped):
    argv = build(tmp_path)
    before = set(tmp_path.rglob("*"))
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    t0 = time.perf_counter()
    assert main(argv) == code
    elapsed = time.perf_counter() - t0
    line = _last_error(capsys.readouterr().err, argv[0])
    for needle in needles:
        assert re.search(needle, line), (needle, line)
    for name in absent:
        assert not (tmp_path / name).is_file(), name
    left = {p for p in set(tmp_path.rglob("*")) - before if "cache" not in p.parts}
    assert not [p for p in left if ".part" in p.name], left
    if capped:
        grown = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024 - rss0
        assert elapsed < TIME_CAP_S and grown < MEMORY_CAP_MB, (elapsed, grown)


def test_there_are_at_least_100_named_cases():
    assert len(CASES) >= 100, len(CASES)


# --- OS faults, interrupts and bugs ----------------------------------------------------
@pytest.fixture()
def read_only(monkeypatch):
    """Make folders read-only for this process (root ignores permission bits): creating a
    file in one raises the PermissionError the OS would."""
    import tempfile

    folders, real = [], tempfile.mkstemp

    def mkstemp(*args, dir=None, **kwargs):
        if dir is not None and Path(dir).resolve() in folders:
            raise PermissionError(13, "Permission denied", str(dir))
        return real(*args, dir=dir, **kwargs)

    monkeypatch.setattr(tempfile, "mkstemp", mkstemp)
    return lambda folder: folders.append(_mkdir(folder).resolve()) or folder


@pytest.mark.parametrize("argv, target", [
    (lambda t: ["mesh", str(box_stl(t)), "--size", "0.05", "-o", str(t / "ro" / "out.vtu")],
     "out.vtu"),
    (lambda t: ["modal", str(box_vtu(t)), "-n", "2", "--csv", str(t / "ro" / "m.csv")], "m.csv"),
    (lambda t: ["reduce", str(box_vtu(t)), "--interface", "root:0,0.025,0.025,1,0,0,0.05,0.001",
                "--method", "guyan", "-o", str(t / "ro" / "se.h5")], "se.h5"),
    (lambda t: ["import-urdf", str(urdf(t, GOOD_URDF)), "-o", str(t / "ro" / "r.toml"),
                "--no-regions"], "r.toml"),
], ids=["mesh", "modal-csv", "reduce", "import-urdf"])
def test_read_only_output_folder(tmp_path, capsys, read_only, argv, target):
    folder = read_only(tmp_path / "ro")
    assert main(argv(tmp_path)) == 2
    line = _last_error(capsys.readouterr().err, argv(tmp_path)[0])
    assert line.endswith(f"{folder}: Permission denied"), line
    assert list(folder.iterdir()) == []


def test_interrupt_exits_130_and_leaves_nothing(tmp_path, capsys, monkeypatch):
    from flexarm.fe import files

    def interrupted_write(path, mesh):  # Ctrl-C in the middle of writing the output
        with files.atomic_path(path) as tmp:
            tmp.write_bytes(b"half")
            raise KeyboardInterrupt

    monkeypatch.setattr("flexarm.meshes.write_volume_mesh", interrupted_write)
    out = tmp_path / "out.vtu"
    assert main(["mesh", str(box_stl(tmp_path)), "--size", "0.05", "-o", str(out)]) == 130
    assert capsys.readouterr().err.splitlines()[-1] == "flexarm mesh: interrupted"
    assert not out.exists() and not list(tmp_path.glob(".*part*"))


def test_a_bug_is_one_line_and_verbose_shows_its_traceback(tmp_path, capsys, monkeypatch):
    def broken(*args, **kwargs):
        raise TypeError("unsupported operand type(s) for +: 'int' and 'str'")

    monkeypatch.setattr("flexarm.studies.part_modes.part_modes", broken)
    argv = ["modal", str(box_vtu(tmp_path)), "-n", "2"]
    assert main(argv) == 1
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert line.startswith("flexarm modal: internal error: TypeError: unsupported operand")
    assert "a bug in flexarm: run with -v for the traceback" in line
    with pytest.raises(TypeError):
        main(["-v", *argv])


# --- fuzzing of the readers ------------------------------------------------------------
hypothesis = pytest.importorskip("hypothesis")
st = hypothesis.strategies
FUZZ = hypothesis.settings(max_examples=120, deadline=2000, derandomize=True,
                           suppress_health_check=[hypothesis.HealthCheck.too_slow])
#: What a mutation may insert: separators, quotes, digits, signs, letters, brackets, junk.
ALPHABET = ",;\t\"'#=[]{}.-+eE0123456789 xyzqnaNinf_\n\x00\xff\u00b5"


@st.composite
def mutated(draw, text: str) -> str:
    """``text`` after 1-4 random edits: delete, insert, replace or duplicate a span or a
    line, or truncate (what a broken export or a bad hand edit does)."""
    for _ in range(draw(st.integers(1, 4))):
        lines = text.splitlines(keepends=True)
        kind = draw(st.sampled_from(["delete", "insert", "line", "duplicate", "truncate"]))
        i = draw(st.integers(0, max(len(text) - 1, 0)))
        if kind == "delete":
            text = text[:i] + text[i + draw(st.integers(1, 12)):]
        elif kind == "insert":
            text = text[:i] + draw(st.text(ALPHABET, min_size=1, max_size=8)) + text[i:]
        elif kind == "line" and lines:
            k = draw(st.integers(0, len(lines) - 1))
            lines[k] = draw(st.text(ALPHABET, max_size=40)) + "\n"
            text = "".join(lines)
        elif kind == "duplicate" and lines:
            k = draw(st.integers(0, len(lines) - 1))
            text = "".join(lines[:k + 1] + [lines[k]] + lines[k + 1:])
        else:
            text = text[:i]
    return text


def _reads_or_refuses(read, path: Path, text: str) -> None:
    """``read(path)`` of ``text`` returns, or raises a ReadError naming the file."""
    from flexarm.fe.errors import ReadError

    path.write_bytes(text.encode("utf-8", "surrogatepass"))
    try:
        read(path)
    except ReadError as exc:
        assert str(path) in str(exc), exc


@pytest.fixture(scope="module")
def fuzz_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


@FUZZ
@hypothesis.given(data=st.data())
def test_fuzzed_measurement_csv_never_escapes(fuzz_dir, data):
    from flexarm.validation import read_measurements

    text = data.draw(mutated(STATIC.read_text()))
    _reads_or_refuses(read_measurements, fuzz_dir / "m.csv", text)


@FUZZ
@hypothesis.given(data=st.data())
def test_fuzzed_robot_toml_never_escapes(fuzz_dir, data):
    from flexarm.robot.formats import read

    base = (DEMO.read_text().replace('mesh = "meshes/', f'mesh = "{DEMO.parent}/meshes/')
            .replace('= "tets/', f'= "{DEMO.parent}/tets/'))
    _reads_or_refuses(read, fuzz_dir / "robot.toml", data.draw(mutated(base)))


@FUZZ
@hypothesis.given(data=st.data())
def test_fuzzed_rapid_module_never_escapes(fuzz_dir, data):
    from importlib.resources import files

    from flexarm.robot.formats.rapid import read_rapid

    base = files("flexarm.data.rapid").joinpath("ldbb_thesis.mod").read_text()
    _reads_or_refuses(read_rapid, fuzz_dir / "p.mod", data.draw(mutated(base)))


# --- measurement files at scale --------------------------------------------------------
@pytest.mark.parametrize("unit", ["mm", "um", "m", "kN", "deg", "mrad", "in"])
def test_vectorised_column_parse_is_bit_for_bit_the_exact_parser(unit):
    import numpy as np

    from flexarm.validation.data.units import QUANTITIES, parse_values
    from flexarm.validation.data.units import parse_decimal_column as _reals

    factor = next(f for units in QUANTITIES.values() for u, f in units.items() if u == unit)
    rng = np.random.default_rng(7)
    values = rng.normal(size=3000) * 10.0 ** rng.integers(-6, 4, 3000)
    texts = ([f"{v:.{d}f}" for v, d in zip(values[:1000], rng.integers(0, 12, 1000), strict=True)]
             + [repr(float(v)) for v in values[1000:2000]]  # exponents where Python puts them
             + [f"{v:.6e}" for v in values[2000:]] + ["0", "-0", ".5", "5.", "+1"])
    for column in (texts[:1000] + texts[-5:], texts):  # plain decimals; with exponents
        fast = _reals(column, factor)
        assert fast is not None and fast.tobytes() == parse_values(column, factor).tobytes()
    assert _reals(["1", "1_0"], factor) is None and _reals(["1", "nan"], factor) is None
    assert _reals(["1", ""], factor) is None and _reals(["1", "\u0661"], factor) is None


def test_twenty_thousand_static_rows_are_read_column_by_column(tmp_path, monkeypatch):
    """A large clean file is split by the byte scan and every column converted in bulk:
    neither the line-by-line reader nor the cell-by-cell parser runs (17 s for 1e5 rows
    before; the time itself is ``benchmarks/io.py``'s, not a test's)."""
    import numpy as np

    from flexarm.validation import read_measurements
    from flexarm.validation.data import decimals
    from flexarm.validation.data.formats import _cells

    head = [ln for ln in STATIC.read_text().splitlines()
            if ln.startswith("#") or ln.startswith("series")]
    d = np.random.default_rng(0).normal(size=(20_000, 3)) * 0.05
    d[::10] = 0.0  # the reference reading of each series
    rows = [f"s{i // 10}, {i % 10}, 0, 52, -19, 12, -15, -11, 0, {20 * (i % 10)}, 0, "
            f"{a:.4f}, {b:.4f}, {c:.4f}, 0.015" for i, (a, b, c) in enumerate(d)]
    path = tmp_path / "big.csv"
    path.write_text("# Messung in µm-Auflösung\n" + "\r\n".join(head + rows) + "\r\n")

    def one_by_one(*args):
        raise AssertionError("read one by one")

    monkeypatch.setattr(_cells, "records", one_by_one)
    monkeypatch.setattr(decimals, "cell_text", one_by_one)
    data = read_measurements(path)
    assert data.disp.shape == (20_000, 3) and data.disp[5, 1] == float(f"{d[5, 1]:.4f}e-3")
