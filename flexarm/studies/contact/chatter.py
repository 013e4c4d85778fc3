"""Mode-coupling chatter: the 2-DOF model of thesis eqs. 2.19–2.21 built from the arm.

Model (in a machining plane with orthonormal axes ``e1, e2``, coordinates ``x`` [m])::

    M x'' + C x' + (K + k_p f n^T) x = 0,        k_p = K_c b  [N/m]

``n`` is the unit surface normal (tool motion along ``+n`` thins the chip,
``d = d0 - n.x``, eq. 2.21) and ``f`` the unit cutting-force direction on the tool, at
the angle ``dir`` from ``n`` (eqs. 2.19/2.20: the force ``K_c b d`` acts along ``f``).
The process stiffness ``k_p f n^T`` is asymmetric unless ``dir = 0``.

From the arm at a pose (:func:`plane_model`):

* ``K = (P^T C P)^-1``: condensed static stiffness, ``C`` the 3x3 translational TCP
  compliance and ``P = [e1 e2]`` (all other TCP loads zero, not a diagonal model).
* The two *dominant modes* ``r`` (largest in-plane static contribution
  ``|P^T psi_r|^2 / omega_r^2``; the second chosen across the first's direction) have
  in-plane shapes ``Psi = P^T [psi_r1 psi_r2]`` (2x2) of mass-normalised modes.  The
  two-mode truncation ``x = Psi eta``, ``eta'' + 2 zeta omega eta' + omega^2 eta =
  Psi^T F`` is, in ``x``: ``M = Psi^-T Psi^-1``, ``C = Psi^-T diag(2 zeta_r omega_r)
  Psi^-1``.  With the exact static ``K`` above (it includes the residual flexibility of
  the other modes) the 2-DOF frequencies lie at or below the modal ones.

Stability (closed form): ``p(s) = det(M s^2 + C s + K_tot) = a4 s^4 + ... + a0``;
stable iff all ``a_i > 0``, ``a3 a2 - a4 a1 > 0`` and ``a1 (a2 a3 - a1 a4) - a0 a3^2 > 0``
(Routh–Hurwitz).  Undamped: unstable iff ``M^-1 K_tot`` has complex eigenvalues
(discriminant < 0, flutter) or a negative one (divergence).  Every ``a_i`` is affine in
``k_p`` (rank-one process), so the limit ``k_p`` is a polynomial root
(:mod:`.chatter_map`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ...assembly.analyses import modes, tcp_compliance
from ...assembly.system import ArmModel
from ...fe.typing import ArrayLike, FloatArray
from ...robot.kinematics import tcp_frame
from ..tolerances import tol

__all__ = ["PlaneModel", "plane_axes", "plane_model", "cnc_model", "process_vectors",
           "char_poly", "hurwitz", "is_stable", "growth_rate", "flutter_discriminant",
           "simulate", "ChatterResult", "analyse"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class PlaneModel:
    """2-DOF structure in a machining plane.

    Attributes
    ----------
    M, C, K : (2, 2) float
        Effective mass [kg], damping [N s/m] and stiffness [N/m] in the plane axes.
    axes : (2, 3) float
        ``e1, e2`` in the base frame.
    freq_hz : (2,) float
        Frequencies of the two dominant arm modes [Hz] (NaN for a typed-in machine).
    name : str
    """

    M: FloatArray
    C: FloatArray
    K: FloatArray
    axes: FloatArray
    freq_hz: FloatArray
    name: str = "robot"

    @property
    def principal_stiffness(self) -> tuple[FloatArray, FloatArray]:
        """Eigenvalues [N/m] (ascending) and in-plane directions (2, 2 columns) of ``K``."""
        return np.linalg.eigh(self.K)


def plane_axes(tool_axis: ArrayLike, first: ArrayLike = (0.0, 1.0, 0.0)) -> FloatArray:
    """(2, 3) axes of the plane normal to ``tool_axis``: ``first`` projected, then ``t x e1``.

    Falls back to base x when ``first`` is (nearly) along the tool axis.
    """
    t = np.asarray(tool_axis, dtype=float)
    t = t / np.linalg.norm(t)
    for ref in (np.asarray(first, dtype=float), np.eye(3)[0]):
        e1 = ref - (ref @ t) * t
        if np.linalg.norm(e1) > 0.1:
            e1 = e1 / np.linalg.norm(e1)
            return np.array([e1, np.cross(t, e1)])
    return np.array([np.eye(3)[1], np.cross(t, np.eye(3)[1])])


def plane_model(arm: ArmModel, q: ArrayLike, axes: ArrayLike | None = None) -> PlaneModel:
    """:class:`PlaneModel` of the arm at the pose ``q`` (6,) [rad].

    Parameters
    ----------
    arm : ArmModel
    q : (6,) float
    axes : (2, 3) float, optional
        Orthonormal plane axes in the base frame; default: normal to the tool axis
        (TCP z), ``e1`` nearest base y (:func:`plane_axes`).

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.assembly import emodel
    >>> r = load_demo_robot()
    >>> pm = plane_model(emodel(r, method="surface"), r.pose("P1"))
    >>> bool(pm.principal_stiffness[0][0] < 2e5)  # the weak (Y) axis
    True
    """
    q = np.asarray(q, dtype=float)
    P = (plane_axes(tcp_frame(arm.chain, q)[:3, 2]) if axes is None
         else np.asarray(axes, dtype=float)).reshape(2, 3)
    if np.abs(P @ P.T - np.eye(2)).max() > tol.plane_orthonormal:
        raise ValueError("plane axes must be orthonormal (2, 3)")
    C3 = tcp_compliance(arm, q)[:3, :3]
    K = np.linalg.inv(P @ C3 @ P.T)
    md = modes(arm, q)
    psi = P @ md.tcp_shapes[:3]  # (2, n) in-plane modal displacements
    w = md.omega
    contrib = np.sum(psi**2, axis=0) / np.maximum(w, np.finfo(float).tiny) ** 2
    r1 = int(np.argmax(contrib))
    d1 = psi[:, r1] / np.linalg.norm(psi[:, r1])
    across = (psi[0] * d1[1] - psi[1] * d1[0]) ** 2 / np.maximum(w, np.finfo(float).tiny) ** 2
    across[r1] = -1.0
    r2 = int(np.argmax(across))
    r = np.array([r1, r2])
    Psi_inv = np.linalg.inv(psi[:, r])
    M = Psi_inv.T @ Psi_inv
    Cd = Psi_inv.T @ np.diag(2 * md.damping[r] * w[r]) @ Psi_inv
    sym = lambda A: 0.5 * (A + A.T)  # noqa: E731
    return PlaneModel(sym(M), sym(Cd), sym(K), P, md.freq_hz[r], "robot")


def cnc_model(stiffness: float | ArrayLike = 5e7, mass: float | ArrayLike = 100.0,
              damping_ratio: float = 0.03, axes: ArrayLike | None = None) -> PlaneModel:
    """A typed-in machine: diagonal stiffness [N/m] and mass [kg] along the plane axes.

    A scalar ``stiffness`` gives ``(k, 1.2 k)`` (a typical 20 % difference between
    axes, so that mode coupling is possible in principle); damping is stiffness- and
    mass-proportional per axis at ``damping_ratio``.
    """
    k = np.atleast_1d(np.asarray(stiffness, dtype=float))
    k = np.array([k[0], 1.2 * k[0]]) if k.size == 1 else k.reshape(2)
    m = np.broadcast_to(np.asarray(mass, dtype=float), (2,)).copy()
    P = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]) if axes is None else np.asarray(axes)
    return PlaneModel(np.diag(m), np.diag(2 * damping_ratio * np.sqrt(k * m)), np.diag(k), P,
                      np.sqrt(k / m) / (2 * np.pi), "CNC")


def process_vectors(normal_deg: float, dir_deg: float) -> tuple[FloatArray, FloatArray]:
    """In-plane unit normal ``n`` (``normal_deg`` from e1) and force ``f`` (``dir_deg`` from n)."""
    a, b = np.radians(normal_deg), np.radians(normal_deg + dir_deg)
    return np.array([np.cos(a), np.sin(a)]), np.array([np.cos(b), np.sin(b)])


def _conv(a: FloatArray, b: FloatArray) -> FloatArray:
    """Product of quadratics ``a0 s^2 + a1 s + a2`` (last axis), highest power first."""
    return np.stack([a[..., 0] * b[..., 0], a[..., 0] * b[..., 1] + a[..., 1] * b[..., 0],
                     a[..., 0] * b[..., 2] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 0],
                     a[..., 1] * b[..., 2] + a[..., 2] * b[..., 1], a[..., 2] * b[..., 2]],
                    axis=-1)


def char_poly(M: ArrayLike, C: ArrayLike, K: ArrayLike) -> FloatArray:
    """(..., 5) coefficients ``[a4, a3, a2, a1, a0]`` of ``det(M s^2 + C s + K)`` (batched)."""
    Q = np.stack(np.broadcast_arrays(np.asarray(M, float), np.asarray(C, float),
                                     np.asarray(K, float)), axis=-1)  # (..., 2, 2, 3)
    return _conv(Q[..., 0, 0, :], Q[..., 1, 1, :]) - _conv(Q[..., 0, 1, :], Q[..., 1, 0, :])


def hurwitz(a: ArrayLike) -> FloatArray:
    """(..., 6) Routh–Hurwitz quantities of a quartic; all > 0 iff stable.

    ``[a3, a2, a1, a0, a3 a2 - a4 a1, a1 (a2 a3 - a1 a4) - a0 a3^2]`` for ``a4 > 0``.
    """
    a = np.asarray(a, dtype=float)
    a4, a3, a2, a1, a0 = np.moveaxis(a, -1, 0)
    d2 = a3 * a2 - a4 * a1
    return np.stack([a3, a2, a1, a0, d2, a1 * d2 - a0 * a3 * a3], axis=-1)


def is_stable(a: ArrayLike) -> np.ndarray:
    """(...) bool: closed-form (Routh–Hurwitz) stability of ``det(M s^2 + C s + K)``."""
    return np.all(hurwitz(a) > 0, axis=-1)


def _state_matrix(M, C, K) -> FloatArray:
    Minv = np.linalg.inv(M)
    n = M.shape[-1]
    A = np.zeros(M.shape[:-2] + (2 * n, 2 * n))
    A[..., :n, n:] = np.eye(n)
    A[..., n:, :n] = -Minv @ K
    A[..., n:, n:] = -Minv @ C
    return A


def growth_rate(M: ArrayLike, C: ArrayLike, K: ArrayLike) -> FloatArray:
    """(...) largest real part [1/s] of the eigenvalues of the 2-DOF system (batched)."""
    A = _state_matrix(np.asarray(M, float), np.asarray(C, float), np.asarray(K, float))
    return np.linalg.eigvals(A).real.max(axis=-1)


def flutter_discriminant(M: ArrayLike, K: ArrayLike) -> FloatArray:
    """(...) ``tr(A)^2 - 4 det(A)`` of ``A = M^-1 K`` [1/s^4]; < 0: undamped flutter."""
    A = np.linalg.solve(np.asarray(M, float), np.asarray(K, float))
    tr = A[..., 0, 0] + A[..., 1, 1]
    return tr * tr - 4 * np.linalg.det(A)


def simulate(M: ArrayLike, C: ArrayLike, K: ArrayLike, x0: ArrayLike, t_end: float,
             n_steps: int = 4000) -> tuple[FloatArray, FloatArray]:
    """Free response after a disturbance ``x0`` (2,) [m], by the exact matrix exponential.

    Returns
    -------
    t : (n_steps + 1,) float
        Times [s].
    x : (n_steps + 1, 2) float
        Plane coordinates [m].
    """
    from scipy.linalg import expm

    A = _state_matrix(np.asarray(M, float), np.asarray(C, float), np.asarray(K, float))
    dt = t_end / n_steps
    step = expm(A * dt)
    z = np.zeros((n_steps + 1, 4))
    z[0, :2] = x0
    for i in range(n_steps):
        z[i + 1] = step @ z[i]
    return np.linspace(0.0, t_end, n_steps + 1), z[:, :2]


@dataclass(frozen=True)
class ChatterResult:
    """Closed-form verdict of one structure under one process.

    Attributes
    ----------
    structure : PlaneModel
    kcb : float
        Process stiffness ``K_c b`` [N/m].
    n, f : (2,) float
        Surface normal and force direction in the plane axes.
    K_total : (2, 2) float
        ``K + K_c b f n^T`` [N/m].
    coefficients : (5,) float
        ``det(M s^2 + C s + K_total)``, highest power first.
    is_stable : bool
        Routh–Hurwitz verdict.
    growth_rate : float
        Largest eigenvalue real part [1/s] (> 0: chatter grows).
    discriminant : float
        Undamped flutter discriminant [1/s^4] (< 0: mode coupling without damping).
    """

    structure: PlaneModel
    kcb: float
    n: FloatArray
    f: FloatArray
    K_total: FloatArray
    coefficients: FloatArray
    is_stable: bool
    growth_rate: float
    discriminant: float


def analyse(structure: PlaneModel, kcb: float, dir_deg: float,
            normal_deg: float = 0.0) -> ChatterResult:
    """Closed-form stability of ``structure`` under ``K_c b`` [N/m] along ``dir_deg``.

    Examples
    --------
    >>> res = analyse(cnc_model(5e7), 2e6, 30.0)
    >>> res.is_stable, bool(res.growth_rate < 0)
    (True, True)
    """
    n, f = process_vectors(normal_deg, dir_deg)
    Kt = structure.K + kcb * np.outer(f, n)
    a = char_poly(structure.M, structure.C, Kt)
    return ChatterResult(structure, float(kcb), n, f, Kt, a, bool(is_stable(a)),
                         float(growth_rate(structure.M, structure.C, Kt)),
                         float(flutter_discriminant(structure.M, Kt)))
