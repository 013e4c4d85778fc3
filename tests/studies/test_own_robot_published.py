"""Two robots as their makers publish them, start to finish: the FANUC M-20iA (closed
convex hulls that overlap at every joint) and the Universal Robots UR10 (its collision
``forearm.stl`` is an open surface), from ``../shared/data/robots`` (read there, never
copied; the tests skip where it is absent).

Default suite, at a coarse mesh (minutes cold for pytetwild, seconds from the test
cache): ``flexarm import-urdf`` with no hand repair, ``flexarm build`` and its seat-pair
check (every joint's two seats within 5 mm along the axis, at least 6 FE nodes a side),
``modes`` and ``compliance`` with ``--model cb``, and CB(10) against the full-FE arm on
the first 10 frequencies.  Slow: the same at each robot's own 30 mm mesh.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from flexarm.assembly.analyses import modes
from flexarm.assembly.arm import ArmSpec, build_arm
from flexarm.robot import load_robot
from flexarm.robot.description import pose_from_string

from ..cli_run import run_cli

pytestmark = pytest.mark.filterwarnings("ignore:.*placeholder stiffness")

DATA = Path(__file__).resolve().parents[3] / "shared/data/robots"
#: name -> (URDF, datasheet mass [kg], coarse tet edge [m] of the default suite)
ROBOTS = {
    "m20ia": (DATA / "fanuc_m20ia/urdf/m20ia.urdf", 250.0, 0.08),
    "ur10": (DATA / "ur10/urdf/ur10.urdf", 28.9, 0.04),
}
#: a bent pose [deg] inside both robots' limits
POSE = "0,20,-20,0,30,0"


_run = run_cli


def _import(name: str, folder: Path) -> tuple[str, Path, str, str]:
    urdf, mass, _ = ROBOTS[name]
    if not urdf.is_file():
        pytest.skip(f"no published {name} description at {urdf}")
    toml = folder / f"{name}.toml"
    code, out, err = _run(["import-urdf", str(urdf), "--total-mass", str(mass), "-o",
                           str(toml)])
    assert code == 0, err
    return name, toml, out, err


@pytest.fixture(scope="module", params=list(ROBOTS))
def imported(request, tmp_path_factory):
    return _import(request.param, tmp_path_factory.mktemp(request.param))


@pytest.fixture(scope="module", params=[pytest.param(name, marks=pytest.mark.slow)
                                        for name in ROBOTS])
def built(request, tmp_path_factory):
    """A robot whose tests build its links: the cold tetrahedralisation of the published
    CAD takes minutes on 2 cores (M-20iA about 3.5, UR10 about 6), so these run with
    ``-m slow``."""
    return _import(request.param, tmp_path_factory.mktemp(request.param + "_built"))


def pair_table(text: str) -> dict[str, list[str]]:
    """joint -> the fields of its row in the ``seat pairs`` table that build prints."""
    lines = text.splitlines()
    start = next(i for i, ln in enumerate(lines) if ln.startswith("seat pairs ("))
    return {ln.split()[0]: ln.split() for ln in lines[start + 2:] if ln.strip()}


def test_imports_as_published_with_every_seat(imported):
    name, toml, out, err = imported
    assert "Traceback" not in err and "Warning:" not in err
    assert all(line.startswith("warning: ") for line in err.splitlines() if line.strip())
    assert "bearing seats: 14 regions found on the link CAD, written out" in out
    assert "no bearing seat" not in err and "review = true" not in toml.read_text()
    seat_lines = [ln for ln in err.splitlines() if "closed surface" in ln]
    if name == "m20ia":  # closed hulls as published
        assert seat_lines == []
    else:  # the open forearm: one line, the user's file, the hull fallback stated
        (line,) = seat_lines
        assert line.startswith("warning: forearm.stl: not a closed surface (6 bodies, 1 open,")
        assert "replaced by its convex hull" in line and "'forearm_link'" in line
        assert ".ply" not in err


def test_build_pairs_every_joint_within_5_mm_on_6_nodes_a_side(built):
    name, toml, _, _ = built
    code, out, err = _run(["build", "--robot", str(toml), "--mesh-size",
                           str(ROBOTS[name][2])])
    assert code == 0, err
    assert "do not pair up" not in err and "review" not in err
    pairs = pair_table(out)
    joints = load_robot(toml).joint_names
    assert list(pairs) == list(joints)
    for joint, row in pairs.items():
        gap_mm, nodes_p, nodes_c = float(row[3]), int(row[5]), int(row[6])
        assert abs(gap_mm) < 5.0, (name, joint, row)
        assert min(nodes_p, nodes_c) >= 6, (name, joint, row)
        assert row[-1] == "ok", (name, joint, row)


def test_modes_and_compliance_with_cb(built):
    name, toml, _, _ = built
    h = str(ROBOTS[name][2])
    code, out, err = _run(["modes", "--robot", str(toml), "--model", "cb", "--mesh-size", h,
                           "--pose", POSE, "-n", "10"])
    assert code == 0, err
    f = np.array([float(v) for v in re.findall(r"^\s*\d+\s+(\d+\.\d+)\s", out, flags=re.M)])
    assert len(f) == 10 and np.all(np.diff(f) >= 0) and f[0] > 1.0
    code, out, err = _run(["compliance", "--robot", str(toml), "--model", "cb",
                           "--mesh-size", h, "--pose", POSE])
    assert code == 0, err
    assert out.startswith("TCP compliance, translations [mm/kN]")


def _cb_against_full_fe(toml: Path, h: float) -> np.ndarray:
    robot = load_robot(toml)
    q = pose_from_string(robot, POSE)
    f_cb = modes(build_arm(robot, ArmSpec("cb", mesh_size=h)).model, q).freq_hz[:10]
    f_fe = modes(build_arm(robot, ArmSpec("full", mesh_size=h, n_modes=12)).model,
                 q).freq_hz[:10]
    return np.abs(f_cb / f_fe - 1.0)


def test_cb_matches_the_full_fe_on_the_first_10_frequencies(built):
    name, toml, _, _ = built
    err = _cb_against_full_fe(toml, ROBOTS[name][2])
    assert err.max() < 1e-3, (name, err)


@pytest.mark.slow
@pytest.mark.parametrize("name", list(ROBOTS))
def test_at_the_robots_own_mesh(name, tmp_path):
    """30 mm: the mesh the seats were found for (about 15 min cold per robot)."""
    _, toml, _, _ = _import(name, tmp_path)
    code, out, err = _run(["build", "--robot", str(toml)])
    assert code == 0, err
    for joint, row in pair_table(out).items():
        assert abs(float(row[3])) < 5.0 and min(int(row[5]), int(row[6])) >= 6, (joint, row)
    assert _cb_against_full_fe(toml, load_robot(toml).options.mesh_size).max() < 1e-3
