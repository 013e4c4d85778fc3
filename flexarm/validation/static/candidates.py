"""The library of candidate effects: signatures on the data, screening, load proposals.

A candidate is a named physical effect (:class:`~flexarm.robot.effects.Effect`)
with *amplitude* parameters that enter the predictions linearly (backlash width, extra
compliance, lost motion, tilt/base/wrist compliances) and at most one *shape* parameter
scanned on a grid (hardening threshold, hysteresis torque radius).  Its *signature* is
how the predictions change per unit amplitude.  Screening (:func:`screen`) measures,
in the GLS metric of the noise model,

* ``norm``: how much an effect of typical size moves the data (in noise units): below
  ``tol.untestable_norm`` the data cannot see it -> **untestable**;
* ``unique``: the share of the signature the current model cannot mimic,
  ``1 - |P s|^2 / |s|^2``: below ``tol.alias_share`` -> **aliased** with the current
  model's parameters;
* ``dchi2`` / ``dbic``: the exact chi-square gain of adding it to the linearised current
  model (a score test), best over the shape grid, and its BIC change.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...robot.effects import Effect
from ..tolerances import tol
from .fit import FitResult, Problem

__all__ = ["Candidate", "Screen", "library", "screen", "load_proposal", "scan_gain", "SCAN",
           "SCANNED"]

#: Typical sizes of amplitudes (signature scaling; untestable check).
TYPICAL = {"width": 1e-4, "lost": 1e-4, "compliance_tilt": 2e-8, "compliance_base": 2e-8,
           "wrist": 1e-6, "tool": 5e-8, "frame_rotation": 1e-2,
           "balancer": 0.1,  # balancer: fraction of the joint's gear stiffness
           "mass": 10.0, "loadcell": 0.02, "reflector": 0.02}
#: Readable names of the candidates without a joint.
LABELS = {"links": "link flexibility", "tool": "tool/adapter compliance",
          "frame": "measurement frame misalignment", "foundation": "anisotropic foundation",
          "loadcell": "load-cell force scale", "reflector": "measurement-point offset"}


@dataclass(frozen=True)
class Candidate:
    """A candidate effect: ``kind``, ``joint``, amplitude names/sizes and a shape grid."""

    kind: str
    joint: int | None
    amplitudes: tuple[str, ...]
    sizes: tuple[float, ...]
    grid_name: str | None = None
    grid: tuple[float, ...] = (np.nan,)

    @property
    def name(self) -> str:
        if self.kind == "mass":
            return f"mass_l{self.joint + 1}"
        return self.kind if self.joint is None else f"{self.kind}_j{self.joint + 1}"

    @property
    def label(self) -> str:
        if self.joint is None:
            return LABELS.get(self.kind, self.kind)
        return self.effect().label

    @property
    def n_params(self) -> int:
        return len(self.amplitudes) + (self.grid_name is not None)

    def effect(self, grid_value: float = np.nan, amplitudes=None) -> Effect:
        amps = np.zeros(len(self.amplitudes)) if amplitudes is None else amplitudes
        params = tuple(zip(self.amplitudes, map(float, amps), strict=True))
        if self.grid_name is not None:
            params += ((self.grid_name, float(grid_value)),)
        return Effect(self.kind, self.joint, params)


def library(problem: Problem) -> list[Candidate]:
    """All candidates for the arm of ``problem`` (shape grids from the data's torques)."""
    arm = problem.arm
    n = arm.chain.n_joints
    moving = ~problem.is_ref
    out: list[Candidate] = []
    for j in range(n):
        k = 1.0 / arm.joints[j].torsion
        tau = np.abs(problem.tau[moving, j]) if moving.any() else np.zeros(1)
        thr = np.unique(np.round(np.quantile(tau, np.linspace(0.1, 0.8, 8)), 1))
        thr = tuple(float(t) for t in thr if t > 0) or (1.0,)
        span = float(np.median([np.ptp(problem.tau[g, j]) for g in problem.groups]))
        radii = tuple(float(f * max(span, 1.0)) for f in (0.02, 0.05, 0.1, 0.2, 0.3, 0.45))
        out.append(Candidate("backlash", j, ("width",), (TYPICAL["width"],)))
        out.append(Candidate("hardening", j, ("extra",), (0.5 * k,), "threshold", thr))
        out.append(Candidate("hysteresis", j, ("lost",), (TYPICAL["lost"],), "radius", radii))
    for j in range(min(3, n)):
        out.append(Candidate("tilt", j, ("compliance",), (TYPICAL["compliance_tilt"],)))
    out.append(Candidate("base", None, ("compliance",), (TYPICAL["compliance_base"],)))
    out.append(Candidate("foundation", None, ("cx", "cy"), (TYPICAL["compliance_base"],) * 2))
    if n >= 6:
        out.append(Candidate("wrist", None, ("c45", "c46", "c56"), (TYPICAL["wrist"],) * 3))
    if getattr(problem, "flexible", None) is not None:
        out.append(Candidate("links", None, ("compliance",), (1.0,)))
    out += _measurement_candidates(problem)
    if getattr(problem, "n_modal", 0):  # what only vibration data can tell from the joints
        out += [Candidate("mass", j, ("mass",), (TYPICAL["mass"],)) for j in range(n)]
        out.append(Candidate("loadcell", None, ("scale",), (TYPICAL["loadcell"],)))
    return out


def _measurement_candidates(problem: Problem) -> list[Candidate]:
    """Tool/adapter compliance, the measurement frame, the measurement point's offset from
    the TCP and a balancer on each of the first three joints whose angle differs between
    series (it is a pose-dependent stiffness)."""
    from ...robot.effects import TOOL_PARAMS

    out = [Candidate("tool", None, TOOL_PARAMS, (TYPICAL["tool"],) * 6),
           # a scale of the frame is all the joint compliances scaled alike: not a candidate
           Candidate("frame", None, ("rx", "ry", "rz"), (TYPICAL["frame_rotation"],) * 3),
           Candidate("reflector", None, ("ox", "oy", "oz"), (TYPICAL["reflector"],) * 3)]
    angles = problem.data.q[problem.ref]
    for j in range(min(3, problem.arm.chain.n_joints)):
        if len(np.unique(np.round(angles[:, j], 6))) >= 2:
            k = TYPICAL["balancer"] * problem.arm.joints[j].torsion
            out.append(Candidate("balancer", j, ("kc", "ks"), (k, k)))
    return out


def signature(problem: Problem, effects, cand: Candidate, grid_value: float) -> np.ndarray:
    """(m, k) whitened change of every observation per unit amplitude (finite difference
    over the typical size; for ``links`` exactly flexible minus E-model prediction)."""
    f0 = problem.wpredict(list(effects) + [cand.effect(grid_value)])
    cols = []
    for a, size in enumerate(cand.sizes):
        amps = np.zeros(len(cand.amplitudes))
        amps[a] = size
        f1 = problem.wpredict(list(effects) + [cand.effect(grid_value, amps)])
        cols.append((f1 - f0) / size)
    return np.stack(cols, axis=-1)


@dataclass(frozen=True)
class Screen:
    """Screening result of one candidate against the current fit.

    ``start``: amplitudes a refit starts from (zeros, or the best of the nonlinear scan
    of :func:`scan_gain`)."""

    candidate: Candidate
    grid_value: float
    norm: float
    unique: float
    dchi2: float
    dbic: float
    columns: np.ndarray  # whitened, unit amplitude, projected off the current model
    start: tuple = ()
    modal: bool = False  # the data hold vibration data besides the static series


#: Multiples of a candidate's typical amplitudes the nonlinear scan tries.
SCAN = (0.1, 0.3, 1.0, 3.0, 10.0, 30.0)
#: Kinds whose amplitudes all lie above zero and change the arm's modes: with vibration
#: data a measured mode may pair only once their amplitude is large enough, which the
#: linearised score test cannot see.
SCANNED = ("tilt", "base", "foundation", "mass", "links", "wrist")
#: Scanned kinds whose amplitudes take either sign (a coupling of compliances moves the
#: frequencies only to second order at zero, so the score test cannot see its sign).
SIGNED = ("wrist",)


def scan_gain(problem: Problem, fit: FitResult, cand: Candidate, grid_value: float
              ) -> tuple[float, tuple]:
    """Largest fall of the chi-square (fixed cost of unpaired modes included) when
    ``cand`` joins the fitted model at multiples :data:`SCAN` of its typical amplitudes
    (each amplitude alone, and all together), and the amplitudes that give it; ``(0, ())``
    when nothing falls."""
    from .fit import try_wpredict

    best, start = 0.0, ()
    wy = problem.wy()
    sizes = np.asarray(cand.sizes, float)
    # every amplitude on its own, and all together
    patterns = [np.eye(len(sizes))[i] for i in range(len(sizes))]
    patterns += [np.ones(len(sizes))] if len(sizes) > 1 else []
    if cand.kind in SIGNED:
        patterns += [-p for p in patterns]
    for k, pattern in ((k, p) for p in patterns for k in SCAN):
        amps = k * sizes * pattern
        f, _ = try_wpredict(problem, list(fit.effects) + [cand.effect(grid_value, amps)])
        if f is None:
            continue
        r = wy - f
        gain = fit.chi2 - float(r @ r)
        if gain > best:
            best, start = gain, tuple(float(a) for a in amps)
    return best, start


def screen(problem: Problem, fit: FitResult, cand: Candidate) -> Screen:
    """Score test of adding ``cand`` to the linearised current model ``fit``."""
    X = fit.sensitivity
    r = fit.residual
    Q = np.zeros((len(r), 0))
    if X.size:
        U, sv, _ = np.linalg.svd(X, full_matrices=False)
        Q = U[:, sv > sv.max() * 1e-8] if sv.max() > 0 else Q
    best = None
    for g in cand.grid:
        S = signature(problem, fit.effects, cand, g)
        St = S * np.asarray(cand.sizes)
        norm = float(np.linalg.norm(St))
        R = St - Q @ (Q.T @ St)
        unique = float((R**2).sum() / max((St**2).sum(), np.finfo(float).tiny))
        if norm < 1e-12 or unique < 1e-12:
            gain = 0.0
        else:
            coef = np.linalg.lstsq(R, r, rcond=1e-10)[0]
            fitted = R @ coef
            gain = float(fitted @ fitted)
        if best is None or gain > best[3]:
            best = (g, norm, unique, gain, R)
    g, norm, unique, gain, R = best
    start = ()
    if getattr(problem, "n_modal", 0) and cand.kind in SCANNED:
        # the pairing of measured with model modes may change along the way, which the
        # linearised gain cannot see: the chi-square at scanned amplitudes can
        scanned, start = scan_gain(problem, fit, cand, g)
        gain = max(gain, scanned)
    dbic = gain - cand.n_params * np.log(fit.n_obs)
    return Screen(cand, g, norm, unique, gain, dbic, R, start,
                  bool(getattr(problem, "n_modal", 0)))


def status_of(s: Screen) -> str | None:
    """'untestable' / 'aliased' from the screening alone, or None (testable).

    Aliased: a small share of the signature is unique.  With vibration data a signature
    may be large in the frequencies, which the model's stiffnesses mimic, while its static
    part, which they do not, is what the data show: there a candidate stays testable when
    its unique part is large in noise units (``tol.alias_unique_norm``) or the residual
    projects on it enough to be accepted (``tol.delta_bic_accept``), and its refit's checks
    (trust, intervals) judge it."""
    if s.norm < tol.untestable_norm:
        return "untestable"
    if s.unique < tol.alias_share and not (
            s.modal and (np.sqrt(s.unique) * s.norm >= tol.alias_unique_norm
                         or s.dbic >= tol.delta_bic_accept)):
        return "aliased"
    return None


def load_proposal(problem: Problem, joint: int, kind: str, max_load: float | None = None,
                  extra_poses: dict | None = None) -> str:
    """Concrete extra loads that would make ``kind`` at ``joint`` testable.

    Backlash needs the joint torque to change sign within a series: at each measured
    pose and direction (+-x, +-y, +-z) the reversing load is ``F* = -tau_g / (dtau/dF)``;
    the smallest ``F*`` within the load range wins; if no measured pose allows it, the
    ``extra_poses`` (e.g. the robot's named poses) are tried.  Hysteresis needs load/unload
    cycles in the direction that loads the joint most.
    """

    arm = problem.arm
    F_max = max_load or max(800.0, float(np.abs(problem.data.force).max()))
    poses = {str(problem.data.series[g[0]]).split("_")[0]: problem.data.q[g[0]]
             for g in problem.groups}
    best = _search(arm, joint, kind, poses, F_max)
    if best is None and extra_poses:
        best = _search(arm, joint, kind, {k: np.asarray(v, float) for k, v in
                                          extra_poses.items() if k not in poses}, F_max)
    if best is None:
        return (f"no load up to {F_max:.0f} N at the measured poses reverses joint {joint + 1}'s "
                f"torque: measure at a pose where its gravity torque is small")
    _, pname, sign, axis, f_star = best
    d = ("-" if sign < 0 else "+") + "xyz"[axis]
    if kind == "hysteresis":
        return (f"add load/unload cycles 0 -> {F_max:.0f} -> 0 N along {d} at pose {pname} "
                f"(flexarm lab --cycles)")
    top = min(F_max, 100 * np.ceil(1.6 * f_star / 100))
    return (f"add loads 0:{top:.0f}:100 N along {d} at pose {pname}: joint {joint + 1}'s "
            f"torque changes sign near {f_star:.0f} N")


def _search(arm, joint, kind, poses, F_max):
    from ...assembly.statics import joint_moments

    best = None
    for pname, q in poses.items():
        tau_g = joint_moments(arm, q, np.zeros(3))[joint, 0]
        for axis in range(3):
            unit = np.zeros(3)
            unit[axis] = 1.0
            dtau = joint_moments(arm, q, unit, gravity=False)[joint, 0]
            for sign in (1.0, -1.0):
                slope = sign * dtau
                if kind == "hysteresis":
                    score = -abs(slope)
                    if best is None or score < best[0]:
                        best = (score, pname, sign, axis, F_max)
                elif abs(slope) > 0 and -tau_g / slope > 0:
                    f_star = -tau_g / slope
                    if f_star <= F_max and (best is None or f_star < best[0]):
                        best = (f_star, pname, sign, axis, f_star)
    return best
