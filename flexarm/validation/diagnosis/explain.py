"""One-sentence explanations of a diagnosed effect, and notes on effects static data cannot see."""

from __future__ import annotations

import numpy as np

from ...assembly.system import ArmModel
from ..dynamic.modal import ModalProblem
from ..static.candidates import Screen, signature
from ..static.fit import Problem

__all__ = ["explain", "static_notes", "span_corr", "signature_corr", "mimic", "links_note",
           "base_note"]


def _switch_loads(problem, joint: int) -> str:
    """Where the joint torque changes sign: '380-420 N in P2_+z, ...'."""
    parts = []
    for g in problem.groups:
        tau = problem.tau[g, joint]
        k = np.flatnonzero(np.diff(np.sign(tau)) != 0)
        if k.size:
            f = np.linalg.norm(problem.data.force[g], axis=1)
            a, b = sorted((f[k[0]], f[k[0] + 1]))
            parts.append(f"{a:.0f}-{b:.0f} N in {problem.data.series[g[0]]}")
    return ", ".join(parts[:4]) + (" ..." if len(parts) > 4 else "")


def _mrad(theta, se) -> str:
    """``"0.200 ± 0.010 mrad"``: a fitted angle [rad] and its standard error in mrad."""
    return f"{theta[0] * 1e3:.3f} ± {se[0] * 1e3:.3f} mrad"


def _compliance(theta, se) -> str:
    """``"2e-07 ± 1e-08 rad/(N m)"``: a fitted compliance and its standard error."""
    return f"{theta[0]:.3g} ± {se[0]:.2g} rad/(N m)"


def _tilt(theta, se) -> str:
    """A fitted tilt compliance [rad/(N m)], its standard error and its stiffness."""
    return f"tilt compliance {_compliance(theta, se)} (stiffness {1 / theta[0]:.3g} N m/rad)"


def _angles_deg(problem, joint: int) -> np.ndarray:
    """Distinct angles [deg] of a 0-based joint over the series' reference readings."""
    return np.degrees(np.unique(np.round(problem.data.q[problem.ref, joint], 6)))


def explain(problem, cand, effect, theta, se) -> str:
    """A sentence a user understands, with the fitted size and where the data show it."""
    j = cand.joint
    if cand.kind == "backlash":
        return (f"joint {j + 1} backlash of {_mrad(theta, se)}: "
                f"residuals jump where joint {j + 1} torque changes sign at "
                f"{_switch_loads(problem, j)}")
    if cand.kind == "hardening":
        k2 = problem.arm.joints[j].torsion
        ratio = 1 / (1 + theta[0] * k2)
        return (f"joint {j + 1} stiffens with load: K1 = {ratio:.2f} K2 below "
                f"{effect.get('threshold'):.0f} N m (extra compliance "
                f"{_compliance(theta, se)}): deflection grows faster than linear at low load "
                f"and straightens above")
    if cand.kind == "hysteresis":
        return (f"joint {j + 1} lost motion of {_mrad(theta, se)} "
                f"(friction torque {effect.get('radius'):.0f} N m): unloading curves lie off "
                f"the loading curves once the load reverses")
    if cand.kind == "tilt":
        return (f"joint {j + 1} bearing {_tilt(theta, se)}: deflections perpendicular to the "
                f"joint-{j + 1} rotation are larger than the gear alone explains")
    if cand.kind == "base":
        return (f"base (foundation) {_tilt(theta, se)}: the whole arm tips about the floor "
                f"by the moment of the load about the base")
    if cand.kind == "wrist":
        vals = _pairs(effect, theta, se, "", cand.amplitudes)
        return (f"coupled wrist: joints 4-6 share compliance ({vals} rad/(N m)): a torque on "
                f"one wrist joint also turns the others")
    if cand.kind == "links":
        return (f"link flexibility: the links are {theta[0]:.2f} ± {se[0]:.2f} times as "
                f"compliant as the CAD flexible model: with the joint compliances fitted to "
                f"the statics, the rigid-link model cannot also match the natural "
                f"frequencies")
    if cand.kind in ("tool", "frame", "balancer"):
        return _explain_measurement(problem, cand, effect, theta, se)
    return f"{cand.label}: {theta}"


def _pairs(effect, theta, se, unit: str, fallback=()) -> str:
    """``"a = 1e-06 ± 2e-08 unit, ..."``: the fitted values of the effect's non-zero
    parameters (``fallback`` names them when none is non-zero)."""
    names = [k for k, v in effect.params if v != 0] or list(fallback)
    return ", ".join(f"{a} = {t:.3g} ± {s:.2g}{unit}"
                     for a, t, s in zip(names, theta, se, strict=False))


def _explain_measurement(problem, cand, effect, theta, se) -> str:
    """The tool, frame and balancer candidates in one sentence."""
    if cand.kind == "tool":
        return (f"tool/adapter compliance in the tool frame ({_pairs(effect, theta, se, '')} "
                f"m/N): the extra deflection follows the tool's orientation, the same at every "
                f"pose (not written to the robot file: model the adapter)")
    if cand.kind == "frame":
        return (f"measurement frame misaligned ({_pairs(effect, theta, se, ' rad')}): every "
                f"deflection is turned alike (a tracker alignment error, not the robot; not "
                f"written to the robot file)")
    j = cand.joint
    qs = _angles_deg(problem, j)
    return (f"joint {j + 1} gravity balancer: stiffness kc cos q{j + 1} + ks sin q{j + 1} in "
            f"parallel with the gear ({_pairs(effect, theta, se, '')} N m/rad): joint "
            f"{j + 1}'s compliance changes with its angle across the series at q{j + 1} = "
            f"{', '.join(f'{v:.0f}' for v in qs)} deg (not written to the robot file)")


def static_notes(arm: ArmModel, links_tested: bool = False, problem=None,
                 structure=None) -> tuple[str, ...]:
    """Effects the library cannot or did not test on the data at hand, and why.

    With ``problem`` (the data) the balancer and payload notes count the data's series
    and joint angles; with ``structure`` (the final model's
    :class:`~flexarm.validation.static.residual_structure.ResidualStructure`) the kinematics
    note quotes the load-linear residual tests.
    """
    flexible = any(not b.is_rigid for b in arm.bodies)
    notes = [_payload_note(problem), _balancer_note(problem), _kinematics_note(structure)]
    if flexible:
        notes.append("link flexibility: part of this model (flexible links)")
    elif not links_tested:
        modal = bool(getattr(problem, "n_modal", 0))
        notes.append("link flexibility: aliased/undetectable from TCP-only static data "
                      "(link bending scales with the same loads as the joint compliances); "
                      "not tested here: give the flexible model (diagnose --flexible)"
                      + ("" if modal else " and modal data (--modal)"))
    return tuple(notes)


def _payload_note(problem) -> str:
    if getattr(problem, "n_modal", 0):
        return ("payload and added masses: tested with the modal data (an added mass on each "
                "link lowers the frequencies by its share of each mode's kinetic energy)")
    n = "each" if problem is None else f"each of the {len(problem.groups)}"
    return (f"payload mass: untestable with relative static data (its weight cancels "
            f"against the first reading of {n} series); it only moves the torque where "
            f"backlash switches: add absolute sag or modal data")


def _balancer_note(problem) -> str:
    if problem is None or problem.arm.chain.n_joints < 2:
        return ("joint-2 gravity balancer: a q2-dependent stiffness needs series at "
                "several q2")
    q2 = _angles_deg(problem, 1)
    listed = ", ".join(f"{v:.0f}" for v in q2)
    if len(q2) >= 3:
        return (f"joint-2 gravity balancer: tested as a candidate (series at q2 = {listed} "
                f"deg)")
    return (f"joint-2 gravity balancer: untestable: the series span {len(q2)} q2 value(s) "
            f"({listed} deg) and a torque constant within a series cancels: add series at "
            f"3 or more q2")


def _kinematics_note(structure) -> str:
    head = ("kinematic errors (tool offset, DH): the file holds displacements relative to "
            "each series' first reading, so only their effect on the load's lever arms shows")
    if structure is None:
        return head
    tests = {t.name: t for t in structure.tests}
    parts = [f"{tests[k].label} p {tests[k].p_value:.2g}" for k in ("tool", "joint_angle")
             if k in tests]
    seen = any(tests[k].found for k in ("tool", "joint_angle") if k in tests)
    return (head + (": a load-linear residual is left (" if seen else ": none is left (")
            + "; ".join(parts) + ")")


def span_corr(A: np.ndarray, B: np.ndarray) -> float:
    """Largest canonical correlation of the column spaces of ``A`` and ``B`` (m, k)."""
    def basis(X):
        X = X.reshape(len(X), -1)
        U, sv, _ = np.linalg.svd(X, full_matrices=False)
        return U[:, sv > sv.max() * 1e-8] if sv.size and sv.max() > 0 else U[:, :0]

    Qa, Qb = basis(A), basis(B)
    if not Qa.shape[1] or not Qb.shape[1]:
        return 0.0
    return float(np.linalg.svd(Qa.T @ Qb, compute_uv=False).max())


def signature_corr(A: np.ndarray, B: np.ndarray) -> float:
    """``|cos|`` of the angle between the first columns of two signatures (m, k)."""
    a, b = A.reshape(len(A), -1)[:, 0], B.reshape(len(B), -1)[:, 0]
    den = np.linalg.norm(a) * np.linalg.norm(b)
    return float(abs(a @ b) / den) if den > 0 else 0.0


def mimic(problem: Problem, fit, s: Screen) -> str:
    """Name the current-model parameter whose sensitivity best mimics the signature."""
    X = fit.sensitivity
    sig = signature(problem, fit.effects, s.candidate, s.grid_value)[:, 0]
    c = np.abs(X.T @ sig) / np.maximum(np.linalg.norm(X, axis=0) * np.linalg.norm(sig), 1e-300)
    k = int(np.argmax(c)) if c.size else 0
    i, name = fit.free[k]
    e = fit.effects[i]
    what = "torsion compliance" if e.kind == "stiffness" else f"{e.kind} {name}"
    return f"with {e.label.replace(' stiffness', '')} {what} (corr {c[k]:.2f})"


def links_note(problem: Problem, fit, s: Screen, status: str) -> str:
    """Why link flexibility is (not) seen, and what data would show it."""
    has_modal = isinstance(problem, ModalProblem)
    text = (f"with the joint compliances: only {s.unique:.1%} of its signature (flexible minus "
            f"E-model, norm {s.norm:.0f} sigma) is not mimicked by them; best single match: "
            f"{mimic(problem, fit, s)[5:]}") if status == "aliased" else (
            f"unique part of its signature {s.unique:.1%} gives dBIC {s.dbic:.1f}")
    if not has_modal:
        text += "; undetectable from TCP-only static data: add modal data (--modal)"
    return text


def base_note(screens) -> str:
    """Why base twist is not a candidate, and how base tilt and joint-1 tilt correlate."""
    by = {s.candidate.name: s for s in screens}
    note = "base twist about z is the same motion as joint-1 torsion (absorbed by it)"
    if "base" in by and "tilt_j1" in by:
        corr = signature_corr(by["base"].columns, by["tilt_j1"].columns)
        note += f"; base tilt vs joint-1 bearing tilt: corr {corr:.2f} after the baseline"
    return note
