"""Test planning: the static series that best separate two to four standing hypotheses.

Each hypothesis is an effect in :func:`~flexarm.robot.effects.parse_effect` form
(``tilt:j1=1e7``, ``stiffness:j2=1.3``).  Its model is the baseline (one torsion scale
per joint, with the diagnosis' weak prior) plus that effect with its amplitudes free; the
torsion scale of a joint that some hypothesis names as ``stiffness`` is held at nominal
in the *other* hypotheses, so that "joint-2 torsion" and "joint-1 tilt" are two models
with their own parameters rather than one nested in the other.  Every hypothesis is
fitted to the data so far (GLS, :mod:`~flexarm.validation.static.fit`).

Candidate series are poses drawn inside the joint limits (TCP at least
``min_height`` above the base) times the six axis load directions, each loaded over
``loads`` (and unloaded with ``cycles``).  With truth ``a``, the planned series alone
give hypothesis ``b`` an expected excess chi-square (non-centrality)::

    lambda_ab = min_delta |W (p_a - p_b) - S_b delta|^2 (+ prior),

``p`` the noise-free predictions of the fitted hypotheses, ``S_b`` the whitened
sensitivities of ``b``'s free parameters (``b`` refitted to the new data) and ``W`` the
shared-reference GLS whitening the fit uses.  For hypotheses with as many parameters
this is the expected ΔBIC; the BIC penalty difference ``(k_b - k_a) ln n`` is added.
Series are chosen greedily, each maximising the smallest ``lambda_ab`` over ordered
pairs (ties: the sum).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...assembly.effects import resolve
from ...assembly.system import ArmModel
from ...fe.files import writes_folder
from ...fe.typing import ArrayLike, PathType
from ...robot.collision import CollisionChecker
from ...robot.description import Robot
from ...robot.effects import TOOL_PARAMS, Effect, parse_effect
from ...robot.kinematics import tcp_frame
from ..data.formats import read_static
from ..data.load_plan import parse_loads
from ..data.measurements import StaticData
from ..models import DEFAULT_OPTIONS, ValidationOptions, load, validation_models
from ..static.fit import Problem, baseline_effects, fit_model
from ..tolerances import tol
from .select import greedy, pair_terms

__all__ = ["Hypothesis", "PlannedSeries", "MeasurementPlan", "plan_test", "hypothesis_model"]

#: Amplitudes fitted for each kind of hypothesis (model form, after ``resolve``).
AMPLITUDES = {"stiffness": ("scale",), "tilt": ("compliance",), "base": ("compliance",),
              "backlash": ("width",), "hardening": ("extra",), "hysteresis": ("lost",),
              "tool": TOOL_PARAMS, "balancer": ("kc", "ks"), "frame": ("rx", "ry", "rz")}
_DIRS = (("+x", (1, 0, 0)), ("+y", (0, 1, 0)), ("+z", (0, 0, 1)),
         ("-x", (-1, 0, 0)), ("-y", (0, -1, 0)), ("-z", (0, 0, -1)))


@dataclass(frozen=True)
class Hypothesis:
    """A hypothesis fitted to the data so far: its text, model effects and free parameters.

    ``effects`` are the baseline torsion scales followed by the hypothesis' effect (SI,
    fitted values); ``free`` (effect index, name); ``scales`` their typical sizes;
    ``chi2`` and ``n_obs`` of the fit to the data so far.
    """

    spec: str
    effects: tuple
    free: tuple
    scales: tuple
    prior: tuple
    chi2: float
    n_obs: int

    @property
    def effect(self) -> Effect:
        """The hypothesis' own effect (fitted)."""
        e = parse_effect(self.spec, len(self.effects))
        return self.effects[e.joint] if e.kind == "stiffness" else self.effects[-1]


def hypothesis_model(arm: ArmModel, spec: str, held: tuple = ()):
    """(effects, free, scales, prior) of hypothesis ``spec`` on ``arm``; the torsion scales
    of joints in ``held`` (0-based) stay nominal unless ``spec`` names them."""
    n = arm.chain.n_joints
    e = resolve(parse_effect(spec, n), arm)
    if e.kind not in AMPLITUDES:
        raise ValueError(f"hypothesis '{spec}': kind '{e.kind}' cannot be planned for "
                         f"(known: {', '.join(AMPLITUDES)})")
    effects, _ = baseline_effects(arm)
    own = e.joint if e.kind == "stiffness" else None
    free = [(j, "scale") for j in range(n) if j not in held or j == own]
    if e.kind == "stiffness":
        effects[e.joint] = e
    else:
        effects.append(e)
        free += [(n, name) for name in AMPLITUDES[e.kind]]
    prior = {f: (1.0, tol.baseline_prior_sd) for f in free if f[0] < n and f[0] != own}
    scales = [1.0 if i < n else max(abs(effects[i].get(name)), 1e-12) for i, name in free]
    return effects, free, np.array(scales), prior


def _fit_hypotheses(arm: ArmModel, problem: Problem, specs) -> list[Hypothesis]:
    n = arm.chain.n_joints
    held = tuple(sorted({parse_effect(s, n).joint for s in specs
                         if parse_effect(s, n).kind == "stiffness"}))
    out = []
    for spec in specs:
        effects, free, scales, prior = hypothesis_model(arm, spec, held)
        fr = fit_model(problem, effects, free, scales, prior)
        out.append(Hypothesis(spec, tuple(fr.effects), tuple(free), tuple(scales),
                              tuple(prior.items()), fr.chi2, fr.n_obs))
    return out


def candidate_poses(robot: Robot, chain, n: int, seed: int, min_height: float,
                    extra=()) -> np.ndarray:
    """(k, 6) poses [rad]: ``extra`` and ``n`` uniform draws inside the joint limits
    (wrist joints within ±90°, rounded to 0.1°) whose TCP is at least ``min_height`` [m]
    above the base and whose links neither collide nor touch the floor
    (:class:`~flexarm.robot.collision.CollisionChecker`)."""
    lo = np.array([j.lower for j in robot.joints], float)
    hi = np.array([j.upper for j in robot.joints], float)
    lo[3:], hi[3:] = np.maximum(lo[3:], -np.pi / 2), np.minimum(hi[3:], np.pi / 2)
    rng = np.random.default_rng(seed)
    draws = np.radians(np.round(np.degrees(lo + (hi - lo) * rng.random((4 * n, 6))), 1))
    q = np.vstack([np.reshape(extra, (-1, 6)), draws])  # drawn angles on a 0.1 deg grid
    z = tcp_frame(chain, q)[:, 2, 3]
    ok = (z >= min_height) & np.all((q >= lo - 1e-9) & (q <= hi + 1e-9), axis=1)
    # a drawn pose the robot cannot take is no candidate (measured ones were taken)
    drawn = np.flatnonzero(ok)
    drawn = drawn[drawn >= len(np.reshape(extra, (-1, 6)))]
    ok[drawn] = ~CollisionChecker(robot).colliding(q[drawn])
    return q[ok][: len(np.reshape(extra, (-1, 6))) + n]


@dataclass(frozen=True)
class PlannedSeries:
    """One planned series: pose ``q`` [rad], load direction (label, unit vector, base
    frame), and the smallest expected ΔBIC over hypothesis pairs once it is added."""

    label: str
    q: np.ndarray
    direction: str
    vector: np.ndarray
    expected: float


@dataclass(frozen=True, eq=False)
class MeasurementPlan:
    """The planned test (:func:`plan_test`).

    Attributes
    ----------
    hypotheses : tuple of Hypothesis
        Fitted to the data so far.
    series : tuple of PlannedSeries
        In the order chosen.
    loads : (k,) float
        Load levels [N] of every series; ``cycles`` adds the unloading.
    expected : (h, h) float
        Expected ΔBIC of the whole plan: row = truth, column = the rival (diagonal 0).
    sigma : float
        Tracker noise [m] assumed for the new series.

    :meth:`rows` has the signature of :meth:`~flexarm.validation.lab.virtual_lab.LabPlan.rows`, so
    :func:`~flexarm.validation.lab.virtual_lab.virtual_lab` simulates the plan directly.
    """

    hypotheses: tuple
    series: tuple
    loads: np.ndarray
    cycles: bool
    expected: np.ndarray
    sigma: float

    def rows(self):
        """Series labels, steps, q (n, 6) [rad], force (n, 3) [N] of every reading."""
        levels = np.asarray(self.loads, float)
        if self.cycles:
            levels = np.r_[levels, levels[-2::-1]]
        m = len(levels)
        series = [f"{s.label}_{s.direction}" for s in self.series for _ in range(m)]
        q = np.repeat([s.q for s in self.series], m, axis=0)
        force = np.concatenate([np.outer(levels, s.vector) for s in self.series])
        return series, np.tile(np.arange(m), len(self.series)), q, force

    def template(self) -> StaticData:
        """The plan as static data with zero displacements (to be measured)."""
        series, steps, q, force = self.rows()
        return StaticData(series=series, steps=steps, q=q, force=force,
                          disp=np.zeros_like(force), sigma=np.full(len(steps), self.sigma))

    def chance(self, threshold: float = 10.0) -> np.ndarray:
        """(h, h) probability that the measured ΔBIC exceeds ``threshold``: the excess
        chi-square is about ``lambda + 2 sqrt(lambda) z`` for expected ``lambda``, z
        standard normal (the fitted hypotheses taken as exact)."""
        from ..distributions import norm_cdf

        lam = np.maximum(self.expected, 1e-12)
        return norm_cdf((lam - threshold) / (2 * np.sqrt(lam)))

    def text(self) -> str:
        names = [h.spec for h in self.hypotheses]
        lines = [f"test plan: {len(self.series)} series, loads {self.loads.min():.0f}.."
                 f"{self.loads.max():.0f} N in {len(self.loads)} levels"
                 + (" loaded and unloaded" if self.cycles else "")]
        for s in self.series:
            deg = ", ".join(f"{v:.1f}" for v in np.degrees(s.q))
            lines.append(f"  {s.label} q = [{deg}] deg, load {s.direction}: "
                         f"expected min ΔBIC {s.expected:.1f}")
        lines.append("expected ΔBIC over the rival refitted to the planned series (chance "
                     "of ΔBIC > 10):")
        p = self.chance()
        for a, name in enumerate(names):
            vals = ", ".join(f"{names[b]} {self.expected[a, b]:.1f} ({100 * p[a, b]:.0f} %)"
                             for b in range(len(names)) if b != a)
            lines.append(f"  if {name}: {vals}")
        return "\n".join(lines)

    @writes_folder("directory")
    def write(self, directory: PathType, robot_name: str = "robot") -> list[Path]:
        """``plan.csv`` (static schema template), ``plan.mod`` (RAPID) and
        ``plan_expected.png`` in ``directory``; returns the paths."""
        from ..data.formats import write_static
        from .write import plot_expected, write_module

        d = Path(directory)
        d.mkdir(parents=True, exist_ok=True)
        csv = write_static(d / "plan.csv", self.template(), comments=(
            f"flexarm plan-test for {robot_name}: hypotheses "
            + " ; ".join(h.spec for h in self.hypotheses),
            "dx..dz to be measured (relative to each series' first reading)"))
        return [csv, write_module(d / "plan.mod", self), plot_expected(d / "plan_expected.png",
                                                                         self)]


def plan_test(robot: Robot | PathType | None, data: StaticData | PathType, hypotheses,
              n_series: int = 6, *, loads: str | ArrayLike = "0:800:100", cycles: bool = True,
              n_poses: int = 150, seed: int = 0, min_height: float = 0.3,
              sigma: float | None = None, options: ValidationOptions = DEFAULT_OPTIONS,
              arm: ArmModel | None = None) -> MeasurementPlan:
    """Plan ``n_series`` static series that best separate ``hypotheses``.

    Parameters
    ----------
    robot : Robot, path or None
        The robot or its file (None: the demo arm); its E-model is built with ``options``
        unless ``arm`` is given.
    data : StaticData or path
        The static series so far (a file's joint angles are checked against the limits).
    hypotheses : sequence of str
        Two to four effects in :func:`~flexarm.robot.effects.parse_effect` form.
    n_series : int
        Budget: series to plan.
    loads : str or (k,) float
        Load levels [N] of each series (``"0:800:100"``); ``cycles`` adds the unloading.
    n_poses, seed, min_height : int, int, float
        Candidate poses drawn in the joint limits, their seed, lowest TCP height [m].
    sigma : float, optional
        Tracker noise [m] of the new series (default: the data's median stated sigma,
        else ``tol.tracker_sigma``).

    Examples
    --------
    >>> from flexarm.validation.lab.virtual_lab import run_lab
    >>> lab = run_lab(effects=["tilt:j1=5e6"], dirs="x,z", seed=1)
    >>> plan = plan_test(None, lab.data, ["tilt:j1=5e6", "stiffness:j2=1"], 2, n_poses=40)
    >>> len(plan.series), bool(plan.expected[0, 1] > 10 and plan.expected[1, 0] > 10)
    (2, True)
    """
    hyps = list(hypotheses)
    if not 2 <= len(hyps) <= 4:
        raise ValueError(f"plan-test needs 2 to 4 hypotheses, got {len(hyps)}")
    if n_series < 1:
        raise ValueError(f"plan-test needs at least 1 series, got {n_series}")
    robot = load(robot)
    if not isinstance(data, StaticData):
        data = read_static(data, np.column_stack([robot.lower, robot.upper]))
    arm = arm or validation_models(robot, options).arm
    if sigma is None:
        sigma = float(np.median(data.sigma)) if data.sigma is not None else tol.tracker_sigma
    fitted = _fit_hypotheses(arm, Problem(arm, data, sigma), hyps)
    poses = candidate_poses(robot, arm.chain, n_poses, seed, min_height, np.unique(data.q, axis=0))
    loads = parse_loads(loads) if isinstance(loads, str) else np.asarray(loads, float)
    terms = pair_terms(arm, fitted, poses, _DIRS, loads, cycles, sigma)
    chosen, steps, final = greedy(terms, n_series)
    nd = len(_DIRS)
    series = tuple(PlannedSeries(f"T{k + 1}", poses[c // nd], _DIRS[c % nd][0],
                                 np.array(_DIRS[c % nd][1], float), float(v))
                   for k, (c, v) in enumerate(zip(chosen, steps, strict=True)))
    return MeasurementPlan(tuple(fitted), series, loads, cycles, final, sigma)
