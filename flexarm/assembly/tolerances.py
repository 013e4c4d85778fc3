"""Tolerances of the arm eigen-solve and of effects applied to a model (``tol.<name>``)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Arm eigenproblem: when lambda_min / lambda_max of ``K phi = lambda M phi`` falls
    #: below this, the highest modes are taken from the Cholesky-of-M form as well (the
    #: inverse form alone keeps them to ~eps / spread).
    eig_spread: float = 1e-10
    #: Stiffness of "rigid" directions of a foundation spring [N/m, N m/rad].
    rigid_foundation: float = 1e13
    #: Floor of a joint compliance scale factor during fits [-] (keeps stiffness > 0).
    min_compliance_scale: float = 1e-6


tol = Tolerances()
