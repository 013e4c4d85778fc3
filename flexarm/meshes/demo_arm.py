"""The built-in demo arm's link CAD: parametric hollow castings.

An arm of the ABB IRB 4600-60/2.05 class (DESIGN §4): base, frame, lower arm,
arm housing, tube shaft, tilt housing and turning disc, each a hollow casting
(outer solid minus a cavity one wall thickness inside, minus the bearing bores),
built with manifold3d booleans in its own link frame.  The robot description around
this CAD (joints, lumped motors, seats, poses) is :mod:`flexarm.robot.demo_arm`.
"""

from __future__ import annotations

import logging
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["LINKS", "Hub", "hubs", "link_solids", "write_stl", "write_link_cad"]

log = logging.getLogger(__name__)

#: (link name, material, kinematic origin of its joint in the parent frame, axis)
LINKS = (
    ("base", "cast_iron", None, None),
    ("frame", "cast_iron", (0.0, 0.0, 0.495), (0, 0, 1)),
    ("lower_arm", "cast_iron", (0.175, 0.0, 0.0), (0, 1, 0)),
    ("arm_housing", "cast_iron", (0.0, 0.0, 0.900), (0, 1, 0)),
    ("tube_shaft", "steel", (0.0, 0.0, 0.175), (1, 0, 0)),
    ("tilt_housing", "cast_iron", (0.960, 0.0, 0.0), (0, 1, 0)),
    ("turning_disc", "steel", (0.135, 0.0, 0.0), (1, 0, 0)),
)
_SEG = 48  # circle segments: smooth enough for 20-40 mm tets, a few thousand triangles


@dataclass(frozen=True)
class Hub:
    """A cylindrical boss with a bearing bore, on ``axis`` (``"x"|"y"|"z"``) through ``c``."""

    c: tuple
    axis: str
    r_out: float
    r_bore: float
    lo: float  # extent along the axis relative to c [m]
    hi: float


def _cyl(axis: str, c, r: float, lo: float, hi: float, seg: int = _SEG):
    from manifold3d import Manifold

    m = Manifold.cylinder(hi - lo, r, r, seg).translate((0.0, 0.0, lo))
    if axis == "x":
        m = m.rotate((0.0, 90.0, 0.0))
    elif axis == "y":
        m = m.rotate((-90.0, 0.0, 0.0))
    return m.translate(tuple(float(v) for v in c))


def _box(lo, hi):
    from manifold3d import Manifold

    size = tuple(float(b - a) for a, b in zip(lo, hi, strict=True))
    return Manifold.cube(size).translate(tuple(float(v) for v in lo))


def _hull(*parts):
    from manifold3d import Manifold

    return Manifold.batch_hull(list(parts))


def _casting(outer, inner, hubs):
    """Outer solid (plus hub bosses) minus cavity minus bores: a hollow casting."""
    solid = outer
    for h in hubs:
        solid = solid + _cyl(h.axis, h.c, h.r_out, h.lo, h.hi)
    if inner is not None:
        solid = solid - inner
    for h in hubs:
        solid = solid - _cyl(h.axis, h.c, h.r_bore, h.lo - 0.01, h.hi + 0.01, 32)
    return solid


def hubs() -> dict[str, list[Hub]]:
    """Bearing hubs per link (link frame); the joint seats the interface regions use."""
    return {
        "base": [Hub((0, 0, 0.37), "z", 0.22, 0.085, 0.0, 0.05)],
        "frame": [Hub((0, 0, 0), "z", 0.23, 0.085, -0.07, 0.0),
                  Hub((0.175, 0, 0), "y", 0.17, 0.075, -0.26, -0.10)],
        "lower_arm": [Hub((0, 0, 0), "y", 0.15, 0.075, -0.10, 0.09),
                      Hub((0, 0, 0.9), "y", 0.12, 0.065, -0.09, 0.09)],
        "arm_housing": [Hub((0, 0, 0), "y", 0.13, 0.065, 0.09, 0.19),
                        Hub((0, 0, 0.175), "x", 0.12, 0.075, 0.10, 0.22)],
        "tube_shaft": [Hub((0, 0, 0), "x", 0.095, 0.06, 0.22, 0.30),
                       Hub((0.96, 0, 0), "y", 0.075, 0.035, 0.065, 0.10),
                       Hub((0.96, 0, 0), "y", 0.075, 0.035, -0.10, -0.065)],
        "tilt_housing": [Hub((0, 0, 0), "y", 0.065, 0.030, -0.062, 0.062),
                         Hub((0, 0, 0), "x", 0.06, 0.035, 0.06, 0.115)],
        "turning_disc": [Hub((0, 0, 0), "x", 0.08, 0.02, -0.025, 0.0)],
    }


def link_solids() -> dict:
    """Manifold solid of every link in its link frame [m] (see module docstring)."""
    H = hubs()
    w = 0.014  # main casting wall [m]
    out = {}
    # base: foot ring + pedestal tube closed by the joint-1 hub
    wb = 0.011
    ped = _cyl("z", (0, 0, 0), 0.20, 0.0, 0.40)
    foot = _cyl("z", (0, 0, 0), 0.28, 0.0, 0.02) - _cyl("z", (0, 0, 0), 0.18, -0.01, 0.04)
    out["base"] = _casting(ped + foot, _cyl("z", (0, 0, 0), 0.20 - wb, -0.01, 0.40 - wb), H["base"])
    # frame: turntable + a hollow side cheek carrying the joint-2 hub (-y side)
    cheek = _hull(_cyl("z", (-0.02, -0.19, -0.07), 0.09, 0.0, 0.02), _cyl("y", (0.175, 0, 0), 0.17,
                                                                         -0.26, -0.10))
    cav = _hull(_cyl("z", (-0.02, -0.19, -0.07 + w), 0.09 - w, 0.0, 0.02),
                _cyl("y", (0.175, 0, 0), 0.17 - w, -0.26 + w, -0.10 - w))
    table = _cyl("z", (0, 0, 0), 0.23, -0.07, 0.0)
    out["frame"] = _casting(table + cheek, cav + _cyl("z", (0, 0, 0), 0.23 - w, -0.07 + w, -w),
                            H["frame"])
    # lower arm: tapered hull of its two hubs
    wa = 0.008
    arm = _hull(_cyl("y", (0, 0, 0), 0.15, -0.08, 0.08), _cyl("y", (0, 0, 0.9), 0.12, -0.08, 0.08))
    arm_c = _hull(_cyl("y", (0, 0, 0), 0.15 - wa, -0.08 + wa, 0.08 - wa),
                  _cyl("y", (0, 0, 0.9), 0.12 - wa, -0.08 + wa, 0.08 - wa))
    out["lower_arm"] = _casting(arm, arm_c, H["lower_arm"])
    # arm housing: hull of the joint-3 hub and the wrist-motor barrel along x
    barrel = _cyl("x", (0, 0, 0.175), 0.12, -0.30, 0.10)
    hs = _hull(_cyl("y", (0, 0, 0), 0.13, 0.09, 0.19), barrel)
    wh = 0.010
    hs_c = _hull(_cyl("y", (0, 0, 0), 0.13 - wh, 0.09 + wh, 0.19 - wh),
                 _cyl("x", (0, 0, 0.175), 0.12 - wh, -0.30 + wh, 0.10 - wh))
    out["arm_housing"] = _casting(hs, hs_c, H["arm_housing"])
    # tube shaft: steel tube with a fork (two cheeks) carrying the joint-5 bearings
    wt = 0.008
    tube = _cyl("x", (0, 0, 0), 0.085, 0.22, 0.84)
    fork = (_hull(_cyl("x", (0, 0, 0), 0.085, 0.82, 0.84),
                  _cyl("y", (0.96, 0, 0), 0.075, 0.065, 0.10))
            + _hull(_cyl("x", (0, 0, 0), 0.085, 0.82, 0.84),
                    _cyl("y", (0.96, 0, 0), 0.075, -0.10, -0.065)))
    tube_c = _cyl("x", (0, 0, 0), 0.085 - wt, 0.30, 0.84 - wt) + _box((0.84, -0.065, -0.2),
                                                                      (1.1, 0.065, 0.2))
    out["tube_shaft"] = _casting(tube + fork, tube_c, H["tube_shaft"])
    # tilt housing: trunnion between the fork cheeks with the joint-6 nose
    wtl = 0.010
    th = _hull(_cyl("y", (0, 0, 0), 0.065, -0.062, 0.062), _cyl("x", (0, 0, 0), 0.06, 0.0, 0.115))
    th_c = _hull(_cyl("y", (0, 0, 0), 0.065 - wtl, -0.062 + wtl, 0.062 - wtl),
                 _cyl("x", (0, 0, 0), 0.06 - wtl, 0.0, 0.115 - wtl))
    out["tilt_housing"] = _casting(th, th_c, H["tilt_housing"])
    # turning disc: solid steel flange
    out["turning_disc"] = _casting(_cyl("x", (0, 0, 0), 0.08, -0.025, 0.0), None,
                                   H["turning_disc"])
    return out


def write_stl(path, vertices: np.ndarray, faces: np.ndarray, name: str) -> None:
    """Write a binary STL with a fixed header (byte-reproducible)."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    tri = v[f]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    rec = np.zeros(len(f), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"] = n
    rec["v"] = tri
    header = f"flexarm demo_arm {name} [m]".encode().ljust(80, b" ")
    with open(path, "wb") as fh:
        fh.write(header + struct.pack("<I", len(f)) + rec.tobytes())


def write_link_cad(folder) -> None:
    """Write every link's CAD as ``folder/<link>.stl`` (binary, metres, byte-reproducible)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    log.info("generating demo arm CAD in %s", folder)
    for name, solid in link_solids().items():
        mesh = solid.to_mesh()
        write_stl(folder / f"{name}.stl", np.asarray(mesh.vert_properties)[:, :3],
                  np.asarray(mesh.tri_verts), name)
