"""Node selections from short text expressions (CLI ``--fix``, tests).

Grammar: terms joined by ``&`` (all must hold).  A term is

* a node-set name of the mesh (``fixed``),
* ``x=min`` / ``y=max`` ...: nodes on the extreme plane of the bounding box,
* ``x<0.01``, ``z>=0.5``, ``y=0.2``: coordinate comparisons in metres
  (``=`` within 1e-6 of the part size),
* ``all``.
"""

from __future__ import annotations

import re

import numpy as np

from .mesh import TetMesh

__all__ = ["select_nodes"]

_TERM = re.compile(r"^\s*([xyz])\s*(<=|>=|<|>|=)\s*(min|max|[-+0-9.eE]+)\s*$")


def select_nodes(mesh: TetMesh, expression: str) -> np.ndarray:
    """(k,) int sorted node indices matching ``expression``.

    Raises ``ValueError`` naming the expression when it is malformed or selects nothing.

    Examples
    --------
    >>> m = TetMesh.box((1.0, 0.1, 0.1), (4, 1, 1))
    >>> select_nodes(m, "x=min").size
    4
    >>> select_nodes(m, "x>0.5 & z=max").size
    4
    """
    pts = mesh.points
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    eps = 1e-6 * float(np.max(hi - lo) or 1.0)
    mask = np.ones(mesh.n_nodes, dtype=bool)
    for raw in expression.split("&"):
        term = raw.strip()
        if not term:
            raise ValueError(f"selection '{expression}' has an empty term")
        if term == "all":
            continue
        if term in mesh.node_sets:
            sel = np.zeros(mesh.n_nodes, dtype=bool)
            sel[mesh.node_sets[term]] = True
            mask &= sel
            continue
        m = _TERM.match(term)
        if not m:
            names = ", ".join(sorted(mesh.node_sets)) or "none"
            raise ValueError(
                f"selection term '{term}' is neither a node set (known: {names}) "
                "nor a comparison like 'x=min', 'z<0.01' [m]"
            )
        axis = "xyz".index(m.group(1))
        op, val = m.group(2), m.group(3)
        c = pts[:, axis]
        if val in ("min", "max"):
            if op != "=":
                raise ValueError(f"selection term '{term}': use '=' with min/max")
            ref = lo[axis] if val == "min" else hi[axis]
            mask &= np.abs(c - ref) <= eps
            continue
        v = float(val)
        mask &= {
            "<": c < v,
            ">": c > v,
            "<=": c <= v + eps,
            ">=": c >= v - eps,
            "=": np.abs(c - v) <= eps,
        }[op]
    nodes = np.flatnonzero(mask)
    if nodes.size == 0:
        raise ValueError(f"selection '{expression}' selects no nodes")
    return nodes
