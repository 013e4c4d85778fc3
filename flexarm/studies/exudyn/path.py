"""The loaded circle in time: the arm's Exudyn model moving along a RAPID path.

The model is built at the path's first pose with gravity on.  Every joint is driven
through its gear spring: before each step the spring's rest rotation about the joint
axis is set to the programmed joint angle minus the start angle (joint angles from the
IK of the sampled path, timed by the programmed speed along the path), so the motors
follow the program exactly and the links lag through the springs and their own
flexibility.  The bar force acts at the load point (a rigid lever from the TCP marker)
along the nominal bar direction.  As on the real test stand, the arm first holds still at
the first pose for ``HOLD`` seconds while gravity settles and the bar force is ramped in
smoothly over ``RAMP`` seconds; then it moves.  The deviation is the load point's
position with the bar force minus the same run without it, as in the quasi-static
:func:`~flexarm.studies.contact.ball_bar.predict_circle` (gravity sag and the motion
itself cancel).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...assembly.arm import Arm
from ...fe.typing import FloatArray
from ...robot.kinematics import link_frames, tcp_frame
from ..contact.ball_bar import CircleSetup, predict_circle
from .model import ExudynArm, _exudyn, exudyn_arm, simulation_settings

__all__ = ["PathRun", "path_run", "path_times", "rapid_speed", "exudyn_circle"]

log = logging.getLogger(__name__)

#: Seconds the arm holds still at the first pose before it moves [s].
HOLD = 2.0
#: Seconds over which the bar force is ramped in (a half cosine) [s].
RAMP = 1.0


@dataclass(frozen=True, eq=False)
class PathRun:
    """A loaded circle run in time next to the quasi-static prediction.

    Attributes
    ----------
    setup : CircleSetup
    speed : float
        Programmed speed along the path [m/s].
    force : float
        Bar force [N] (sign: + pushes the load point away from the pivot).
    t : (n,) float
        Time of each path sample [s].
    deviation : (n, 3) float
        Load-point deviation caused by the bar force, base frame [m] (Exudyn, in time).
    quasi_static : (n, 3) float
        The same from :func:`~flexarm.studies.contact.ball_bar.predict_circle` [m].
    seconds : float
        Wall time of both Exudyn runs [s].
    """

    setup: CircleSetup
    speed: float
    force: float
    t: FloatArray
    deviation: FloatArray
    quasi_static: FloatArray
    seconds: float

    @property
    def bar(self) -> FloatArray:
        """(n,) bar-length change [m]: Exudyn."""
        return self.setup.along_bar(self.deviation)

    @property
    def bar_static(self) -> FloatArray:
        """(n,) bar-length change [m]: quasi-static."""
        return self.setup.along_bar(self.quasi_static)

    @property
    def error(self) -> float:
        """Largest difference of the deviation vectors over the largest quasi-static
        deviation [-]."""
        d = np.linalg.norm(self.deviation - self.quasi_static, axis=1).max()
        return float(d / np.linalg.norm(self.quasi_static, axis=1).max())

    def text(self) -> str:
        """One summary block (µm, s)."""
        return "\n".join([
            f"{self.setup.name} at {self.speed * 1e3:g} mm/s, bar force {self.force:g} N: "
            f"{self.t[-1]:.1f} s of motion in {self.seconds:.1f} s",
            f"bar-length change [µm]: Exudyn {self.bar.min() * 1e6:.2f} .. "
            f"{self.bar.max() * 1e6:.2f}, quasi-static {self.bar_static.min() * 1e6:.2f} .. "
            f"{self.bar_static.max() * 1e6:.2f}",
            f"largest difference of the deviation: {100 * self.error:.2f} % of its amplitude"])

    def write(self, folder) -> list[Path]:
        """``path_<name>.png``: bar-length change along the path, in time and quasi-static."""
        from ...fe.plotting import pyplot, save_figure

        plt = pyplot()
        fig, ax = plt.subplots(figsize=(7, 4))
        ax.plot(self.t, self.bar * 1e6, label=f"Exudyn, {self.speed * 1e3:g} mm/s")
        ax.plot(self.t, self.bar_static * 1e6, "--", label="quasi-static")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("bar-length change [µm]")
        ax.set_title(f"{self.setup.name}: bar force {self.force:g} N")
        ax.legend()
        ax.grid(True, alpha=0.3)
        return [save_figure(fig, Path(folder) / f"path_{self.setup.name}.png", dpi=100)]


def rapid_speed(module, name: str) -> float:
    """Programmed TCP speed [m/s] of procedure ``name``: its first motion's ``vNNN``
    speeddata (NNN mm/s).  Zones (``z100``) are not modelled: the path is the sampled
    programmed geometry.

    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> rapid_speed(read_rapid(THESIS_RAPID), "Path_20")
    1.0
    """
    import re

    motions = module.procedures[name].motions
    speed = motions[0].speed if motions else ""
    m = re.fullmatch(r"v(\d+(?:\.\d+)?)", str(speed).strip())
    if m is None:
        raise ValueError(f"procedure {name}: speed '{speed}' is not a vNNN speeddata; give "
                         "the speed explicitly")
    return float(m.group(1)) * 1e-3


def path_times(setup: CircleSetup, speed: float) -> FloatArray:
    """(n,) time [s] of each path sample at constant ``speed`` [m/s] along the path."""
    if speed <= 0:
        raise ValueError(f"speed must be > 0 m/s, got {speed}")
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(setup.points, axis=0),
                                                        axis=1))])
    return s / speed


def _drive(ea: ExudynArm, t_k: FloatArray, q: FloatArray, lever: FloatArray,
           f_dir: FloatArray):
    """Pre-step function setting the joints' rest rotations; force/torque functions.

    Simulation time ``t`` runs ``HOLD`` seconds ahead of the path time ``t_k``."""
    dq = q - q[0]

    def ramp(t):
        return 0.5 * (1 - np.cos(np.pi * min(t / RAMP, 1.0)))

    def interp(t, values):
        return np.array([np.interp(t - HOLD, t_k, v) for v in values.T])

    def pre_step(mbs, t):
        rot = interp(t, dq)
        for spring, a in zip(ea.joint_springs, rot, strict=True):
            mbs.SetObjectParameter(spring, "offset", [0.0, 0.0, 0.0, float(a), 0.0, 0.0])
        return True

    def force(mbs, t, v):
        return list(ramp(t) * interp(t, f_dir))

    def torque(mbs, t, v):
        return list(ramp(t) * np.cross(interp(t, lever), interp(t, f_dir)))

    return pre_step, force, torque


def _run(arm: Arm, setup: CircleSetup, t_k: FloatArray, f: float, dt: float,
         links) -> FloatArray:
    """(n, 3) load-point positions [m] at the sample times for bar force ``f`` [N]."""
    exu = _exudyn()
    import exudyn.itemInterface as eii

    q = setup.ik.q
    ea = exudyn_arm(arm, q[0], links=links)
    mbs = ea.mbs
    chain = arm.model.chain
    F = link_frames(chain, q)
    p_tcp = tcp_frame(chain, q, F)[:, :3, 3]
    lever = setup.points - p_tcp
    pre_step, force, torque = _drive(ea, t_k, q, lever, f * setup.bar_dirs)
    mbs.AddLoad(eii.LoadForceVector(markerNumber=ea.tcp_rigid_marker, loadVector=[0, 0, 0],
                                    loadVectorUserFunction=force))
    mbs.AddLoad(eii.LoadTorqueVector(markerNumber=ea.tcp_rigid_marker, loadVector=[0, 0, 0],
                                     loadVectorUserFunction=torque))
    pos = mbs.AddSensor(eii.SensorMarker(markerNumber=ea.tcp_rigid_marker, writeToFile=False,
                                         outputVariableType=exu.OutputVariableType.Position,
                                         storeInternal=True))
    rot = mbs.AddSensor(eii.SensorMarker(
        markerNumber=ea.tcp_rigid_marker, writeToFile=False, storeInternal=True,
        outputVariableType=exu.OutputVariableType.RotationMatrix))
    mbs.SetPreStepUserFunction(pre_step)
    mbs.Assemble()
    sims = simulation_settings()
    end = HOLD + float(t_k[-1])
    sims.timeIntegration.endTime = end
    sims.timeIntegration.numberOfSteps = max(1, int(np.ceil(end / dt)))
    # some numerical damping of the highest modes keeps the index-3 joints stable over
    # long runs (the trapezoidal rule drifts); the modes that matter have omega dt << 1
    sims.timeIntegration.generalizedAlpha.spectralRadius = 0.8
    sims.timeIntegration.verboseMode = 0
    # the light turning disc on its gear spring stalls Newton at ~1e-8 (round-off)
    sims.timeIntegration.newton.relativeTolerance = 1e-6
    sims.solution.file.write = False
    sims.solution.sensors.writePeriod = dt
    mbs.SolveDynamic(sims)
    P = np.asarray(mbs.GetSensorStoredData(pos), dtype=float)
    R = np.asarray(mbs.GetSensorStoredData(rot), dtype=float)[:, 1:].reshape(-1, 3, 3)
    r_local = R[0].T @ lever[0]  # the lever in the TCP marker's axes (rigid)
    p_load = P[:, 1:4] + R @ r_local
    return np.array([np.interp(t_k + HOLD, P[:, 0], p_load[:, i]) for i in range(3)]).T


def path_run(arm: Arm, setup: CircleSetup, speed: float, force: float, pull: bool = False,
             dt: float = 2e-3, links: list | None = None,
             progress: Callable[[str], None] | None = None) -> PathRun:
    """Run the circle ``setup`` at ``speed`` [m/s] with the bar force ``force`` [N] (pushing,
    or pulling with ``pull``) on the Exudyn model of ``arm``, and without it, with time
    step ``dt`` [s]; compare with the quasi-static prediction."""
    from .model import ffrf_links

    locked = [n for n, jm in zip(arm.model.joint_names, arm.model.joints, strict=True)
              if not np.isfinite(jm.torsion)]
    if locked:  # the drive acts through the gear spring
        raise ValueError(f"joints {', '.join(locked)} have rigid torsion: they cannot be "
                         "driven along a path through their gear springs")
    t_k = path_times(setup, speed)
    links = ffrf_links(arm, progress) if links is None else links
    f = -force if pull else force
    t0 = time.perf_counter()
    loaded = _run(arm, setup, t_k, f, dt, links)
    if progress:
        progress(f"{setup.name}: loaded run done, now without the bar force")
    free = _run(arm, setup, t_k, 0.0, dt, links)
    seconds = time.perf_counter() - t0
    qs = predict_circle(arm.model, setup, [force], pull=pull).deviation[0]
    log.info("path %s at %g m/s: %.1f s simulated in %.1f s", setup.name, speed, t_k[-1],
             seconds)
    return PathRun(setup, float(speed), float(f), t_k, loaded - free, qs, seconds)


def exudyn_circle(arm: Arm, rapid=None, proc: str = "Path_30", force: float = 200.0,
                  pull: bool = False, speed: float | None = None, step_mm: float = 5.0,
                  dt: float = 2e-3, progress: Callable[[str], None] | None = None) -> PathRun:
    """The loaded circle ``proc`` of RAPID module ``rapid`` (default: the thesis's
    appendix B) in time on the Exudyn model of ``arm``, at the programmed speed unless
    ``speed`` [m/s] is given; see :func:`path_run`."""
    from ...robot.formats.rapid import read_rapid
    from ..contact.ball_bar import rapid_circle
    from ..contact.loaded_circle import THESIS_RAPID

    module = read_rapid(THESIS_RAPID if rapid is None else rapid)
    if proc not in module.procedures:
        raise ValueError(f"procedure must be one of {', '.join(module.procedures)}, "
                         f"got '{proc}'")
    v = rapid_speed(module, proc) if speed is None else float(speed)
    setup = rapid_circle(arm.robot, module, proc, step_mm=step_mm)
    return path_run(arm, setup, v, force, pull, dt, progress=progress)
