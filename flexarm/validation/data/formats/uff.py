"""Universal files (UFF/UNV) as test rigs write them, read and written through pyuff.

Datasets understood:

- **151** header (model name, description, program): kept as text.
- **164** units: the factors that turn file units into SI (``SI = value / factor``,
  as the UFF definition says); a file without one is SI.  They apply to the datasets
  after them.
- **15** / **2411** nodes: the test geometry, base frame [m].
- **58** FRFs (``func_type`` 4): one response DOF per reference DOF, ordinate
  displacement (8), velocity (11) or acceleration (12) over force (13); turned into
  receptance [m/N] at ``+x, +y, +z`` (a negative UFF direction flips the sign).
- **55** mode shapes: normal (analysis type 2, real shapes, viscous damping ratio)
  or complex (3, eigenvalue ``-ζω ± iω√(1-ζ²)``); x, y, z per node.  A DOF that is
  exactly zero in every mode of a pose is taken as not measured and dropped.

A pose is not a universal-file notion: flexarm writes ``flexarm pose=<label>
q_deg=<q1,...,q6>`` into ID line 4 of every 55 and 58 set it writes and reads it
back; other files get the ``pose`` and ``q`` the caller gives.  Every error names
the file, the dataset (1-based, with its type) and the field.  The writer is
:mod:`.uff_write`.
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

__all__ = ["EXTENSIONS", "UffFrf", "UffContent", "read_uff", "read"]

log = logging.getLogger(__name__)

EXTENSIONS = (".uff", ".unv")
_MARK = re.compile(r"flexarm pose=(\S+) q_deg=(\S+)")
_RESPONSE = {8: 0, 11: 1, 12: 2}  # ordinate type -> power of i*omega that divides it
_FORCE = (0, 13)  # unknown or force
_NODES = (15, 2411)


def _pyuff():
    try:
        import pyuff
    except ImportError:
        raise MissingDependencyError("pyuff", "universal files") from None
    return pyuff


@dataclass(frozen=True, eq=False)
class UffFrf:
    """FRFs of one pose from 58 datasets, receptance in the base frame.

    Attributes
    ----------
    pose : str
    q : (6,) float
        Joint angles [rad] (zeros when neither the file nor the caller gave them).
    freq_hz : (nf,) float
        Frequency lines [Hz], shared by every FRF.
    out_nodes, in_nodes : (n,) int
        Response and reference node of each FRF.
    out_dirs, in_dirs : (n,) str
        Their directions, ``x``, ``y`` or ``z`` (positive).
    H : (n, nf) complex
        Receptance [m/N].
    """

    pose: str
    q: np.ndarray
    freq_hz: np.ndarray
    out_nodes: np.ndarray
    out_dirs: np.ndarray
    in_nodes: np.ndarray
    in_dirs: np.ndarray
    H: np.ndarray

    def matrix(self) -> tuple[list[str], list[str], np.ndarray]:
        """Output DOF labels, input DOF labels and (nf, n_out, n_in) receptance [m/N]
        (NaN where the file has no FRF for the pair)."""
        outs = [f"{n}{d}" for n, d in zip(self.out_nodes, self.out_dirs, strict=True)]
        ins = [f"{n}{d}" for n, d in zip(self.in_nodes, self.in_dirs, strict=True)]
        uo, ui = list(dict.fromkeys(outs)), list(dict.fromkeys(ins))
        A = np.full((len(self.freq_hz), len(uo), len(ui)), np.nan + 0j)
        A[:, [uo.index(o) for o in outs], [ui.index(i) for i in ins]] = self.H.T
        return uo, ui, A

    def to_frf_data(self, node: int | None = None) -> FrfData:
        """The FRFs at one node (the TCP) as :class:`FrfData`; ``node`` None: the
        only node the FRFs use."""
        nodes = np.unique(np.r_[self.out_nodes, self.in_nodes])
        if node is None:
            if len(nodes) != 1:
                raise ValueError(f"the FRFs of pose '{self.pose}' use nodes "
                                 f"{', '.join(map(str, nodes))}: name the TCP node")
            node = int(nodes[0])
        keep = (self.out_nodes == node) & (self.in_nodes == node)
        nf, k = len(self.freq_hz), int(keep.sum())
        return FrfData(poses=[self.pose] * (nf * k), q=np.tile(self.q, (nf * k, 1)),
                       inputs=np.repeat(self.in_dirs[keep], nf),
                       outputs=np.repeat(self.out_dirs[keep], nf),
                       freq_hz=np.tile(self.freq_hz, k), receptance=self.H[keep].ravel())


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
        Node ids of the 15/2411 geometry.
    coordinates : (k, 3) float
        Their coordinates [m].
    frfs : tuple of UffFrf
        One per pose, from the 58 sets.
    shapes : ShapeData or None
        Mode shapes of the 55 sets.
    """

    header: dict
    units: str
    nodes: np.ndarray
    coordinates: np.ndarray
    frfs: tuple = ()
    shapes: ShapeData | None = None
    types: tuple = field(default=())


class _Where:
    """Error messages naming the file, the dataset and the field."""

    def __init__(self, path: Path):
        self.path = path

    def error(self, i: int, kind: int, name: str, message: str) -> ReadError:
        return ReadError(f"{self.path}, dataset {i + 1} (type {kind}), field '{name}': "
                         f"{message}")


def _pose_of(dset: dict, pose: str | None, q) -> tuple[str, np.ndarray]:
    text = " ".join(str(dset.get(f"id{k}", "")) for k in range(1, 6))
    m = _MARK.search(text)
    if m is not None:
        qd = np.array([float(v) for v in m.group(2).split(",")])
        return m.group(1), np.deg2rad(np.r_[qd, np.zeros(6 - len(qd))])
    return (pose or "uff"), np.zeros(6) if q is None else np.asarray(q, float)


def _direction(where: _Where, i: int, name: str, code) -> tuple[str, float]:
    code = int(code)
    if abs(code) not in (1, 2, 3):
        raise where.error(i, 58, name, f"direction {code} is not a translation (±1, ±2, ±3): "
                          "rotational DOFs are not supported")
    return DIRECTIONS[abs(code) - 1], float(np.sign(code))


def _frf(where: _Where, i: int, dset: dict, factor: float):
    """(freq [Hz], receptance [m/N]) of one 58 set (positive directions)."""
    if int(dset.get("func_type", -1)) != 4:
        raise where.error(i, 58, "func_type", f"function type {dset.get('func_type')} is not "
                          "a frequency response function (4)")
    spec = int(dset.get("ordinate_spec_data_type", 8))
    if spec not in _RESPONSE:
        raise where.error(i, 58, "ordinate_spec_data_type", f"ordinate type {spec} is not "
                          "displacement (8), velocity (11) or acceleration (12)")
    if int(dset.get("orddenom_spec_data_type", 13)) not in _FORCE:
        raise where.error(i, 58, "orddenom_spec_data_type", "the denominator must be a force "
                          f"(13), got {dset.get('orddenom_spec_data_type')}")
    freq = np.asarray(dset["x"], float)
    data = np.asarray(dset["data"])
    if not np.iscomplexobj(data):
        raise where.error(i, 58, "ord_data_type", "FRF data must be complex (5 or 6)")
    power = _RESPONSE[spec]
    if power and np.any(freq <= 0):
        raise where.error(i, 58, "x", "a velocity or acceleration FRF cannot be turned into "
                          "receptance at 0 Hz: the abscissa must be positive")
    H = data * factor / (2j * np.pi * np.where(freq > 0, freq, 1.0)) ** power
    _, s_out = _direction(where, i, "rsp_dir", dset["rsp_dir"])
    _, s_in = _direction(where, i, "ref_dir", dset["ref_dir"])
    return freq, H * s_out * s_in


def _collect_frfs(where: _Where, items: list) -> tuple[UffFrf, ...]:
    """One :class:`UffFrf` per pose from (index, dset, pose, q, freq, H) items."""
    out = []
    for label in dict.fromkeys(it[2] for it in items):
        mine = [it for it in items if it[2] == label]
        i0, _, _, q, freq, _ = mine[0]
        for i, _, _, _, f, _ in mine[1:]:
            if f.shape != freq.shape or not np.array_equal(f, freq):
                raise where.error(i, 58, "x", f"frequency lines differ from dataset {i0 + 1} "
                                  f"of the same pose '{label}'")
        d = [it[1] for it in mine]
        out.append(UffFrf(
            label, q, freq,
            np.array([int(s["rsp_node"]) for s in d]),
            np.array([_direction(where, it[0], "rsp_dir", it[1]["rsp_dir"])[0] for it in mine]),
            np.array([int(s["ref_node"]) for s in d]),
            np.array([_direction(where, it[0], "ref_dir", it[1]["ref_dir"])[0] for it in mine]),
            np.array([it[5] for it in mine])))
    return tuple(out)


def _mode(where: _Where, i: int, dset: dict) -> tuple[float, float, np.ndarray, np.ndarray]:
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


def _collect_shapes(where: _Where, items: list) -> ShapeData | None:
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


def _sets(path: Path) -> list:
    pyuff = _pyuff()
    try:
        uff = pyuff.UFF(str(path))
        types = list(uff.get_set_types())
    except Exception as exc:  # noqa: BLE001 - pyuff raises bare Exceptions
        raise ReadError(f"{path}: not a readable universal file ({exc})") from None
    out = []
    for i, t in enumerate(types):
        try:
            out.append(uff.read_sets(i))
        except Exception as exc:  # noqa: BLE001
            raise ReadError(f"{path}, dataset {i + 1} (type {int(t)}): cannot read it "
                            f"({exc})") from None
    if not out:
        raise ReadError(f"{path}: no datasets (a universal file holds blocks between "
                        "'    -1' lines)")
    return out


def read_uff(path: PathType, pose: str | None = None, q=None) -> UffContent:
    """Read the 151, 164, 15/2411, 58 and 55 datasets of a universal file.

    Parameters
    ----------
    path : path-like
        ``.uff`` or ``.unv`` file (ASCII or binary 58).
    pose : str, optional
        Pose label of sets without a flexarm pose mark (default ``"uff"``).
    q : (6,) float, optional
        Their joint angles [rad] (default zeros).

    Returns
    -------
    UffContent
        FRFs as receptance [m/N], shapes, nodes [m], in the base frame.
    """
    path = Path(path)
    where = _Where(path)
    header, units, factors = {}, "SI", (1.0, 1.0)
    nodes, coords, frfs, modes = [], [], [], []
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
            nodes.append(np.asarray(d["node_nums"], float).astype(np.int64))
            coords.append(np.column_stack([d["x"], d["y"], d["z"]]) / factors[0])
        elif t == 58:
            label, qq = _pose_of(d, pose, q)
            f, H = _frf(where, i, d, factors[1] / factors[0])
            frfs.append((i, d, label, qq, f, H))
        elif t == 55:
            label, qq = _pose_of(d, pose, q)
            modes.append((i, d, label, qq, *_mode(where, i, d)))
    log.info("read %s: %d datasets (%d FRFs, %d modes)", path, len(sets), len(frfs), len(modes))
    return UffContent(header, units or "SI",
                      np.concatenate(nodes) if nodes else np.zeros(0, np.int64),
                      np.concatenate(coords) if coords else np.zeros((0, 3)),
                      _collect_frfs(where, frfs), _collect_shapes(where, modes),
                      tuple(int(d["type"]) for d in sets))


def read(path: PathType, limits=None):
    """A universal file as measurements: its mode shapes (:class:`ShapeData`) when it
    has 55 sets, else its FRFs at one node (:class:`FrfData`)."""
    content = read_uff(path)
    if content.shapes is not None:
        return content.shapes
    if len(content.frfs) == 1:
        return content.frfs[0].to_frf_data()
    if content.frfs:
        raise ReadError(f"{path}: FRFs of {len(content.frfs)} poses; read them with read_uff")
    raise ReadError(f"{path}: no mode shapes (55) or FRFs (58) in it")
