"""Joint angles along a sampled path, for every sample at once.

The motions' ends are solved with their programmed configuration, all from the first
one's solution in one batched Newton loop (:func:`~.ik_batch.newton_ik`); the samples
between them start from the joint-space interpolation of the ends.  Where a seed lands
on another branch (or nowhere) the target is solved alone by the closed form
(:func:`~flexarm.robot.ik_path.ik_conf`), and where the batched path jumps between
neighbours the sequential solver of :func:`~flexarm.robot.ik_path.ik_path` takes over.
"""

from __future__ import annotations

import logging

import numpy as np

from ....fe.typing import FloatArray, IntArray
from ....robot.ik import ik
from ....robot.ik_path import ik_conf, ik_path, rapid_conf, target_frames
from ....robot.kinematics import Chain
from ....robot.paths import SampledPath
from ...tolerances import tol
from .ik_batch import newton_ik

__all__ = ["batched_path_ik", "conf_met"]

log = logging.getLogger(__name__)


def conf_met(ch: Chain, q: FloatArray, confs: IntArray) -> np.ndarray:
    """(k,) bool: joint angles ``q`` (k, 6) [rad] have the RAPID configurations ``confs``
    (k, 4), a joint within :attr:`~flexarm.studies.tolerances.Tolerances.conf_boundary` of
    a quadrant boundary (or axis 5 of zero) meeting either side.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> ch = load_demo_robot().chain
    >>> q = np.radians([[10.0, 30, 0, -1e-9, 60, 0]])  # axis 4 at a boundary
    >>> conf_met(ch, q, [[0, 0, 0, 0]]).tolist(), conf_met(ch, q, [[0, -1, 0, 0]]).tolist()
    ([True], [True])
    """
    q = np.atleast_2d(np.asarray(q, dtype=float))
    want = np.atleast_2d(np.asarray(confs, dtype=np.int64))
    have = rapid_conf(ch, q)
    ok = have == want
    for col, j in ((0, 0), (1, 3), (2, 5)):
        a = q[:, j] / (np.pi / 2)
        m = np.round(a)
        near = np.abs(a - m) * (np.pi / 2) < tol.conf_boundary
        ok[:, col] |= near & ((want[:, col] == m) | (want[:, col] == m - 1))
    near5 = np.abs(q[:, 4]) < tol.conf_boundary
    ok[:, 3] |= near5 & ((have[:, 3] ^ want[:, 3]) == 1)
    return ok.all(axis=1)


def _anchor_q(ch: Chain, T: FloatArray, confs: IntArray, lower, upper) -> FloatArray:
    """(k, 6) joint angles of the frames ``T`` (k, 4, 4) with configurations ``confs``.

    All from the first one's solution at once; the few that land on another branch (or
    nowhere) are solved alone, nearest their predecessor when the configuration cannot
    be met.
    """
    first = ik_conf(ch, T[0], confs[0], lower, upper)
    if first is None:
        first = ik(ch, T[0], q_near=np.zeros(6), lower=lower, upper=upper)
    q, err = newton_ik(ch, T, np.repeat(first[None], len(T), axis=0))
    outside = np.any((q < lower) | (q > upper), axis=-1)
    bad = (err > tol.ik_pose_error) | outside | ~conf_met(ch, q, confs)
    for i in np.flatnonzero(bad):
        sol = ik_conf(ch, T[i], confs[i], lower, upper)
        if sol is None:
            sol = ik(ch, T[i], q_near=q[i - 1] if i else first, lower=lower, upper=upper)
        q[i] = sol
    return q


def batched_path_ik(ch: Chain, path: SampledPath, confs: IntArray, lower, upper) -> FloatArray:
    """(n, 6) joint angles [rad] along ``path``: the motions' ends with their programmed
    configuration, the samples between them by Newton steps from the joint-space
    interpolation of the ends.

    Falls back to :func:`~flexarm.robot.ik_path.ik_path` (sequential, continuous) when a
    sample is not reached or the batched solution jumps between neighbours.

    Raises
    ------
    UnreachableTargetError
        A target or the path out of reach (from the sequential solver).

    Examples
    --------
    >>> from dataclasses import replace
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.robot.ik_path import TOOL0
    >>> from flexarm.robot.kinematics import tcp_frame
    >>> from flexarm.robot.paths import sample_procedure
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> r = load_demo_robot()
    >>> proc = read_rapid(THESIS_RAPID).procedures["Path_30"]
    >>> path = sample_procedure(proc, step_mm=10)
    >>> ch = replace(r.chain, tool=TOOL0)
    >>> q = batched_path_ik(ch, path, np.array([m.to_point.conf for m in proc.motions]),
    ...                     r.lower, r.upper)
    >>> bool(np.abs(tcp_frame(ch, q)[:, :3, 3] * 1e3 - path.points_mm).max() < 1e-8)
    True
    """
    T = target_frames(path.points_mm, path.quats)
    seg = path.segments
    ends = np.flatnonzero(np.r_[seg[1:] != seg[:-1], True])
    try:
        q_end = _anchor_q(ch, T[ends], confs[seg[ends]], lower, upper)
    except ValueError:
        q_end = None
    if q_end is not None:
        # seeds: linear in joint space by sample index between consecutive ends
        x = np.arange(len(T), dtype=float)
        seed = np.column_stack([np.interp(x, ends, q_end[:, j]) for j in range(6)])
        q, err = newton_ik(ch, T, seed)
        q[ends] = q_end
        steps = np.abs(np.diff(q, axis=0)).max(axis=1) if len(q) > 1 else np.zeros(0)
        if err.max() <= tol.ik_pose_error and (steps.max(initial=0.0) <= tol.ik_path_jump):
            return q
    log.info("%s: batched IK left the branch; solving sample by sample", path.name)
    return ik_path(ch, path, confs, lower, upper, tool=ch.tool).q
