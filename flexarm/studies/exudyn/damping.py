"""Proportional dampers that give the arm's modal damping ratios (for Exudyn).

Exudyn damps a joint spring with a viscous damper and a flexible body with
stiffness-proportional damping; our arm model damps each mode with its own ratio
(the joint and link ratios weighted by the mode's strain energy).  Give every spring
``k`` of a joint, the foundation and every link its own time constant ``tau`` (damper
``c = tau k``, or ``beta = tau`` for a link): mode ``r`` then has
``zeta_r ~ omega_r / 2 * sum_k tau_k e_kr`` with ``e_kr`` the share of its strain energy
in spring ``k``.  The ``tau_k >= 0`` are fitted to our ratios of the lowest ``n_fit``
modes (weighted relative least squares, non-negative), pulled weakly towards
``2 zeta_k / omega`` at the mode where spring ``k`` stores most energy.  The ratios the
dampers really give (complex eigenvalues of ``M, C, K``) come with the fit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

from ...assembly.analyses import modes
from ...assembly.system import ArmModel, system_matrices
from ...fe.typing import ArrayLike, FloatArray

__all__ = ["ProportionalDamping", "fit_damping", "damping_matrix", "damping_ratios"]


@dataclass(frozen=True, eq=False)
class ProportionalDamping:
    """Time constants of the arm's dampers [s].

    Attributes
    ----------
    joint_tau : tuple of (k_j,) float
        Per joint, per free DOF (order of ``JointModel.free_dofs``): damper = tau x spring.
    link_beta : (n_bodies,) float
        Stiffness-proportional factor of each body (0 for rigid bodies).
    foundation_tau : float
        Of the foundation spring (0 when the base is clamped).
    zeta_target, zeta_fit : (n_fit,) float
        Our modal ratios and those the dampers give (complex eigenvalues) [-].
    """

    joint_tau: tuple
    link_beta: FloatArray
    foundation_tau: float
    zeta_target: FloatArray
    zeta_fit: FloatArray


def _energy_columns(arm: ArmModel, Phi: FloatArray, K: FloatArray):
    """(n_springs, n) strain energy of each spring per mode, the springs' names' groups
    (``joint``, ``link``, ``foundation``) and the prior ratio of each."""
    lay = arm.layout
    Ks = arm.spring_stiffness()
    rows, kinds, ratios = [], [], []
    if arm.foundation is not None:
        f = lay["foundation"]
        rows.append(np.einsum("ir,ij,jr->r", Phi[f], Ks[np.ix_(f, f)], Phi[f]))
        kinds.append(("foundation", 0, 0))
        ratios.append(arm.foundation_damping)
    for j, (idx, jm) in enumerate(zip(lay["joint"], arm.joints, strict=True)):
        for d, col in enumerate(idx):
            rows.append(Ks[col, col] * Phi[col] ** 2)
            kinds.append(("joint", j, d))
            ratios.append(jm.damping_ratio)
    for i, (idx, b) in enumerate(zip(lay["body"], arm.bodies, strict=True)):
        if b.is_rigid or idx.size == 0:
            continue
        Kb = np.asarray(b.K, dtype=float)[6:, 6:]
        rows.append(np.einsum("ir,ij,jr->r", Phi[idx], Kb, Phi[idx]))
        kinds.append(("link", i, 0))
        ratios.append(b.damping_ratio)
    return np.array(rows), kinds, np.array(ratios)


def fit_damping(arm: ArmModel, q: ArrayLike, n_fit: int = 4, prior_weight: float = 1e-3,
                decay: float = 2.0) -> ProportionalDamping:
    """Fit the dampers to our modal ratios of the lowest ``n_fit`` modes at ``q`` [rad],
    mode ``r`` weighted by ``(omega_1 / omega_r)^decay``.

    A viscous damper damps a spring's share of a mode in proportion to the mode's
    frequency, so one joint that strains both a low and a high mode cannot give both our
    (frequency-independent) ratio: the fit favours the lowest modes (demo arm, P1-P3,
    E-model and CB: the first four within 1 %) and leaves higher modes over-damped
    (3-10x from the fifth on).

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> pd = fit_damping(two_link_arm(), [0.0, 0.5])
    >>> pd.zeta_target.tolist(), pd.zeta_fit.round(4).tolist()
    ([0.02, 0.02], [0.02, 0.02])
    """
    md = modes(arm, q)
    n = min(int(n_fit), md.freq_hz.size)
    w, Phi, zeta = md.omega[:n], md.shapes[:, :n], md.damping[:n]
    sm = system_matrices(arm, np.asarray(q, dtype=float))
    E, kinds, ratios = _energy_columns(arm, Phi, sm.K)
    E = E / w**2  # strain energy of a mass-normalised mode is omega^2 / 2: shares
    A = (0.5 * w * E).T  # zeta_r = sum_k A_rk tau_k
    home = np.argmax(E, axis=1)
    prior = 2 * ratios / w[home]
    active = E.max(axis=1) > 1e-9  # springs no fitted mode strains keep the prior
    weight = (w[0] / w) ** decay  # the lowest modes first: one tau cannot fit all
    rows = np.vstack([A[:, active] * (weight / zeta)[:, None],
                      prior_weight * np.diag(1 / prior[active])])
    rhs = np.concatenate([weight, prior_weight * np.ones(active.sum())])
    tau = prior.copy()
    tau[active] = nnls(rows, rhs)[0]
    joint = [np.zeros(len(jm.free_dofs)) for jm in arm.joints]
    beta, found = np.zeros(len(arm.bodies)), 0.0
    for (kind, i, d), t in zip(kinds, tau, strict=True):
        if kind == "joint":
            joint[i][d] = t
        elif kind == "link":
            beta[i] = t
        else:
            found = float(t)
    pd = ProportionalDamping(tuple(joint), beta, found, zeta, np.zeros(n))
    return ProportionalDamping(pd.joint_tau, beta, found, zeta,
                               damping_ratios(arm, q, pd)[:n])


def damping_matrix(arm: ArmModel, pd: ProportionalDamping) -> FloatArray:
    """(n_x, n_x) viscous damping of the dampers ``pd`` on the arm's coordinates."""
    lay = arm.layout
    Ks = arm.spring_stiffness()
    C = np.zeros_like(Ks)
    if arm.foundation is not None:
        f = lay["foundation"]
        C[np.ix_(f, f)] = pd.foundation_tau * Ks[np.ix_(f, f)]
    for idx, tau in zip(lay["joint"], pd.joint_tau, strict=True):
        C[idx, idx] = tau * Ks[idx, idx]
    for idx, b, beta in zip(lay["body"], arm.bodies, pd.link_beta, strict=True):
        if idx.size and beta:
            C[np.ix_(idx, idx)] = beta * np.asarray(b.K, dtype=float)[6:, 6:]
    return C


def damping_ratios(arm: ArmModel, q: ArrayLike, pd: ProportionalDamping) -> FloatArray:
    """(n_x,) damping ratios [-] of the arm with the dampers ``pd``, ascending by
    frequency: ``-Re(s) / |s|`` of the eigenvalues of ``M s^2 + C s + K``."""
    sm = system_matrices(arm, np.asarray(q, dtype=float))
    n = sm.K.shape[0]
    Minv = np.linalg.inv(sm.M)
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-Minv @ sm.K, -Minv @ damping_matrix(arm, pd)]])
    s = np.linalg.eigvals(A)
    s = s[s.imag > 0] if np.count_nonzero(s.imag > 0) == n else s[np.argsort(-s.imag)][:n]
    s = s[np.argsort(np.abs(s))]
    return -s.real / np.abs(s)
