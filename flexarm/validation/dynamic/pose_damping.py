"""Modal damping per pose: identified ratios stored in the robot file and used by the FRF.

``fit-damping --method modal`` keeps what was measured instead of fitting a joint law:
the damping ratios identified at each measured pose go into the robot's
``[modal_damping]`` table (:mod:`flexarm.robot.formats.toml_modal_damping`).  At a pose
whose joint angles match one of those poses, :func:`pose_damping` gives the model modes
matched to the stored frequencies (by frequency, :func:`~.modal.match_modes`) the stored
ratios, and every other mode its joint-law damping; :func:`damped_frf` is the TCP FRF
with them.  At any other pose nothing changes: a modal ratio belongs to the pose it was
measured at.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...assembly.analyses import frf, modes
from ...assembly.system import ArmModel
from ...fe.text import text_table
from ...fe.typing import ArrayLike, FloatArray, PathType
from ...robot.description import Robot
from ..data.formats import UffOptions, read_modal
from ..data.measurements import ModalData
from ..models import DEFAULT_OPTIONS, load, validation_models
from .modal import match_modes

__all__ = ["POSE_ATOL", "PoseDamping", "pose_of", "pose_damping", "damped_frf",
           "store_modal_damping"]

#: Joint angles within this of a stored pose's [rad] are that pose.
POSE_ATOL = 1e-6


def pose_of(robot: Robot, q: ArrayLike) -> str | None:
    """Name of the pose of ``robot.modal_damping`` at joint angles ``q`` [rad], or None.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> r = load_demo_robot()
    >>> r = replace(r, modal_damping={"P1": ((8.0,), (0.05,))})
    >>> pose_of(r, r.pose("P1")), pose_of(r, r.pose("P2"))
    ('P1', None)
    """
    q = np.asarray(q, float)
    for name in robot.modal_damping:
        if np.allclose(robot.pose(name), q[:len(robot.joints)], rtol=0.0, atol=POSE_ATOL):
            return name
    return None


def pose_damping(robot: Robot, arm: ArmModel, q: ArrayLike) -> FloatArray | None:
    """(n,) modal damping ratios [-] of every mode of ``arm`` at ``q``: the stored ones
    where ``q`` is a pose of ``robot.modal_damping`` (matched by frequency), the
    joint-law ones elsewhere; None when ``q`` is no such pose."""
    name = pose_of(robot, q)
    if name is None:
        return None
    md = modes(arm, q)
    freq, zeta = (np.asarray(v, float) for v in robot.modal_damping[name])
    k = match_modes(freq, md.freq_hz)
    out = np.array(md.damping, float)
    out[k[k >= 0]] = zeta[k >= 0]
    return out


def damped_frf(robot: Robot, arm: ArmModel, q: ArrayLike, freq_hz: ArrayLike):
    """TCP receptance (nf, 6, 6) of ``arm`` at ``q`` (:func:`~flexarm.assembly.analyses.frf`)
    with the stored modal damping of ``robot`` where ``q`` is one of its poses."""
    return frf(arm, q, freq_hz, pose_damping(robot, arm, q))


@dataclass(frozen=True, eq=False)
class PoseDamping:
    """Result of :func:`store_modal_damping`: the robot with ``[modal_damping]`` and the
    stored ratios next to what its joint damping gives at the same modes."""

    robot: Robot
    rows: tuple  # (pose, freq_hz, stored zeta, model zeta)
    added_poses: tuple = ()

    def text(self) -> str:
        """Table of the stored ratios per pose and mode, the model's ratio beside them."""
        lines = [text_table(["pose", "freq_Hz", "zeta_stored", "zeta_joints"],
                            [list(r) for r in self.rows], "{:.4g}")]
        if self.added_poses:
            lines.append("poses added to [poses] (joint angles from the data): "
                         + ", ".join(self.added_poses))
        lines.append(f"{len(self.rows)} modal damping ratios at "
                     f"{len(self.robot.modal_damping)} pose(s) stored in [modal_damping]; "
                     "the FRF at those poses uses them")
        return "\n".join(lines)


def store_modal_damping(data: ModalData | PathType, robot: Robot | PathType | None = None,
                        max_hz: float | None = None, pose: str | None = None) -> PoseDamping:
    """``robot`` with the damping ratios identified in ``data`` stored per pose.

    A data pose whose name is not among the robot's poses is added with the data's joint
    angles; a name the robot has with other angles is an error.  Rows without a ratio
    (NaN or <= 0) and modes above ``max_hz`` [Hz] are left out.
    """
    src = data if not isinstance(data, ModalData) else "modal data"
    robot = load(robot)
    if not isinstance(data, ModalData):  # a universal file without pose marks: at ``pose``
        data = read_modal(data, uff=UffOptions.at(robot, pose))
    if data.damping_ratio is None:
        raise ValueError(f"{src}: no 'damping_ratio' column: nothing to store")
    n = len(robot.joints)
    zeta = np.asarray(data.damping_ratio, float)
    f = np.asarray(data.freq_hz, float)
    keep = np.isfinite(zeta) & (zeta > 0) & (f <= (np.inf if max_hz is None else max_hz))
    poses, table, added, rows = dict(robot.poses), dict(robot.modal_damping), [], []
    arm = validation_models(robot, DEFAULT_OPTIONS).arm
    for name in dict.fromkeys(np.asarray(data.poses)[keep].tolist()):
        r = np.flatnonzero((np.asarray(data.poses) == name) & keep)
        r = r[np.argsort(f[r])]
        qs = np.asarray(data.q, float)[r, :n]
        q = qs[0]
        if not np.allclose(qs, q, rtol=0.0, atol=POSE_ATOL):
            raise ValueError(f"{src}: the rows of pose '{name}' hold different joint angles")
        if name in poses and not np.allclose(poses[name], q, rtol=0.0, atol=POSE_ATOL):
            raise ValueError(f"{src}: pose '{name}' has other joint angles than the robot's "
                             f"pose of that name")
        if name not in poses:
            poses[name] = q.tolist()
            added.append(name)
        table[name] = (tuple(f[r].tolist()), tuple(zeta[r].tolist()))
        md = modes(arm, q)
        k = match_modes(f[r], md.freq_hz)
        rows += [(name, fi, zi, md.damping[ki] if ki >= 0 else np.nan)
                 for fi, zi, ki in zip(f[r], zeta[r], k, strict=True)]
    if not table:
        raise ValueError(f"{src}: no mode with a damping ratio > 0"
                         + ("" if max_hz is None else f" up to {max_hz:g} Hz"))
    return PoseDamping(replace(robot, poses=poses, modal_damping=table), tuple(rows),
                       tuple(added))
