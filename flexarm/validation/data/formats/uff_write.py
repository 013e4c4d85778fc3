"""Universal files written through pyuff: 151 header, 164 SI units, 15 nodes, 55 mode
shapes, 58 receptances (see :mod:`.uff` for what each holds and how poses are marked).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ....fe.files import atomic_path
from ....fe.typing import PathType
from ..measurements import DIRECTIONS
from ..shape_data import ShapeData
from .uff import UffFrf, _pyuff

__all__ = ["write_uff", "write"]


def _mark(pose: str, q) -> str:
    return f"flexarm pose={pose} q_deg=" + ",".join(f"{v:.10g}" for v in np.rad2deg(q))


def _shape_sets(pyuff, shapes: ShapeData) -> list[dict]:
    nodes = np.unique(shapes.nodes)
    col = {d: k for k, d in enumerate(DIRECTIONS)}
    out = []
    for r in range(len(shapes.poses)):
        phi = np.zeros((len(nodes), 3), dtype=shapes.shapes.dtype)
        phi[np.searchsorted(nodes, shapes.nodes), [col[d] for d in shapes.dirs]] = shapes.shapes[r]
        zeta = 0.0 if shapes.damping_ratio is None else float(shapes.damping_ratio[r])
        common = dict(model_type=1, data_ch=2, spec_data_type=8, load_case=1,
                      mode_n=int(shapes.modes[r]), node_nums=nodes, r1=phi[:, 0],
                      r2=phi[:, 1], r3=phi[:, 2], id1="flexarm mode shape",
                      id4=_mark(str(shapes.poses[r]), shapes.q[r]))
        w = 2 * np.pi * float(shapes.freq_hz[r])
        if np.iscomplexobj(phi):
            eig = w * complex(-zeta, np.sqrt(1 - zeta**2))
            out.append(pyuff.prepare_55(analysis_type=3, eig=eig, **common))
        else:
            out.append(pyuff.prepare_55(analysis_type=2, freq=float(shapes.freq_hz[r]),
                                        modal_damp_vis=zeta, **common))
    return out


def _frf_sets(pyuff, frf: UffFrf, binary: bool) -> list[dict]:
    f = np.asarray(frf.freq_hz, float)
    # evenly spaced lines, as analyzers write them: first line and increment, no abscissae
    step = np.diff(f)
    even = int(f.size > 1 and np.allclose(step, step[0], rtol=1e-9, atol=0))
    out = []
    for k in range(len(frf.H)):
        d = pyuff.prepare_58(
            binary=int(binary), id1="flexarm receptance", id4=_mark(frf.pose, frf.q),
            func_type=4, rsp_node=int(frf.out_nodes[k]),
            rsp_dir=DIRECTIONS.index(str(frf.out_dirs[k])) + 1, ref_node=int(frf.in_nodes[k]),
            ref_dir=DIRECTIONS.index(str(frf.in_dirs[k])) + 1, data=np.asarray(frf.H[k]),
            x=f, abscissa_spacing=even, abscissa_spec_data_type=18, ordinate_spec_data_type=8,
            orddenom_spec_data_type=13, ordinate_axis_units_lab="m/N",
            abscissa_axis_units_lab="Hz")
        out.append(d)
    return out


def write_uff(path: PathType, shapes: ShapeData | None = None, frfs=(), nodes=None,
              coordinates=None, description: str = "flexarm virtual lab",
              binary: bool = False) -> Path:
    """Write a universal file (151, 164 SI, 15, 55, 58) with pyuff's writer, atomically.

    Parameters
    ----------
    path : path-like
        Target ``.uff``/``.unv`` file.
    shapes : ShapeData, optional
        Mode shapes: one 55 set per pose and mode (real: normal modes with their
        viscous damping ratio; complex: complex modes).  pyuff writes 6 significant
        digits (``%13.5e``).
    frfs : sequence of UffFrf
        Receptances [m/N]: one 58 set per FRF (ASCII: 12 significant digits, or
        ``binary`` doubles).
    nodes, coordinates : (k,) int and (k, 3) float, optional
        Test geometry [m], base frame (a 15 set).
    description : str
        Text of the 151 header.
    """
    pyuff = _pyuff()
    sets = [pyuff.prepare_151(model_name=Path(path).stem, description=description,
                              db_app="flexarm", program="flexarm"),
            pyuff.prepare_164(units_code=1, units_description="SI", temp_mode=1, length=1.0,
                              force=1.0, temp=1.0, temp_offset=273.15)]
    if nodes is not None:
        c = np.asarray(coordinates, float).reshape(-1, 3)
        k = len(c)
        sets.append(pyuff.prepare_15(node_nums=np.asarray(nodes, int), def_cs=[0] * k,
                                     disp_cs=[0] * k, color=[1] * k, x=c[:, 0], y=c[:, 1],
                                     z=c[:, 2]))
    if shapes is not None:
        sets += _shape_sets(pyuff, shapes)
    for frf in frfs:
        sets += _frf_sets(pyuff, frf, binary)
    with atomic_path(path) as tmp:
        pyuff.UFF(str(tmp)).write_sets(sets, mode="overwrite")
    return Path(path)


def write(path: PathType, data, comments=()) -> Path:
    """Write :class:`ShapeData` as 55 sets (the measurement registry's writer)."""
    if not isinstance(data, ShapeData):
        raise ValueError(f"a universal file from measurements needs mode shapes (ShapeData), "
                         f"got {type(data).__name__}")
    return write_uff(path, shapes=data, description=" ".join(map(str, comments)) or
                     "flexarm mode shapes")
