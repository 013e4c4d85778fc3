"""Universal files (UFF/UNV) as test rigs write them, read and written through pyuff.

Datasets understood:

- **151** header (model name, description, program): kept as text.
- **164** units: the factors that turn file units into SI (``SI = value / factor``,
  as the UFF definition says); a file without one is SI.  They apply to the datasets
  after them.
- **15** / **2411** nodes and **82** tracelines: the test geometry, base frame [m];
  a flexarm file has one block of each per pose (:mod:`.uff_geometry`), and a file
  without a points table gives one through it
  (:func:`~flexarm.validation.dynamic.point_geometry.points_from_geometry`).
- **2420** / **18** coordinate systems: each node is put from its definition system
  into the base frame, and the directions of its 55, 2414 and 58 data are turned from
  its displacement system into base axes before anything uses them
  (:mod:`.uff_systems`, :mod:`.uff_directions`); a node naming a system the file does
  not define is refused.
- **58** FRFs (``func_type`` 4): one response DOF per reference DOF, ordinate
  displacement (8), velocity (11) or acceleration (12) over force (13); turned into
  receptance [m/N] at ``+x, +y, +z`` (a negative UFF direction flips the sign).  An
  ordinate of type unknown (0) or general (1) is taken from its unit label (``m/s^2``,
  ``(1/N)*(m/s²)``: acceleration) or from the caller's ``response``; the 0 Hz line of a
  velocity or acceleration FRF (which an FFT analyzer exports, set to zero) is dropped.
  A 58 ordinary coherence (function type 6) of the same nodes and axes is kept with
  its FRF (:attr:`UffFrf.coherence`) and weights the FRF comparison.
- **55** mode shapes: normal (analysis type 2, real shapes, viscous damping ratio)
  or complex (3, eigenvalue ``-ζω ± iω√(1-ζ²)``); x, y, z per node.  A DOF that is
  exactly zero in every mode of a pose is taken as not measured and dropped.
- **2414** analysis data: mode shapes as NX writes them, read like 55 sets
  (:mod:`.uff_modes`); other 2414 results are left alone.  The modal mass of 55 and
  2414 sets is kept (:attr:`UffContent.modal_mass`).

A pose is not a universal-file notion: flexarm writes ``flexarm pose=<label>
q_deg=<q1,...,q6>`` into ID line 4 of every 55 and 58 set it writes (and, past the
first pose, ``flexarm nodes+=<offset>`` into ID line 5) and reads it back, node ids less
the offset; other files get the ``pose`` and ``q`` the caller gives, and without them are refused
(never read at zero joint angles).  Every error names the file, the dataset (1-based,
with its type) and the field, and what to give instead.  A file cut short (a
last dataset without its closing delimiter, which pyuff drops) is refused naming that
dataset and its pose, and a value pyuff cannot parse is named with its line
(:mod:`.uff_scan`).  The writer is :mod:`.uff_write`.
"""

from __future__ import annotations

import logging
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ....fe.errors import MissingDependencyError, ReadError
from ....fe.typing import PathType
from ..measurements import DIRECTIONS, FrfData
from ..shape_data import ShapeData
from .uff_directions import frf_to_base, shapes_to_base
from .uff_frf import COHERENCE, RESPONSES, UffFrf, Where, coherence_of, collect_frfs, frf_of
from .uff_geometry import pose_geometries
from .uff_modes import is_mode_2414, modal_mass, mode_2414
from .uff_scan import bad_number, truncation
from .uff_systems import node_frames, systems_18, systems_2420

__all__ = ["EXTENSIONS", "RESPONSES", "UffFrf", "UffContent", "UffOptions", "read_uff", "read"]

log = logging.getLogger(__name__)

EXTENSIONS = (".uff", ".unv")
_MARK = re.compile(r"flexarm pose=(\S+) q_deg=(\S+)")
_OFFSET = re.compile(r"flexarm nodes\+=(\d+)")
_NODES = (15, 2411)


@dataclass(frozen=True)
class UffOptions:
    """What a universal file from another tool may need said about it.

    ``pose``: ``(label, q [rad])`` of sets without a flexarm pose mark; ``response``: what
    an ordinate of type unknown or general is (``"displacement"``, ``"velocity"``,
    ``"acceleration"``); ``tcp_node``: the node whose driving-point FRFs are the TCP's.
    """

    pose: tuple | None = None
    response: str | None = None
    tcp_node: int | None = None

    def __post_init__(self) -> None:
        if self.response is not None and self.response not in RESPONSES:
            raise ValueError(f"--response {self.response}: one of {', '.join(RESPONSES)}")

    @classmethod
    def at(cls, robot, pose: str | None = None, response: str | None = None,
           tcp_node: int | None = None) -> UffOptions:
        """The options with the measured ``pose`` (a pose name of ``robot`` or
        ``q1,...,q6`` in degrees, checked against its limits) resolved."""
        from ....robot.description import pose_from_string

        q = None if pose is None else pose_from_string(robot, pose)
        label = None if pose is None else (pose.strip() if pose.strip() in robot.poses
                                           else "measured")
        return cls(None if q is None else (label, q), response, tcp_node)


def _pyuff():
    try:
        import pyuff
    except ImportError:
        raise MissingDependencyError("pyuff", "universal files") from None
    return pyuff


@dataclass(frozen=True, eq=False)
class UffContent:
    """What :func:`read_uff` found in a universal file (SI, base frame).

    Attributes
    ----------
    header : dict
        The 151 header's text fields (empty without one).
    units : str
        The 164 units description (``"SI"`` without one).
    nodes : (k,) int
        Node ids of the 15/2411 geometry, as in the file.
    coordinates : (k, 3) float
        Their positions in the base frame [m] (from their definition systems).
    frfs : tuple of UffFrf
        One per pose, from the 58 sets.
    shapes : ShapeData or None
        Mode shapes of the 55 and 2414 sets.
    types : tuple of int
        Every dataset's type, in file order.
    geometry : tuple of PoseGeometry
        The geometry pose by pose, in point ids (one of pose None for a file without
        flexarm's pose marks).
    modal_mass : (m,) float or None
        Modal mass of each row of ``shapes`` (SI; 0 where the file does not give it).
    """

    header: dict
    units: str
    nodes: np.ndarray
    coordinates: np.ndarray
    frfs: tuple = ()
    shapes: ShapeData | None = None
    types: tuple = field(default=())
    geometry: tuple = ()
    modal_mass: np.ndarray | None = None


def _pose_of(dset: dict, pose: str | None, q) -> tuple[str | None, np.ndarray | None, int]:
    """The set's pose mark, else the caller's pose, else ``(None, None)``; and the
    offset of its node ids (0 without one)."""
    text = " ".join(str(dset.get(f"id{k}", "")) for k in range(1, 6))
    m = _MARK.search(text)
    if m is not None:
        qd = np.array([float(v) for v in m.group(2).split(",")])
        offset = _OFFSET.search(text)
        return (m.group(1), np.deg2rad(np.r_[qd, np.zeros(6 - len(qd))]),
                int(offset.group(1)) if offset else 0)
    if q is None:
        return None, None, 0
    q = np.asarray(q, float)
    return (pose or "uff"), np.r_[q, np.zeros(6 - len(q))], 0


def _renumbered(dset: dict, offset: int) -> dict:
    """The set with its node ids less the pose's offset."""
    if not offset:
        return dset
    out = dict(dset)
    for name in ("node_nums", "rsp_node", "ref_node"):
        if name in out:
            out[name] = np.asarray(out[name], np.int64) - offset
    return out


def _mode(where: Where, i: int, dset: dict) -> tuple[float, float, np.ndarray, np.ndarray]:
    """(freq [Hz], damping ratio, node ids, (k, 3) shape) of one 55 set."""
    kind = int(dset.get("analysis_type", -1))
    nodes = np.asarray(dset["node_nums"], dtype=np.int64)
    phi = np.column_stack([np.asarray(dset[r]) for r in ("r1", "r2", "r3")])
    if kind == 2:
        return float(dset["freq"]), float(dset.get("modal_damp_vis", 0.0)), nodes, phi
    if kind in (3, 7):
        eig = complex(dset["eig"])
        w = abs(eig)
        if w == 0:
            raise where.error(i, 55, "eig", "the eigenvalue is zero")
        return w / (2 * np.pi), -eig.real / w, nodes, phi
    raise where.error(i, 55, "analysis_type", f"analysis type {kind} is not normal (2) or "
                      "complex (3) modes")


def _collect_shapes(where: Where, items: list) -> ShapeData | None:
    """:class:`ShapeData` from (index, dset, pose, q, freq, zeta, nodes, phi) items."""
    if not items:
        return None
    i0, nodes0 = items[0][0], items[0][6]
    for i, *_, nodes, _ in items[1:]:
        if not np.array_equal(nodes, nodes0):
            raise where.error(i, 55, "node_nums", f"the nodes differ from dataset {i0 + 1}'s "
                              "(every mode must list the same nodes)")
    poses = np.array([it[2] for it in items])
    phi = np.array([it[7].ravel() for it in items])  # node-major: x, y, z per node
    measured = np.zeros(phi.shape[1], bool)
    for p in np.unique(poses):
        measured |= np.any(phi[poses == p] != 0, axis=0)
    modes = np.zeros(len(items), np.int64)
    for p in np.unique(poses):
        modes[poses == p] = np.arange(1, int((poses == p).sum()) + 1)
    zeta = np.array([it[5] for it in items])
    return ShapeData(poses=poses, q=np.array([it[3] for it in items]), modes=modes,
                     freq_hz=np.array([it[4] for it in items]),
                     damping_ratio=zeta if np.any(zeta) else None,
                     nodes=np.repeat(nodes0, 3)[measured],
                     dirs=np.tile(list(DIRECTIONS), len(nodes0))[measured],
                     shapes=phi[:, measured])


def _modes_to_base(path: Path, frames, items: list, offsets: dict) -> list:
    """The mode items with their shapes turned into the base frame, pose by pose (a
    pose's modes tell together which local directions were measured)."""
    out = list(items)
    for label in dict.fromkeys(it[2] for it in items):
        mine = [k for k, it in enumerate(items) if it[2] == label]
        nodes = items[mine[0]][6]
        if any(not np.array_equal(items[k][6], nodes) for k in mine):
            continue  # refused by _collect_shapes, naming the dataset
        phi = shapes_to_base(path, frames, nodes + offsets.get(label, 0),
                             np.array([items[k][7] for k in mine]))
        for k, shape in zip(mine, phi, strict=True):
            out[k] = (*items[k][:7], shape)
    return out


def _read_all(pyuff, name: str, path: Path) -> list:
    """Every dataset of the universal file ``name`` (``path`` in messages)."""
    import contextlib
    import io

    with contextlib.redirect_stdout(io.StringIO()):  # pyuff prints notes of its own
        try:
            uff = pyuff.UFF(name)
            types = list(uff.get_set_types())
        except Exception as exc:  # noqa: BLE001 - pyuff raises bare Exceptions
            raise ReadError(f"{path}: not a readable universal file ({exc})") from None
        out = []
        for i, t in enumerate(types):
            try:
                out.append(uff.read_sets(i))
            except Exception as exc:  # noqa: BLE001
                where = bad_number(Path(name).read_bytes(), i)
                why = f"{where}" if where else f"cannot read it ({exc})"
                raise ReadError(f"{path}, dataset {i + 1} (type {int(t)}): {why}") from None
    return out


def _sets(path: Path) -> list:
    """The datasets of ``path`` through pyuff.  A fixed-format file whose lines are padded
    with blanks to 80 columns (as SDynPy writes it; valid, but pyuff 2.5 reads a padded
    last data line of a 58 set as numbers and fails) is read again with its lines
    right-trimmed, which changes no field."""
    import tempfile

    pyuff = _pyuff()
    cut = truncation(path.read_bytes()) if path.is_file() else None
    if cut is not None:
        raise ReadError(f"{path}: {cut}; export it again")
    try:
        out = _read_all(pyuff, str(path), path)
    except ReadError:
        raw = path.read_bytes()
        lines = raw.split(b"\n")
        if b"\x00" in raw or not any(line.endswith(b" ") for line in lines):
            raise
        with tempfile.TemporaryDirectory() as tmp:
            trimmed = Path(tmp) / path.name
            trimmed.write_bytes(b"\n".join(line.rstrip(b" \r") for line in lines))
            out = _read_all(pyuff, str(trimmed), path)
        log.info("%s: lines padded with blanks were right-trimmed for pyuff", path)
    if not out:
        raise ReadError(f"{path}: no datasets (a universal file holds blocks between "
                        "'    -1' lines)")
    return out


def read_uff(path: PathType, pose: str | None = None, q=None,
             response: str | None = None) -> UffContent:
    """Read the 151, 164, 2420/18, 15/2411, 82, 58, 55 and 2414 datasets of a universal
    file.

    Parameters
    ----------
    path : path-like
        ``.uff`` or ``.unv`` file (ASCII or binary 58).
    pose : str, optional
        Pose label of sets without a flexarm pose mark (default ``"uff"``).
    q : (n,) float, optional
        Their joint angles [rad].  Without them a file whose 55 or 58 sets carry no pose
        mark is refused: it is never read at zero joint angles.
    response : {"displacement", "velocity", "acceleration"}, optional
        What the ordinate of 58 sets of type unknown or general is, when their unit label
        does not say.

    Returns
    -------
    UffContent
        FRFs as receptance [m/N] (with their coherence), shapes and their modal mass,
        the geometry [m] pose by pose, in the base frame.
    """
    path = Path(path)
    where = Where(path)
    header, units, factors = {}, "SI", (1.0, 1.0)
    blocks, systems, frfs, modes = [], {}, [], []
    traces, coherence, masses, offsets = [], [], [], {}
    sets = _sets(path)
    for i, d in enumerate(sets):
        t = int(d["type"])
        if t == 151:
            header = {k: str(v) for k, v in d.items() if k != "type"}
        elif t == 164:
            length, force = float(d.get("length", 1.0)), float(d.get("force", 1.0))
            if not (length > 0 and force > 0):
                raise where.error(i, 164, "length" if not length > 0 else "force",
                                  "unit factors must be positive")
            units, factors = str(d.get("units_description", "")).strip(), (length, force)
        elif t in _NODES:
            blocks.append((d["node_nums"], np.column_stack([d["x"], d["y"], d["z"]]),
                           d.get("def_cs", 0), d.get("disp_cs", 0), factors[0]))
        elif t == 2420:
            systems.update((c.label, c) for c in systems_2420(path, i, d, factors[0]))
        elif t == 18:
            systems.update((c.label, c) for c in systems_18(path, i, d, systems, factors[0]))
        elif t == 82:
            n = int(d.get("n_nodes", len(d["nodes"])))  # pyuff pads the last line with 0
            traces.append(np.asarray(d["nodes"], float).astype(np.int64)[:n])
        elif t == 58 and int(d.get("func_type", -1)) == COHERENCE:
            label, qq, off = _pose_of(d, pose, q)
            coherence.append((i, _renumbered(d, off), label, *coherence_of(where, i, d)))
        elif t == 58:
            label, qq, off = _pose_of(d, pose, q)
            f, H = frf_of(where, i, d, factors[1] / factors[0], response)
            frfs.append((i, _renumbered(d, off), label, qq, f, H))
            offsets.setdefault(label, off)
        elif t == 55 or (t == 2414 and is_mode_2414(d)):
            label, qq, off = _pose_of(d, pose, q)
            d = _renumbered(d, off)
            modes.append((i, d, label, qq, *(_mode if t == 55 else mode_2414)(where, i, d)))
            masses.append(modal_mass(d))
            offsets.setdefault(label, off)
    if coherence and not frfs:
        raise where.error(coherence[0][0], 58, "func_type", "coherence, not frequency response "
                          "functions (type 4): export the FRFs (H1/H2) with it")
    unposed = [it[0] for it in frfs + modes if it[2] is None]
    if unposed:
        more = f" and {len(unposed) - 1} more" if len(unposed) > 1 else ""
        raise ReadError(f"{path}: dataset {unposed[0] + 1}{more} carry no robot pose (files "
                        "of other tools have no 'flexarm pose=' mark): give the pose they were "
                        "measured at, --pose NAME or --pose q1,...,q6 [deg]")
    log.info("read %s: %d datasets (%d FRFs, %d modes)", path, len(sets), len(frfs), len(modes))
    frames = node_frames(path, blocks, systems)
    return UffContent(header, units or "SI", frames.nodes, frames.coordinates,
                      tuple(frf_to_base(path, frames, f, offsets.get(f.pose, 0))
                            for f in collect_frfs(where, frfs, coherence)),
                      _collect_shapes(where, _modes_to_base(path, frames, modes, offsets)),
                      tuple(int(d["type"]) for d in sets),
                      pose_geometries(frames.nodes, frames.coordinates, traces, offsets),
                      np.array(masses) if masses else None)


def read(path: PathType, limits=None, uff: UffOptions | None = None):
    """A universal file as measurements: its mode shapes (:class:`ShapeData`) when it
    has 55 sets, else its FRFs at the TCP node (:class:`FrfData`, every pose).

    ``uff`` says what the file does not (:class:`UffOptions`).
    """
    uff = uff or UffOptions()
    label, q = uff.pose if uff.pose is not None else (None, None)
    content = read_uff(path, label, q, uff.response)
    if content.shapes is not None:
        return content.shapes
    if not content.frfs:
        found = ", ".join(str(t) for t in dict.fromkeys(content.types)) or "none"
        raise ReadError(f"{path}: no mode shapes (55) or FRFs (58) in it (datasets: {found}; "
                        "geometry alone cannot be compared): export the test's FRFs or mode "
                        "shapes")
    try:
        parts = [f.to_frf_data(uff.tcp_node) for f in content.frfs]
    except ValueError as exc:
        raise ReadError(f"{path}: {exc}") from None
    g2 = [d.coherence for d in parts]
    return FrfData(**{name: np.concatenate([np.asarray(getattr(d, name)) for d in parts])
                      for name in ("poses", "q", "inputs", "outputs", "freq_hz",
                                   "receptance")},
                   coherence=None if any(g is None for g in g2) else np.concatenate(g2))
