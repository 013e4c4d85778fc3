"""The TCP compliance ellipsoid: principal compliances, the drawn surface, and how it sits
on the arm pictures of :mod:`flexarm.studies.render_arm` (centred on the TCP, moving
with it, the tool drawn as a line from the flange).

Compliances are in the base frame [m/N]; drawn lengths in metres.  Geometry is pure
numpy; only :func:`add_ellipsoid` imports pyvista.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..assembly.arm import Arm
from ..assembly.system import system_matrices
from ..fe.typing import ArrayLike, FloatArray, IntArray

__all__ = ["ELLIPSOID_FLOOR", "TcpEllipsoid", "compliance_ellipsoid", "ellipsoid_axes",
           "ellipsoid_surface", "polydata", "add_ellipsoid", "tcp_ellipsoid"]

#: Shortest drawn semi-axis of the compliance ellipsoid as a fraction of the longest: a
#: TCP is often ~100x stiffer along one axis, which would draw a flat disc; the picture
#: says when an axis was drawn at this floor.
ELLIPSOID_FLOOR = 0.25


def compliance_ellipsoid(C: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Principal compliances (3,) [m/N], descending, and directions (3, 3) (columns).

    The translational block ``C[:3, :3]`` of a TCP compliance (base frame): a unit
    force along column ``k`` moves the TCP by ``radii[k]`` along the same column.

    >>> r, V = compliance_ellipsoid(np.diag([1.0, 3.0, 2.0, 0, 0, 0]))
    >>> r.tolist(), np.abs(V[:, 0]).tolist()
    ([3.0, 2.0, 1.0], [0.0, 1.0, 0.0])
    """
    Ct = np.asarray(C, dtype=float)[:3, :3]
    w, V = np.linalg.eigh(0.5 * (Ct + Ct.T))
    return w[::-1].copy(), V[:, ::-1].copy()


def polydata(points, faces):
    """A PyVista surface of ``points`` (n, 3) [m] and triangle ``faces`` (m, 3)."""
    import pyvista as pv

    f = np.column_stack([np.full(len(faces), 3), faces]).ravel()
    return pv.PolyData(np.asarray(points, dtype=float), f)


def ellipsoid_axes(C: ArrayLike, length: float,
                   floor: float = ELLIPSOID_FLOOR) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Principal compliances (3,) [m/N] (descending), directions (3, 3) (columns, a
    right-handed frame) and drawn semi-axes (3,) [m] of the TCP compliance ellipsoid.

    The drawn semi-axes are proportional to the principal compliances, the longest
    ``length`` [m]; none is drawn shorter than ``floor * length``.

    >>> r, V, a = ellipsoid_axes(np.diag([4.0, 2.0, 0.01, 0, 0, 0]), 0.2)
    >>> a.round(3).tolist(), round(float(np.linalg.det(V)), 12)
    ([0.2, 0.1, 0.05], 1.0)
    """
    radii, V = compliance_ellipsoid(C)
    if not radii[0] > 0:
        raise ValueError(f"the TCP compliance has no positive principal value: {radii}")
    V = V * np.sign(np.linalg.det(V))
    return radii, V, length * np.clip(radii / radii[0], floor, None)


def ellipsoid_surface(center: ArrayLike, V: ArrayLike, semi_axes: ArrayLike,
                      n: int = 24) -> tuple[FloatArray, IntArray]:
    """Triangulated ellipsoid ``center + V diag(semi_axes) s``, ``s`` on the unit sphere.

    Returns the points (p, 3) [m] and triangles (f, 3): ``n`` meridians, ``n // 2``
    latitude bands and one pole point at each end.

    >>> pts, tri = ellipsoid_surface([1.0, 0, 0], np.eye(3), [3.0, 2.0, 1.0], n=8)
    >>> pts.min(axis=0).round(6).tolist(), pts.max(axis=0).round(6).tolist()
    ([-2.0, -2.0, -1.0], [4.0, 2.0, 1.0])
    """
    n_lat = max(n // 2, 2)
    theta = np.linspace(0.0, np.pi, n_lat + 1)[1:-1]
    phi = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    T, P = np.meshgrid(theta, phi, indexing="ij")
    ring = np.column_stack([(np.sin(T) * np.cos(P)).ravel(), (np.sin(T) * np.sin(P)).ravel(),
                            np.cos(T).ravel()])
    unit = np.vstack([[0.0, 0.0, 1.0], ring, [0.0, 0.0, -1.0]])
    pts = np.asarray(center, float) + (unit * np.asarray(semi_axes, float)) @ np.asarray(V).T
    j = np.arange(n)
    k = (j + 1) % n
    top = np.column_stack([np.zeros(n, int), 1 + j, 1 + k])
    rows = np.arange(n_lat - 2)[:, None] * n + 1
    a, b, c, d = rows + j, rows + k, rows + n + j, rows + n + k
    bands = np.vstack([np.column_stack([a.ravel(), c.ravel(), b.ravel()]),
                       np.column_stack([b.ravel(), c.ravel(), d.ravel()])])
    last = 1 + (n_lat - 2) * n
    south = len(unit) - 1
    bottom = np.column_stack([np.full(n, south), last + k, last + j])
    return pts, np.vstack([top, bands, bottom]).astype(np.int64)


@dataclass(frozen=True, eq=False)
class TcpEllipsoid:
    """What :func:`render_arm` draws at the TCP.

    Attributes
    ----------
    C : (6, 6) float
        TCP compliance [m/N, rad/(N m)], base frame.
    tcp : (3,) float
        TCP position at the pose [m], base frame (the ellipsoid's centre).
    flange : (3,) float
        The tool's mounting point [m]: the tool is drawn as a line from here to ``tcp``.
    u : (6,) float
        TCP motion (translation, small rotation [rad]) of the drawn field, scaled as
        :attr:`LinkField.u`: the ellipsoid moves with the TCP, the tool rigidly with it.
    """

    C: FloatArray
    tcp: FloatArray
    flange: FloatArray
    u: FloatArray


def add_ellipsoid(p, e: TcpEllipsoid, length: float, scale: float) -> list[tuple]:
    """Add the ellipsoid, the tool line and the TCP caption to plotter ``p``; the meshes
    that move with the TCP as ``(mesh, points, u)``."""
    import pyvista as pv

    radii, V, axes = ellipsoid_axes(e.C, length)
    pts, tri = ellipsoid_surface(e.tcp, V, axes)
    ell = polydata(pts, tri)
    u, theta = np.asarray(e.u, float)[:3], np.asarray(e.u, float)[3:]
    flange, tcp = np.asarray(e.flange, float), np.asarray(e.tcp, float)
    tool = pv.Line(flange, tcp)
    tool_u = np.array([u + np.cross(theta, flange - tcp), u])
    floored = radii / radii[0] < ELLIPSOID_FLOOR
    drawn = ell.copy()
    drawn.points = pts + scale * u
    p.add_mesh(drawn, color="tomato", opacity=0.5, smooth_shading=True, specular=0.4)
    # the principal axes through the TCP make the ellipsoid read as a solid from any view
    ends = np.asarray(e.tcp, float) + np.concatenate([-(V * axes).T, (V * axes).T])
    axis_lines = pv.PolyData(ends, lines=np.array([[2, k, k + 3] for k in range(3)]).ravel())
    shown_axes = axis_lines.copy()
    shown_axes.points = ends + scale * u
    p.add_mesh(shown_axes, color="darkred", line_width=2)
    shown_tool = tool.copy()
    shown_tool.points = tool.points + scale * tool_u
    p.add_mesh(shown_tool, color="black", line_width=3)
    note = (f" (axes below {ELLIPSOID_FLOOR:.0%} of the longest drawn at {ELLIPSOID_FLOOR:.0%})"
            if floored.any() else "")
    p.add_text("TCP compliance ellipsoid, principal values [mm/kN]: "
               + ", ".join(f"{1e6 * r:.3g}" for r in radii)
               + f"\nlongest semi-axis drawn {length * 1e3:.0f} mm{note}; tool: black line",
               position="lower_left", font_size=9)
    return [(drawn, pts, np.broadcast_to(u, pts.shape)), (shown_axes, ends, np.tile(u, (6, 1))),
            (shown_tool, tool.points.copy(), tool_u)]


def tcp_ellipsoid(arm: Arm, q: ArrayLike, x: ArrayLike) -> TcpEllipsoid:
    """TCP compliance, TCP, tool flange and the TCP motion of arm coordinates ``x``."""
    from ..assembly.analyses import tcp_compliance

    sm = system_matrices(arm.model, np.asarray(q, dtype=float))
    c = arm.model.chain.tcp_body
    frame = sm.frames[c] @ arm.model.chain.tool
    return TcpEllipsoid(tcp_compliance(arm.model, q), frame[:3, 3], sm.frames[c, :3, 3],
                        sm.G_tcp @ np.asarray(x, float))
