"""A Python script that builds the arm's Exudyn model (``flexarm export-exudyn``).

The script names the robot, the arm model and the pose, builds the ``mbs`` through
:func:`~flexarm.studies.exudyn.model.exudyn_arm` (flexible links from the cache) and,
run as a program, lets the arm settle under gravity for a short time.  Engineers edit it:
add loads, sensors and a longer simulation.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...assembly.arm import ArmSpec
from ...fe.files import atomic_path
from ...fe.typing import ArrayLike

__all__ = ["exudyn_script", "write_exudyn_script"]

_TEMPLATE = '''"""Exudyn model of the flexarm arm {name!r} at pose {pose} ({label}).

Written by `flexarm export-exudyn`; needs `pip install flexarm[mbs]`.  Every flexible
link is an ObjectFFRFreducedOrder made from its superelement, every joint a
GenericJoint plus a RigidBodySpringDamper with the joint springs; SI units, base frame.
`ea.tcp_marker` is a position marker at the TCP for loads.
"""

import numpy as np
import exudyn as exu

from flexarm.assembly.arm import ArmSpec, build_arm
from flexarm.robot import load_robot
from flexarm.studies.exudyn.model import exudyn_arm

ROBOT = {robot!r}  # None: the built-in demo arm
SPEC = ArmSpec(model={model!r}, mass={mass!r}, mesh_size={mesh_size!r}, n_modes={n_modes!r},
               coupling={coupling!r})
Q_DEG = {q_deg!r}
GRAVITY = {gravity!r}  # [m/s^2], base frame

robot = load_robot(ROBOT)
arm = build_arm(robot, SPEC)
ea = exudyn_arm(arm, np.radians(Q_DEG), gravity=GRAVITY)
SC, mbs = ea.SC, ea.mbs

if __name__ == "__main__":
    sims = exu.SimulationSettings()
    sims.timeIntegration.endTime = 0.2
    sims.timeIntegration.numberOfSteps = 400
    sims.timeIntegration.verboseMode = 1
    mbs.SolveDynamic(sims)
    p = mbs.GetMarkerOutput(ea.tcp_marker, exu.OutputVariableType.Position)
    print("TCP moved by", np.round((p - ea.tcp_position) * 1e3, 4), "mm")
'''


def exudyn_script(robot_name: str, robot_path, spec: ArmSpec, q: ArrayLike, pose: str = "",
                  gravity: ArrayLike | None = (0.0, 0.0, -9.80665)) -> str:
    """The script's text: ``robot_path`` (None: the demo arm), the arm ``spec``, the pose
    ``q`` (n,) [rad] (named ``pose`` in the docstring) and ``gravity`` [m/s^2].

    Examples
    --------
    >>> text = exudyn_script("demo", None, ArmSpec("cb"), [0.0] * 6, "home")
    >>> "ObjectFFRFreducedOrder" in text and "Q_DEG = [0.0, 0.0" in text
    True
    """
    q_deg = [round(float(v), 12) for v in np.degrees(np.asarray(q, dtype=float))]
    return _TEMPLATE.format(
        name=robot_name, pose=pose or "q", label=spec.label,
        robot=None if robot_path is None else str(Path(robot_path).resolve()),
        model=spec.model, mass=spec.mass, mesh_size=spec.mesh_size, n_modes=spec.n_modes,
        coupling=spec.coupling, q_deg=q_deg,
        gravity=None if gravity is None else [float(v) for v in gravity])


def write_exudyn_script(path, *args, **kwargs) -> Path:
    """Write :func:`exudyn_script` ``(*args, **kwargs)`` to ``path`` atomically."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(exudyn_script(*args, **kwargs))
    return path
