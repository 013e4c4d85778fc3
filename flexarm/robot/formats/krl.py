"""KUKA KRL programs: the procedures of a RAPID module as a ``.src``/``.dat`` pair.

:func:`write_krl` writes what a KUKA controller runs from what
:func:`~flexarm.robot.formats.rapid.read_rapid` reads: the ``.dat`` declares every
robtarget the procedures use as an ``E6POS`` (and joint targets as ``E6AXIS``), the
``.src`` holds one ``DEF`` per procedure and a main ``DEF`` (named after the file, as KRL
wants) that sets the base frame and calls them in module order.

The mapping, RAPID to KRL:

* positions [mm] in the base frame (``wobj0``, ``$BASE`` = null frame);
* orientation: KUKA's ``A, B, C`` [deg], intrinsic Z-Y'-X'' Euler angles
  (``R = Rz(A) Ry(B) Rx(C)``, :func:`abc_from_matrix`) of RAPID's quaternion;
* ``MoveL``/``MoveC``/``MoveJ``/``MoveAbsJ`` to ``LIN``/``CIRC``/``PTP``/``PTP``;
* speeds: ``$VEL.CP`` [m/s] from the speeddata's TCP speed (``v100`` is 0.1 m/s, a
  ``\\V`` argument wins, ``vmax`` is the controller's ``$VEL_MA.CP``); point-to-point
  moves at ``$VEL_AXIS[1..6]`` [%] as asked, else :data:`DEFAULT_PTP_PERCENT` with a
  comment saying so (RAPID gives ``MoveJ`` a TCP speed, not an axis share);
* the payload: ``$LOAD`` (mass [kg], centre of mass [mm] and its axes, inertia
  [kg m²]) from the tooldata's ``tload``; a comment where the program gives none;
* zones: ``fine`` stops, ``zN`` approximates (``C_DIS`` with ``$APO.CDIS`` = the zone's
  TCP radius [mm]; ``C_PTP`` for point-to-point moves);
* the tool: ``$TOOL`` from the instruction's ``tooldata`` (``tool0``: the flange);
* status and turn ``S``/``T`` of each ``E6POS`` from a table the caller derives (from
  the joint angles, :func:`status_turn`), else :data:`DEFAULT_STATUS_TURN`.

Positions are written to 1e-6 mm and angles to 1e-10 deg.  A KRL ``REAL`` is single
precision on the controller (about 0.1 µm at 1.5 m): far below any deflection.
:func:`~flexarm.robot.formats.krl_read.read_krl` reads the pair back.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ...fe.files import atomic_path
from ...fe.typing import ArrayLike, FloatArray, IntArray, PathType
from ..quaternions import quat_normalize, quat_to_matrix
from ..tolerances import tol
from .krl_read import read_status_turn
from .rapid_data import JointTarget, Motion, RapidModule, RobTarget

__all__ = ["abc_from_matrix", "status_turn", "krl_texts", "write_krl", "read_status_turn",
           "check_krl_name", "DEFAULT_STATUS_TURN", "DEFAULT_PTP_PERCENT"]

#: ``S`` and ``T`` of a target whose configuration is not known: the usual upright arm.
DEFAULT_STATUS_TURN = (2, 0)
#: ``$VEL_AXIS`` [% of each axis's maximum] when the program gives no PTP speed (a RAPID
#: ``MoveJ`` speed is the TCP's): slow, for a first run.
DEFAULT_PTP_PERCENT = 10.0
#: Decimals of positions [mm] and angles [deg].
POS_DECIMALS, ANGLE_DECIMALS = 6, 10
_NAME = re.compile(r"[A-Za-z_$][A-Za-z0-9_$]{0,23}\Z")
_KINDS = {"MoveL": "LIN", "MoveC": "CIRC", "MoveJ": "PTP", "MoveAbsJ": "PTP"}
#: The TCP radius [mm] of RAPID's predefined ``z0``; ``zN`` is N mm otherwise.
_Z0_MM = 0.3


def abc_from_matrix(R: ArrayLike) -> FloatArray:
    """KUKA's ``[A, B, C]`` [deg] of rotation matrices: ``R = Rz(A) Ry(B) Rx(C)``.

    ``B`` is in [-90, 90] deg.  ``C`` is taken from what is left after ``Rz(A) Ry(B)``,
    so the three angles give ``R`` back to round-off even at ``B = ±90`` deg (where only
    ``A ∓ C`` is defined).

    Parameters
    ----------
    R : (..., 3, 3) float

    Returns
    -------
    (..., 3) float

    Examples
    --------
    >>> abc_from_matrix(np.diag([-1.0, 1.0, -1.0])).round(9).tolist()  # tool pointing down
    [180.0, -0.0, 180.0]
    >>> abc_from_matrix([[0, 0, 1], [0, 1, 0], [-1, 0, 0]]).tolist()  # B = 90 deg: A = 0
    [0.0, 90.0, 0.0]
    """
    R = np.asarray(R, dtype=np.float64)
    cos_b = np.hypot(R[..., 0, 0], R[..., 1, 0])
    # at B = ±90 deg any A will do (C takes the rest): A = 0 rather than round-off's angle
    A = np.where(cos_b > tol.euler_gimbal, np.arctan2(R[..., 1, 0], R[..., 0, 0]), 0.0)
    B = np.arctan2(-R[..., 2, 0], cos_b)
    ca, sa, cb, sb = (x[..., None] for x in (np.cos(A), np.sin(A), np.cos(B), np.sin(B)))
    # rows of (Rz(A) Ry(B))^T applied to R: what is left is Rx(C)
    y = -sa * R[..., 0, :] + ca * R[..., 1, :]
    z = sb * (ca * R[..., 0, :] + sa * R[..., 1, :]) + cb * R[..., 2, :]
    C = np.arctan2(z[..., 1], y[..., 1])
    return np.degrees(np.stack([A, B, C], axis=-1))


def status_turn(q_deg: ArrayLike, cfx: ArrayLike) -> tuple[IntArray, IntArray]:
    """KUKA status ``S`` and turn ``T`` of joint angles ``q_deg`` (..., 6) [deg].

    ``S`` bit 0: the wrist centre behind axis 1 (overhead area); bit 1: the wrist centre
    in front of the lower arm (axis 3 past the stretched position, the usual elbow);
    bit 2: axis 5 at or below zero.  ``T`` bit ``i``: axis ``i + 1`` below zero.  The
    wrist geometry comes from ABB's ``cfx`` (:func:`~flexarm.robot.ik_path.rapid_conf`
    of the same angles: bit 2 behind axis 1, bit 1 behind the lower arm).  The signs are
    the robot file's joint signs, taken as the controller's.

    Examples
    --------
    >>> s, t = status_turn([[0, 10, 20, 0, 30, 0], [-5, 10, -20, 0, -30, -90]], [0, 1])
    >>> s.tolist(), t.tolist()
    ([2, 6], [0, 53])
    """
    q = np.asarray(q_deg, dtype=np.float64)
    cfx = np.asarray(cfx, dtype=np.int64)
    S = ((cfx >> 2) & 1) | ((1 - ((cfx >> 1) & 1)) << 1) | ((q[..., 4] <= 0) << 2)
    T = np.sum((q < 0).astype(np.int64) << np.arange(q.shape[-1]), axis=-1)
    return S.astype(np.int64), T.astype(np.int64)


def check_krl_name(name: str, what: str) -> str:
    """``name`` if it is a KRL name (24 letters, digits or ``_`` at most, no leading
    digit), else ``ValueError`` naming ``what``.

    Examples
    --------
    >>> check_krl_name("Path_30", "procedure")
    'Path_30'
    """
    if not _NAME.match(name):
        raise ValueError(f"{what} '{name}': a KRL name is at most 24 letters, digits or _ "
                         "and does not start with a digit")
    return name


def _num(x: float, decimals: int) -> str:
    s = f"{round(float(x), decimals):.{decimals}f}".rstrip("0")
    s = s + "0" if s.endswith(".") else s
    return "0.0" if s in ("-0.0", "") else s


def _frame(pos_mm: ArrayLike, R: ArrayLike) -> str:
    """``X .., Y .., Z .., A .., B .., C ..`` of a position [mm] and rotation matrix."""
    abc = abc_from_matrix(R)
    return ",".join([f"{k} {_num(v, POS_DECIMALS)}" for k, v in zip("XYZ", pos_mm, strict=True)]
                    + [f"{k} {_num(v, ANGLE_DECIMALS)}" for k, v in zip("ABC", abc, strict=True)])


def _e6pos(t: RobTarget, st: tuple[int, int] | None) -> str:
    text = _frame(t.pos_mm, quat_to_matrix(quat_normalize(t.quat)))
    if st is not None:
        text += f",S {int(st[0])},T {int(st[1])}"
    ext = np.where(t.is_extax_used, t.extax, 0.0)
    return "{" + text + "".join(f",E{i + 1} {_num(v, POS_DECIMALS)}"
                                 for i, v in enumerate(ext)) + "}"


def _e6axis(t: JointTarget) -> str:
    ext = np.where(t.extax < 9e9 * (1 - 1e-6), t.extax, 0.0)
    return "{" + ",".join([f"A{i + 1} {_num(v, ANGLE_DECIMALS)}" for i, v in
                           enumerate(t.joints_deg)]
                          + [f"E{i + 1} {_num(v, POS_DECIMALS)}"
                             for i, v in enumerate(ext)]) + "}"


def _declared(module: RapidModule, name: str, kind: str):
    return next((d for k, d in module.data.items()
                 if k.lower() == name.lower() and d.type.lower() == kind), None)


def _speed(module: RapidModule, m: Motion, where: str) -> str:
    """``$VEL.CP`` value of motion ``m`` [m/s] (text)."""
    v = dict(m.options).get("V")
    if v is not None:
        try:
            return _num(float(v) * 1e-3, 9)
        except ValueError:
            raise ValueError(f"{where}, line {m.line}: \\V:={v}: give the speed as a "
                             "number [mm/s]") from None
    match = re.fullmatch(r"v(\d+(?:\.\d*)?)", m.speed, re.IGNORECASE)
    if match:
        return _num(float(match.group(1)) * 1e-3, 9)
    if m.speed.lower() == "vmax":
        return "$VEL_MA.CP"
    decl = _declared(module, m.speed, "speeddata")
    if decl is not None and decl.value is not None:
        return _num(float(decl.value[0]) * 1e-3, 9)
    raise ValueError(f"{where}, line {m.line}: speed '{m.speed}' is neither a predefined "
                     "speeddata (v10, v100, vmax ...) nor declared in the module")


def _zone(module: RapidModule, m: Motion, where: str) -> float | None:
    """TCP zone radius [mm] of motion ``m``; None for ``fine``."""
    z = dict(m.options).get("Z")
    if m.is_fine:
        return None
    if z is not None:
        return float(z)
    match = re.fullmatch(r"z(\d+)", m.zone, re.IGNORECASE)
    if match:
        return float(match.group(1)) or _Z0_MM
    decl = _declared(module, m.zone, "zonedata")
    if decl is not None and decl.value is not None:
        return None if decl.value[0] is True else float(decl.value[1])
    raise ValueError(f"{where}, line {m.line}: zone '{m.zone}' is neither a predefined "
                     "zonedata (fine, z1, z10 ...) nor declared in the module")


def _tool(module: RapidModule, m: Motion, where: str) -> np.ndarray:
    """(4, 4) tool frame on the flange [mm] of motion ``m``."""
    T = np.eye(4)
    if m.tool.lower() == "tool0":
        return T
    decl = _declared(module, m.tool, "tooldata")
    if decl is None or decl.value is None:
        raise ValueError(f"{where}, line {m.line}: tool '{m.tool}' is not a tooldata of the "
                         "module")
    T[:3, :3] = quat_to_matrix(quat_normalize(np.asarray(decl.value[1][1], float)))
    T[:3, 3] = np.asarray(decl.value[1][0], float)
    return T


def _load(module: RapidModule, m: Motion) -> str:
    """``$LOAD`` of the instruction's tooldata, or a comment line when it gives none."""
    decl = None if m.tool.lower() == "tool0" else _declared(module, m.tool, "tooldata")
    load = None if decl is None or decl.value is None or len(decl.value) < 3 \
        else decl.value[2]
    if load is None or not float(load[0]) > 0:
        return (f"; $LOAD: {m.tool} gives no payload; the controller's is kept (set mass "
                "[kg], centre of mass [mm] and inertia [kg m2] there)")
    cm = _frame(np.asarray(load[1], float), quat_to_matrix(quat_normalize(
        np.asarray(load[2], float))))
    j = ",".join(f"{k} {_num(v, 9)}" for k, v in zip("XYZ", load[3:6], strict=True))
    return f"$LOAD = {{M {_num(load[0], 9)},CM {{{cm}}},J {{{j}}}}}"


def _ref(t, named: Mapping[str, str]) -> str:
    """The target as a motion argument: its declared name, else an inline aggregate."""
    key = t.name.lower()
    if key in named:
        return named[key]
    return _e6axis(t) if isinstance(t, JointTarget) else _e6pos(t, None)


def _routine(module: RapidModule, name: str, named, tool, where: str) -> list[str]:
    """Lines of the ``DEF`` of procedure ``name``."""
    proc = module.procedure(name)
    lines = [f"DEF {proc.name}( )"]
    state: dict[str, object] = {}

    def setting(key, text):
        if state.get(key) != text:
            state[key] = text
            lines.append(text)

    for m in proc.motions:
        if m.wobj is not None and m.wobj.lower() != "wobj0":
            raise ValueError(f"{where}, line {m.line}: work object '{m.wobj}': KRL output is "
                             "in the base frame (wobj0) only")
        T = _tool(module, m, where) if tool is None else tool
        setting("tool", f"$TOOL = {{{_frame(T[:3, 3], T[:3, :3])}}}")
        setting("load", _load(module, m))
        kind = _KINDS[m.kind]
        zone, speed = _zone(module, m, where), _speed(module, m, where)
        if kind != "PTP":
            setting("vel", f"$VEL.CP = {speed}")
            if zone is not None:
                setting("apo", f"$APO.CDIS = {_num(zone, 3)}")
        approx = "" if zone is None else (" C_PTP" if kind == "PTP" else " C_DIS")
        args = ", ".join(_ref(t, named) for t in m.targets)
        lines.append(f"{kind} {args}{approx}  ; {m.kind} {m.speed} {m.zone}")
    return [*lines, "END"]


def _vel_axis(module: RapidModule, names, percent: float | None) -> list[str]:
    """``$VEL_AXIS`` lines for the point-to-point moves of the procedures ``names``."""
    if not any(_KINDS[m.kind] == "PTP" for p in names for m in module.procedure(p).motions):
        return []
    if percent is None:
        why = ("; PTP axis speeds [% of each axis's maximum]: the program gives none (a "
               f"RAPID MoveJ speed is the TCP's): {_num(DEFAULT_PTP_PERCENT, 3)} % for a "
               "first run")
        percent = DEFAULT_PTP_PERCENT
    elif not 0 < percent <= 100:
        raise ValueError(f"PTP speed {percent:g} %: expected 0 < % <= 100")
    else:
        why = "; PTP axis speeds [% of each axis's maximum], as asked"
    return [why, *(f"$VEL_AXIS[{i}] = {_num(percent, 3)}" for i in range(1, 7))]


def krl_texts(module: RapidModule, name: str, procs: Sequence[str] | None = None,
              tools: Mapping[str, ArrayLike] | None = None,
              status: Mapping[str, tuple[int, int]] | None = None,
              header: Sequence[str] = (),
              ptp_percent: float | None = None) -> tuple[str, str]:
    """The ``.src`` and ``.dat`` texts of the procedures ``procs`` of ``module``.

    Parameters
    ----------
    module : RapidModule
    name : str
        The KRL module (file stem and main ``DEF``).
    procs : sequence of str, optional
        Procedures written (default: every procedure with motions).
    tools : mapping, optional
        Procedure -> (4, 4) tool frame on the flange [mm] (default: the instructions'
        ``tooldata``).
    status : mapping, optional
        Lower-case robtarget name -> ``(S, T)`` (default :data:`DEFAULT_STATUS_TURN`).
    header : sequence of str
        Comment lines after the ``DEF``/``DEFDAT`` lines.
    ptp_percent : float, optional
        ``$VEL_AXIS[1..6]`` of the point-to-point moves [%] (default
        :data:`DEFAULT_PTP_PERCENT`, with a comment saying the program gave none).

    Raises
    ------
    ValueError
        A name KRL cannot hold, an undeclared speed, zone or tool, another work object.

    Examples
    --------
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> src, dat = krl_texts(read_rapid(THESIS_RAPID), "thesis", ["Path_30"])
    >>> src.splitlines()[-5]
    'PTP Target_70  ; MoveJ v10 fine'
    >>> dat.splitlines()[3][:76]
    'DECL E6POS Target_70={X 1488.34,Y 47.78,Z 588.13,A 0.0,B 90.0,C 90.0,S 2,T 0'
    """
    where = module.path or f"module {module.name}"
    check_krl_name(name, "KRL module")
    names = [p for p, pr in module.procedures.items() if pr.motions] if procs is None \
        else [module.procedure(p).name for p in procs]
    status = {k.lower(): v for k, v in (status or {}).items()}
    tools = {k.lower(): np.asarray(v, float) for k, v in (tools or {}).items()}
    known = {k.lower(): t for k, t in module.targets.items()}
    known.update({k.lower(): t for k, t in module.joint_targets.items()})
    used: dict[str, object] = {}
    for p in names:
        check_krl_name(p, f"{where}: procedure")
        for m in module.procedure(p).motions:
            for t in m.targets:
                if t.name.lower() in known and t.name.lower() not in used:
                    used[t.name.lower()] = check_krl_name(t.name, f"{where}, line {m.line}: "
                                                                  "target")
    clash = {p.lower() for p in names} & (set(used) | {name.lower()})
    if clash:
        raise ValueError(f"{where}: '{sorted(clash)[0]}' names both a procedure and a target "
                         "or the module: KRL names must differ")
    notes = [f"; {h}" for h in header]
    dat = ["&ACCESS RVP", "&REL 1", f"DEFDAT {name}", *notes]
    for key, written in used.items():
        t = known[key]
        if isinstance(t, JointTarget):
            dat.append(f"DECL E6AXIS {written}={_e6axis(t)}")
        else:
            dat.append(f"DECL E6POS {written}={_e6pos(t, status.get(key, DEFAULT_STATUS_TURN))}")
    dat.append("ENDDAT")
    src = ["&ACCESS RVP", "&REL 1", f"DEF {name}( )", *notes, "BAS (#INITMOV,0 )",
           *_vel_axis(module, names, ptp_percent),
           "$BASE = {X 0.0,Y 0.0,Z 0.0,A 0.0,B 0.0,C 0.0}", *[f"{p}( )" for p in names], "END"]
    for p in names:
        src += ["", *_routine(module, p, used, tools.get(p.lower()), where)]
    return "\n".join(src) + "\n", "\n".join(dat) + "\n"


def write_krl(path: PathType, module: RapidModule, procs: Sequence[str] | None = None,
              tools: Mapping[str, ArrayLike] | None = None,
              status: Mapping[str, tuple[int, int]] | None = None,
              header: Sequence[str] = (),
              ptp_percent: float | None = None) -> list[Path]:
    """Write ``path`` (``.src``) and the ``.dat`` beside it (see :func:`krl_texts`);
    both texts are made before either file is written.  Returns the two paths.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "thesis.src"
    >>> [p.name for p in write_krl(out, read_rapid(THESIS_RAPID), ["Path_30"])]
    ['thesis.src', 'thesis.dat']
    """
    path = Path(path)
    src, dat = krl_texts(module, path.stem, procs, tools, status, header, ptp_percent)
    out = []
    for p, text in ((path.with_suffix(".src"), src), (path.with_suffix(".dat"), dat)):
        with atomic_path(p) as tmp:
            Path(tmp).write_text(text, encoding="utf-8")
        out.append(p)
    return out

