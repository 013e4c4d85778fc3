"""Universal files as a vibration analyzer writes them, through pyuff's writer.

Datasets, in this order:

- **151** header and **164** units (SI: every factor 1);
- **2420** coordinate system 1, the robot's base frame (identity), which every node
  uses for its position and its directions;
- **2411** nodes, one block per pose: the measurement points where they are at that
  pose [m], numbered per pose as :mod:`.uff_geometry` says (pose ``j`` adds
  ``j * stride`` to the point ids; one 2411 block per pose with the same ids would make
  SDynPy and pyuff, which join every 2411 block into one geometry, see each node
  several times);
- **82** tracelines, one per pose: the arm as a stick figure through that pose's points;
- **55** mode shapes, one per pose and mode: x, y, z at every point of the pose, with
  frequency, viscous damping ratio and modal mass;
- **58** receptances [m/N], one per FRF (evenly spaced lines as first line and
  increment), and a 58 coherence (function type 6) beside each FRF that carries one.

Dataset 15, the older node format, is not written: 2411 holds the same nodes, SDynPy
skips 15 with a note on stdout, and a reader that takes both would see every node twice.

**Modal mass.**  The caller states it per mode.  The lab's shapes are mass-normalised
(``phi^T M phi = 1``, metres per unit modal coordinate), so the lab writes 1 (SI): the
receptance is ``sum_r phi_o phi_i / (m_r (w_r^2 - w^2 + 2 i zeta_r w_r w))`` with
``m_r = 1``, which is how the lab's 58 FRFs are made.  Shapes of unknown scaling get 0,
which UFF readers take as "not given".

**Poses.**  ID line 4 of every 55 and 58 set holds ``flexarm pose=<label>
q_deg=<q1,...,q6>`` and, past the first pose, ID line 5 ``flexarm nodes+=<offset>``
(ID line 4 keeps its 80 columns for the angles); :mod:`.uff` reads both back.

**Precision**: 55 values (shapes, frequency, damping, modal mass) with 7 significant
digits in the format's 13-column fields (:mod:`.uff_write55`; pyuff's writer puts 6
there), 58 ASCII ordinates with 12 (or binary doubles), 2411 coordinates with 17.
"""

from __future__ import annotations

from itertools import groupby
from pathlib import Path

import numpy as np

from ....fe.files import atomic_path
from ....fe.typing import PathType
from ..measurements import DIRECTIONS
from ..shape_data import ShapeData
from .uff import UffFrf, _pyuff
from .uff_geometry import PoseGeometry, pose_offsets
from .uff_write55 import write_55

__all__ = ["write_uff", "write"]

#: Base frame as a UFF coordinate system: rotation rows, then the origin.
_BASE = np.vstack([np.eye(3), np.zeros((1, 3))])


def _mark(pose: str, q, offset: int = 0) -> dict:
    """ID lines 4 and 5 of a set of ``pose`` whose node ids are shifted by ``offset``."""
    mark = f"flexarm pose={pose} q_deg=" + ",".join(f"{v:.10g}" for v in np.rad2deg(q))
    return dict(id4=mark, id5=f"flexarm nodes+={offset}" if offset else "NONE")


def _color(j: int) -> int:
    """A UFF colour per pose (1 blue ... 14; not 0 black nor 15 white)."""
    return 1 + j % 14


def _shape_sets(pyuff, shapes: ShapeData, offsets: dict, modal_mass) -> list[dict]:
    nodes = np.unique(shapes.nodes)
    col = {d: k for k, d in enumerate(DIRECTIONS)}
    mass = np.broadcast_to(np.asarray(0.0 if modal_mass is None else modal_mass, float),
                           (len(shapes.poses),))
    out = []
    for r in range(len(shapes.poses)):
        pose = str(shapes.poses[r])
        phi = np.zeros((len(nodes), 3), dtype=shapes.shapes.dtype)
        phi[np.searchsorted(nodes, shapes.nodes), [col[d] for d in shapes.dirs]] = shapes.shapes[r]
        zeta = 0.0 if shapes.damping_ratio is None else float(shapes.damping_ratio[r])
        common = dict(model_type=1, data_ch=2, spec_data_type=8, load_case=1,
                      mode_n=int(shapes.modes[r]), node_nums=nodes + offsets[pose],
                      r1=phi[:, 0], r2=phi[:, 1], r3=phi[:, 2], id1="flexarm mode shape",
                      **_mark(pose, shapes.q[r], offsets[pose]))
        w = 2 * np.pi * float(shapes.freq_hz[r])
        if np.iscomplexobj(phi):
            eig = w * complex(-zeta, np.sqrt(1 - zeta**2))
            # modal A of a complex mode scaled like a normal one: 2 i w_d m_r
            out.append(pyuff.prepare_55(analysis_type=3, eig=eig, modal_a=2j * eig.imag * mass[r],
                                        modal_b=0j, **common))
        else:
            out.append(pyuff.prepare_55(analysis_type=2, freq=float(shapes.freq_hz[r]),
                                        modal_m=float(mass[r]), modal_damp_vis=zeta, **common))
    return out


def _frf_sets(pyuff, frf: UffFrf, binary: bool, offset: int) -> list[dict]:
    f = np.asarray(frf.freq_hz, float)
    # evenly spaced lines, as analyzers write them: first line and increment, no abscissae
    step = np.diff(f)
    even = int(f.size > 1 and np.allclose(step, step[0], rtol=1e-9, atol=0))
    out = []
    for k in range(len(frf.H)):
        where = dict(
            binary=int(binary), **_mark(frf.pose, frf.q, offset),
            rsp_node=int(frf.out_nodes[k]) + offset,
            rsp_dir=DIRECTIONS.index(str(frf.out_dirs[k])) + 1,
            ref_node=int(frf.in_nodes[k]) + offset,
            ref_dir=DIRECTIONS.index(str(frf.in_dirs[k])) + 1, x=f, abscissa_spacing=even,
            abscissa_spec_data_type=18, abscissa_axis_units_lab="Hz")
        out.append(pyuff.prepare_58(
            id1="flexarm receptance", func_type=4, data=np.asarray(frf.H[k]),
            ordinate_spec_data_type=8, orddenom_spec_data_type=13,
            ordinate_axis_units_lab="m/N", **where))
        if frf.coherence is not None:
            out.append(pyuff.prepare_58(
                id1="flexarm coherence", func_type=6,
                data=np.asarray(frf.coherence[k], float), ordinate_spec_data_type=0,
                orddenom_spec_data_type=0, ordinate_axis_units_lab="", **where))
    return out


def _geometry_sets(pyuff, geometry, offsets: dict) -> list[dict]:
    sets = [pyuff.prepare_2420(Part_UID=1, Part_Name="flexarm", CS_sys_labels=[1],
                               CS_types=[0], CS_colors=[8], CS_names=["base frame"],
                               CS_matrices=[_BASE])]
    lines = []
    for j, g in enumerate(geometry):
        offset = offsets.get(g.pose, 0)
        c = np.asarray(g.coordinates, float).reshape(-1, 3)
        k = len(c)
        sets.append(pyuff.prepare_2411(
            node_nums=np.asarray(g.nodes, np.int64) + offset, def_cs=np.ones(k, int),
            disp_cs=np.ones(k, int), color=np.full(k, _color(j)), x=c[:, 0], y=c[:, 1],
            z=c[:, 2]))
        if len(g.lines):
            chain = np.asarray(g.lines, np.int64)
            lines.append(pyuff.prepare_82(
                trace_num=j + 1, n_nodes=len(chain), color=_color(j),
                id=f"pose {g.pose}" if g.pose else "test geometry",
                nodes=np.where(chain == 0, 0, chain + offset)))
    return sets + lines


def write_uff(path: PathType, shapes: ShapeData | None = None, frfs=(),
              geometry: tuple[PoseGeometry, ...] = (), modal_mass=None,
              description: str = "flexarm virtual lab", binary: bool = False) -> Path:
    """Write a universal file (see the module docstring) with pyuff's writer, atomically.

    Parameters
    ----------
    path : path-like
        Target ``.uff``/``.unv`` file.
    shapes : ShapeData, optional
        Mode shapes: one 55 set per pose and mode (real: normal modes with their
        viscous damping ratio; complex: complex modes).
    frfs : sequence of UffFrf
        Receptances [m/N] (with their coherence, if any): 58 sets.
    geometry : sequence of PoseGeometry
        Test geometry per pose [m], base frame: a 2411 block and an 82 traceline each.
    modal_mass : float or (n,) float, optional
        Modal mass of each shape row (SI; 1 for mass-normalised shapes); None: 0, not
        given.
    description : str
        Text of the 151 header.
    binary : bool
        58 ordinates as binary doubles.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.validation.data.formats.uff import read_uff
    >>> s = ShapeData(poses=["P1"], q=np.zeros((1, 6)), modes=[1], freq_hz=[7.5],
    ...               nodes=[1, 1], dirs=["x", "z"], shapes=[[0.5, -1.0]])
    >>> g = PoseGeometry("P1", np.array([1]), np.array([[0.2, 0.0, 1.1]]), np.array([1]))
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "one.uff"
    >>> back = read_uff(write_uff(f, s, geometry=[g], modal_mass=1.0))
    >>> back.coordinates.tolist(), back.modal_mass.tolist(), back.shapes.dofs
    ([[0.2, 0.0, 1.1]], [1.0], ['1x', '1z'])
    """
    pyuff = _pyuff()
    frfs = list(frfs)
    labels = [g.pose for g in geometry if g.pose is not None]
    ids = [np.asarray(g.nodes) for g in geometry] + [np.r_[f.out_nodes, f.in_nodes]
                                                     for f in frfs]
    if shapes is not None:
        labels += [str(p) for p in shapes.poses]
        ids.append(np.asarray(shapes.nodes))
    labels += [f.pose for f in frfs]
    ids = np.concatenate([np.ravel(i).astype(np.int64) for i in ids] + [np.ones(1, np.int64)])
    offsets = pose_offsets(labels, ids)
    if len(offsets) < 2:
        offsets = dict.fromkeys(offsets, 0)
    sets = [pyuff.prepare_151(model_name=Path(path).stem, description=description,
                              db_app="flexarm", program="flexarm"),
            pyuff.prepare_164(units_code=1, units_description="SI", temp_mode=1, length=1.0,
                              force=1.0, temp=1.0, temp_offset=273.15)]
    if len(geometry):
        sets += _geometry_sets(pyuff, geometry, offsets)
    if shapes is not None:
        sets += _shape_sets(pyuff, shapes, offsets, modal_mass)
    for frf in frfs:
        sets += _frf_sets(pyuff, frf, binary, offsets[frf.pose])
    with atomic_path(path) as tmp:
        _write_sets(pyuff, tmp, sets)
    return Path(path)


def _write_sets(pyuff, path: Path, sets: list[dict]) -> None:
    """The sets in their order: 55 sets with seven digits (:mod:`.uff_write55`), every
    other one with pyuff's writer."""
    first = True
    for is_55, run in groupby(sets, key=lambda d: d["type"] == 55):
        run = list(run)
        if is_55:
            with open(path, "w" if first else "a", encoding="ascii", newline="\n") as fh:
                for d in run:
                    write_55(fh, d)
        else:
            pyuff.UFF(str(path)).write_sets(run, mode="overwrite" if first else "add")
        first = False


def write(path: PathType, data, comments=()) -> Path:
    """Write :class:`ShapeData` as 55 sets (the measurement registry's writer); their
    modal mass is not known (0)."""
    if not isinstance(data, ShapeData):
        raise ValueError(f"a universal file from measurements needs mode shapes (ShapeData), "
                         f"got {type(data).__name__}")
    return write_uff(path, shapes=data, description=" ".join(map(str, comments)) or
                     "flexarm mode shapes")
