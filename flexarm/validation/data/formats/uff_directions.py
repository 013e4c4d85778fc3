"""Measured directions of 55/2414 shapes and 58 FRFs turned from each node's displacement
coordinate system (:mod:`.uff_systems`) into the base frame.

A node measured in a system turned against the base axes holds, per local direction, a
mix of base-axis motions.  A base component is known only where every local direction
that feeds it (direction cosine above ``tol.cs_axis_round_off``) was measured: a triaxial
sensor gives all three, a uniaxial one along an axis-parallel system gives its own
axis.  A measured direction that feeds no known base component (a uniaxial sensor on a
slant) cannot be told in base axes and is refused, naming the node and its system.

- **Shapes**: a local direction is measured where some mode of the pose moves it (a 55
  set writes 0 for what it did not measure); unknown base components are written 0 and
  so dropped as not measured.
- **FRFs**: ``H_base = R_out H_local R_in^T`` per pair of nodes, over the local pairs
  the file has; the coherence of a base FRF is the least of those it is made of.
"""

from __future__ import annotations

import numpy as np

from ....fe.errors import ReadError
from ...tolerances import tol
from ..measurements import DIRECTIONS
from .uff_frf import UffFrf
from .uff_systems import NodeFrames

__all__ = ["shapes_to_base", "frf_to_base"]


def _needs(rotations) -> np.ndarray:
    """(..., 3, 3) bool: which local direction (column) feeds which base axis (row)."""
    return np.abs(rotations) > tol.cs_axis_round_off


def _slant(path, node, cs) -> ReadError:
    return ReadError(f"{path}: node {node} is measured along a direction of its coordinate "
                     f"system {cs} that is turned against the base axes, without the other "
                     "directions there: measure x, y and z at the node, or export it in a "
                     "system parallel to the base axes")


def shapes_to_base(path, frames: NodeFrames, nodes, phi) -> np.ndarray:
    """(m, k, 3) mode shapes of one pose in the base frame from ``phi`` (m, k, 3) in the
    displacement systems of ``nodes`` (k,) (file ids).

    Examples
    --------
    >>> from flexarm.validation.data.formats.uff_systems import NodeFrames
    >>> quarter = np.array([[[0.0, -1, 0], [1, 0, 0], [0, 0, 1]]])  # local x along +y
    >>> f = NodeFrames(np.array([7]), np.zeros((1, 3)), quarter, np.array([2]))
    >>> shapes_to_base("a.unv", f, [7], np.array([[[0.5, 0.0, 0.0]]])).tolist()
    [[[0.0, 0.5, 0.0]]]
    """
    phi = np.asarray(phi)
    if frames.is_global(nodes):
        return phi
    rot, cs = frames.of(nodes)
    measured = np.any(phi != 0, axis=0)  # (k, 3) local
    need = _needs(rot)  # (k, base, local)
    known = ~np.any(need & ~measured[:, None, :], axis=2)  # (k, base)
    used = np.any(need & known[:, :, None], axis=1)  # (k, local)
    lost = np.argwhere(measured & ~used)
    if lost.size:
        k = lost[0, 0]
        raise _slant(path, int(np.ravel(nodes)[k]), int(cs[k]))
    out = np.einsum("kbl,mkl->mkb", np.where(need, rot, 0.0), phi)
    return np.where(known[None], out, 0.0)


def frf_to_base(path, frames: NodeFrames, frf: UffFrf, offset: int = 0) -> UffFrf:
    """The FRFs of one pose with their directions in the base frame; ``offset`` is what the
    pose added to its node ids in the file (``frf`` holds them less it)."""
    if frames.is_global(np.r_[frf.out_nodes, frf.in_nodes] + offset):
        return frf
    axis = {d: k for k, d in enumerate(DIRECTIONS)}
    a = np.array([axis[str(d)] for d in frf.out_dirs])
    b = np.array([axis[str(d)] for d in frf.in_dirs])
    nf = len(frf.freq_hz)
    rows = {key: [] for key in ("out", "od", "in", "id", "H", "g2")}
    for o, i in dict.fromkeys(zip(frf.out_nodes.tolist(), frf.in_nodes.tolist(), strict=True)):
        mine = np.flatnonzero((frf.out_nodes == o) & (frf.in_nodes == i))
        L = np.zeros((3, 3, nf), complex)
        G = np.ones((3, 3, nf))
        have = np.zeros((3, 3), bool)
        L[a[mine], b[mine]], have[a[mine], b[mine]] = frf.H[mine], True
        if frf.coherence is not None:
            G[a[mine], b[mine]] = frf.coherence[mine]
        (ro, ri), (co, ci) = frames.of([o + offset, i + offset])
        no, ni = _needs(ro), _needs(ri)
        # base entry (p, q) needs local (x, y) where no[p, x] and ni[q, y]
        need = no[:, None, :, None] & ni[None, :, None, :]  # (p, q, x, y)
        known = ~np.any(need & ~have, axis=(2, 3))
        used = np.any(need & known[:, :, None, None], axis=(0, 1))
        if np.any(have & ~used):
            slant = not np.all(np.sum(no, axis=1) == 1)
            raise _slant(path, o + offset if slant else i + offset, co if slant else ci)
        H = np.einsum("px,qy,xyf->pqf", np.where(no, ro, 0.0), np.where(ni, ri, 0.0), L)
        for p, q in np.argwhere(known):
            rows["out"].append(o), rows["od"].append(DIRECTIONS[p])
            rows["in"].append(i), rows["id"].append(DIRECTIONS[q])
            rows["H"].append(H[p, q])
            rows["g2"].append(np.min(G[need[p, q]], axis=0))
    return UffFrf(frf.pose, frf.q, frf.freq_hz, np.array(rows["out"]), np.array(rows["od"]),
                  np.array(rows["in"]), np.array(rows["id"]), np.array(rows["H"]),
                  None if frf.coherence is None else np.array(rows["g2"]))
