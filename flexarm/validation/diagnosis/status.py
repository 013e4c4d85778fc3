"""The status of each screened candidate in one round of the diagnosis, and why:
accepted, rejected (with the checks it failed), aliased (with what it mimics or the
proxy that explains more) or untestable (with the data that would test it)."""

from __future__ import annotations

from ..static.candidates import Screen, status_of
from ..static.fit import Problem
from ..tolerances import tol
from .explain import base_note, links_note, mimic, signature_corr
from .results import CandidateReport
from .versions import untestable_detail

__all__ = ["candidate_report"]


def candidate_report(problem: Problem, fr, s: Screen, screens, best: Screen | None,
            refit, poses) -> CandidateReport:
    """The status of the screened candidate ``s`` in this round and why."""
    c = s.candidate
    st, detail = _status(problem, fr, s, best, refit, poses)
    if c.kind == "base":
        detail = (detail + "; " if detail else "") + base_note(screens)
    if c.kind == "links" and st in ("rejected", "untestable"):
        detail = (detail + "; " if detail else "") + links_note(problem, fr, s, st)
    return CandidateReport(c.name, c.label, st, s.dbic, s.unique, s.norm, detail)


def _status(problem: Problem, fr, s: Screen, best: Screen | None, refit,
            poses) -> tuple[str, str]:
    """Status and detail of ``s`` before the notes on the base and link candidates."""
    st = status_of(s)
    c = s.candidate
    winner = None if refit is None else refit.winner
    if st == "untestable":
        return st, untestable_detail(problem, c, poses)
    if st == "aliased":
        return st, (links_note(problem, fr, s, "aliased") if c.kind == "links"
                    else mimic(problem, fr, s))
    if winner is not None and c.name == winner.name and refit.proxies:
        p = max(refit.proxies, key=lambda x: x.dchi2)
        return "aliased", (f"with {p.candidate.label} (a proxy: their unique signatures "
                           f"correlate {signature_corr(p.columns, s.columns):.2f} and "
                           f"{p.candidate.label} explains more, dchi2 {p.dchi2:.0f} vs "
                           f"{s.dchi2:.0f})")
    if winner is not None and c.name == winner.name:
        ok = winner.checks.passed
        return ("accepted" if ok else "rejected",
                "" if ok else "failed: " + ", ".join(winner.checks.failed))
    if winner is not None and signature_corr(s.columns, best.columns) > tol.alias_correlation:
        return "aliased", f"with {winner.label} (same pattern on this data)"
    return "rejected", ""
