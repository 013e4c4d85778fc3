"""Tolerances of the chatter models (``tol.<name>``)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Largest ``|P P^T - I|`` entry of user-given machining-plane axes (chatter model).
    plane_orthonormal: float = 1e-9
    #: Relative step above a candidate limit K_c b at which stability is re-checked.
    chatter_limit_probe: float = 1e-7


tol = Tolerances()
