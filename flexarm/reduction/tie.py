"""Tie a superelement's 3-DOF master nodes rigidly to each interface centre.

A superelement reduced with ``coupling="nodes"`` keeps ``k`` seat nodes per interface as
3-DOF masters.  Tied rigidly to the seat centre in the reduced space, it becomes a
bolt-like connection through ``k`` points with one 6-DOF node per interface, so it joins
an assembly like an RBE2 superelement.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..fe.files import digest
from .couplings import rigid_transport
from .superelement import Superelement

__all__ = ["tied_superelement"]


def tied_superelement(se: Superelement) -> Superelement:
    """A 3-DOF-node superelement with its masters tied rigidly to each seat centre.

    Master node ``p`` of interface ``i`` moves as ``u_p = u_c + theta_c x (p - c_i)``;
    the result has one 6-DOF node per interface at ``interface_positions`` (then the
    modal coordinates unchanged), so it joins the arm like an RBE2 superelement.
    """
    if se.dofs_per_node != 3:
        raise ValueError(f"expected 3-DOF master nodes, got {se.dofs_per_node}-DOF nodes")
    n_if = len(se.interface_names)
    nb, m = se.n_boundary, se.n_modes
    nodes = np.asarray(se.node_positions, dtype=float)
    owner = np.asarray(se.node_interface, dtype=int)
    A = rigid_transport(nodes - np.asarray(se.interface_positions)[owner])  # (n_b, 3, 6)
    S = np.zeros((nb + m, 6 * n_if + m))
    rows = np.arange(nb).reshape(-1, 3)
    cols = 6 * owner[:, None] + np.arange(6)
    S[rows[:, :, None], cols[:, None, :]] = A
    S[nb:, 6 * n_if:] = np.eye(m)
    K = S.T @ np.asarray(se.K) @ S
    M = S.T @ np.asarray(se.M) @ S
    T = None if se.T is None else (np.asarray(se.T, dtype=float) @ S).astype(se.T.dtype)
    return dataclasses.replace(
        se, K=0.5 * (K + K.T), M=0.5 * (M + M.T), T=T, dofs_per_node=6,
        node_positions=np.array(se.interface_positions, dtype=float),
        node_interface=np.arange(n_if), input_hash=digest(se.input_hash, "tied"))
