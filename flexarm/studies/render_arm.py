"""Pictures of the assembled arm at a pose: mode shapes and the TCP compliance ellipsoid.

Recovery of a link's full-field displacement from the arm's independent coordinates
``x`` (``system_matrices`` conventions):

1. body coordinates in the base frame ``d_i = T_i x``;
2. into the link frame ``y_i = Q_i^T d_i`` (``Q_i = blockdiag(R_i, R_i)`` on the
   six joint-point DOFs, identity on the rest);
3. superelement DOFs ``s_i = S_i y_i`` (``S_i`` of
   :func:`~flexarm.assembly.flexible.body_coordinates`, origin = link origin);
4. full field ``u = se.T s_i`` (link frame), rotated back ``u R_i^T``.

Rigid links (E-model, rigid base) carry their CAD surface rigidly:
``u(p) = u_o + theta_o x p``.  Geometry is pure numpy; only the ``render_*``
functions import pyvista (off-screen through the probe of
:mod:`flexarm.reduction.render`).
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..assembly.arm import Arm
from ..assembly.build import LinkBuild
from ..assembly.flexible import body_coordinates
from ..assembly.system import ArmModel, SystemMatrices, rotation_blocks, system_matrices
from ..fe.typing import ArrayLike, FloatArray, IntArray
from ..reduction.couplings import rigid_transport
from ..reduction.render import _picture_suffix, save_picture
from ..robot.description import Robot

__all__ = ["LinkField", "superelement_dofs", "link_fields", "mode_fields",
           "compliance_ellipsoid", "render_arm", "render_arm_mode"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class LinkField:
    """One link's surface at the pose and its displacement field.

    Attributes
    ----------
    name : str
    points : (p, 3) float
        Undeformed surface vertices at the pose [m], base frame.
    faces : (f, 3) int
        Triangles into ``points``.
    u : (p, 3) float
        Displacement of each vertex [m] (or mode-shape units), base frame.
    """

    name: str
    points: FloatArray
    faces: IntArray
    u: FloatArray


def superelement_dofs(arm: ArmModel, sm: SystemMatrices, i: int, x: ArrayLike,
                      se=None) -> FloatArray:
    """(n_se,) DOFs of body ``i`` in its link frame from coordinates ``x`` (n_x,).

    With ``se`` (the body's :class:`Superelement`) the floating-frame body
    coordinates are mapped to the superelement's own DOFs (6 per interface node, then
    modal); without, the body coordinates in the link frame are returned.
    """
    b = arm.bodies[i]
    d = sm.T[i] @ np.asarray(x, dtype=float)
    Q = rotation_blocks(sm.frames[i, :3, :3], b.n_dofs, b.n_nodes)
    y = Q.T @ d
    if se is None:
        return y
    return body_coordinates(se.node_positions, np.zeros(3), se.n_dofs) @ y


def _cad_surface(robot: Robot, i: int) -> tuple[FloatArray, IntArray]:
    from ..meshes import load_surface

    lk = robot.links[i]
    if lk.mesh is None:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    s = load_surface(lk.mesh, units=lk.units)
    return np.asarray(s.vertices, dtype=float), np.asarray(s.faces, dtype=np.int64)


def link_fields(robot: Robot, arm: ArmModel, q: ArrayLike, x: ArrayLike,
                builds: Sequence[LinkBuild] | None = None) -> list[LinkField]:
    """Surface and displacement of every link at pose ``q`` (n,) [rad] for ``x`` (n_x,).

    ``builds`` gives the superelements of a flexible arm (recovered to the full
    field); links without one move rigidly with their CAD surface.
    """
    sm = system_matrices(arm, np.asarray(q, dtype=float))
    out = []
    for i, lk in enumerate(robot.links):
        se = None if builds is None else builds[i].superelement
        R, t = sm.frames[i, :3, :3], sm.frames[i, :3, 3]
        if se is not None:
            s = superelement_dofs(arm, sm, i, x, se)
            pts = np.asarray(se.surface_points, dtype=float)
            faces = np.asarray(se.surface_faces, dtype=np.int64)
            u = se.expand(s)[np.asarray(se.surface_nodes)]
        else:
            y = superelement_dofs(arm, sm, i, x)
            pts, faces = _cad_surface(robot, i)
            node = np.asarray(arm.bodies[i].node_positions[0], dtype=float)
            u = rigid_transport(pts - node) @ y[:6]
        out.append(LinkField(lk.name, pts @ R.T + t, faces, u @ R.T))
    return out


def mode_fields(robot: Robot, arm: ArmModel, q: ArrayLike, mode: int,
                builds: Sequence[LinkBuild] | None = None) -> tuple[float, list[LinkField]]:
    """Frequency [Hz] and link fields of arm mode ``mode`` (1-based) at pose ``q``."""
    from ..assembly.analyses import modes

    md = modes(arm, q)
    if not 1 <= mode <= md.freq_hz.size:
        raise ValueError(f"mode must be in 1..{md.freq_hz.size}, got {mode}")
    return float(md.freq_hz[mode - 1]), link_fields(robot, arm, q, md.shapes[:, mode - 1],
                                                    builds)


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


def _polydata(points, faces):
    import pyvista as pv

    f = np.column_stack([np.full(len(faces), 3), faces]).ravel()
    return pv.PolyData(np.asarray(points, dtype=float), f)


def _ellipsoid_mesh(C, center, size: float):
    import pyvista as pv

    radii, V = compliance_ellipsoid(C)
    r = size * np.clip(radii / radii[0], 0.05, None)
    ell = pv.ParametricEllipsoid(*r)
    T = np.eye(4)
    T[:3, :3] = V * np.sign(np.linalg.det(V))
    T[:3, 3] = center
    return ell.transform(T, inplace=False), radii


def render_arm(fields: Sequence[LinkField], path=None, title: str = "",
               amplitude: float = 0.06, n_frames: int = 20, interactive: bool = False,
               window_size=(1024, 768), ellipsoid: tuple | None = None) -> Path | None:
    """Draw the links deformed by their fields, coloured by |u| (largest = 1).

    Parameters
    ----------
    fields : sequence of LinkField
    path : str or Path, optional
        ``.png`` or ``.gif`` (``n_frames`` of one harmonic oscillation).
    amplitude : float
        Largest drawn displacement as a fraction of the arm's bounding-box diagonal.
    ellipsoid : (C (6, 6), tcp (3,) [m]), optional
        TCP compliance drawn as its principal ellipsoid at the TCP (largest semi-axis
        = 12 % of the arm size).
    interactive : bool
        Also open a window (needs :func:`~flexarm.reduction.render.has_display`).
    """
    _picture_suffix(path, interactive)
    import pyvista as pv

    live = [f for f in fields if len(f.points)]
    allp = np.vstack([f.points for f in live])
    diag = float(np.linalg.norm(np.ptp(allp, axis=0)))
    peak = max(float(np.linalg.norm(f.u, axis=1).max()) for f in live)
    scale = amplitude * diag / max(peak, np.finfo(float).tiny)

    def scene(off_screen: bool):
        p = pv.Plotter(off_screen=off_screen, window_size=window_size)
        moving = []
        for k, f in enumerate(live):
            base = _polydata(f.points, f.faces)
            p.add_mesh(base, color="lightgrey", opacity=0.25)
            m = base.copy()
            m.points = f.points + scale * f.u
            m["|u| / max"] = np.linalg.norm(f.u, axis=1) / max(peak, np.finfo(float).tiny)
            p.add_mesh(m, scalars="|u| / max", cmap="viridis", clim=(0.0, 1.0),
                       show_scalar_bar=k == 0)
            moving.append((m, f))
        if ellipsoid is not None:
            ell, radii = _ellipsoid_mesh(ellipsoid[0], ellipsoid[1], 0.12 * diag)
            p.add_mesh(ell, color="tomato", opacity=0.6)
            p.add_text("TCP compliance [mm/kN]: " + ", ".join(f"{1e6 * r:.3g}" for r in radii),
                       position="lower_left", font_size=9)
        p.add_title(title, font_size=11)
        p.view_isometric()
        p.reset_camera()
        return p, moving

    out = None
    if path is not None:
        p, moving = scene(True)

        def move(phase):
            for m, f in moving:
                m.points = f.points + phase * scale * f.u

        out = save_picture(p, path, n_frames, move)
    if interactive:
        scene(False)[0].show()
    return out


def render_arm_mode(arm: Arm, q: ArrayLike, mode: int = 1, path=None, ellipsoid: bool = False,
                    pose_name: str = "", **options) -> Path | None:
    """Picture (PNG/GIF) of mode ``mode`` of ``arm`` (:func:`~flexarm.assembly.arm.build_arm`)
    at pose ``q`` [rad], model and frequency in the title.

    ``ellipsoid`` adds the TCP compliance ellipsoid; ``options`` go to :func:`render_arm`.
    """
    from ..assembly.analyses import tcp_compliance
    from ..robot.kinematics import tcp_frame

    freq, fields = mode_fields(arm.robot, arm.model, q, mode, arm.builds)
    title = (f"{arm.robot.name} {pose_name} {arm.spec.label}: mode {mode}, {freq:.1f} Hz"
             .replace("  ", " "))
    ell = None
    if ellipsoid:
        ell = (tcp_compliance(arm.model, q), tcp_frame(arm.model.chain, q)[:3, 3])
    return render_arm(fields, path, title, ellipsoid=ell, **options)
