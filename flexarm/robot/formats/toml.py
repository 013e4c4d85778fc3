"""Robot description TOML (DESIGN §5): ``read(path) -> Robot``, ``write(path, robot)``.

Angles are degrees in the file (keys ending ``_deg``), radians inside.  Mesh paths
are relative to the TOML file.  Rigid joint directions are written ``"rigid"``;
``placeholder = true`` in ``[joints.model]`` marks unmeasured default stiffness (a URDF
import; omitted when false); ``review = true`` in ``[links.regions.<name>]`` marks a
region suggested where no seat was found on the CAD (omitted when false).
Nonlinear joint laws live in an optional ``[nonlinear.<joint name>]`` table (keys:
``backlash_rad``; ``hardening_extra_rad_per_Nm`` + ``hardening_threshold_Nm``;
``hysteresis_lost_rad`` + ``hysteresis_radius_Nm``), read into ``Robot.effects``.
Every error names the file, the key and the value.
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

import numpy as np
import tomllib

from ...fe.errors import ReadError
from ...fe.files import atomic_path
from ...fe.material import MATERIALS, Material, material_from_string
from ..description import (
    BaseSupport,
    Joint,
    Link,
    LumpedMass,
    ModelOptions,
    Region,
    Robot,
    Tool,
)
from ..joints import JointModel
from ..seat_review import ReviewRegion, is_review
from . import toml_keys as tk
from .toml_effects import effects_from_tables, effects_tables
from .toml_modal_damping import modal_damping_from_table, modal_damping_table
from .toml_nonlinear import nonlinear_effects, nonlinear_table

__all__ = ["read", "write", "dumps", "FORMAT_VERSION"]

FORMAT_VERSION = 1
def _stiff(value, key: str) -> float:
    if isinstance(value, str):
        if value.strip().lower() != "rigid":
            raise ValueError(f"{key} must be a number or \"rigid\", got '{value}'")
        return math.inf
    v = float(value)
    if not v > 0:
        raise ValueError(f"{key} must be > 0 (or \"rigid\"), got {value}")
    return v


def _material(value, key: str) -> Material:
    if isinstance(value, dict):
        tk.check_keys(value, tk.MATERIAL_KEYS, key)
        try:
            return Material(float(value["E"]), float(value["nu"]), float(value["rho"]),
                            str(value.get("name", "custom")))
        except KeyError as exc:
            raise ValueError(f"{key} needs E, nu and rho, missing {exc}") from None
        except ValueError as exc:  # Material's own check: say which link
            raise ValueError(f"{key}: {exc}") from None
    try:
        return material_from_string(str(value))
    except ValueError:
        raise ValueError(f"{key}: unknown material '{value}' (known: "
                         f"{'|'.join(MATERIALS)} or {{E, nu, rho}})") from None


def _inertia(value, key: str) -> tuple:
    J = np.asarray(value, dtype=float)
    if J.shape == (3,):
        J = np.diag(J)
    if J.shape != (3, 3):
        raise ValueError(f"{key} must be 3 principal values or a 3x3 matrix, got {value!r}")
    return tuple(map(tuple, J.tolist()))


def _link(d: dict, folder: Path) -> Link:
    name = str(d.get("name", ""))
    key = f"links.{name or '?'}"
    if not name:
        raise ValueError("links: every link needs a name")
    tk.check_keys(d, tk.LINK_KEYS, key)
    mesh = d.get("mesh")
    mesh_path = None
    if mesh:
        mesh_path = (folder / mesh).resolve() if not Path(mesh).is_absolute() else Path(mesh)
        if not mesh_path.is_file():
            raise ValueError(f"{key}.mesh: file not found: '{mesh}' (looked in {mesh_path})")
    lumped = []
    for m in tk.tables(d, "lumped", f"{key}."):
        mkey = f"{key}.lumped.{m.get('name', '?')}"
        tk.check_keys(m, tk.LUMPED_KEYS, mkey)
        if "mass" not in m:
            raise ValueError(f"{mkey}.mass is required [kg]")
        mass = float(m["mass"])
        if not mass >= 0:
            raise ValueError(f"{mkey}.mass must be >= 0 kg, got {m['mass']}")
        lumped.append(LumpedMass(str(m.get("name", "")), mass,
                                 tuple(float(v) for v in m.get("position", (0, 0, 0))),
                                 _inertia(m.get("inertia", [0, 0, 0]), f"{mkey}.inertia")))
    regions = {}
    for rname, r in tk.table(d, "regions", f"{key}.").items():
        rkey = f"{key}.regions.{rname}"
        if not isinstance(r, dict):
            raise ValueError(f"{rkey} must be a table, got {r!r}")
        tk.check_keys(r, tk.REGION_KEYS, rkey)
        review = r.get("review", False)
        if not isinstance(review, bool):
            raise ValueError(f"{rkey}.review must be true or false, got {review!r}")
        try:
            regions[rname] = (ReviewRegion if review else Region)(
                tuple(float(v) for v in r["center"]), tuple(float(v) for v in r["axis"]),
                float(r["r_min"]), float(r["r_max"]), float(r["half_width"]),
                str(r.get("coupling", "rbe2")))
        except KeyError as exc:
            raise ValueError(f"{rkey}: missing key {exc}") from None
    return Link(name, mesh_path, _material(d.get("material", "steel"), f"{key}.material"),
                str(d.get("units", "m")), tuple(lumped), regions,
                _volume_meshes(tk.table(d, "volume_meshes", f"{key}."), folder,
                               f"{key}.volume_meshes"))


def _volume_meshes(table: dict, folder: Path, key: str) -> dict:
    """``{"0.03" = "tets/base.vtu"}`` -> ``{0.03: Path}`` (edge length [m] -> file)."""
    out = {}
    for size, file in table.items():
        try:
            h = float(size)
        except ValueError:
            h = float("nan")
        if not h > 0:
            raise ValueError(f"{key}: key '{size}' must be a tet edge length in metres")
        path = Path(file) if Path(file).is_absolute() else (folder / file).resolve()
        if not path.is_file():
            raise ValueError(f"{key}.'{size}': file not found: '{file}' (looked in {path})")
        out[h] = path
    return out


def _joint(d: dict) -> Joint:
    name = str(d.get("name", ""))
    key = f"joints.{name or '?'}"
    if not name:
        raise ValueError("joints: every joint needs a name")
    tk.check_keys(d, tk.JOINT_KEYS, key)
    model = _joint_model(dict(d.get("model", {})), f"{key}.model")
    emodel = _joint_model(dict(d["emodel"]), f"{key}.emodel") if "emodel" in d else None
    lim = d.get("limits_deg", [-180.0, 180.0])
    if len(lim) != 2:
        raise ValueError(f"{key}.limits_deg must be [lower, upper], got {lim!r}")
    for k in ("parent", "child", "origin", "axis"):
        if k not in d:
            raise ValueError(f"{key}.{k} is required")
    return Joint(name, str(d["parent"]), str(d["child"]),
                 tuple(float(v) for v in d["origin"]), tuple(float(v) for v in d["axis"]),
                 math.radians(lim[0]), math.radians(lim[1]), model,
                 tuple(math.radians(v) for v in d.get("rpy_deg", (0, 0, 0))),
                 float(d.get("gear_ratio", 1.0)), emodel)


def _joint_model(m: dict, key: str) -> JointModel:
    """A ``[joints.model]`` (physical) or ``[joints.emodel]`` (equivalent) table."""
    tk.check_keys(m, tk.MODEL_KEYS, key)
    if "torsion" not in m:
        raise ValueError(f"{key}.torsion is required [N m/rad]")
    placeholder = m.get("placeholder", False)
    if not isinstance(placeholder, bool):
        raise ValueError(f"{key}.placeholder must be true or false, got {placeholder!r}")
    values = dict(
        torsion=_stiff(m["torsion"], f"{key}.torsion"),
        tilt=_stiff(m.get("tilt", "rigid"), f"{key}.tilt"),
        radial=_stiff(m.get("radial", "rigid"), f"{key}.radial"),
        axial=_stiff(m.get("axial", "rigid"), f"{key}.axial"),
        damping_ratio=float(m.get("damping_ratio", 0.02)),
        rayleigh=tuple(m["rayleigh"]) if "rayleigh" in m else None,
        tilt2=_stiff(m["tilt2"], f"{key}.tilt2") if "tilt2" in m else None,
        source="placeholder" if placeholder else "given",
    )
    try:
        return JointModel(**values)
    except ValueError as exc:  # "joint damping_ratio must ...": say which joint
        raise ValueError(f"{key}.{str(exc).removeprefix('joint ')}") from None


def from_dict(data: dict, folder: Path, source: Path | None = None) -> Robot:
    """Build a :class:`Robot` from parsed TOML ``data``; mesh paths relative to ``folder``."""
    version = data.get("format_version", FORMAT_VERSION)
    if version != FORMAT_VERSION:
        raise ValueError(f"format_version: cannot read version {version} "
                         f"(this flexarm reads {FORMAT_VERSION})")
    tk.check_keys(data, tk.TOP_KEYS, "top level")
    b = tk.table(data, "base", "", tk.BASE_KEYS)
    kind = str(b.get("support", "clamped"))
    Kb = None
    if "stiffness" in b:
        Kb = np.asarray(b["stiffness"], dtype=float)
        Kb = np.diag(Kb) if Kb.shape == (6,) else Kb
        if np.any(np.diag(Kb) < 0):
            raise ValueError(f"base.stiffness: negative stiffness {np.diag(Kb).min():g}")
        Kb = tuple(map(tuple, Kb.tolist()))
    t = tk.table(data, "tool", "", tk.TOOL_KEYS)
    opts = tk.table(data, "model", "", tk.OPTION_KEYS)
    w = tk.table(data, "wrist", "", tk.WRIST_KEYS)
    poses = {k: _angles(v, f"poses.{k}") for k, v in tk.table(data, "poses", "").items()}
    joints = tk.tables(data, "joints")
    joint_names = [str(d.get("name", "")) for d in joints]
    twice = [n for i, n in enumerate(joint_names) if n in joint_names[:i]]
    if twice:  # before [nonlinear] is matched to the joints by name
        raise ValueError(f"joints: duplicate name '{twice[0]}' (names must be unique)")
    return Robot(
        name=str(data.get("name", "robot")),
        links=tuple(_link(d, folder) for d in tk.tables(data, "links")),
        joints=tuple(_joint(d) for d in joints),
        base=BaseSupport(kind, Kb, float(b.get("damping_ratio", 0.02))),
        tool=Tool(tuple(float(v) for v in t.get("xyz", (0, 0, 0))),
                  tuple(math.radians(float(v)) for v in t.get("rpy_deg", (0, 0, 0))),
                  t.get("link")),
        poses=poses,
        options=ModelOptions(int(opts.get("element_order", 1)),
                             float(opts.get("mesh_size", 0.03)), int(opts.get("cb_modes", 10)),
                             str(opts.get("mesher", "tetwild"))),
        wrist_coupling=tuple(map(tuple, w["coupling"])) if "coupling" in w else None,
        wrist_stiffness=tuple(map(tuple, w["stiffness"])) if "stiffness" in w else None,
        source=source,
        effects=(nonlinear_effects(tk.table(data, "nonlinear", ""), joint_names)
                 + effects_from_tables(tk.tables(data, "effects"), joint_names)),
        modal_damping=modal_damping_from_table(tk.table(data, "modal_damping", "")),
    )


def _angles(value, key: str) -> list[float]:
    """Joint angles [rad] of a list of degrees."""
    if not isinstance(value, list) or not all(isinstance(a, int | float) for a in value):
        raise ValueError(f"{key} must be a list of joint angles in degrees, got {value!r}")
    return [math.radians(float(a)) for a in value]


def read(path) -> Robot:
    """Read a robot TOML file; errors become :class:`ReadError` naming the file.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import demo_robot_path
    >>> read(demo_robot_path()).joint_names[:2]
    ('joint_1', 'joint_2')
    """
    path = Path(path)
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except FileNotFoundError:
        raise
    except tomllib.TOMLDecodeError as exc:
        raise ReadError(f"{path}: {exc}") from None
    except UnicodeDecodeError as exc:
        raise ReadError(f"{path}: not a UTF-8 text file ({exc.reason} at byte {exc.start})") \
            from None
    try:
        return from_dict(data, path.parent, source=path.resolve())
    except (ValueError, KeyError, TypeError, AttributeError, IndexError) as exc:
        # a value of the wrong shape (a number where a list belongs, ...) in a user file
        raise ReadError(f"{path}: {exc}") from None


def _num(v: float):
    return "rigid" if math.isinf(v) else float(v)


def _model_dict(m: JointModel) -> dict:
    model = {"torsion": _num(m.torsion), "tilt": _num(m.tilt), "radial": _num(m.radial),
             "axial": _num(m.axial), "damping_ratio": m.damping_ratio}
    if m.tilt2 is not None:
        model["tilt2"] = _num(m.tilt2)
    if m.rayleigh is not None:
        model["rayleigh"] = list(m.rayleigh)
    if m.is_placeholder:  # omitted when false: files with given stiffness stay as they were
        model["placeholder"] = True
    return model


def to_dict(robot: Robot, folder: Path) -> dict:
    """Plain TOML-ready dict of ``robot``; mesh paths relative to ``folder``."""
    links = []
    for lk in robot.links:
        d: dict = {"name": lk.name}
        if lk.mesh is not None:
            d["mesh"] = Path(os.path.relpath(lk.mesh, folder)).as_posix()
        d["units"] = lk.units
        mat = lk.material
        d["material"] = (mat.name if MATERIALS.get(mat.name) == mat
                         else {"E": mat.E, "nu": mat.nu, "rho": mat.rho, "name": mat.name})
        if lk.lumped:
            d["lumped"] = [{"name": m.name, "mass": m.mass, "position": list(m.position),
                            "inertia": [list(r) for r in m.inertia]} for m in lk.lumped]
        if lk.volume_meshes:
            d["volume_meshes"] = {f"{h:g}": Path(os.path.relpath(f, folder)).as_posix()
                                  for h, f in sorted(lk.volume_meshes.items())}
        if lk.regions:
            d["regions"] = {k: {"center": list(r.center), "axis": list(r.axis),
                                "r_min": r.r_min, "r_max": r.r_max,
                                "half_width": r.half_width, "coupling": r.coupling,
                                **({"review": True} if is_review(r) else {})}
                            for k, r in lk.regions.items()}
        links.append(d)
    joints = []
    for j in robot.joints:
        joints.append({
            "name": j.name, "parent": j.parent, "child": j.child,
            "origin": list(j.origin), "rpy_deg": [math.degrees(v) for v in j.rpy],
            "axis": list(j.axis),
            "limits_deg": [math.degrees(j.lower), math.degrees(j.upper)],
            "gear_ratio": j.gear_ratio, "model": _model_dict(j.model),
        })
        if j.emodel is not None:
            joints[-1]["emodel"] = _model_dict(j.emodel)
    base: dict = {"support": robot.base.kind, "damping_ratio": robot.base.damping_ratio}
    if robot.base.stiffness is not None:
        base["stiffness"] = [list(r) for r in robot.base.stiffness]
    tool: dict = {"xyz": list(robot.tool.xyz), "rpy_deg": [math.degrees(v) for v in robot.tool.rpy]}
    if robot.tool.link:
        tool["link"] = robot.tool.link
    out = {
        "format_version": FORMAT_VERSION,
        "name": robot.name,
        "model": {"element_order": robot.options.element_order,
                  "mesh_size": robot.options.mesh_size, "cb_modes": robot.options.cb_modes,
                  **({"mesher": robot.options.mesher}
                     if robot.options.mesher != "tetwild" else {})},
        "base": base,
        "tool": tool,
        "poses": {k: [round(math.degrees(a), 10) for a in v] for k, v in robot.poses.items()},
    }
    wrist = {}
    if robot.wrist_coupling is not None:
        wrist["coupling"] = [list(r) for r in robot.wrist_coupling]
    if robot.wrist_stiffness is not None:
        wrist["stiffness"] = [list(r) for r in robot.wrist_stiffness]
    if wrist:
        out["wrist"] = wrist
    out["links"] = links
    out["joints"] = joints
    nonlinear = nonlinear_table(robot)
    if nonlinear:
        out["nonlinear"] = nonlinear
    stored = effects_tables(robot.effects, robot.joint_names)
    if stored:
        out["effects"] = stored
    if robot.modal_damping:
        out["modal_damping"] = modal_damping_table(robot.modal_damping)
    return out


#: An array of scalars as tomli_w writes it: one item per line, trailing commas.
_SCALAR_ARRAY = re.compile(r"\[\n((?:[ ]+[^\[\]\n]+,\n)+)[ ]*\]")


def dumps(data: dict) -> str:
    """TOML text of ``data`` as people edit it: arrays of numbers on one line
    (``xyz = [0.15, 0.0, 0.0]``), matrices one row per line.

    Examples
    --------
    >>> print(dumps({"tool": {"xyz": [0.15, 0.0, 0.0], "link": "flange"}}), end="")
    [tool]
    xyz = [0.15, 0.0, 0.0]
    link = "flange"
    """
    import tomli_w

    def one_line(m: re.Match) -> str:
        items = [line.strip().rstrip(",") for line in m.group(1).splitlines()]
        return "[" + ", ".join(items) + "]"

    return _SCALAR_ARRAY.sub(one_line, tomli_w.dumps(data))


def write(path, robot: Robot) -> None:
    """Write ``robot`` as TOML (atomically); mesh paths relative to the file."""
    path = Path(path)
    data = to_dict(robot, path.resolve().parent)
    with atomic_path(path) as tmp:
        tmp.write_bytes(dumps(data).encode())
