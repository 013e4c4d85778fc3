"""Users' files whose content is wrong, through ``flexarm.cli.main``: each is refused with
exit code 2 and one error line naming the file, line, link or joint and the figure at
fault, with nothing written.

Three families: robot and link data before they become mass properties (the CAD surface
``flexarm mesh`` would refuse, implausible densities and masses, damping ratios, units of
a link that carries no joint), superelement files whose matrices no free link has (with
a valid checksum: written through flexarm's own writers), and measurement files with what
a lab gets wrong (a pose that moves inside a load series, a one-line FRF, a path far from
the programmed circle, a universal file cut short or holding NaN, no header row, a points
table that does not fit the arm).  The helpers and the one-line assertion are those of
:mod:`tests.cli.test_hostile`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import re
from pathlib import Path

import numpy as np
import pytest

from ..cli_run import run_cli
from .test_hostile import DEMO, STATIC, _last_error, _write, cell, robot, static_csv

CASES = []


def case(id_, build, *needles, absent=()):
    """``build(tmp) -> argv``; ``needles`` are regexes the error line must match;
    ``absent`` are outputs (relative to tmp) that must not exist afterwards."""
    CASES.append(pytest.param(build, needles, absent, id=id_))


# --- robot and link data ---------------------------------------------------------------
SHAFT = f"{DEMO.parent}/meshes/tube_shaft.stl"


def _robot_case(id_, edits, *needles, command="compliance", extra=()):
    case(id_, lambda t: [command, "--robot", str(robot(t, *edits)), *extra], *needles)


def _cad_case(id_, make_stl, *needles, command="compliance", extra=()):
    """The tube shaft's CAD replaced by ``make_stl(path)``."""
    def build(t):
        stl = t / f"{id_}.stl"
        make_stl(stl)
        return [command, "--robot", str(robot(t, (SHAFT, str(stl)))), *extra]
    case(id_, build, r"links\.tube_shaft\.mesh: ", *needles)


def _shaft():
    import trimesh

    return trimesh.load(SHAFT, force="mesh")


def _open_shaft(path):
    s = _shaft()
    keep = np.ones(len(s.faces), bool)
    keep[: len(s.faces) // 5] = False
    s.update_faces(keep)
    s.export(path)


def _touching_boxes(path):
    """Two 0.4 m boxes that share one edge: that edge has four faces."""
    import trimesh

    a, b = trimesh.creation.box((0.4, 0.4, 0.4)), trimesh.creation.box((0.4, 0.4, 0.4))
    b.apply_translation([0.4, 0.4, 0.0])
    trimesh.util.concatenate([a, b]).export(path)


def _flat(path):
    import trimesh

    pts = np.array([[0, 0, 0], [1.0, 0, 0], [1.0, 0.2, 0], [0, 0.2, 0]])
    trimesh.Trimesh(pts, [[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2]]).export(path)


def _no_faces(path):
    path.write_text("solid empty\nendsolid empty\n")


_DISC_UNITS = ('turning_disc.stl"\nunits = "m"', 'turning_disc.stl"\nunits = "{}"')
for unit, size in (("mm", "0.00016"), ("cm", "0.0016"), ("in", "0.00406")):
    _robot_case(f"link-units-{unit}-on-the-last-link",
                [(_DISC_UNITS[0], _DISC_UNITS[1].format(unit))],
                r"robot\.toml: links\.turning_disc\.units: the CAD is " + re.escape(size)
                + rf" m across with units='{unit}' but the robot reaches 2\.84 m")
_cad_case("link-cad-open", _open_shaft, r"open\.stl: the surface is open \(\d+ boundary edges")
_cad_case("link-cad-open-tets", _open_shaft, r"the surface is open \(\d+ boundary edges",
          extra=("--mass", "tets"))
_cad_case("link-cad-open-modes", _open_shaft, "the surface is open", command="modes")
_cad_case("link-cad-non-manifold", _touching_boxes,
          r"manifold\.stl: the surface is not manifold \(1 edge shared by more than two")
_cad_case("link-cad-zero-volume", _flat, r"volume\.stl: the surface encloses zero volume")
_cad_case("link-cad-no-faces", _no_faces, r"faces\.stl: the surface has no faces")
_RHO = ('material = "steel"', "material = {{ E = 2.1e11, nu = 0.3, rho = {} }}")
for label, rho, needle in (("zero", "0.0", r"0 kg/m\^3 is not a plausible density"),
                           ("grams-per-cc", "7.85", r"7\.85 kg/m\^3 is not a plausible density"),
                           ("huge", "7.85e6", r"7\.85e\+06 kg/m\^3 is not a plausible density"),
                           ("negative", "-7850.0", r"density must be >= 0 kg/m\^3, got -7850")):
    _robot_case(f"link-density-{label}", [(_RHO[0], _RHO[1].format(rho))],
                r"links\.tube_shaft\.material(\.rho)?: " + needle)
for label, mass, needle in (("1.9e9", "1.9e9", r"1\.9e\+09 kg is not a plausible lumped mass"),
                            ("inf", "inf", "inf kg is not a plausible lumped mass"),
                            ("nan", "nan", "must be >= 0 kg, got nan")):
    _robot_case(f"lumped-mass-{label}", [("mass = 19.0", f"mass = {mass}")],
                r"links\.frame\.lumped\.motor_gear_1\.mass", needle)
_robot_case("link-without-mass", [
    ('turning_disc.stl"\nunits = "m"\nmaterial = "steel"\n', 'turning_disc.stl"\nunits = "m"\n'
     'material = "steel"\n\n[[links.lumped]]\nname = "nothing"\nmass = 0.0\n'),
    ('mesh = "' + str(DEMO.parent) + '/meshes/turning_disc.stl"\n', "")],
    r"links\.turning_disc: the link has no mass \(no CAD solid, lumped masses 0 kg\)")
for label, old, new, needle in (
        ("negative", "damping_ratio = 0.03", "damping_ratio = -0.03",
         r"joints\.joint_1\.model\.damping_ratio must be in \[0, 1\), got -0\.03"),
        ("huge", "damping_ratio = 0.03", "damping_ratio = 30.0",
         r"joints\.joint_1\.model\.damping_ratio must be in \[0, 1\), got 30\.0"),
        ("nan", "damping_ratio = 0.03", "damping_ratio = nan",
         r"joints\.joint_1\.model\.damping_ratio must be in \[0, 1\), got nan"),
        ("emodel", "damping_ratio = 0.03\ntilt2", "damping_ratio = 1.5\ntilt2",
         r"joints\.joint_1\.emodel\.damping_ratio must be in \[0, 1\), got 1\.5"),
        ("base", "damping_ratio = 0.02", "damping_ratio = -0.2",
         r"base\.damping_ratio must be in \[0, 1\), got -0\.2")):
    _robot_case(f"damping-ratio-{label}", [(old, new)], needle)
_robot_case("joint-rpy-nan", [("rpy_deg = [0.0, 0.0, 0.0]", "rpy_deg = [nan, 0.0, 0.0]")],
            re.escape("joints.joint_1.rpy_deg must be finite, got [nan, 0.0, 0.0]"))
_robot_case("tool-rpy-nan", [("rpy_deg = [0.0, 90.0, 0.0]", "rpy_deg = [0.0, nan, 0.0]")],
            re.escape("tool.rpy_deg must be finite, got [0.0, nan, 0.0]"))
_robot_case("tool-xyz-inf", [("xyz = [0.15, 0.0, 0.0]", "xyz = [inf, 0.0, 0.0]")],
            re.escape("tool.xyz must be finite"))


# --- superelement files ------------------------------------------------------------------
@functools.lru_cache(maxsize=1)
def _bar():
    """A Craig-Bampton bar (0.4 m steel, two RBE2 ends, 4 modes): 16 DOF."""
    from flexarm.fe import MATERIALS, TetMesh
    from flexarm.reduction import CylinderRegion, reduce_part

    mesh = TetMesh.box((0.4, 0.04, 0.04), (8, 2, 2))
    ends = [CylinderRegion(n, (x, 0.02, 0.02), (1, 0, 0), 0.0, 0.04, 1e-6)
            for n, x in (("a", 0.0), ("b", 0.4))]
    return reduce_part(mesh, MATERIALS["steel"], ends, "rbe2", "cb", 4)


def _damaged(t: Path, name: str, **matrices) -> Path:
    """The bar with ``matrices`` (functions of the good one) written by flexarm's writer:
    its checksum is valid."""
    from flexarm.reduction import formats

    se = _bar()
    changed = {k: f(np.array(getattr(se, k))) for k, f in matrices.items()}
    return formats.write(t / name, dataclasses.replace(se, **changed))


def _nan(A):
    A[2, 3] = A[3, 2] = np.nan
    return A


def _mechanism(K):
    K[-1, :] = K[:, -1] = 0.0
    return K


def _swap(K):
    P = np.eye(len(K))
    P[[0, 1]] = P[[1, 0]]
    return P @ K @ P.T


_SE = {
    "nan-in-M": (dict(M=_nan), r"M holds 2 non-finite entries \(nan at row 3, column 4\)"),
    "M-negated": (dict(M=np.negative), r"M is not positive definite \(eigenvalues -3\.321"),
    "inf-in-K": (dict(K=lambda K: K + np.diag(np.full(len(K), np.inf))),
                 r"K holds 16 non-finite entries \(inf at row 1, column 1\)"),
    "K-negated": (dict(K=np.negative), r"K is not positive semi-definite \(omega\^2 = -"),
    "M-asymmetric": (dict(M=lambda M: M + np.triu(np.full_like(M, 1e-3), 1)),
                     r"M is not symmetric \(relative asymmetry \d\.\de-\d+, at most 1e-10\)"),
    "K-mechanism": (dict(K=_mechanism), r"K has 7 zero-energy modes, not the 6 rigid-body"),
    "M-in-grams": (dict(M=lambda M: 1000 * M), r"M holds 5024 kg but the file states 5\.024 kg"),
    "K-rows-swapped": (dict(K=_swap), r"the rigid-body motions of its boundary nodes strain K "
                                      r"\(relative residual \d\.\de-01"),
}
for label, (damage, needle) in _SE.items():
    case(f"se-{label}-show", lambda t, d=damage: ["show", str(_damaged(t, "bar.h5", **d))],
         r"bar\.h5: " + needle)
for label, ext in (("M-negated", "h5"), ("nan-in-M", "npz"), ("M-in-grams", "mtx"),
                   ("K-negated", "bdf")):
    damage, needle = _SE[label]
    case(f"se-{label}-convert-{ext}",
         lambda t, d=damage, e=ext: ["convert", str(_damaged(t, f"bar.{e}", **d)), "-o",
                                     str(t / "clean.h5")],
         rf"bar\.{ext}: " + needle, absent=("clean.h5",))


# --- measurement files -----------------------------------------------------------------
def _moved(rows, value="53", first=2, last=2):
    """Series c1_y with joint 2 at ``value`` from row ``first`` to ``last``."""
    for r in range(first, last + 1):
        rows[r][3] = value
    return rows


case("static-pose-moves-in-one-row", lambda t: ["compare", str(static_csv(t, _moved))],
     r"static\.csv, line \d+, column 'q2_deg': series 'c1_y' has other joint angles here "
     r"than on line \d+ \(53 instead of 52: a load series holds one pose")
case("static-pose-moves-for-good", lambda t: ["compare", str(static_csv(
    t, lambda rows: _moved(rows, "60", 3, 4)))], r"column 'q2_deg': series 'c1_y' .*60 "
     "instead of 52")
case("static-pose-moves-diagnose", lambda t: ["diagnose", str(static_csv(t, _moved))],
     r"static\.csv, line \d+, column 'q2_deg': series 'c1_y' has other joint angles")
case("static-wrist-moves", lambda t: ["compare", str(static_csv(t, cell(8, 7, "-10.5")))],
     r"column 'q6_deg': series 'c2_x' .*-10\.5 instead of 0")


def _frf_lines(t: Path, keep: int) -> Path:
    from flexarm.validation import example_path

    text = example_path("frf").read_text().splitlines()
    head = [ln for ln in text if ln.startswith("#") or ln.startswith("pose")]
    rows = [ln for ln in text if ln not in head and ln.strip()]
    yy = [r for r in rows if ", y, y, " in r][:keep]
    return _write(t / "frf.csv", "\n".join(head + yy + [r for r in rows if ", y, x, " in r])
                  .encode() + b"\n")


case("frf-one-line", lambda t: ["compare", str(_frf_lines(t, 1))],
     r"frf\.csv, line \d+, column 'freq_Hz': the FRF of pose 'c1', input y, output y has 1 "
     r"frequency line; comparing FRFs needs at least 3")
case("frf-two-lines", lambda t: ["compare", str(_frf_lines(t, 2))],
     r"frf\.csv, line \d+, .*has 2 frequency lines; comparing FRFs needs at least 3")


def _no_header(t: Path, example: str) -> Path:
    from flexarm.validation import example_path

    text = example_path(example).read_text().splitlines()
    return _write(t / f"{example}.csv", "\n".join(
        ln for ln in text if not ln.startswith(("series", "pose"))).encode() + b"\n")


for kind, first in (("static", "0, 0, 52"), ("frf", "0, 52, -19")):
    case(f"csv-no-header-{kind}", lambda t, k=kind: ["compare", str(_no_header(t, k))],
         rf"{kind}\.csv, line \d+: no header row: the first row that is not a comment holds "
         rf"numbers \({first}, \.\.\.\)")


def _circle_path(t: Path, centre=(1333.34, 47.78, 588.13), radius=155.0, typo=None) -> Path:
    rows = ["step, x_mm, y_mm, z_mm, f_N"]
    for k in range(12):
        a = 2 * math.pi * k / 12
        p = [centre[0] + radius * math.cos(a), centre[1] + radius * math.sin(a), centre[2]]
        if k == typo:
            p[0] *= 10
        rows.append(f"{k}, {p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}, {0 if k % 2 else 400}")
    return _write(t / "path.csv", ("\n".join(rows) + "\n").encode())


def _circle_case(id_, build, *needles):
    case(id_, lambda t: ["circle", "--loads", "0,400", "--step", "10", "--measured",
                         str(build(t)), "-o", str(t / "out")], *needles, absent=("out",))


_circle_case("path-10x-typo", lambda t: _circle_path(t, typo=3),
             r"path\.csv, step 3: the reading \(13333\.4, 202\.8, 588\.1\) mm lies 11846\.1 mm "
             r"from the programmed circle Path_30 \(centre \(1333\.3, 47\.8, 588\.1\) mm, radius "
             r"155\.0 mm; at most 10 mm\)")
_circle_case("path-another-circle", lambda t: _circle_path(t, radius=118.43,
                                                           centre=(1333.34, 47.78, 688.13)),
             r"path\.csv, step \d+: .* mm lies 10\d\.\d mm from the programmed circle Path_30")
_circle_case("path-smaller-radius", lambda t: _circle_path(t, radius=100.0),
             r"path\.csv, step \d+: .* lies 55\.0 mm from the programmed circle Path_30")


def _static_circle(t: Path) -> Path:
    from importlib.resources import files

    text = (files("flexarm") / "data" / "examples" / "circle_static_example.csv").read_text()
    lines = text.splitlines()
    k = next(i for i, ln in enumerate(lines) if ln.startswith("F400N,5,"))
    fields = lines[k].split(",")
    fields[13] = str(float(fields[13]) + 500.0)  # dz_mm: half a metre off
    lines[k] = ",".join(fields)
    return _write(t / "circle.csv", ("\n".join(lines) + "\n").encode())


_circle_case("path-static-schema-reading-off", _static_circle,
             r"circle\.csv, series 'F400N', step 5: the reading .* lies 50\d\.\d mm from the "
             "programmed circle Path_30")

# Universal files, written with pyuff itself (flexarm's pose mark in ID line 4).
P1 = "flexarm pose=P1 q_deg=0,52,-19,12,-15,-11"
P2 = "flexarm pose=P2 q_deg=0,0,66,0,-66,0"


def _uff(t: Path, name="lab.uff", lines=40, bad=None, poses=(P1, P2)) -> Path:
    """58 receptances (driving point y and cross x of node 1) at two poses."""
    pyuff = pytest.importorskip("pyuff")
    f = np.linspace(2.0, 80.0, lines)
    sets = []
    for mark in poses:
        for out in (2, 1):
            H = (1e-6 / (1 - (f / 30.0) ** 2 + 0.04j * f / 30.0)) * (1.0 if out == 2 else 0.2)
            sets.append(pyuff.prepare_58(
                func_type=4, rsp_node=1, rsp_dir=out, ref_node=1, ref_dir=2, data=H, x=f,
                abscissa_spacing=1, id1="receptance", id4=mark,
                abscissa_spec_data_type=18,
                ordinate_spec_data_type=8, orddenom_spec_data_type=13))
    path = t / name
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    if bad is not None:  # a value of the second set's first data line, as some tools print NaN
        text = path.read_text().splitlines(keepends=True)
        starts = [i for i, ln in enumerate(text) if ln.rstrip() == "    58"]
        k = starts[1] + 12
        first = text[k].split()[0]
        text[k] = text[k].replace(first, bad.rjust(len(first)), 1)
        path.write_text("".join(text))
    return path


def _cut(t: Path, keep: float) -> Path:
    path = _uff(t)
    data = path.read_bytes()
    return _write(path, data[: int(len(data) * keep)])


case("uff-truncated-in-last-frf", lambda t: ["compare", str(_cut(t, 0.9)), "--pose", "P1"],
     r"lab\.uff: the file ends inside dataset 4 \(type 58, pose 'P2', from line \d+\): no "
     r"closing '    -1' line, so the file is truncated there")
case("uff-truncated-after-first-pose", lambda t: ["compare", str(_cut(t, 0.55))],
     r"lab\.uff: the file ends inside dataset 3 \(type 58, pose 'P2', from line \d+\)")
case("uff-nan-as-windows-prints-it", lambda t: ["compare", str(_uff(t, bad="1.#QNAN"))],
     r"lab\.uff, dataset 2 \(type 58\): line \d+: '1\.#QNAN' is not a number")
case("uff-nan", lambda t: ["compare", str(_uff(t, bad="NaN"))],
     r"lab\.uff, dataset 2 \(type 58\), field 'data': 1 value not finite, the first at "
     r"frequency line 1 \(2 Hz\)")
case("uff-two-line-frf", lambda t: ["compare", str(_uff(t, lines=2))],
     r"lab\.uff, dataset 1 \(type 58\), field 'x': 2 frequency lines; an FRF needs at least "
     "3")


def _shapes_uff(t: Path, points: str | None) -> Path:
    """Two mode shapes at P1 on nodes 100 and 101 (55 sets), and a points table beside."""
    pyuff = pytest.importorskip("pyuff")
    path = t / "shapes.uff"
    sets = [pyuff.prepare_55(
        model_type=1, analysis_type=2, data_ch=2, spec_data_type=8, load_case=1, mode_n=m,
        freq=f, modal_damp_vis=0.02, node_nums=np.array([100, 101]), r1=np.zeros(2),
        r2=np.array([0.5, 1.0]) * (1 if m == 1 else -1), r3=np.array([0.1, 0.2]),
        id1="mode shape", id4=P1) for m, f in ((1, 9.0), (2, 14.0))]
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    if points is not None:
        _write(t / "shapes.points.csv", points.encode())
    return path


_POINTS = "node,link,x_mm,y_mm,z_mm\n100,1,87.5,0,0\n{}\n"
case("points-table-link-9", lambda t: ["compare", str(_shapes_uff(
    t, _POINTS.format("101,9,175,0,0")))],
    r"shapes\.points\.csv, line 3, column 'link': link 9 does not exist \(the arm has bodies "
    r"0\.\.6, 0 = base\)")
case("points-table-node-missing", lambda t: ["compare", str(_shapes_uff(
    t, _POINTS.format("102,1,175,0,0")))],
    r"shapes\.points\.csv: node 101 of shapes\.uff is not in it \(it has 100, 102\)")
case("points-table-text", lambda t: ["compare", str(_shapes_uff(
    t, _POINTS.format("101,1,abc,0,0")))],
    r"shapes\.points\.csv, line 3, column 'x_mm': 'abc' is not a number")


# --- the table ------------------------------------------------------------------------------
@pytest.mark.parametrize("build, needles, absent", CASES)
def test_a_bad_file_gives_one_line_and_writes_nothing(tmp_path, build, needles, absent):
    argv = build(tmp_path)
    before = set(tmp_path.rglob("*"))
    code, out, err = run_cli(argv)
    assert code == 2, (out, err)
    line = _last_error(err, argv[0])
    for needle in needles:
        assert re.search(needle, line), (needle, line)
    for name in absent:
        assert not (tmp_path / name).exists(), name
    left = {p for p in set(tmp_path.rglob("*")) - before if "cache" not in p.parts}
    assert not [p for p in left if ".part" in p.name], left


def test_there_are_at_least_40_named_cases():
    assert len(CASES) >= 40, len(CASES)


def test_the_shipped_files_still_load_without_a_warning(tmp_path, recwarn, caplog):
    """The demo arm, the examples and a good superelement pass every new check."""
    import logging

    from flexarm.reduction import formats
    from flexarm.validation import example_path, read_measurements

    with caplog.at_level(logging.WARNING):
        for argv in (["compliance", "--robot", str(DEMO)], ["show", str(formats.write(
                tmp_path / "bar.h5", _bar()))]):
            code, _, err = run_cli(argv)
            assert code == 0 and "warning" not in err, err
        for kind in ("static", "modal", "frf", "path"):
            read_measurements(example_path(kind))
        read_measurements(STATIC.parent / "circle_static_example.csv")
    assert not [r for r in caplog.records if r.levelno >= logging.WARNING]
    assert not [w for w in recwarn if "flexarm" in str(w.filename)]
