"""What a superelement file's matrices must be before anything uses them.

A checksum only proves the bytes are the ones written: a file written with NaN in ``M``
or ``M`` negated passes it.  :func:`check_matrices` checks the content, cheapest first:
``K`` and ``M`` finite and symmetric (relative to their largest entry), ``M`` positive
definite, ``K`` positive semi-definite with exactly the six rigid-body motions of a free
link as zero-energy modes (generalised eigenvalues ``omega^2`` of ``K phi = omega^2 M
phi``, relative to the largest), those motions free of strain energy in ``K``, and the
mass ``M`` holds equal to the file's.  Reduced matrices are small (tens to a few hundred
DOFs), so the eigenvalues are computed densely.  Bounds:
:class:`~flexarm.reduction.tolerances.Tolerances` (``file_*``).
"""

from __future__ import annotations

import numpy as np

from ..fe.errors import ReadError
from ..fe.typing import FloatArray
from .tolerances import tol

__all__ = ["RIGID_BODY_MODES", "check_matrices"]

#: Zero-energy modes of a free link: three translations, three rotations.
RIGID_BODY_MODES = 6


def _finite(A: FloatArray, name: str, source: str) -> None:
    bad = np.argwhere(~np.isfinite(A))
    if bad.size:
        i, j = (int(k) for k in bad[0])
        raise ReadError(f"{source}: {name} holds {len(bad)} non-finite "
                        f"entr{'y' if len(bad) == 1 else 'ies'} ({A[i, j]} at row {i + 1}, "
                        f"column {j + 1})")


def _symmetric(A: FloatArray, name: str, source: str) -> None:
    scale = max(float(np.abs(A).max()), np.finfo(float).tiny)
    asym = float(np.abs(A - A.T).max()) / scale
    if not asym <= tol.file_symmetry:
        raise ReadError(f"{source}: {name} is not symmetric (relative asymmetry {asym:.1e}, "
                        f"at most {tol.file_symmetry:g})")


def check_matrices(K, M, rigid_modes: FloatArray, mass: float, source: str) -> None:
    """Raise :class:`~flexarm.fe.errors.ReadError` naming ``source`` and the figure at
    fault unless ``K`` and ``M`` can be a free link's reduced matrices.

    Parameters
    ----------
    K, M : (n, n) float
        Reduced stiffness and mass [SI].
    rigid_modes : (n, 6) float
        The rigid motions in the reduced coordinates
        (:func:`~flexarm.reduction.superelement.reduced_rigid_modes`).
    mass : float
        The mass the file states [kg].
    source : str
        File name for messages.

    Examples
    --------
    A rigid body of 2 kg (one node, six DOFs, no stiffness) passes; its mass matrix
    negated does not:

    >>> K, M, R = np.zeros((6, 6)), 2.0 * np.eye(6), np.eye(6)
    >>> check_matrices(K, M, R, 2.0, "rigid.h5")
    >>> check_matrices(K, -M, R, 2.0, "negated.h5")
    Traceback (most recent call last):
    ...
    flexarm.fe.errors.ReadError: negated.h5: M is not positive definite (eigenvalues -2 to \
-2): every motion of a body has a positive kinetic energy
    """
    K, M = np.asarray(K, dtype=np.float64), np.asarray(M, dtype=np.float64)
    for A, name in ((K, "K"), (M, "M")):
        _finite(A, name, source)
    for A, name in ((K, "K"), (M, "M")):
        _symmetric(A, name, source)
    K, M = 0.5 * (K + K.T), 0.5 * (M + M.T)
    ev = np.linalg.eigvalsh(M)
    if not ev[0] > tol.file_mass_definite * abs(ev[-1]):
        raise ReadError(f"{source}: M is not positive definite (eigenvalues {ev[0]:.4g} to "
                        f"{ev[-1]:.4g}): every motion of a body has a positive kinetic energy")
    _spectrum(K, M, source)
    R = np.asarray(rigid_modes, dtype=np.float64)
    size = max(float(np.linalg.norm(K)) * float(np.linalg.norm(R)), np.finfo(float).tiny)
    residual = float(np.linalg.norm(K @ R)) / size
    if not residual <= tol.file_rigid:
        raise ReadError(f"{source}: the rigid-body motions of its boundary nodes strain K "
                        f"(relative residual {residual:.1e}, at most {tol.file_rigid:g}): K "
                        "does not belong to these node positions")
    held = float((R.T @ M @ R)[0, 0])
    if not abs(held - mass) <= tol.file_mass * abs(mass):
        raise ReadError(f"{source}: M holds {held:.6g} kg but the file states {mass:.6g} kg")


def _spectrum(K: FloatArray, M: FloatArray, source: str) -> None:
    """``K`` positive semi-definite with exactly the rigid-body modes at zero."""
    import scipy.linalg

    w2 = scipy.linalg.eigh(K, M, eigvals_only=True)
    scale = max(float(np.abs(w2).max()), np.finfo(float).tiny)
    if not w2[0] >= -tol.file_psd * scale:
        raise ReadError(f"{source}: K is not positive semi-definite (omega^2 = {w2[0]:.4g} "
                        f"rad^2/s^2, the largest {w2[-1]:.4g}): a link stores no negative "
                        "strain energy")
    n_zero = int(np.sum(w2 <= tol.file_psd * scale))
    expected = min(RIGID_BODY_MODES, len(w2))
    if n_zero != expected:
        freq = np.sqrt(np.maximum(w2[: expected + 1], 0.0)) / (2 * np.pi)
        shown = ", ".join(f"{f:.4g}" for f in freq)
        raise ReadError(f"{source}: K has {n_zero} zero-energy modes, not the "
                        f"{expected} rigid-body motions of a free link (first frequencies "
                        f"{shown} Hz)")
