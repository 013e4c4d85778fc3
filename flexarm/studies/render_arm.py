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
from ..fe.picture_cache import cached_picture
from ..fe.typing import ArrayLike, FloatArray, IntArray
from ..reduction.couplings import rigid_transport
from ..reduction.render import _picture_suffix, save_picture, scene_key
from ..robot.description import Robot
from . import tcp_ellipsoid as _ellipsoid_module
from .tcp_ellipsoid import (
    ELLIPSOID_FLOOR,
    TcpEllipsoid,
    add_ellipsoid,
    compliance_ellipsoid,
    ellipsoid_axes,
    ellipsoid_surface,
    polydata,
    tcp_ellipsoid,
)

__all__ = ["LinkField", "TcpEllipsoid", "superelement_dofs", "link_fields", "mode_fields",
           "compliance_ellipsoid", "ellipsoid_axes", "ellipsoid_surface", "render_arm",
           "render_arm_mode", "write_arm_mode", "ELLIPSOID_FLOOR"]

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


def render_arm(fields: Sequence[LinkField], path=None, title: str = "",
               amplitude: float = 0.06, n_frames: int = 20, interactive: bool = False,
               window_size=(1024, 768), ellipsoid: TcpEllipsoid | tuple | None = None,
               ) -> Path | None:
    """Draw the links deformed by their fields, coloured by ``|u|`` (largest = 1).

    Parameters
    ----------
    fields : sequence of LinkField
    path : str or Path, optional
        ``.png`` or ``.gif`` (``n_frames`` of one harmonic oscillation).
    amplitude : float
        Largest drawn displacement as a fraction of the arm's bounding-box diagonal.
    ellipsoid : TcpEllipsoid or (C (6, 6), tcp (3,) [m]), optional
        TCP compliance drawn as its principal ellipsoid centred at the (moving) TCP, the
        longest semi-axis 10 % of the arm size (:func:`ellipsoid_axes`), with the tool
        drawn from the flange to the TCP.
    interactive : bool
        Also open a window (needs :func:`~flexarm.reduction.render.has_display`).
    """
    _picture_suffix(path, interactive)
    live = [f for f in fields if len(f.points)]
    allp = np.vstack([f.points for f in live])
    diag = float(np.linalg.norm(np.ptp(allp, axis=0)))
    peak = max(float(np.linalg.norm(f.u, axis=1).max()) for f in live)
    scale = amplitude * diag / max(peak, np.finfo(float).tiny)
    if ellipsoid is not None and not isinstance(ellipsoid, TcpEllipsoid):
        C, tcp = ellipsoid
        ellipsoid = TcpEllipsoid(np.asarray(C), np.asarray(tcp, float), np.asarray(tcp, float),
                                 np.zeros(6))
    # vertical, right: the title sits above the bar, clear of the tick labels beside it
    bar = {"title": "u / u_max", "vertical": True, "position_x": 0.86,
           "position_y": 0.2, "height": 0.55, "width": 0.05, "title_font_size": 14,
           "label_font_size": 12, "n_labels": 5, "fmt": "%.2f"}

    def scene(off_screen: bool):
        import pyvista as pv

        p = pv.Plotter(off_screen=off_screen, window_size=window_size)
        moving = []
        for k, f in enumerate(live):
            base = polydata(f.points, f.faces)
            p.add_mesh(base, color="lightgrey", opacity=0.25)
            m = base.copy()
            m.points = f.points + scale * f.u
            m["|u| / max"] = np.linalg.norm(f.u, axis=1) / max(peak, np.finfo(float).tiny)
            p.add_mesh(m, scalars="|u| / max", cmap="viridis", clim=(0.0, 1.0),
                       show_scalar_bar=k == 0, scalar_bar_args=bar)
            moving.append((m, f.points, f.u))
        # room between the bar's title and its top tick label (VTK puts them flush)
        p.scalar_bar.SetVerticalTitleSeparation(int(0.03 * window_size[1]))
        if ellipsoid is not None:
            moving += add_ellipsoid(p, ellipsoid, 0.1 * diag, scale)
        # the title fits the window: ~1.6 px per point per character at VTK's font
        p.add_title(title, font_size=int(min(11, 0.95 * window_size[0] / (1.6 * max(len(title),
                                                                                  1)))))
        p.view_isometric()
        p.reset_camera()
        return p, moving

    def draw(target: Path) -> None:
        p, moving = scene(True)

        def move(phase):
            for m, points, u in moving:
                m.points = points + phase * scale * u

        save_picture(p, target, n_frames, move)

    out = None
    if path is not None:
        key = scene_key(path, "arm", title, amplitude, n_frames, tuple(window_size),
                        *_drawn_arrays(live, ellipsoid),
                        code=(__file__, _ellipsoid_module.__file__))
        out = cached_picture(path, key, draw)[0]
    if interactive:
        scene(False)[0].show()
    return out


def _drawn_arrays(fields: Sequence[LinkField], ellipsoid: TcpEllipsoid | None) -> list:
    """Everything :func:`render_arm` draws, as names and arrays (the picture's key)."""
    out: list = []
    for f in fields:
        out += [f.name, np.asarray(f.points, float), np.asarray(f.faces), np.asarray(f.u, float)]
    if ellipsoid is not None:
        out += [np.asarray(a, float) for a in (ellipsoid.C, ellipsoid.tcp, ellipsoid.flange,
                                               ellipsoid.u)]
    return out


def render_arm_mode(arm: Arm, q: ArrayLike, mode: int = 1, path=None, ellipsoid: bool = False,
                    pose_name: str = "", **options) -> Path | None:
    """Picture (PNG/GIF) of mode ``mode`` of ``arm`` (:func:`~flexarm.assembly.arm.build_arm`)
    at pose ``q`` [rad], model and frequency in the title.

    ``ellipsoid`` adds the TCP compliance ellipsoid at the TCP; ``options`` go to
    :func:`render_arm`.
    """
    from ..assembly.analyses import modes

    freq, fields = mode_fields(arm.robot, arm.model, q, mode, arm.builds)
    ell = None
    if ellipsoid:
        ell = tcp_ellipsoid(arm, q, modes(arm.model, q).shapes[:, mode - 1])
    return render_arm(fields, path, _title(arm, pose_name, mode, freq), ellipsoid=ell,
                      **options)


def _title(arm: Arm, pose_name: str, mode: int, freq: float) -> str:
    return (f"{arm.robot.name} {pose_name} {arm.spec.label}: mode {mode}, {freq:.1f} Hz"
            .replace("  ", " "))


def write_arm_mode(arm: Arm, q: ArrayLike, mode: int, path, pose_name: str = "",
                   amplitude: float | None = None) -> Path:
    """Mode ``mode`` (1-based) of ``arm`` at pose ``q`` [rad] as a ``.vtu`` or ``.vtk``
    surface mesh of all links (base frame, undeformed points at the pose [m]).

    Point data ``mode_shape`` (p, 3) is the recovered displacement of each vertex of the
    mass-normalised arm mode (``phi^T M phi = 1`` on the arm's coordinates), or scaled to a
    largest displacement of ``amplitude`` [m]; the mode number, its frequency [Hz] and the
    scale are field data (:mod:`~flexarm.reduction.mode_file`); cell data ``link`` is the
    index of each triangle's link in ``arm.robot.links``.  In ParaView: *Warp By Vector*
    on ``mode_shape``.
    """
    from ..reduction.mode_file import MODE_EXTENSIONS, write_mode_mesh

    path = Path(path)
    if path.suffix.lower() not in MODE_EXTENSIONS:
        raise ValueError(f"mode-shape file must be {' or '.join(MODE_EXTENSIONS)}, got '{path}'")
    freq, fields = mode_fields(arm.robot, arm.model, q, mode, arm.builds)
    live = [(k, f) for k, f in enumerate(fields) if len(f.points)]
    offsets = np.cumsum([0] + [len(f.points) for _, f in live])
    faces = np.vstack([f.faces + o for (_, f), o in zip(live, offsets, strict=False)])
    link = np.concatenate([np.full(len(f.faces), k, dtype=np.int32) for k, f in live])
    write_mode_mesh(path, np.vstack([f.points for _, f in live]), faces,
                    np.vstack([f.u for _, f in live]), mode, freq, amplitude, {"link": link})
    log.info("wrote %s (%s, mode %d at %s)", path, _title(arm, pose_name, mode, freq), mode,
             pose_name or "the pose")
    return path
