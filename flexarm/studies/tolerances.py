"""Tolerances of the chatter models and of program compensation (``tol.<name>``)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Largest ``|P P^T - I|`` entry of user-given machining-plane axes (chatter model).
    plane_orthonormal: float = 1e-9
    #: Relative step above a candidate limit K_c b at which stability is re-checked.
    chatter_limit_probe: float = 1e-7
    #: Compensation: the fixed point has converged when no target's predicted deflection
    #: changes by more than this between iterations [m, rad].
    compensation_step: float = 1e-10
    #: Compensation: most fixed-point iterations before a target is reported unconverged.
    compensation_max_iter: int = 30
    #: Batched Newton IK: pose error [m, rad] at which a target is reached.
    ik_pose_error: float = 1e-11
    #: Batched Newton IK: iterations before a target is declared out of reach.
    ik_max_iter: int = 60
    #: Batched Newton IK: largest joint step per iteration [rad] (far seeds stay on branch).
    ik_max_step: float = 0.25
    #: Batched Newton IK: damping of ``J J^T`` [-], far below any real column, so that a
    #: singular Jacobian stays solvable.
    ik_damping: float = 1e-9
    #: Batched path IK: largest joint change between neighbouring samples [rad] before
    #: the path falls back to the sequential solver (a branch jump).
    ik_path_jump: float = 0.2
    #: Batched path IK: a joint this close to a quadrant boundary [rad] meets the
    #: configuration of either side (a target programmed on a boundary, q1 = 0 on the
    #: base x axis, crosses it by the milliradians a compensation turns the joints).
    conf_boundary: float = 1e-2
    #: Compensation limits: condition number of the scaled tool Jacobian above which a
    #: target is near a singularity (joint corrections blow up).
    singular_condition: float = 80.0
    #: Compensation limits: a law's jump along a path is reported when its extra joint
    #: rotation changes by this share of the law's width [-] (a backlash crossing its band).
    law_switch_share: float = 0.25
    #: Compensation limits: a law's extra rotation is moving between two samples when it
    #: changes by more than this share of the law's width [-].
    law_moving_share: float = 1e-3
    #: Compensation notes: a target used by several procedures is named when their loads
    #: ask for shifts further apart than this [m].
    shared_target_spread: float = 1e-6
    #: Compensation reports: a programmed path is a circle (radial deviation, polar plot)
    #: when one circle fits every sample within this share of its radius [-] (RAPID
    #: targets are printed to 1e-3 mm).
    circle_share: float = 1e-5


tol = Tolerances()
