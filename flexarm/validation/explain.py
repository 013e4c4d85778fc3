"""One-sentence explanations of a diagnosed effect, and notes on effects static data cannot see."""

from __future__ import annotations

import numpy as np

from ..assembly.system import ArmModel

__all__ = ["explain", "static_notes"]


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


def explain(problem, cand, effect, theta, se) -> str:
    """A sentence a user understands, with the fitted size and where the data show it."""
    j = cand.joint
    if cand.kind == "backlash":
        return (f"joint {j + 1} backlash of {theta[0] * 1e3:.3f} ± {se[0] * 1e3:.3f} mrad: "
                f"residuals jump where joint {j + 1} torque changes sign at "
                f"{_switch_loads(problem, j)}")
    if cand.kind == "hardening":
        k2 = problem.arm.joints[j].torsion
        ratio = 1 / (1 + theta[0] * k2)
        return (f"joint {j + 1} stiffens with load: K1 = {ratio:.2f} K2 below "
                f"{effect.get('threshold'):.0f} N m (extra compliance {theta[0]:.3g} ± "
                f"{se[0]:.2g} rad/(N m)): deflection grows faster than linear at low load "
                f"and straightens above")
    if cand.kind == "hysteresis":
        return (f"joint {j + 1} lost motion of {theta[0] * 1e3:.3f} ± {se[0] * 1e3:.3f} mrad "
                f"(friction torque {effect.get('radius'):.0f} N m): unloading curves lie off "
                f"the loading curves once the load reverses")
    if cand.kind == "tilt":
        return (f"joint {j + 1} bearing tilt compliance {theta[0]:.3g} ± {se[0]:.2g} rad/(N m) "
                f"(stiffness {1 / theta[0]:.3g} N m/rad): deflections perpendicular to the "
                f"joint-{j + 1} rotation are larger than the gear alone explains")
    if cand.kind == "base":
        return (f"base (foundation) tilt compliance {theta[0]:.3g} ± {se[0]:.2g} rad/(N m) "
                f"(stiffness {1 / theta[0]:.3g} N m/rad): the whole arm tips about the floor "
                f"by the moment of the load about the base")
    if cand.kind == "wrist":
        names = [k for k, v in effect.params if v != 0] or list(cand.amplitudes)
        vals = ", ".join(f"{a} = {t:.3g} ± {s:.2g}"
                         for a, t, s in zip(names, theta, se, strict=False))
        return (f"coupled wrist: joints 4-6 share compliance ({vals} rad/(N m)): a torque on "
                f"one wrist joint also turns the others")
    if cand.kind == "links":
        return (f"link flexibility: the links are {theta[0]:.2f} ± {se[0]:.2f} times as "
                f"compliant as the CAD flexible model: with the joint compliances fitted to "
                f"the statics, the rigid-link model cannot also match the natural "
                f"frequencies")
    return f"{cand.label}: {theta}"


def static_notes(arm: ArmModel, links_tested: bool = False) -> tuple[str, ...]:
    """Effects of the library that relative static TCP data cannot test, and why."""
    flexible = any(not b.is_rigid for b in arm.bodies)
    notes = [
        "payload mass: untestable with relative static data (its weight cancels against the "
        "first reading); it only moves the torque where backlash switches: add absolute sag "
        "or modal data",
        "joint-2 gravity compensator: untestable with relative static data at fixed poses "
        "(a q2-dependent torque is constant within a series): add series at several q2",
        "kinematic (DH) errors: not applicable: the file holds displacements relative to "
        "each series' first reading, not absolute positions",
    ]
    if flexible:
        notes.append("link flexibility: part of this model (flexible links)")
    elif not links_tested:
        notes.append("link flexibility: aliased/undetectable from TCP-only static data "
                      "(link bending scales with the same loads as the joint compliances); "
                      "not tested here: give the flexible model (diagnose --flexible) and "
                      "modal data (--modal)")
    return tuple(notes)
