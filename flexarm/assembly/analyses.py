"""Analyses of an assembled arm at a pose: modes, TCP compliance, FRF, gravity sag.

Every function takes an :class:`~flexarm.assembly.system.ArmModel` (or the full-FE arm,
:class:`~flexarm.assembly.full_arm.FullFEArm`, solved pose by pose) and joint angles
``q`` (..., n) [rad]; those marked *batched* accept many poses at once.  Loads and
displacements at the TCP are in the base frame: (F_x, F_y, F_z [N], M_x, M_y, M_z
[N m]) and (u_x, u_y, u_z [m], theta_x, theta_y, theta_z [rad]).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from scipy.linalg import lapack

from ..fe.typing import ArrayLike, FloatArray
from .batched import constant_stiffness, fast_tcp_compliance, has_constant_stiffness, mass_matrix
from .full_arm import (
    FullFEArm,
    full_frf,
    full_gravity_sag,
    full_modes,
    full_natural_frequencies,
    full_tcp_compliance,
)
from .modal import Modes
from .system import ArmModel, rotation_blocks, system_matrices
from .tolerances import tol

__all__ = [
    "Modes",
    "modes",
    "natural_frequencies",
    "tcp_compliance",
    "diagonal_compliance",
    "stiffness_from_load_cases",
    "IdentificationReport",
    "identify_stiffness",
    "frf",
    "gravity_sag",
]

log = logging.getLogger(__name__)

#: Standard gravity [m/s^2], along -z of the base frame.
GRAVITY = np.array([0.0, 0.0, -9.80665])


def _mass_form_eigh(K: FloatArray, M: FloatArray, vectors: bool):
    """Batched ``K phi = lambda M phi`` via Cholesky of ``M`` (accurate for high modes)."""
    Linv = np.linalg.inv(np.linalg.cholesky(M))
    A = Linv @ K @ np.swapaxes(Linv, -1, -2)
    A = 0.5 * (A + np.swapaxes(A, -1, -2))
    if not vectors:
        return np.linalg.eigvalsh(A), None
    lam, Y = np.linalg.eigh(A)
    return lam, np.swapaxes(Linv, -1, -2) @ Y


def _lower_inverse(L: FloatArray) -> FloatArray:
    """``L^-1`` of a lower-triangular ``L`` (n, n) or (..., n, n): LAPACK's triangular
    inverse for one matrix (a third of a general inverse's work), NumPy's for a stack."""
    if L.ndim != 2:
        return np.linalg.inv(L)
    Linv, info = lapack.dtrtri(L, lower=1)
    if info != 0:
        raise np.linalg.LinAlgError(f"singular triangular factor (dtrtri info {info})")
    return np.tril(Linv)


def _generalized_eigh(K: FloatArray, M: FloatArray, vectors: bool = True):
    """Batched ``K phi = lambda M phi``: ascending ``lambda`` and mass-normalised ``phi``.

    ``K`` (n, n) or (..., n, n), ``M`` (..., n, n).  When ``K`` is positive definite the
    problem is solved in inverse form, ``L^-1 M L^-T y = mu y`` with ``K = L L^T`` and
    ``lambda = 1 / mu``: the *lowest* modes are then the largest ``mu`` and keep full
    relative accuracy even when ``K`` spans many decades (links with E x 1e6: the
    Cholesky-of-M form loses ``eps lambda_max / lambda_1`` there, ~4e-4).  If the
    spread ``lambda_1 / lambda_n`` is below ``tol.eig_spread`` the modes above the
    geometric mean of the spectrum are taken from the Cholesky-of-M form, which is
    accurate for them.  A singular ``K`` (free base) uses the Cholesky-of-M form.
    A constant ``K`` (2-D) is factored once for all poses.
    """
    try:
        L = np.linalg.cholesky(K)
    except np.linalg.LinAlgError:
        return _mass_form_eigh(K, M, vectors)
    Linv = _lower_inverse(L)
    A = Linv @ M @ np.swapaxes(Linv, -1, -2)
    A = 0.5 * (A + np.swapaxes(A, -1, -2))
    if vectors:
        mu, Y = np.linalg.eigh(A)
        mu, Y = mu[..., ::-1], Y[..., ::-1]
    else:
        mu, Y = np.linalg.eigvalsh(A)[..., ::-1], None
    tiny = np.finfo(float).tiny
    lam = 1.0 / np.maximum(mu, tiny)
    Phi = None
    if vectors:
        Phi = (np.swapaxes(Linv, -1, -2) @ Y) / np.sqrt(np.maximum(mu, tiny))[..., None, :]
    if np.all(mu[..., -1] >= tol.eig_spread * mu[..., 0]):
        return lam, Phi
    lam_m, Phi_m = _mass_form_eigh(np.broadcast_to(K, M.shape), M, vectors)
    high = lam > np.sqrt(lam[..., :1] * lam_m[..., -1:])
    lam = np.where(high, lam_m, lam)
    if vectors:
        Phi = np.where(high[..., None, :], Phi_m, Phi)
    return lam, Phi


def natural_frequencies(arm: ArmModel, q: ArrayLike, chunk: int = 50) -> FloatArray:
    """(..., n_x) natural frequencies [Hz], ascending (*batched*).

    Arms with a pose-independent ``K`` (rigid or floating-frame flexible links, see
    :mod:`~flexarm.assembly.batched`) factor ``K`` once and assemble only ``M(q)``,
    ``chunk`` poses at a time (bounds memory and keeps the batches in cache).
    """
    if isinstance(arm, FullFEArm):
        return full_natural_frequencies(arm, q)
    q = np.asarray(q, dtype=float)
    if not has_constant_stiffness(arm):
        sm = system_matrices(arm, q)
        lam, _ = _generalized_eigh(sm.K, sm.M, vectors=False)
        return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)
    K = constant_stiffness(arm)
    flat = q.reshape(-1, q.shape[-1])
    lam = np.zeros((len(flat), K.shape[0]))
    for s in range(0, len(flat), chunk):
        lam[s : s + chunk] = _generalized_eigh(K, mass_matrix(arm, flat[s : s + chunk]),
                                               vectors=False)[0]
    return (np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)).reshape(q.shape[:-1] + (-1,))


def modes(arm: ArmModel, q: ArrayLike) -> Modes:
    """All modes of the arm at one pose ``q`` (n,) [rad].

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> m = modes(two_link_arm(), [0.0, 0.5])
    >>> m.freq_hz.shape, bool(m.freq_hz[0] < m.freq_hz[1])
    ((2,), True)
    """
    if isinstance(arm, FullFEArm):
        return full_modes(arm, q)
    sm = system_matrices(arm, np.asarray(q, dtype=float))
    lam, Phi = _generalized_eigh(sm.K, sm.M)
    omega = np.sqrt(np.clip(lam, 0.0, None))
    big = np.argmax(np.abs(Phi), axis=0)
    Phi = Phi * np.sign(Phi[big, np.arange(Phi.shape[1])])
    lay = arm.layout
    Ks = arm.spring_stiffness()
    e = Phi * (Ks @ Phi)  # energy density per coordinate, sums to phi^T K_s phi
    total = np.maximum(np.einsum("in,in->n", Phi, sm.K @ Phi), np.finfo(float).tiny)
    energy = np.array([e[idx].sum(axis=0) for idx in lay["joint"]]) / total
    zeta = np.zeros_like(omega)
    for jm, share in zip(arm.joints, energy, strict=True):
        zeta += share * jm.ratio(omega)
    if arm.foundation is not None:
        zeta += e[lay["foundation"]].sum(axis=0) / total * arm.foundation_damping
    flexible = [b.damping_ratio for b in arm.bodies if not b.is_rigid]
    if flexible:
        rest = 1 - energy.sum(axis=0) - (e[lay["foundation"]].sum(axis=0) / total)
        zeta += np.clip(rest, 0, None) * float(np.mean(flexible))
    return Modes(omega / (2 * np.pi), Phi, sm.G_tcp @ Phi, zeta, energy, arm.coordinate_names)


def tcp_compliance(arm: ArmModel, q: ArrayLike) -> FloatArray:
    """(..., 6, 6) TCP compliance ``G K^-1 G^T`` in the base frame (*batched*).

    Units: [m/N] for the translational block, [rad/(N m)] for the rotational one.
    """
    if isinstance(arm, FullFEArm):
        return full_tcp_compliance(arm, q)
    if has_constant_stiffness(arm):
        # K does not depend on the pose: K^-1 once, only the TCP map per pose
        return fast_tcp_compliance(arm, q)
    sm = system_matrices(arm, q)
    G = sm.G_tcp
    C = G @ np.linalg.solve(sm.K, np.swapaxes(G, -1, -2))
    return 0.5 * (C + np.swapaxes(C, -1, -2))


def diagonal_compliance(C: ArrayLike) -> FloatArray:
    """(..., 3, 3) diagonal-only translational compliance (thesis eq. 3.9).

    The axial stiffness ``K_ii = 1 / C_ii`` is the inverse static gain of a unit
    force in direction ``i``; coupling terms are dropped.
    """
    C = np.asarray(C, dtype=float)[..., :3, :3]
    return np.einsum("...ii->...i", C)[..., None] * np.eye(3)


def stiffness_from_load_cases(forces: ArrayLike, displacements: ArrayLike) -> FloatArray:
    """(3, 3) translational TCP stiffness from three load cases (thesis eq. 3.12).

    Parameters
    ----------
    forces : (3, 3) float
        Row ``k`` is the force [N] of load case ``k`` (three independent directions).
    displacements : (3, 3) float
        Row ``k`` is the measured TCP displacement [m] of load case ``k``.

    Returns
    -------
    (3, 3) float
        ``K`` with ``F_k = K x_k`` for all three cases (eq. 3.13, ``F = K X``).
    """
    Fm = np.asarray(forces, dtype=float).T
    Xm = np.asarray(displacements, dtype=float).T
    if Fm.shape != (3, 3) or Xm.shape != (3, 3):
        raise ValueError(f"forces and displacements must be (3, 3), got {Fm.shape}, {Xm.shape}")
    if abs(np.linalg.det(Xm)) < np.finfo(float).eps * np.abs(Xm).max() ** 3:
        raise ValueError("the three load cases give dependent displacements")
    return np.linalg.solve(Xm.T, Fm.T).T


@dataclass(frozen=True)
class IdentificationReport:
    """Stiffness identified from three simulated load cases at one pose.

    Attributes
    ----------
    forces, displacements : (3, 3) float
        Load cases (rows) [N] and TCP displacements [m].
    K_full : (3, 3) float
        Identified full stiffness (eq. 3.12) [N/m].
    K_diag : (3, 3) float
        Diagonal-only stiffness from axial static gains (eq. 3.9) [N/m].
    error_diag : (3,) float
        Relative error ``|x_diag - x| / |x|`` of the diagonal model per load case [-].
    error_full : (3,) float
        The same for the identified full matrix (round-off only) [-].
    """

    forces: FloatArray
    displacements: FloatArray
    K_full: FloatArray
    K_diag: FloatArray
    error_diag: FloatArray
    error_full: FloatArray


def identify_stiffness(arm: ArmModel, q: ArrayLike, forces: ArrayLike | None = None):
    """Identify the TCP stiffness from three load cases on the model (eq. 3.12).

    ``forces`` (3, 3), rows = load cases [N]; by default 800 N along +X, +Y, +Z.
    """
    Fk = 800.0 * np.eye(3) if forces is None else np.asarray(forces, dtype=float)
    C = tcp_compliance(arm, q)[:3, :3]
    X = Fk @ C.T
    K_full = stiffness_from_load_cases(Fk, X)
    K_diag = np.diag(1.0 / np.diag(C))
    x_diag = Fk @ np.linalg.inv(K_diag).T
    x_full = np.linalg.solve(K_full, Fk.T).T
    norm = np.linalg.norm(X, axis=1)
    return IdentificationReport(
        Fk, X, K_full, K_diag,
        np.linalg.norm(x_diag - X, axis=1) / norm,
        np.linalg.norm(x_full - X, axis=1) / norm,
    )


def frf(arm: ArmModel, q: ArrayLike, freq_hz: ArrayLike, damping: ArrayLike | None = None):
    """TCP receptance ``H(f)`` (nf, 6, 6) complex: TCP motion per TCP load (base frame).

    Modal superposition over all modes with the modal damping of :func:`modes`
    (or the ratios ``damping`` (n,)): ``H = sum_r psi_r psi_r^T /
    (omega_r^2 - omega^2 + 2 i zeta_r omega_r omega)``, ``psi = G_tcp phi``.
    ``H(0)`` is the static gain, equal to :func:`tcp_compliance`.
    """
    if isinstance(arm, FullFEArm):
        return full_frf(arm, q, freq_hz, damping)
    md = modes(arm, q)
    zeta = md.damping if damping is None else np.broadcast_to(damping, md.freq_hz.shape)
    w = 2 * np.pi * np.asarray(freq_hz, dtype=float)
    wr = md.omega
    den = wr[None, :] ** 2 - w[:, None] ** 2 + 2j * zeta * wr[None, :] * w[:, None]
    psi = md.tcp_shapes
    return np.einsum("ir,fr,jr->fij", psi, 1.0 / den, psi)


def gravity_sag(arm: ArmModel, q: ArrayLike, gravity: ArrayLike = GRAVITY) -> FloatArray:
    """(..., 6) TCP displacement [m, rad] under the arm's own weight (*batched*).

    The load is ``sum_i T_i^T M_i U_i g`` with ``U_i`` the rigid translation of body i.
    """
    if isinstance(arm, FullFEArm):
        return full_gravity_sag(arm, q, gravity)
    sm = system_matrices(arm, q)
    g = np.asarray(gravity, dtype=float)
    f = np.zeros(sm.K.shape[:-1])
    F = sm.frames
    for i, b in enumerate(arm.bodies):
        # weight in the link frame, then body load in the link frame, then to base DOFs
        g_link = np.einsum("...ji,j->...i", F[..., i, :3, :3], g)
        f_link = np.einsum("ab,bc,...c->...a", b.M, b.translation_modes(), g_link)
        Q = rotation_blocks(F[..., i, :3, :3], b.n_dofs, b.n_nodes)
        f += np.einsum("...ax,...a->...x", sm.T[i], np.einsum("...ab,...b->...a", Q, f_link))
    x = np.linalg.solve(sm.K, f[..., None])[..., 0]
    return np.einsum("...ix,...x->...i", sm.G_tcp, x)
