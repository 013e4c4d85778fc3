"""Diagnosis: fit the baseline, find what is missing, name the effect, refit, repeat.

Loop (DESIGN §8): (1) fit the current model (baseline = per-joint torsion compliance
scales, GLS with the shared-reference noise model); (2) say whether something is
missing (chi^2_red against its band, leave-one-pose-out); (3) screen every candidate of
:mod:`~flexarm.validation.static.candidates` (untestable / aliased / score-test gain and
ΔBIC); (4) refit the best one's physical model with the baseline (shapes of two effects
on one joint searched together, :mod:`~flexarm.validation.static.shape_search`); (5) accept it
only if ΔBIC > ``tol.delta_bic_accept``, the held-out RMS falls, its amplitudes are
plausible and their intervals exclude zero, it is no proxy of a candidate that explains
more, its amplitude is trusted (enough of its signature unique, or no load-linear
structure left) and its refit leaves no measurement fault (offsets, drift, frame); a
misfit it leaves (chi^2_red above its band) shrinks its ΔBIC and widens its intervals as
in an F test; a best candidate failing on trust, as a proxy or on a fault it leaves gives
way to the next;
(6) add it, search every shape parameter again, repeat; (7) judge the final model
(:mod:`~flexarm.validation.static.misfit`): outliers are discounted and the search run again,
and a misfit left unexplained is reported with the structure of the residual.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from ...assembly.system import ArmModel
from ..data.measurements import ModalData, StaticData
from ..data.shape_data import Points, ShapeData
from ..dynamic.modal import ModalProblem
from ..dynamic.shape_fit import SHAPE_NOISE, ShapeProblem
from ..static.candidates import Screen, library, screen, status_of
from ..static.fit import (
    MODEL_ERRORS,
    FitResult,
    Problem,
    baseline_effects,
    chi2_band,
    fit_model,
)
from ..static.heldout import heldout_rms
from ..static.misfit import Misfit, misfit_verdict
from ..static.refit import physical_refit as _refit
from ..static.refit import shape_marginal as _shape_marginal
from ..static.residual_structure import residual_structure
from ..static.shape_search import research_shapes, shaped
from ..tolerances import tol
from .backward import backward_step
from .explain import explain, signature_corr, span_corr, static_notes
from .identifiability import identifiability, leave_one_pose_out
from .plausibility import plausible
from .results import (
    CandidateReport,
    Checks,
    Diagnosis,
    Identifiability,
    Step,
    Winner,
)
from .status import candidate_report
from .versions import static_rms
from .versions import version as model_version

__all__ = ["CandidateReport", "Checks", "Winner", "Step", "Identifiability", "Diagnosis",
           "Misfit", "diagnose"]

#: Structures of the residual a joint or base effect cannot cause: a candidate whose refit
#: leaves one of them is a proxy of a measurement fault, not accepted.
MEASUREMENT_STRUCTURES = ("offsets", "drift", "frame")
#: Load-linear structures a candidate with a small unique share may be borrowing from: it
#: is trusted only if its refit leaves none of them.
LINEAR_STRUCTURES = ("tool", "joint_angle", "frame")
#: A candidate -> the simpler one it contains (the isotropic foundation is the anisotropic
#: one with equal compliances): the richer one wins only by ``tol.delta_bic_accept``.
NESTED = {"foundation": "base"}
#: Candidates with several amplitudes of which one excluding zero is enough.
ANY_AMPLITUDE = ("wrist", "tool", "frame", "balancer", "foundation", "reflector")

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class _Refit:
    """The best candidate refitted: the winner and the model it would give."""

    winner: Winner
    fit: FitResult
    free: list
    scales: np.ndarray
    proxies: tuple
    explanation: str


def _rank(winner: Winner) -> tuple:
    """Order of refitted candidates: those passing every check first, then by dBIC."""
    return winner.checks.passed, winner.dbic


def _reason(exc: BaseException) -> str:
    """One line of what went wrong in a candidate's fit."""
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def _name(effect) -> str:
    """The candidate name of an accepted effect (``"tilt_j1"``, ``"base"``)."""
    return effect.kind + (f"_j{effect.joint + 1}" if effect.joint is not None else "")


def arm_joints(problem: Problem) -> int:
    """Number of baseline effects (one torsion scale per joint) in front of the others."""
    return problem.arm.chain.n_joints


def diagnose(arm: ArmModel, data: StaticData, sigma: float = tol.tracker_sigma,
             noise_model: str = "shared", max_effects: int = 3,
             heldout: bool = True, poses: dict | None = None,
             modal: ModalData | None = None, flexible: ArmModel | None = None,
             freq_noise: float = tol.freq_noise, exclude: tuple = (),
             points: Points | None = None, shape_noise: float = SHAPE_NOISE,
             builds=None) -> Diagnosis:
    """Diagnose which effects the model ``arm`` misses in the static ``data``.

    ``poses`` (name -> q [rad], e.g. ``robot.poses``) widen the search for load proposals.
    ``modal`` (measured natural frequencies, relative noise ``freq_noise``) joins the
    static data in every fit; ``flexible`` (the robot's flexible model) adds the
    link-flexibility candidate (:mod:`~flexarm.assembly.linkflex`).  ``exclude`` names
    candidates (``"frame"``, ``"tool"``, ``"balancer_j2"``) or kinds left out of the library.
    When ``modal`` carries mode shapes (:class:`~.shape_data.ShapeData`) at ``points``,
    its modes are paired with the model's by MAC and a shape residual (noise
    ``shape_noise`` times each shape's largest entry) joins every fit
    (:class:`~.shape_fit.ShapeProblem`; ``builds`` give flexible links their shapes).
    Returns a :class:`Diagnosis`; ``accepted`` holds the accepted effects with fitted
    parameters, ``final_effects`` the full fitted model (baseline scales included) and
    ``misfit`` the verdict on it (:mod:`~flexarm.validation.static.misfit`).  Readings the final
    model's residual shows as isolated outliers are discounted and the search runs again
    (robust handling; they are named in the verdict).
    """
    log.info("diagnosis of %d readings%s", len(data.series),
             "" if modal is None else f" and {len(modal.freq_hz)} frequencies")
    if modal is None:
        problem = Problem(arm, data, sigma, noise_model, flexible)
    elif isinstance(modal, ShapeData) and points is not None:
        problem = ShapeProblem(arm, data, sigma, noise_model, flexible, modal, freq_noise,
                               points, shape_noise, builds)
    else:
        problem = ModalProblem(arm, data, sigma, noise_model, flexible, modal, freq_noise)
    channels = ()
    if isinstance(problem, ShapeProblem):  # a reversed sensor spoils every pair: turn it
        flips = problem.reversed_channels(problem.start_effects)
        if flips:
            channels = tuple(line for _, line in flips)
            log.warning("%s; turned for the diagnosis", "; ".join(channels))
            shapes = np.array(modal.shapes)
            shapes[:, [i for i, _ in flips]] *= -1
            problem = ShapeProblem(arm, data, sigma, noise_model, flexible,
                                   replace(modal, shapes=shapes), freq_noise, points,
                                   shape_noise, builds)
    for _ in range(3):
        dg, final_fit = _search(problem, max_effects, heldout, poses, exclude)
        rs = residual_structure(problem, final_fit.effects, final_fit.sensitivity,
                                final_fit.n_identified + final_fit.n_shape)
        if not rs.outlier_rows:
            break
        problem.discount(list(rs.outlier_rows))
        log.info("%d outlier(s) discounted, search again", len(rs.outlier_rows))
    rows = np.flatnonzero(problem.discounted)
    discounted = tuple((str(data.series[i]), int(data.steps[i])) for i in rows)
    final = dg.final
    lonely = tuple(problem.lonely_lines(dg.final_effects)) if modal is not None else ()
    verdict = misfit_verdict(final.label, final.chi2_red, final.band, rs, discounted, lonely,
                             channels)
    log.info("diagnosis done: %d effects accepted%s", len(dg.accepted),
             ", unexplained misfit" if verdict.unexplained else "")
    notes = static_notes(arm, flexible is not None, problem, rs)
    if isinstance(problem, ShapeProblem):
        notes += (problem.shape_note(dg.final_effects),)
    return replace(dg, misfit=verdict, notes=notes)


def _search(problem: Problem, max_effects: int, heldout: bool, poses, exclude=()):
    """The search loop on ``problem``: the diagnosis (without verdict) and the final fit."""
    arm = problem.arm
    effects, free = baseline_effects(arm)
    n_base = len(effects)
    scales = np.ones(len(free))
    prior = {f: (1.0, tol.baseline_prior_sd) for f in free}
    effects = list(getattr(problem, "start_effects", effects))
    if problem.noise_model != "shared":  # the trap demonstration keeps the joint library:
        # the measurement candidates read patterns only the GLS metric makes meaningful
        exclude = tuple(exclude) + ("tool", "frame", "balancer", "reflector", "loadcell")
    cands = [c for c in library(problem) if c.name not in exclude and c.kind not in exclude]
    steps, accepted, labels, ident = [], [], [], None
    n_shape = 0  # shape parameters (thresholds, radii) of the accepted effects: fixed, counted
    dropped = ()
    for it in range(max_effects + 1):
        label = " + ".join(["baseline", *labels])
        fr = fit_model(problem, effects, free, scales, prior, n_shape=n_shape)
        cur_ho = heldout_rms(problem, effects, free, scales, prior) if heldout else np.nan
        if it == 0:
            ident = replace(identifiability(problem, fr), leave_one_pose_out=leave_one_pose_out(
                problem, effects, free, scales, prior))
        version = replace(model_version(problem, label, fr, cur_ho), dropped=dropped)
        step, refit = _round(problem, fr, version, cands, accepted, free, scales, prior, n_shape,
                             heldout, poses)
        steps.append(step)
        if not step.accepted:
            break
        effects, free, scales = list(refit.fit.effects), refit.free, refit.scales
        n_shape = refit.fit.n_shape
        accepted.append(refit.fit.effects[-1])
        labels.append(refit.winner.label)
        dropped = ()
        if len(accepted) > 1:  # every shape again, with all accepted effects free
            full = refit.fit
            try:
                full = research_shapes(problem, effects, free, scales, prior, n_shape,
                                       shaped(effects, n_base))
                effects = list(full.effects)
            except MODEL_ERRORS as exc:  # keep the shapes found one at a time
                log.info("shape search again failed: %s", _reason(exc))
            # an effect accepted earlier may have stood in for the one just found
            while len(accepted) > 1:
                first = len(effects) - len(accepted)
                gone = backward_step(problem, full, free, scales, prior, n_shape,
                                     range(first, len(effects) - 1))
                if gone is None:
                    break
                k = gone.index - first
                e = accepted.pop(k)
                cands = [c for c in cands if c.name != _name(e)]
                dropped += ((_name(e), replace(gone, label=labels.pop(k)).text(labels[-1])),)
                full, free, scales, n_shape = gone.fit, gone.free, gone.scales, gone.n_shape
                effects = list(full.effects)
    if steps[-1].accepted:  # the loop ran out of iterations after an acceptance
        fr = fit_model(problem, effects, free, scales, prior, n_shape=n_shape)
        steps.append(replace(model_version(
            problem, " + ".join(["baseline", *labels]), fr,
            heldout_rms(problem, effects, free, scales, prior) if heldout else np.nan),
            dropped=dropped))
    final = tuple(steps[-1].effects)
    return Diagnosis(tuple(steps), ident, final[n_base:], final,
                     static_notes(arm, problem.flexible is not None, problem, None)), fr


def _round(problem: Problem, fr, version: Step, cands, accepted, free, scales, prior,
           n_shape: int, heldout: bool, poses):
    """One round against the model version ``version`` (fitted as ``fr``): screen the
    candidates not yet accepted, refit the best testable one, rank them all.

    Returns ``version`` with the ranking and the winner, and the refit (None if no
    candidate was testable)."""
    done = {_name(e) for e in accepted}
    screens, fit_failed = [], {}
    for c in cands:
        if c.name in done:
            continue
        try:
            screens.append(screen(problem, fr, c))
        except MODEL_ERRORS as exc:  # its trial model left the domain where it is valid
            fit_failed[c.name] = (c, _reason(exc))
    testable = sorted((s for s in screens if status_of(s) is None), key=lambda s: -s.dbic)
    best, refit, untrusted = None, None, {}
    # the leading candidates are refitted and the one whose refit explains most wins: a
    # screen is a linearisation, and with vibration data a candidate may look better
    # than it fits.  One that fails on trust, as a proxy or on a fault it leaves (another
    # effect still missing can look like one) gives way to the next, so a true effect
    # behind it is still found; one whose refit fails is rejected with the reason
    refits: dict = {}

    def refit_of(s):
        if s.candidate.name not in refits:
            refits[s.candidate.name] = _refit_best(problem, fr, s, screens, free, scales,
                                                   prior, n_shape, version.rms_heldout, heldout,
                                                   vetoed)
        return refits[s.candidate.name]

    seen, vetoed = set(), {}
    for s in testable:
        if len(seen) >= tol.max_refits:
            break
        try:
            r = refit_of(s)
            simpler = next((x for x in testable
                            if x.candidate.name == NESTED.get(s.candidate.name)), None)
            if simpler is not None:  # the simpler one stands in unless clearly worse
                rs = refit_of(simpler)
                if r.winner.dbic - rs.winner.dbic < tol.delta_bic_accept:
                    s, r = simpler, rs
        except MODEL_ERRORS as exc:
            fit_failed[s.candidate.name] = (s.candidate, _reason(exc))
            continue
        if s.candidate.name in seen:
            continue
        seen.add(s.candidate.name)
        if best is None:
            best, refit = s, r
        failed = r.winner.checks.failed
        # a refitted candidate is weighed as a proxy of another by its refit, not its screen
        vetoed[s.candidate.name] = -np.inf if failed else r.winner.dbic
        if {"trusted", "distinct", "clean"} & set(failed):
            untrusted[s.candidate.name] = (r, failed)
            continue
        modal = bool(getattr(problem, "n_modal", 0))
        if (not modal or refit.winner.name in untrusted
                or _rank(r.winner) > _rank(refit.winner)):
            best, refit = s, r
        if not modal:
            break
    reports = [candidate_report(problem, fr, s, screens, best, refit, poses) for s in screens
               if s.candidate.name not in fit_failed]
    reports += [CandidateReport(c.name, c.label, "rejected", np.nan, np.nan, np.nan,
                                f"fit failed ({why})") for c, why in fit_failed.values()]
    reports = [replace(r, status="rejected", detail="failed: " + ", ".join(untrusted[r.name][1]))
               if r.name in untrusted and (refit is None or r.name != refit.winner.name) else r
               for r in reports]
    order = {"accepted": 0, "rejected": 1, "aliased": 2, "untestable": 3}
    reports.sort(key=lambda r: (order[r.status], -np.nan_to_num(r.dbic, nan=-np.inf)))
    if refit is None:
        return replace(version, candidates=tuple(reports)), None
    return replace(version, candidates=tuple(reports), winner=refit.winner,
                   accepted=refit.winner.checks.passed, explanation=refit.explanation), refit


def _refit_best(problem: Problem, fr, best: Screen, screens, free, scales, prior,
                n_shape: int, cur_ho: float, heldout: bool, vetoed=None) -> _Refit:
    """Refit the best testable candidate with the current model and check it for
    acceptance (module docstring, step 5)."""
    c = best.candidate
    vetoed = {} if vetoed is None else vetoed
    fr2, free2, scales2, keep, grid_sd = _refit(problem, fr, free, scales, prior, best, n_shape)
    same = [i for i in shaped(fr2.effects, arm_joints(problem), c.joint)
            if i < len(fr2.effects) - 1] if c.joint is not None else []
    if same:  # two effects on one joint: their shapes are searched together
        fr2 = research_shapes(problem, fr2.effects, free2, scales2, prior, fr2.n_shape,
                              same + shaped(fr2.effects, len(fr2.effects) - 1))
        if c.grid_name is not None:
            fr2, grid_sd = _shape_marginal(problem, fr2, scales2, prior, c.grid_name)
    theta = fr2.theta[len(free):]
    band2 = chi2_band(fr2.dof)
    # residual variance above the stated noise (a misfit the candidate leaves) widens the
    # intervals and shrinks its chi^2 gain, as in an F test
    # (with the GLS noise model: the "independent" one exists to show the trap unguarded)
    guarded = problem.noise_model == "shared"
    infl = max(1.0, fr2.chi2_red) if fr2.chi2_red > band2[1] and guarded else 1.0
    se = fr2.stderr[len(free):] * np.sqrt(infl)
    dbic = (fr.chi2 - fr2.chi2) / infl - c.n_params * np.log(fr.n_obs)
    new_ho = heldout_rms(problem, fr2.effects, free2, scales2, prior) if heldout else 0.0
    excl = np.abs(theta) > tol.interval_z * se
    rs2 = residual_structure(problem, fr2.effects, fr2.sensitivity,
                             fr2.n_identified + fr2.n_shape)
    clean = not guarded or not any(t.found for t in rs2.tests
                                   if t.name in MEASUREMENT_STRUCTURES and t.name != c.kind)
    trusted = bool(not guarded or best.unique >= tol.trusted_share
                   or not any(t.found for t in rs2.tests if t.name in LINEAR_STRUCTURES))
    # A proxy: an aliased candidate whose unique signature correlates with the best one's
    # and which would explain more of the residual.
    proxies = [s for s in screens if status_of(s) == "aliased" and s.dchi2 > best.dchi2
               and signature_corr(s.columns, best.columns) > tol.proxy_correlation]
    # with the GLS model, also a candidate with a small unique share that explains more
    # (a flexible effect, e.g. a tool compliance, standing in for a base tilt)
    proxies += [s for s in screens if problem.noise_model == "shared" and s is not best
                and status_of(s) is None and s.unique < tol.trusted_share
                and s.dchi2 > best.dchi2 and s.candidate.n_params < c.n_params
                and span_corr(s.columns, best.columns) > tol.proxy_correlation]
    # the simpler candidate a richer one contains is weighed by refits, not as a proxy
    # (and one whose own refit failed its checks, or explained less, is no better
    # explanation: ``vetoed`` maps it to its refit's dBIC, -inf when it failed)
    proxies = [s for s in proxies if NESTED.get(c.name) != s.candidate.name
               and not vetoed.get(s.candidate.name, np.inf) < dbic]
    checks = Checks(dbic=bool(dbic > tol.delta_bic_accept),
                    heldout=bool(new_ho < tol.heldout_gain * cur_ho) if heldout else True,
                    plausible=plausible(problem, fr2.effects[-1], keep),
                    interval=bool(excl.any() if c.kind in ANY_AMPLITUDE else excl.all()),
                    distinct=not proxies, trusted=trusted, clean=clean)
    winner = Winner(
        name=c.name, label=c.label, dbic=float(dbic),
        params={a: (float(t), float(s)) for a, t, s in zip(keep, theta, se, strict=True)},
        grid_name=c.grid_name,
        grid_value=None if c.grid_name is None else fr2.effects[-1].get(c.grid_name),
        grid_sd=grid_sd, checks=checks, chi2_red_after=fr2.chi2_red,
        rms_heldout_after=new_ho, rms_fit_after=static_rms(problem, fr2.effects))
    return _Refit(winner, fr2, free2, scales2, tuple(proxies),
                  explain(problem, c, fr2.effects[-1], theta, se))
