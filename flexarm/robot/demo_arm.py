"""The built-in demo arm's robot description: joints, lumped motors, seats, poses.

An arm of the ABB IRB 4600-60/2.05 class (DESIGN §4) around the link CAD of
:mod:`flexarm.meshes.demo_arm`.  Motors, gearboxes and the balancing cylinder are
lumped masses; each joint seat is an interface region on its hub's bearing bore.

Run ``python -m flexarm.robot.demo_arm [folder]`` to regenerate the shipped files
(``meshes/*.stl`` and ``robot.toml``); the output is byte-for-byte reproducible.  The
pinned tetrahedra (``tets/*.vtu``, :data:`PINNED_SIZES`) are made again only with
``--pin`` (fTetWild never gives the same mesh twice).
"""

from __future__ import annotations

import logging
import sys
from importlib import resources
from pathlib import Path

import numpy as np

from ..meshes.demo_arm import LINKS, Hub, hubs, write_link_cad

__all__ = ["LUMPED", "JOINTS", "POSES_DEG", "TOOL", "WRIST_TRAINS", "wrist_coupling",
           "robot_dict", "generate", "PINNED_SIZES", "pin_volume_meshes", "demo_robot_path",
           "load_demo_robot"]

log = logging.getLogger(__name__)


def _motor(name, mass, pos, radius, length, axis):
    """Lumped motor+gear as a solid cylinder (inertia about its own centre)."""
    a = "xyz".index(axis)
    J = np.full(3, mass * (3 * radius**2 + length**2) / 12)
    J[a] = mass * radius**2 / 2
    return {"name": name, "mass": mass, "position": list(pos), "inertia": [float(x) for x in J]}


#: Lumped motors, gearboxes and the balancing cylinder per link [kg, m].
LUMPED = {
    "frame": [_motor("motor_gear_1", 19.0, (-0.16, 0.12, 0.06), 0.09, 0.30, "z"),
              _motor("motor_gear_2", 22.0, (0.175, -0.36, 0.0), 0.10, 0.25, "y"),
              _motor("balancer", 10.0, (-0.05, 0.20, 0.20), 0.05, 0.50, "z")],
    "lower_arm": [_motor("motor_gear_3", 21.0, (0.0, 0.17, 0.0), 0.09, 0.20, "y")],
    "arm_housing": [_motor("motor_4", 8.0, (-0.38, 0.0, 0.175), 0.06, 0.20, "x"),
                    _motor("motor_5", 6.0, (-0.25, 0.10, 0.26), 0.05, 0.18, "x"),
                    _motor("motor_6", 6.0, (-0.25, -0.10, 0.26), 0.05, 0.18, "x"),
                    _motor("gear_4", 4.0, (0.12, 0.0, 0.175), 0.08, 0.10, "x")],
    "tube_shaft": [_motor("gear_5", 4.0, (0.96, 0.12, 0.0), 0.05, 0.06, "y")],
    "tilt_housing": [_motor("gear_6", 2.5, (0.08, 0.0, 0.0), 0.05, 0.06, "x")],
}

#: Physical joint models (DESIGN §4): gear torsion [N m/rad], bearing tilt [N m/rad] (None
#: = rigid), limits [deg], gear ratio.  The flexible arm uses these as they are; the links'
#: bending comes from their superelements.
JOINTS = (
    ("joint_1", 6.5e5, 3.0e7, (-180.0, 180.0), 120.0),
    ("joint_2", 4.0e6, 1.5e7, (-90.0, 150.0), 150.0),
    ("joint_3", 4.0e6, 1.5e7, (-180.0, 75.0), 120.0),
    ("joint_4", 3.0e5, None, (-400.0, 400.0), 80.0),
    ("joint_5", 2.5e5, None, (-125.0, 120.0), 80.0),
    ("joint_6", 1.5e5, None, (-400.0, 400.0), 50.0),
)
#: Equivalent bearing tilt (tilt, tilt2) [N m/rad] of the rigid-link E-model: the bearing
#: in series with the child link's bending between its interface nodes, from
#: ``flexarm.assembly.equivalent.equivalent_joint_models`` on the default build (CB, 30 mm
#: Tet4), rounded to 3 digits; ``tests/assembly/test_equivalent.py`` checks them (slow).
EMODEL_TILT = {
    "joint_1": (5.64e6, 1.10e7),
    "joint_2": (4.64e6, 4.23e6),
    "joint_3": (4.40e6, 4.16e6),
}
POSES_DEG = {
    "P1": [0.0, 52.0, -19.0, 12.0, -15.0, -11.0],
    "P2": [0.0, 0.0, 66.0, 0.0, -66.0, 0.0],
    "P3": [0.0, 32.0, 20.0, 101.0, -98.0, -35.0],
    "home": [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
}
#: TCP: a 150 mm tool on the flange, tool z along the flange normal (like ROS tool0).
TOOL = {"xyz": [0.15, 0.0, 0.0], "rpy_deg": [0.0, 90.0, 0.0], "link": "turning_disc"}
#: Wrist drive trains [-]: joints 5 and 6 are driven from motors at the rear of the arm
#: housing by concentric shafts through the hollow joint-4 tube shaft.  ``motor_stage``:
#: spur stage from the (offset) motor onto its drive shaft, inside the arm housing;
#: ``bevel_45``: bevel pair from the tube axis (x) onto the joint-5 axis (y), an idler on
#: the joint-5 axis for joint 6; ``bevel_56``: bevel pair from the joint-5 axis onto the
#: joint-6 axis (x) inside the tilt housing; ``reducer``: the joint's own reducer.  The
#: products equal the joints' ``gear_ratio`` (80 and 50).  See :func:`wrist_coupling`.
WRIST_TRAINS = {
    "joint_5": {"motor_stage": 2.0, "bevel_45": 1.0, "reducer": 40.0},
    "joint_6": {"motor_stage": 2.0, "bevel_45": 1.25, "bevel_56": 1.0, "reducer": 20.0},
}


def wrist_coupling() -> list[list[float]]:
    """(3, 3) joint-to-motor coupling ``C`` of joints 4-6 [-] (``robot.toml [wrist]``).

    Convention of :class:`~flexarm.robot.kinematics.Chain`: motor angle
    ``theta_m = n * (C @ q)`` on the wrist block, ``n`` the gear ratios (80, 80, 50).

    Derivation (angles [rad]; every shaft angle relative to the body carrying its
    bearings; the stage ratios ``WRIST_TRAINS`` are input/output speed ratios [-]):

    * Joint 4: motor 4 drives the tube shaft through its own gearbox in the arm housing,
      ``theta_m4 = n4 q4``: row ``(1, 0, 0)``.
    * Joint 5: the drive shaft turns ``phi5 = theta_m5 / a5`` in the arm housing
      (motor stage ``a5``), i.e. ``phi5 - q4`` relative to the tube shaft that carries the
      bevel pair and the reducer, so ``q5 = (phi5 - q4) / N5`` with the wrist-side ratio
      ``N5 = b45 r5 = 40``.  Hence ``theta_m5 = n5 (q5 + q4 / N5)``: ``c54 = 1/N5 = 0.025``.
    * Joint 6: the shaft turns ``phi6 - q4`` in the tube shaft; the idler on the joint-5
      axis turns ``psi = (phi6 - q4) / b45`` in the tube shaft and ``psi - q5`` in the tilt
      housing; ``q6 = (psi - q5) / (b56 r6)``.  Hence ``theta_m6 = n6 (q6 + q5 / (b56 r6)
      + q4 / (b45 b56 r6))``: ``c65 = 1/(b56 r6) = 0.05``, ``c64 = 1/N6 = 0.04``.

    The couplings are the inverse *wrist-side* ratios (of order 1/gear ratio, because
    the reduction sits at the wrist and the shafts run at near motor speed).  Their signs
    are the sense of the bevel meshes, taken positive here.

    The coupled wrist stiffness (:func:`~flexarm.assembly.flexible.coupled_wrist_stiffness`)
    is ``K_w = C^T diag(k) C`` [N m/rad], with ``k = (3.0, 2.5, 1.5) 1e5 N m/rad`` the
    joint-referred torsion stiffness of each drive train (its elastic twist with the
    motor held is ``(C dq)_i``).  Hence ``K_66 = k6``; ``K_44 = k4 + c54^2 k5 + c64^2 k6``
    and ``K_55 = k5 + c65^2 k6`` exceed ``k4, k5`` by 0.13 % and 0.15 %; the
    off-diagonal terms ``K_45 = c54 k5 + c64 c65 k6 = 6550``, ``K_46 = c64 k6 = 6000``,
    ``K_56 = c65 k6 = 7500 N m/rad`` are 2-4 % of ``sqrt(K_ii K_jj)``.  The compliance
    ``K_w^-1 = C^-1 diag(1/k) C^-T`` keeps ``(K_w^-1)_44 = 1/k4`` exactly (C is unit lower
    triangular) and gains the cross terms ``(K_w^-1)_45 = -c54/k4`` etc.  Only
    ``coupling`` is written (no ``stiffness``), so the E-model and the default flexible
    model keep the individual springs ``k``; ``flexible_arm(..., coupled_wrist=True)``
    uses ``K_w``.  The model holds the motors (no rotor inertia coordinates), so the
    coupling shifts the wrist modes (by up to 0.2-0.4 % in frequency at P1-P3) and changes the TCP
    compliance (up to 1.2 % translational, 3 % rotational) but adds no modes.
    """
    t5, t6 = WRIST_TRAINS["joint_5"], WRIST_TRAINS["joint_6"]
    c54 = 1.0 / (t5["bevel_45"] * t5["reducer"])
    c65 = 1.0 / (t6["bevel_56"] * t6["reducer"])
    c64 = 1.0 / (t6["bevel_45"] * t6["bevel_56"] * t6["reducer"])
    return [[1.0, 0.0, 0.0], [c54, 1.0, 0.0], [c64, c65, 1.0]]


def _region(h: Hub, ring: float = 0.015) -> dict:
    """Interface region on the bore surface of a hub (nodes within ``ring`` of it)."""
    a = {"x": [1.0, 0.0, 0.0], "y": [0.0, 1.0, 0.0], "z": [0.0, 0.0, 1.0]}[h.axis]
    mid = (h.lo + h.hi) / 2
    c = [float(ci + mid * ai) for ci, ai in zip(h.c, a, strict=True)]
    return {"center": c, "axis": a, "r_min": max(h.r_bore - ring, 0.0),
            "r_max": h.r_bore + ring, "half_width": (h.hi - h.lo) / 2 + 0.005, "coupling": "rbe2"}


def robot_dict() -> dict:
    """The demo arm's robot description as a TOML-ready dict (meshes in ``meshes/``)."""
    H = hubs()
    names = [lk[0] for lk in LINKS]
    seats = {  # joint -> (hub on parent, hub on child)
        "joint_1": (H["base"][0], H["frame"][0]),
        "joint_2": (H["frame"][1], H["lower_arm"][0]),
        "joint_3": (H["lower_arm"][1], H["arm_housing"][0]),
        "joint_4": (H["arm_housing"][1], H["tube_shaft"][0]),
        "joint_5": (H["tube_shaft"][1], H["tilt_housing"][0]),
        "joint_6": (H["tilt_housing"][1], H["turning_disc"][0]),
    }
    links = []
    for i, (name, mat, _, _) in enumerate(LINKS):
        d = {"name": name, "mesh": f"meshes/{name}.stl", "units": "m", "material": mat}
        if name in LUMPED:
            d["lumped"] = LUMPED[name]
        regions = {}
        if i < len(JOINTS):
            regions[JOINTS[i][0]] = _region(seats[JOINTS[i][0]][0])
        if i > 0:
            regions[JOINTS[i - 1][0]] = _region(seats[JOINTS[i - 1][0]][1])
        if name == "base":  # foundation seat: the underside of the foot ring
            regions["base"] = {"center": [0.0, 0.0, 0.0], "axis": [0.0, 0.0, 1.0],
                               "r_min": 0.18, "r_max": 0.29, "half_width": 0.002,
                               "coupling": "rbe2"}
        if name == "turning_disc":  # flange ring outside the joint-6 seat (r <= 0.035)
            regions["tcp"] = {"center": [-0.0125, 0.0, 0.0], "axis": [1.0, 0.0, 0.0],
                              "r_min": 0.04, "r_max": 0.08, "half_width": 0.0125,
                              "coupling": "rbe3"}
        d["regions"] = dict(sorted(regions.items()))
        d["volume_meshes"] = {f"{h:g}": _pinned_file(name, h) for h in PINNED_SIZES}
        links.append(d)
    joints = []
    for j, (jname, k_t, k_tilt, lim, ratio) in enumerate(JOINTS):
        _, _, origin, axis = LINKS[j + 1]
        model = {"torsion": k_t, "tilt": k_tilt if k_tilt else "rigid", "radial": "rigid",
                 "axial": "rigid", "damping_ratio": 0.03}
        joints.append({"name": jname, "parent": names[j], "child": names[j + 1],
                       "origin": list(origin), "rpy_deg": [0.0, 0.0, 0.0],
                       "axis": [float(a) for a in axis], "limits_deg": list(lim),
                       "gear_ratio": ratio, "model": model})
        if jname in EMODEL_TILT:
            tilt, tilt2 = EMODEL_TILT[jname]
            joints[-1]["emodel"] = dict(model, tilt=tilt, tilt2=tilt2)
    return {
        "format_version": 1,
        "name": "flexarm demo arm (IRB 4600-60/2.05 class)",
        "model": {"element_order": 1, "mesh_size": 0.03, "cb_modes": 10},
        "base": {"support": "clamped", "damping_ratio": 0.02},
        "tool": TOOL,
        "poses": POSES_DEG,
        "wrist": {"coupling": wrist_coupling()},
        "links": links,
        "joints": joints,
    }


#: Tet edge lengths [m] at which the shipped demo arm's tetrahedra are pinned: the
#: robot's ``mesh_size``, the coarser size of its accuracy study, and the coarse mesh of
#: quick flexible models (tests, examples).  fTetWild gives different tetrahedra on every
#: run; pinned, every fresh demo reproduces its figures.
PINNED_SIZES = (0.03, 0.045, 0.06)


def _pinned_file(name: str, size: float) -> str:
    """Path of a link's pinned volume mesh, relative to the robot file."""
    return f"tets/{name}_{size * 1e3:g}mm.vtu"


def pin_volume_meshes(folder) -> list[Path]:
    """Tetrahedralise every link's CAD in ``folder/meshes`` at :data:`PINNED_SIZES` with
    fTetWild (no cache) and write the pinned meshes the robot file names."""
    from ..meshes import load_surface, tetrahedralize
    from ..meshes.volume_io import write_volume_mesh

    folder = Path(folder)
    written = []
    for name, *_ in LINKS:
        surface = load_surface(folder / "meshes" / f"{name}.stl")
        for h in PINNED_SIZES:
            mesh = tetrahedralize(surface, h, cache=False, name=name)
            path = folder / _pinned_file(name, h)
            path.parent.mkdir(parents=True, exist_ok=True)
            write_volume_mesh(path, mesh)
            log.info("%s at %g mm: %d tets -> %s", name, h * 1e3, mesh.n_tets, path)
            written.append(path)
    return written


def generate(folder, pin: bool = False) -> Path:
    """Write ``meshes/*.stl`` and ``robot.toml`` into ``folder`` (and with ``pin`` new
    pinned tetrahedra, :func:`pin_volume_meshes`); returns the TOML path."""
    from .formats.toml import dumps

    folder = Path(folder)
    write_link_cad(folder / "meshes")
    if pin:
        pin_volume_meshes(folder)
    path = folder / "robot.toml"
    text = "# Generated by `python -m flexarm.robot.demo_arm`; do not edit by hand.\n"
    path.write_bytes(text.encode() + dumps(robot_dict()).encode())
    log.info("demo arm written: %s", path)
    return path


def demo_robot_path() -> Path:
    """Path of the shipped demo ``robot.toml`` (package data)."""
    return Path(str(resources.files("flexarm") / "data" / "demo_arm" / "robot.toml"))


def load_demo_robot():
    """The demo arm as a :class:`~flexarm.robot.description.Robot`."""
    from .formats.toml import read

    return read(demo_robot_path())


if __name__ == "__main__":
    logging.basicConfig(level=logging.INFO)
    args = [a for a in sys.argv[1:] if a != "--pin"]
    target = Path(args[0]) if args else demo_robot_path().parent
    generate(target, pin="--pin" in sys.argv)
