"""Diagnosis: fit the baseline, find what is missing, name the effect, refit, repeat.

Loop (DESIGN §8): (1) fit the current model (baseline = per-joint torsion compliance
scales, GLS with the shared-reference noise model); (2) say whether something is
missing (chi^2_red against its band, leave-one-pose-out); (3) screen every candidate of
:mod:`~flexarm.validation.candidates` (untestable / aliased / score-test gain and
ΔBIC); (4) refit the best one's physical model with the baseline; (5) accept it only if
ΔBIC > ``tol.delta_bic_accept``, the held-out RMS falls, its amplitudes are plausible
and their intervals exclude zero; (6) add it and repeat.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from ..assembly.system import ArmModel
from .candidates import Screen, library, load_proposal, screen, status_of
from .diagnosis import CandidateReport, Checks, Diagnosis, Identifiability, Step, Winner
from .explain import explain, static_notes
from .fit import FitResult, Problem, baseline_effects, chi2_band, fit_model, heldout_rms
from .measurements import ModalData, StaticData
from .modal import ModalProblem
from .tolerances import tol

__all__ = ["CandidateReport", "Checks", "Winner", "Step", "Identifiability", "Diagnosis",
           "diagnose"]

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


def _rms(problem: Problem, effects) -> float:
    r = (problem.y - problem.predict(effects))[~problem.is_ref]
    return float(np.sqrt(np.mean(r**2))) if r.size else float("nan")


def identifiability(problem: Problem, fit) -> Identifiability:
    """SVD of the whitened baseline sensitivities, correlations, torque sign changes
    (``leave_one_pose_out`` left empty: :func:`leave_one_pose_out`)."""
    X = fit.sensitivity
    sv = np.linalg.svd(X, compute_uv=False) if X.size else np.zeros(0)
    sd = fit.stderr
    corr = fit.cov / np.outer(np.maximum(sd, 1e-300), np.maximum(sd, 1e-300))
    flips = []
    for j in range(problem.arm.chain.n_joints):
        series = [str(problem.data.series[g[0]]) for g in problem.groups
                  if np.any(np.diff(np.sign(problem.tau[g, j])) != 0)]
        flips.append(tuple(series))
    return Identifiability(
        singular_values=tuple(sv.tolist()),
        condition=float(sv.max() / max(sv.min(), 1e-300)) if sv.size else float("nan"),
        correlation=tuple(map(tuple, corr.tolist())), stderr=tuple(sd.tolist()),
        sign_changes={f"joint_{j + 1}": s for j, s in enumerate(flips)})


def leave_one_pose_out(problem: Problem, effects, free, scales, prior) -> dict:
    """chi^2_red on each pose when the model is fitted on the other poses."""
    out = {}
    poses = problem.pose_index
    if problem.uq.shape[0] < 3:
        return out
    for p in range(problem.uq.shape[0]):
        test = poses == p
        fr = fit_model(problem, effects, free, scales, prior, rows=~test, iterations=2)
        r = problem.whiten(problem.y - problem.predict(fr.effects), test)
        label = str(problem.data.series[np.flatnonzero(test)[0]]).split("_")[0]
        out[label] = float(r @ r / max(r.size, 1))
    return out


def _plausible(kind: str, theta: np.ndarray) -> bool:
    if kind == "links":
        return bool(np.all(theta > 0) and np.all(theta < tol.max_link_compliance))
    if kind == "wrist":
        return True
    if kind in ("backlash", "hysteresis"):
        return bool(np.all(theta > 0) and np.all(theta < tol.max_backlash))
    return bool(np.all(theta > 0))


def diagnose(arm: ArmModel, data: StaticData, sigma: float = tol.tracker_sigma,
             noise_model: str = "shared", max_effects: int = 3,
             heldout: bool = True, poses: dict | None = None,
             modal: ModalData | None = None, flexible: ArmModel | None = None,
             freq_noise: float = tol.freq_noise) -> Diagnosis:
    """Diagnose which effects the model ``arm`` misses in the static ``data``.

    ``poses`` (name -> q [rad], e.g. ``robot.poses``) widen the search for load proposals.
    ``modal`` (measured natural frequencies, relative noise ``freq_noise``) joins the
    static data in every fit; ``flexible`` (the robot's flexible model) adds the
    link-flexibility candidate (:mod:`~flexarm.assembly.linkflex`).
    Returns a :class:`Diagnosis`; ``accepted`` holds the accepted effects with fitted
    parameters, ``final_effects`` the full fitted model (baseline scales included).
    """
    log.info("diagnosis of %d readings%s", len(data.series),
             "" if modal is None else f" and {len(modal.freq_hz)} frequencies")
    problem = (Problem(arm, data, sigma, noise_model, flexible) if modal is None else
               ModalProblem(arm, data, sigma, noise_model, flexible, modal, freq_noise))
    effects, free = baseline_effects(arm)
    scales = np.ones(len(free))
    prior = {f: (1.0, tol.baseline_prior_sd) for f in free}
    cands = library(problem)
    steps, accepted, ident = [], [], None
    label = "baseline"
    n_shape = 0  # shape parameters (thresholds, radii) of the accepted effects: fixed, counted
    for it in range(max_effects + 1):
        fr = fit_model(problem, effects, free, scales, prior, n_shape=n_shape)
        band = chi2_band(fr.dof)
        cur_ho = heldout_rms(problem, effects, free, scales, prior) if heldout else np.nan
        if it == 0:
            ident = replace(identifiability(problem, fr), leave_one_pose_out=leave_one_pose_out(
                problem, effects, free, scales, prior))
        version = Step(label, fr.effects, fr.chi2_red, band, fr.dof, _rms(problem, fr.effects),
                       cur_ho)
        step, refit = _round(problem, fr, version, cands, accepted, free, scales, prior, n_shape,
                             heldout, poses)
        steps.append(step)
        if not step.accepted:
            break
        effects, free, scales = list(refit.fit.effects), refit.free, refit.scales
        n_shape = refit.fit.n_shape
        accepted.append(refit.fit.effects[-1])
        label = label + " + " + refit.winner.label
    if steps[-1].accepted:  # the loop ran out of iterations after an acceptance
        steps.append(_last_version(problem, label, effects, free, scales, prior, n_shape,
                                   heldout))
    log.info("diagnosis done: %d effects accepted", len(accepted))
    return Diagnosis(tuple(steps), ident, tuple(accepted), tuple(steps[-1].effects),
                     _notes(arm, problem, flexible))


def _round(problem: Problem, fr, version: Step, cands, accepted, free, scales, prior,
           n_shape: int, heldout: bool, poses):
    """One round against the model version ``version`` (fitted as ``fr``): screen the
    candidates not yet accepted, refit the best testable one, rank them all.

    Returns ``version`` with the ranking and the winner, and the refit (None if no
    candidate was testable)."""
    done = {e.kind + (f"_j{e.joint + 1}" if e.joint is not None else "") for e in accepted}
    screens = [screen(problem, fr, c) for c in cands if c.name not in done]
    testable = sorted((s for s in screens if status_of(s) is None), key=lambda s: -s.dbic)
    best = testable[0] if testable else None
    refit = None if best is None else _refit_best(problem, fr, best, screens, free, scales,
                                                  prior, n_shape, version.rms_heldout, heldout)
    reports = [_report(problem, fr, s, screens, best, refit, poses) for s in screens]
    order = {"accepted": 0, "rejected": 1, "aliased": 2, "untestable": 3}
    reports.sort(key=lambda r: (order[r.status], -r.dbic))
    if refit is None:
        return replace(version, candidates=tuple(reports)), None
    return replace(version, candidates=tuple(reports), winner=refit.winner,
                   accepted=refit.winner.checks.passed, explanation=refit.explanation), refit


def _refit_best(problem: Problem, fr, best: Screen, screens, free, scales, prior,
                n_shape: int, cur_ho: float, heldout: bool) -> _Refit:
    """Refit the best testable candidate with the current model and check it for
    acceptance (module docstring, step 5)."""
    c = best.candidate
    fr2, free2, scales2, keep, grid_sd = _refit(problem, fr, free, scales, prior, best, n_shape)
    theta = fr2.theta[len(free):]
    se = fr2.stderr[len(free):]
    dbic = fr.chi2 - fr2.chi2 - c.n_params * np.log(fr.n_obs)
    new_ho = heldout_rms(problem, fr2.effects, free2, scales2, prior) if heldout else 0.0
    excl = np.abs(theta) > tol.interval_z * se
    # A proxy: an aliased candidate whose unique signature correlates with the best one's
    # and which would explain more of the residual.
    proxies = [s for s in screens if status_of(s) == "aliased" and s.dchi2 > best.dchi2
               and _corr(s.columns, best.columns) > tol.proxy_correlation]
    checks = Checks(dbic=bool(dbic > tol.delta_bic_accept),
                    heldout=bool(new_ho < tol.heldout_gain * cur_ho) if heldout else True,
                    plausible=_plausible(c.kind, theta),
                    interval=bool(excl.any() if c.kind == "wrist" else excl.all()),
                    distinct=not proxies)
    winner = Winner(
        name=c.name, label=c.label, dbic=float(dbic),
        params={a: (float(t), float(s)) for a, t, s in zip(keep, theta, se, strict=True)},
        grid_name=c.grid_name,
        grid_value=None if c.grid_name is None else fr2.effects[-1].get(c.grid_name),
        grid_sd=grid_sd, checks=checks, chi2_red_after=fr2.chi2_red,
        rms_heldout_after=new_ho, rms_fit_after=_rms(problem, fr2.effects))
    return _Refit(winner, fr2, free2, scales2, tuple(proxies),
                  explain(problem, c, fr2.effects[-1], theta, se))


def _report(problem: Problem, fr, s: Screen, screens, best: Screen | None,
            refit: _Refit | None, poses) -> CandidateReport:
    """The status of the screened candidate ``s`` in this round and why."""
    c = s.candidate
    st, detail = _status(problem, fr, s, best, refit, poses)
    if c.kind == "base":
        detail = (detail + "; " if detail else "") + _base_note(screens)
    if c.kind == "links" and st in ("rejected", "untestable"):
        detail = (detail + "; " if detail else "") + _links_note(problem, fr, s, st)
    return CandidateReport(c.name, c.label, st, s.dbic, s.unique, s.norm, detail)


def _status(problem: Problem, fr, s: Screen, best: Screen | None, refit: _Refit | None,
            poses) -> tuple[str, str]:
    """Status and detail of ``s`` before the notes on the base and link candidates."""
    st = status_of(s)
    c = s.candidate
    winner = None if refit is None else refit.winner
    if st == "untestable":
        return st, _untestable_detail(problem, c, poses)
    if st == "aliased":
        return st, (_links_note(problem, fr, s, "aliased") if c.kind == "links"
                    else _mimic(problem, fr, s))
    if winner is not None and c.name == winner.name and refit.proxies:
        p = max(refit.proxies, key=lambda x: x.dchi2)
        return "aliased", (f"with {p.candidate.label} (a proxy: their unique signatures "
                           f"correlate {_corr(p.columns, s.columns):.2f} and "
                           f"{p.candidate.label} explains more, dchi2 {p.dchi2:.0f} vs "
                           f"{s.dchi2:.0f})")
    if winner is not None and c.name == winner.name:
        ok = winner.checks.passed
        return ("accepted" if ok else "rejected",
                "" if ok else "failed: " + ", ".join(winner.checks.failed))
    if winner is not None and _corr(s.columns, best.columns) > tol.alias_correlation:
        return "aliased", f"with {winner.label} (same pattern on this data)"
    return "rejected", ""


def _untestable_detail(problem: Problem, c, poses) -> str:
    """Why candidate ``c`` cannot be tested on these data, and what data would test it."""
    if c.joint is not None and not np.any(np.abs(problem.J[:, :, c.joint]) > 1e-9):
        return (f"joint {c.joint + 1} turns the TCP about its own axis: invisible in "
                f"TCP translations; measure TCP rotations (rx, ry, rz)")
    if c.kind in ("backlash", "hysteresis"):
        return "add these loads: " + load_proposal(problem, c.joint, c.kind, extra_poses=poses)
    return "the data barely load it: add poses/loads that do"


def _last_version(problem: Problem, label: str, effects, free, scales, prior, n_shape: int,
                  heldout: bool) -> Step:
    """The model after the last acceptance when the rounds ran out (not screened)."""
    fr = fit_model(problem, effects, free, scales, prior, n_shape=n_shape)
    return Step(label, fr.effects, fr.chi2_red, chi2_band(fr.dof), fr.dof,
                _rms(problem, fr.effects),
                heldout_rms(problem, effects, free, scales, prior) if heldout else np.nan)


def _notes(arm: ArmModel, problem: Problem, flexible: ArmModel | None) -> tuple[str, ...]:
    """Effects these data cannot test, and measured modes no model mode matched."""
    return (static_notes(arm, links_tested=flexible is not None)
            + tuple("modal data: " + u for u in getattr(problem, "unmatched", ())))


def _refit(problem: Problem, fr, free, scales, prior, best: Screen, n_shape: int = 0):
    """Physical refit of a candidate with the current model: amplitudes the data can see
    (whitened norm at typical size >= ``tol.untestable_norm``) are free, the others stay
    0; the shape parameter (if any) is optimised around its best grid value and counted
    in the degrees of freedom (with the ``n_shape`` of the current model).

    Returns the fit, its free parameters and scales, the amplitudes kept and the standard
    deviation of the shape parameter (NaN without one); the fit's covariance is then
    marginal over the shape parameter (:func:`_shape_marginal`)."""
    from scipy.optimize import minimize_scalar

    from .candidates import signature

    c = best.candidate
    S = signature(problem, fr.effects, c, best.grid_value) * np.asarray(c.sizes)
    keep = [a for a, n in zip(c.amplitudes, np.linalg.norm(S, axis=0), strict=True)
            if n >= tol.untestable_norm] or list(c.amplitudes[:1])
    i = len(fr.effects)
    free2 = list(free) + [(i, a) for a in keep]
    scales2 = np.r_[scales, [s for a, s in zip(c.amplitudes, c.sizes, strict=True) if a in keep]]

    n_shape2 = n_shape + (c.grid_name is not None)

    def run(g, iterations=3):
        eff = list(fr.effects) + [c.effect(g)]
        return fit_model(problem, eff, free2, scales2, prior, iterations=iterations,
                         n_shape=n_shape2)

    g = best.grid_value
    if c.grid_name is not None:
        lo, hi = np.log(g / 10), np.log(g * 10)
        opt = minimize_scalar(lambda x: run(np.exp(x), 2).chi2, bounds=(lo, hi),
                              method="bounded", options={"xatol": 1e-3})
        g = float(np.exp(opt.x))
        fr2, g_sd = _shape_marginal(problem, run(g), scales2, prior, c.grid_name)
        return fr2, free2, scales2, keep, g_sd
    return run(g), free2, scales2, keep, float("nan")


def _shape_marginal(problem: Problem, fit, scales, prior, name: str):
    """``fit`` (whose last effect has the shape parameter ``name``, found by search) with
    the covariance of its free parameters marginal over that shape parameter, and the
    shape parameter's standard deviation.

    At a fixed shape the amplitude's interval is conditional and too narrow when the two
    trade off (a hardening threshold a little higher with a little more extra compliance
    fits almost as well): with it, the 99 % intervals of the hardening amplitude covered
    the truth on 17 of 20 seeds.  The shape's sensitivity column (finite difference)
    joins the linearised normal equations, with the same prior on the baseline."""
    eff = list(fit.effects)
    g = eff[-1].get(name)
    h = tol.fd_step * abs(g)
    f0 = problem.wpredict(eff)
    xg = (problem.wpredict(eff[:-1] + [eff[-1].with_params(**{name: g + h})]) - f0) / h
    X = np.column_stack([fit.sensitivity, xg])
    D = np.r_[scales, abs(g)]
    sd = np.array([prior.get(f, (0.0, np.inf))[1] for f in fit.free] + [np.inf])
    P = np.where(np.isfinite(sd), 1 / np.where(np.isfinite(sd), sd, 1) ** 2, 0.0)
    A = (X * D).T @ (X * D) + np.diag(P * D**2)
    cov = D[:, None] * np.linalg.pinv(A, rcond=1e-12) * D[None, :]
    return replace(fit, cov=cov[:-1, :-1]), float(np.sqrt(max(cov[-1, -1], 0.0)))


def _corr(A: np.ndarray, B: np.ndarray) -> float:
    a, b = A.reshape(len(A), -1)[:, 0], B.reshape(len(B), -1)[:, 0]
    den = np.linalg.norm(a) * np.linalg.norm(b)
    return float(abs(a @ b) / den) if den > 0 else 0.0


def _mimic(problem: Problem, fit, s: Screen) -> str:
    """Name the current-model parameter whose sensitivity best mimics the signature."""
    X = fit.sensitivity
    from .candidates import signature

    sig = signature(problem, fit.effects, s.candidate, s.grid_value)[:, 0]
    c = np.abs(X.T @ sig) / np.maximum(np.linalg.norm(X, axis=0) * np.linalg.norm(sig), 1e-300)
    k = int(np.argmax(c)) if c.size else 0
    i, name = fit.free[k]
    e = fit.effects[i]
    what = "torsion compliance" if e.kind == "stiffness" else f"{e.kind} {name}"
    return f"with {e.label.replace(' stiffness', '')} {what} (corr {c[k]:.2f})"


def _links_note(problem: Problem, fit, s: Screen, status: str) -> str:
    """Why link flexibility is (not) seen, and what data would show it."""
    has_modal = isinstance(problem, ModalProblem)
    text = (f"with the joint compliances: only {s.unique:.1%} of its signature (flexible minus "
            f"E-model, norm {s.norm:.0f} sigma) is not mimicked by them; best single match: "
            f"{_mimic(problem, fit, s)[5:]}") if status == "aliased" else (
            f"unique part of its signature {s.unique:.1%} gives dBIC {s.dbic:.1f}")
    if not has_modal:
        text += "; undetectable from TCP-only static data: add modal data (--modal)"
    return text


def _base_note(screens) -> str:
    by = {s.candidate.name: s for s in screens}
    note = "base twist about z is the same motion as joint-1 torsion (absorbed by it)"
    if "base" in by and "tilt_j1" in by:
        note += (f"; base tilt vs joint-1 bearing tilt: corr "
                 f"{_corr(by['base'].columns, by['tilt_j1'].columns):.2f} after the baseline")
    return note
