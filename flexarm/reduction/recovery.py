"""Full-field results from reduced coordinates: mode shapes and static deflections."""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ..fe.errors import InterfaceError
from ..fe.tolerances import tol
from ..fe.typing import FloatArray
from .superelement import Superelement

__all__ = ["interface_dofs", "reduced_modes", "mode_coordinates", "mode_shape", "static_deflection"]


def interface_dofs(se: Superelement, names) -> np.ndarray:
    """(k,) sorted reduced DOFs of the boundary nodes of the named interfaces."""
    idx = []
    for name in names:
        if name not in se.interface_names:
            raise InterfaceError(f"no interface '{name}' (has {', '.join(se.interface_names)})")
        i = se.interface_names.index(name)
        nodes = np.flatnonzero(se.node_interface == i)
        idx.append((se.dofs_per_node * nodes[:, None] + np.arange(se.dofs_per_node)).ravel())
    return np.unique(np.concatenate(idx)) if idx else np.zeros(0, dtype=np.int64)


def reduced_modes(se: Superelement, clamped=(), n: int | None = None):
    """Modes of the reduced model with the ``clamped`` interfaces held.

    Returns
    -------
    omega2 : (k,) float
        [rad^2/s^2], ascending (rigid modes of a free part included, ~0).
    Q : (n_dofs, k) float
        Mass-normalised reduced coordinates (zero on clamped DOFs).
    """
    fixed = interface_dofs(se, clamped)
    free = np.setdiff1d(np.arange(se.n_dofs), fixed)
    K = se.K[np.ix_(free, free)]
    M = se.M[np.ix_(free, free)]
    hi = len(free) - 1 if n is None else min(n, len(free)) - 1
    w, V = sla.eigh(K, M, subset_by_index=(0, hi))
    Q = np.zeros((se.n_dofs, V.shape[1]))
    Q[free] = V
    return w, Q


def mode_coordinates(se: Superelement, mode: int, boundary: str = "fixed"):
    """Frequency [Hz] and mass-normalised reduced coordinates (n_dofs,) of mode number
    ``mode`` (1-based): ``q^T M q = 1`` with the superelement's ``M``.

    ``boundary="fixed"``: the ``mode``-th fixed-interface (Craig-Bampton) mode;
    ``"free"``: the ``mode``-th elastic mode of the free superelement (rigid modes
    skipped).
    """
    if mode < 1:
        raise ValueError(f"mode numbers start at 1, got {mode}")
    if boundary == "fixed":
        if mode > se.n_modes:
            raise ValueError(f"the superelement has {se.n_modes} fixed-interface modes, "
                             f"asked for mode {mode} (use boundary='free')")
        q = np.zeros(se.n_dofs)
        q[se.n_boundary + mode - 1] = 1.0
        freq = float(se.freq_hz[mode - 1])
    elif boundary == "free":
        w, Q = reduced_modes(se)
        scale = max(abs(w[-1]), 1.0)
        elastic = np.flatnonzero(np.abs(w) > tol.rigid_mode * scale)
        if mode > elastic.size:
            raise ValueError(f"the free superelement has {elastic.size} elastic modes, "
                             f"asked for mode {mode}")
        k = elastic[mode - 1]
        q, freq = Q[:, k], float(np.sqrt(max(w[k], 0.0)) / (2 * np.pi))
    else:
        raise ValueError(f"boundary must be 'fixed' or 'free', got '{boundary}'")
    return freq, q / np.sqrt(float(q @ se.M @ q))


def mode_shape(se: Superelement, mode: int, boundary: str = "fixed"):
    """Frequency [Hz] and (n_nodes, 3) shape of mode number ``mode`` (1-based), as
    :func:`mode_coordinates` chooses it, scaled to a largest displacement of 1."""
    freq, q = mode_coordinates(se, mode, boundary)
    u = se.expand(q)
    peak = np.abs(u).max()
    return freq, u / (peak if peak > 0 else 1.0)


def static_deflection(se: Superelement, loads: dict, clamped) -> FloatArray:
    """(n_nodes, 3) displacement [m] under interface loads with interfaces clamped.

    Parameters
    ----------
    loads : dict of str to (6,) float
        Force [N] and moment [N m] at each named interface node (link frame);
        for kept region nodes (3 DOFs each) the force is shared equally.
    clamped : sequence of str
        Interfaces held fixed (at least one for a free part).
    """
    f = np.zeros(se.n_dofs)
    for name, wrench in loads.items():
        dofs = interface_dofs(se, [name]).reshape(-1, se.dofs_per_node)
        w = np.asarray(wrench, dtype=float)
        if se.dofs_per_node == 6:
            f[dofs[0]] += w
        else:
            f[dofs] += w[:3] / len(dofs)
    fixed = interface_dofs(se, clamped)
    if fixed.size == 0:
        raise InterfaceError("clamp at least one interface for a static deflection")
    free = np.setdiff1d(np.arange(se.n_dofs), fixed)
    q = np.zeros(se.n_dofs)
    q[free] = sla.solve(se.K[np.ix_(free, free)], f[free], assume_a="sym")
    return se.expand(q)
