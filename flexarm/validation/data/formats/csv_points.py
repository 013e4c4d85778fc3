"""Measurement points table: ``node, link, x_mm, y_mm, z_mm``.

One row per node of the test geometry: the body it is fixed to (``0`` = base, ``i`` =
link ``i``) and its position in that body's link frame ``L_i`` (the URDF link frame
at zero joint angles).  This is not a measurement kind (nothing is measured in it):
it maps the nodes of universal files and of mode-shape CSVs onto the arm.  Checked
on reading: each node once, ``link`` ≥ 0 (and a body of the arm, given its count).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ....fe.typing import PathType
from ..shape_data import Points
from ._checks import check_positive, check_unique
from ._table import Field, Schema, read_table, vector, write_table

__all__ = ["SCHEMA", "read_points", "write_points"]

SCHEMA = Schema("points", (Field("node", "int"), Field("link", "int"),
                           *vector("", "length", "mm")), noun="a measurement points table")


def read_points(path: PathType, n_bodies: int | None = None) -> Points:
    """Read a points table; with ``n_bodies`` (the robot's links, base included) a
    ``link`` outside ``0 .. n_bodies - 1`` is refused at its line.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "points.csv"
    >>> _ = f.write_text("node,link,x_mm,y_mm,z_mm\\n1,2,0,0,450\\n2,6,100,0,0\\n")
    >>> read_points(f).positions[:, 2].tolist()
    [0.45, 0.0]
    """
    table = read_table(path, SCHEMA.vocabulary)
    v = table.parse(SCHEMA)
    check_unique(table, [v["node"]], "node", lambda i: f"node {v['node'][i]}")
    check_positive(table, v["link"], "link", "link index (0 = base)", strict=False)
    if n_bodies is not None and np.any(v["link"] >= n_bodies):
        i = int(np.flatnonzero(v["link"] >= n_bodies)[0])
        raise table.error(i, "link", f"link {v['link'][i]} does not exist (the arm has "
                          f"bodies 0..{n_bodies - 1}, 0 = base)")
    return Points(nodes=v["node"], links=v["link"],
                  positions=v["xyz"])


def write_points(path: PathType, points: Points, comments=()) -> Path:
    """Write ``points`` in mm, atomically; reading it back gives equal arrays."""
    values = {"node": points.nodes, "link": points.links}
    values.update({c: points.positions[:, k] for k, c in enumerate("xyz")})
    return write_table(path, SCHEMA, values, comments)
