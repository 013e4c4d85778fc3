"""The FANUC M-20iA and the Universal Robots UR10 as their makers publish them
(``../shared/data/robots``, ROS-Industrial, BSD; read there, never copied), run through
the commands a user types: ``import-urdf --wall auto``, ``build``, then ``modes``,
``compliance``, ``compare-models`` and ``map`` with ``--model cb``.

:func:`run_robot` runs the chain once and keeps every command's exit code and output in
a :class:`RobotRun`, so one session-scoped fixture per robot serves every assertion;
tests that need the description skip where it is absent.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from .cli_run import run_cli

DATA = Path(__file__).resolve().parents[2] / "shared/data/robots"


@dataclass(frozen=True)
class Published:
    """One published robot: its URDF, datasheet ``mass`` [kg], the tet ``edge`` [m] its
    chain is built at and a bent ``pose`` [deg] inside its limits."""

    name: str
    urdf: Path
    mass: float
    edge: float
    pose: str = "0,20,-20,0,30,0"


#: The robots of issue 26, at the edge their seats were found for (the build refines the
#: mesh over a seat too small for it: :mod:`flexarm.robot.seat_mesh`).
ROBOTS = {
    "m20ia": Published("m20ia", DATA / "fanuc_m20ia/urdf/m20ia.urdf", 250.0, 0.03),
    "ur10": Published("ur10", DATA / "ur10/urdf/ur10.urdf", 28.9, 0.03),
}


@dataclass(frozen=True)
class RobotRun:
    """What the chain of commands gave: ``steps`` maps a command name to its (exit
    code, stdout, stderr); ``toml`` is the robot file written, ``folder`` where the
    outputs went."""

    robot: Published
    toml: Path
    folder: Path
    steps: dict = field(default_factory=dict)
    edge: float = 0.0
    hollowed: bool = True

    def out(self, step: str) -> str:
        """stdout of ``step``; fails the test, with its stderr, when the step failed or
        never ran (an earlier one failed)."""
        if step not in self.steps:
            ran = ", ".join(f"{k} ({v[0]})" for k, v in self.steps.items())
            pytest.fail(f"{self.robot.name}: {step} did not run (ran: {ran})")
        code, out, err = self.steps[step]
        if code != 0:
            pytest.fail(f"{self.robot.name}: {step} exited with {code}: {err.strip()}")
        return out


def require(name: str) -> Published:
    """The robot ``name``; skips the test where its description is absent."""
    robot = ROBOTS[name]
    if not robot.urdf.is_file():
        pytest.skip(f"no published {name} description at {robot.urdf}")
    return robot


def run_robot(name: str, folder: Path, *import_options: str, edge: float | None = None,
              hollowed: bool = True) -> RobotRun:
    """Import (``--total-mass``, ``--wall auto`` unless not ``hollowed``, and
    ``import_options``), build and analyse robot ``name`` in ``folder`` at ``edge`` [m]
    (default: the robot's); stops at the first command that fails."""
    robot = require(name)
    edge = robot.edge if edge is None else edge
    toml = folder / f"{name}.toml"
    h = ["--mesh-size", str(edge)]
    at = [*h, "--pose", robot.pose]
    wall = ["--wall", "auto"] if hollowed else []
    chain = {
        "import-urdf": ["import-urdf", str(robot.urdf), "--total-mass", str(robot.mass),
                        *wall, *import_options, "-o", str(toml)],
        "build": ["build", "--robot", str(toml), *h],
        "modes": ["modes", "--robot", str(toml), "--model", "cb", *at, "-n", "10"],
        "compliance": ["compliance", "--robot", str(toml), "--model", "cb", *at],
        "compare-models": ["compare-models", "--robot", str(toml), *h, "--poses",
                           f"{robot.pose};", "-o", str(folder / "compare")],
        "map": ["map", "--robot", str(toml), "--model", "cb", *at, "--n", "7",
                "--no-frequencies", "-o", str(folder / "map")],
    }
    steps = {}
    for step, args in chain.items():
        steps[step] = run_cli(args)
        if steps[step][0] != 0:
            break
    return RobotRun(robot, toml, folder, steps, edge, hollowed)


def mode_table(text: str) -> np.ndarray:
    """Frequencies [Hz] of the ``mode  freq_Hz ...`` table of ``flexarm modes``."""
    return np.array([float(f) for f in re.findall(r"^\s*\d+\s+(\d+\.\d+)\s", text,
                                                   flags=re.M)])


def pair_table(text: str) -> dict[str, list[str]]:
    """joint -> the fields of its row in the ``seat pairs`` table ``flexarm build``
    prints."""
    lines = text.splitlines()
    start = next(i for i, ln in enumerate(lines) if ln.startswith("seat pairs ("))
    return {ln.split()[0]: ln.split() for ln in lines[start + 2:] if ln.strip()}


def band(import_out: str) -> tuple[float, float]:
    """The first-mode band [Hz] the placeholder rule promises, as ``import-urdf`` prints it."""
    lo, hi = re.search(r"first E-model mode ([\d.]+)-([\d.]+) Hz at mid-workspace",
                       import_out).groups()
    return float(lo), float(hi)


def first_emodel_hz(toml: Path) -> float:
    """First E-model frequency [Hz] of the robot file at its mid-workspace pose."""
    import warnings

    from flexarm.assembly.analyses import natural_frequencies
    from flexarm.assembly.emodel import emodel
    from flexarm.robot import load_robot
    from flexarm.robot.placeholder_stiffness import mid_workspace_pose

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the placeholder stiffness: the subject here
        robot = load_robot(toml)
        q = mid_workspace_pose(robot.chain, robot.lower, robot.upper)
        return float(natural_frequencies(emodel(robot), q)[0])


@pytest.fixture(scope="session")
def m20ia_run(tmp_path_factory) -> RobotRun:
    """The M-20iA's chain, run once for the session."""
    return run_robot("m20ia", tmp_path_factory.mktemp("m20ia_run"))


@pytest.fixture(scope="session")
def ur10_coarse_run(tmp_path_factory) -> RobotRun:
    """The UR10's chain as published (solid hulls) at a 60 mm edge, run once for the
    session: the default suite's turn of the chain (five of its links go to fTetWild)."""
    return run_robot("ur10", tmp_path_factory.mktemp("ur10_coarse_run"), edge=0.06,
                     hollowed=False)


@pytest.fixture(scope="session")
def ur10_run(tmp_path_factory) -> RobotRun:
    """The UR10's chain, run once for the session."""
    return run_robot("ur10", tmp_path_factory.mktemp("ur10_run"))
