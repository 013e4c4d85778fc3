"""Model versions of a diagnosis: what each one leaves in the data (static RMS, the
paired frequencies' error, unpaired modes), and why a candidate cannot be tested."""

from __future__ import annotations

import numpy as np

from ..static.candidates import load_proposal
from ..static.fit import Problem, chi2_band
from .results import Step

__all__ = ["static_rms", "modal_error", "version", "untestable_detail"]


def static_rms(problem: Problem, effects) -> float:
    """RMS [m] of the static residual of the model with ``effects`` (reference readings
    left out)."""
    r = (problem.y - problem.predict(effects))[~problem.is_ref]
    return float(np.sqrt(np.mean(r**2))) if r.size else float("nan")


def modal_error(problem: Problem, effects) -> dict:
    """``freq_rms`` (RMS relative error [-] of the paired measured frequencies) and
    ``n_unpaired`` of the model with ``effects``; empty without modal data."""
    if not getattr(problem, "n_modal", 0):
        return {}
    pr = problem.pairing(effects)
    rel = (pr["model_hz"] - problem.f_meas)[pr["paired"]] / problem.f_meas[pr["paired"]]
    return {"freq_rms": float(np.sqrt(np.mean(rel**2))) if rel.size else float("nan"),
            "n_unpaired": int((~pr["paired"]).sum())}


def version(problem: Problem, label: str, fr, heldout: float) -> Step:
    """The :class:`Step` of the fitted model ``fr`` (a ``FitResult``) with its held-out
    RMS ``heldout`` [m], before any candidate is screened against it."""
    return Step(label, fr.effects, fr.chi2_red, chi2_band(fr.dof), fr.dof,
                static_rms(problem, fr.effects), heldout, **modal_error(problem, fr.effects))


def untestable_detail(problem: Problem, c, poses) -> str:
    """Why candidate ``c`` cannot be tested on these data, and what data would test it."""
    if c.joint is not None and not np.any(np.abs(problem.J[:, :, c.joint]) > 1e-9):
        return (f"joint {c.joint + 1} turns the TCP about its own axis: invisible in "
                f"TCP translations; measure TCP rotations (rx, ry, rz)")
    if c.kind in ("backlash", "hysteresis"):
        return "add these loads: " + load_proposal(problem, c.joint, c.kind, extra_poses=poses)
    return "the data barely load it: add poses/loads that do"
