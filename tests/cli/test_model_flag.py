"""``--model cb`` on every arm analysis, on the demo arm and on the imported IRB 4600.

Each command runs through :func:`flexarm.cli.main` as a user would type it.  Where a
command prints or writes numbers, the CB arm is held to two references:

* the E-model with the CB arm's own joints and the rigid-body mass properties of the same
  tet meshes: links only add compliance, so by Rayleigh's principle the CB first
  frequency is at most the E-model's and its 800 N Y deflection at least the E-model's;
* the full-FE arm (``--model full``, the unreduced links): within 0.5 %.

The imported IRB 4600 has one set of joints, so its ``--model emodel --mass tets`` *is*
that E-model.  The demo arm's ``--model emodel`` uses *equivalent* joints (bearing in
series with link bending, what a user identifies from measurements), which already hold
the links' compliance; its rigid-link reference is the bearing-joint E-model
(``emodel(..., equivalent=False)``), and its equivalent E-model must agree with CB.
"""

from __future__ import annotations

import contextlib
import csv
import io
import re

import numpy as np
import pytest

from flexarm.assembly.analyses import frf, natural_frequencies, tcp_compliance
from flexarm.assembly.emodel import emodel
from flexarm.assembly.maps import limits_map
from flexarm.cli import main
from flexarm.robot import load_robot
from flexarm.robot.description import pose_from_string

from ..irb4600 import COARSE, P1, import_irb

pytestmark = pytest.mark.filterwarnings("ignore:.*placeholder stiffness")

DEMO_MESH = 0.06  # [m] the demo arm's coarse flexible model (shared with tests/conftest.py)


def run(args: list[str]) -> str:
    """stdout of ``flexarm ARGS``; fails the test on a non-zero exit."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(args)
    assert code == 0, f"flexarm {' '.join(args)}: exit {code}\n{err.getvalue()}"
    return out.getvalue()


@pytest.fixture(scope="module", params=["demo", "irb4600"])
def arm(request, tmp_path_factory):
    """(robot/mesh options, pose, lab poses, robot, mesh size) of one robot."""
    if request.param == "demo":
        return ["--mesh-size", str(DEMO_MESH)], "P1", "P1,P2", load_robot(), DEMO_MESH
    toml, _, _ = import_irb(tmp_path_factory.mktemp("irb"))
    return (["--robot", str(toml), "--mesh-size", str(COARSE)], P1, f"{P1};0,0,66,0,-66,0",
            load_robot(toml), COARSE)


def rigid_links(arm):
    """The E-model with the flexible models' joints and tet-mesh mass properties, and q."""
    robot, mesh = arm[3], arm[4]
    return emodel(robot, "tets", mesh, equivalent=False), pose_from_string(robot, arm[1])


@pytest.fixture(scope="module")
def lab_csv(arm, tmp_path_factory):
    """A small virtual-lab file of the CB arm (compare and diagnose read it)."""
    opts, _, poses = arm[:3]
    path = tmp_path_factory.mktemp("lab") / "lab.csv"
    run(["lab", *opts, "--model", "cb", "--poses", poses, "--loads", "0:800:200",
         "--dirs", "y,z", "--noise", "10um", "-o", str(path)])
    return path


def frequencies(text: str) -> np.ndarray:
    """[Hz] of the ``mode freq_Hz ...`` table of ``flexarm modes``."""
    return np.array([float(f) for f in re.findall(r"^\s*\d+\s+(\d+\.\d+)\s", text, re.M)])


def deflection_y(text: str) -> float:
    """The 800 N Y deflection [mm] that ``flexarm compliance`` prints."""
    return float(re.search(r"deflection under 800 N \[mm\]:.*\by=\s*(-?[\d.]+)", text)[1])


def table(path) -> dict[str, np.ndarray]:
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


@pytest.mark.parametrize("command", ["modes", "compliance", "frf", "map", "chatter",
                                     "chatter-map", "circle", "lab", "compare", "diagnose"])
def test_every_arm_command_accepts_model_cb(arm, lab_csv, command, tmp_path):
    opts, pose, poses = arm[:3]
    extra = {"modes": ["--pose", pose], "compliance": ["--pose", pose],
             "frf": ["--pose", pose], "map": ["--n", "6"], "chatter": ["--pose", pose],
             "chatter-map": ["--n", "4"], "circle": [],
             "lab": ["--poses", poses, "--loads", "0:400:200", "--dirs", "y"],
             "compare": [str(lab_csv)], "diagnose": [str(lab_csv)]}[command]
    out = tmp_path / ("lab.csv" if command == "lab" else "out")
    flag = "--report" if command == "diagnose" else "-o"  # diagnose -o: the --apply TOML
    text = run([command, *extra, *opts, "--model", "cb", flag, str(out)])
    assert text.strip()
    written = [out] if out.is_file() else list(out.iterdir())
    assert written and all(p.stat().st_size > 0 for p in written)


def test_modes_cb_between_emodel_and_full(arm):
    opts, pose = arm[:2]
    f = {m: frequencies(run(["modes", *opts, "--model", m, "--mass", "tets", "--pose", pose,
                             "-n", "6"])) for m in ("emodel", "cb", "full")}
    rigid, q = rigid_links(arm)
    f_rigid = natural_frequencies(rigid, q)
    assert f["cb"][0] <= f_rigid[0] + 1e-3  # printed to 1e-3 Hz
    if any(j.emodel is not None for j in arm[3].joints):  # equivalent joints hold the links
        assert f["emodel"][0] == pytest.approx(f["cb"][0], rel=0.01)
    else:  # the E-model of the command line is the rigid-link one
        assert f["emodel"][:6] == pytest.approx(f_rigid[:6], abs=1e-3)
    assert np.abs(f["cb"][:6] / f["full"][:6] - 1).max() < 0.005


def test_compliance_cb_between_emodel_and_full(arm):
    opts, pose = arm[:2]
    dy = {m: deflection_y(run(["compliance", *opts, "--model", m, "--mass", "tets",
                               "--pose", pose])) for m in ("emodel", "cb", "full")}
    rigid, q = rigid_links(arm)
    dy_rigid = 800.0 * tcp_compliance(rigid, q)[1, 1] * 1e3  # [mm]
    assert dy["cb"] >= dy_rigid - 1e-3  # printed to 1 µm
    assert dy["cb"] == pytest.approx(dy["full"], rel=0.005)


def test_frf_cb_static_receptance(arm, tmp_path):
    opts, pose = arm[:2]
    h = {}
    for m in ("cb", "full"):
        run(["frf", *opts, "--model", m, "--pose", pose, "-o", str(tmp_path / m)])
        t = table(tmp_path / m / "frf.csv")
        h[m] = t[next(k for k in t if k.startswith("re_Hyy"))][0]
        f_lo = t[next(k for k in t if k.lower().startswith("freq"))][0]
    rigid, q = rigid_links(arm)
    h_rigid = frf(rigid, q, [f_lo])[0, 1, 1].real  # the lowest frequency: quasi-static
    assert h["cb"] >= h_rigid
    assert h["cb"] == pytest.approx(h["full"], rel=0.005)


def test_map_cb_softer_than_rigid_links_everywhere(arm, tmp_path):
    opts, _, _, robot, _ = arm
    run(["map", *opts, "--model", "cb", "--pose", arm[1], "--n", "6", "-o", str(tmp_path)])
    t = table(tmp_path / "map.csv")
    rigid, q = rigid_links(arm)
    m = limits_map(rigid, q, robot.lower, robot.upper, 6)
    kyy = next(k for k in t if k.lower().startswith("kyy"))
    a, b = np.meshgrid(np.degrees(m.a), np.degrees(m.b), indexing="ij")
    assert t["q2_deg"] == pytest.approx(a.ravel()) and t["q3_deg"] == pytest.approx(b.ravel())
    assert np.all(t["f1_Hz"] <= m.freq_hz.ravel() * (1 + 1e-8))  # CSV: 10 digits
    assert np.all(t[kyy] * 1e3 <= m.stiffness[..., 1].ravel() * (1 + 1e-8))


def test_compare_models_defaults_to_the_robots_named_poses(arm, tmp_path):
    """P1..P3 on the demo arm; an imported robot has only its own ('home')."""
    opts, robot = arm[0], arm[3]
    text = run(["compare-models", *opts, "--no-full-fe", "-o", str(tmp_path)])
    expected = [p for p in ("P1", "P2", "P3") if p in robot.poses] or list(robot.poses)
    table = (tmp_path / "model_comparison.csv").read_text()
    assert all(f"\n{p}," in table for p in expected), table[:200]
    assert text.strip()


def test_every_arm_command_defaults_to_the_emodel():
    """One default model: a command that takes ``--model`` starts from the E-model."""
    from flexarm.cli import parser

    subs = next(a for a in parser()._subparsers._group_actions if a.dest == "command").choices
    defaults = {name: sub.get_default("model") for name, sub in subs.items()
                if any(a.dest == "model" for a in sub._actions)}
    assert {"show-arm", "export-exudyn", "exudyn-impulse", "modes"} <= set(defaults)
    assert set(defaults.values()) == {"emodel"}, defaults
